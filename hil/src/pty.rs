//! A pseudo-terminal pair in raw mode: the device side writes the master, the host opens the
//! slave by its path as it would open `/dev/ttyACM0`.

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::path::{Path, PathBuf};

/// Both ends and the slave's path.
pub struct Pty {
    /// Non-blocking master (the device's end).
    pub master: OwnedFd,
    /// The slave kept open by the device side, so the line stays up (and raw) until the host
    /// opens it; without an open slave the master reads EIO.
    pub slave: OwnedFd,
    pub path: PathBuf,
}

impl Pty {
    /// Open a pair, switch the line to raw (no echo, no newline translation: frames are binary),
    /// and make both ends close-on-exec so child processes cannot keep them alive.
    pub fn open() -> io::Result<Self> {
        let (mut m, mut s) = (0, 0);
        // SAFETY: openpty writes two fds; null name, termios and winsize are allowed.
        let r = unsafe {
            libc::openpty(
                &mut m,
                &mut s,
                std::ptr::null_mut(),
                std::ptr::null(),
                std::ptr::null(),
            )
        };
        if r != 0 {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: both fds were just returned by openpty and belong to nobody else.
        let (master, slave) = unsafe { (OwnedFd::from_raw_fd(m), OwnedFd::from_raw_fd(s)) };
        // SAFETY: termios is plain data filled by tcgetattr from a valid fd; fcntl on valid fds.
        unsafe {
            let mut t: libc::termios = std::mem::zeroed();
            if libc::tcgetattr(s, &mut t) != 0 {
                return Err(io::Error::last_os_error());
            }
            libc::cfmakeraw(&mut t);
            if libc::tcsetattr(s, libc::TCSANOW, &t) != 0 {
                return Err(io::Error::last_os_error());
            }
            let flags = libc::fcntl(m, libc::F_GETFL);
            libc::fcntl(m, libc::F_SETFL, flags | libc::O_NONBLOCK);
            libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC);
        }
        let mut name = [0 as libc::c_char; 256];
        // SAFETY: the buffer and its length are passed together.
        let r = unsafe { libc::ttyname_r(s, name.as_mut_ptr(), name.len()) };
        if r != 0 {
            return Err(io::Error::from_raw_os_error(r));
        }
        // SAFETY: ttyname_r wrote a NUL-terminated string into the buffer.
        let path = unsafe { std::ffi::CStr::from_ptr(name.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        Ok(Self {
            master,
            slave,
            path: PathBuf::from(path),
        })
    }
}

/// Read what the master has; `Ok(0)` when nothing is waiting.
pub fn read_master(master: &OwnedFd, buf: &mut [u8]) -> io::Result<usize> {
    // SAFETY: the buffer and its length are passed together; the fd is valid.
    let n = unsafe { libc::read(master.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
    if n >= 0 {
        return Ok(n as usize);
    }
    let e = io::Error::last_os_error();
    match e.kind() {
        io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted => Ok(0),
        // EIO: no slave open at this moment (the host closed it); nothing to read.
        _ if e.raw_os_error() == Some(libc::EIO) => Ok(0),
        _ => Err(e),
    }
}

/// Write as much as the master takes now; returns the count written.
pub fn write_master(master: &OwnedFd, bytes: &[u8]) -> io::Result<usize> {
    if bytes.is_empty() {
        return Ok(0);
    }
    // SAFETY: the buffer and its length are passed together; the fd is valid.
    let n = unsafe { libc::write(master.as_raw_fd(), bytes.as_ptr().cast(), bytes.len()) };
    if n >= 0 {
        return Ok(n as usize);
    }
    let e = io::Error::last_os_error();
    match e.kind() {
        io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted => Ok(0),
        _ => Err(e),
    }
}

/// Atomically (re)point the stable path `link` at `target` (a device node that changes name
/// when the device returns, as udev's by-id symlinks do).
pub fn relink(link: &Path, target: &Path) -> io::Result<()> {
    let tmp = link.with_extension("relink");
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(target, &tmp)?;
    std::fs::rename(&tmp, link)
}

/// Open the slave at `path` and keep it open without reading, so that a device that drops its
/// output while nobody has the pty open (QEMU) sees a reader from the moment it runs.
pub fn hold_open(path: &Path) -> io::Result<OwnedFd> {
    let c =
        std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).map_err(io::Error::other)?;
    // SAFETY: a valid NUL-terminated path; the fd returned is owned by the OwnedFd.
    let fd = unsafe { libc::open(c.as_ptr(), libc::O_RDWR | libc::O_NOCTTY | libc::O_CLOEXEC) };
    if fd < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: fd was just opened and belongs to nobody else.
    Ok(unsafe { OwnedFd::from_raw_fd(fd) })
}
