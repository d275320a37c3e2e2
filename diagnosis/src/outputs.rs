//! Where every command writes (the diagnosis, `simulate`, `import`, `plot`): every output path
//! checked before any work, and every output written where the user points ([`Sink`]).
//!
//! `-` (and `/dev/stdout`) is the standard output. A path that is not a regular file (a
//! character device such as `/dev/null` or `/dev/full`, a FIFO, a process's stream such as
//! `/dev/fd/3`) is opened and written to as it is, never replaced or renamed over: running as
//! root, replacing `/dev/null` with a regular file would break the machine. A write error
//! there (`/dev/full`: no space) is an error naming the path.
//!
//! The rule for folders (`docs/bad-input.md`): an output's missing folders are created when it
//! is written, for `--json`, `--report` and `--out-dir` alike. Before any work, the nearest
//! folder that exists on each output's path must be a folder this process can write into
//! (something on the path that is a file fails at once, naming it), the output itself must
//! not be a folder, two outputs of one run must not be one file, and no output may be one of
//! the recordings read, which writing it would destroy.
//!
//! Each regular file is written to a temporary file beside it and renamed over it
//! ([`write_whole`], [`write_all_whole`]): a run that fails or is killed leaves either the old
//! file or the new one, never a half-written one. A symlink is written through: the file it
//! names is replaced, the link kept.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Why an output cannot be written where the arguments say.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output names an existing folder.
    #[error("{}: is a folder; the output is a file", .0.display())]
    IsFolder(PathBuf),
    /// An output folder that names an existing file.
    #[error("{}: is a file; the output is a folder", .0.display())]
    IsFile(PathBuf),
    /// Something on the output's path is a file where a folder would have to be.
    #[error("{}: cannot be created: {} is a file, not a folder", .path.display(), .file.display())]
    FileOnPath { path: PathBuf, file: PathBuf },
    /// The folder that would hold the output cannot be written into.
    #[error("{}: cannot be created in {}: {source}", .path.display(), .folder.display())]
    Unwritable {
        path: PathBuf,
        folder: PathBuf,
        source: std::io::Error,
    },
    /// The output is one of the recordings read.
    #[error("{}: is one of the recordings read; writing it would destroy it", .0.display())]
    IsInput(PathBuf),
    /// Two outputs of one run at one file.
    #[error("{} and {} are one file: each output needs its own", .first.display(), .second.display())]
    Twice { first: PathBuf, second: PathBuf },
}

/// An output that cannot be created is `CANT_CREATE` (forbidden: `NO_PERM`); one that
/// clashes with an input or another output, a usage error.
impl sysexit::ExitStatus for OutputError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::IsFolder(_) | Self::IsFile(_) | Self::FileOnPath { .. } => sysexit::CANT_CREATE,
            Self::Unwritable { source, .. } => match source.kind() {
                std::io::ErrorKind::PermissionDenied => sysexit::NO_PERM,
                _ => sysexit::CANT_CREATE,
            },
            Self::IsInput(_) | Self::Twice { .. } => sysexit::USAGE,
        }
    }
}

/// Check the output files `files` and output folders `folders` of one run that reads
/// `inputs`, before any work (the module's rule). A path that is not a regular file (a
/// device, a FIFO, `-`) needs no folder; two outputs may share a device, never a regular file
/// or the standard output.
pub fn check(files: &[&Path], folders: &[&Path], inputs: &[PathBuf]) -> Result<(), OutputError> {
    for &file in files {
        if std::fs::metadata(file).is_ok_and(|m| m.is_dir()) {
            return Err(OutputError::IsFolder(file.to_path_buf()));
        }
        if let Sink::Whole(_) = Sink::of(file) {
            writable_folder_above(file)?;
        }
    }
    for &dir in folders {
        match std::fs::metadata(dir) {
            Ok(m) if m.is_dir() => probe(dir, dir)?,
            Ok(_) => return Err(OutputError::IsFile(dir.to_path_buf())),
            Err(_) => writable_folder_above(dir)?,
        }
    }
    let inputs: Vec<PathBuf> = inputs
        .iter()
        .filter_map(|p| std::fs::canonicalize(p).ok())
        .collect();
    let mut resolved: Vec<(PathBuf, &Path)> = Vec::new();
    for &file in files {
        let at = match Sink::of(file) {
            Sink::AsIs(_) => continue,
            Sink::Stdout => PathBuf::from("-"),
            Sink::Whole(_) => resolve(file),
        };
        if inputs.contains(&at) {
            return Err(OutputError::IsInput(file.to_path_buf()));
        }
        if let Some((_, first)) = resolved.iter().find(|(r, _)| *r == at) {
            return Err(OutputError::Twice {
                first: first.to_path_buf(),
                second: file.to_path_buf(),
            });
        }
        resolved.push((at, file));
    }
    Ok(())
}

/// The nearest folder that exists above `path` must be a folder this process can write into.
fn writable_folder_above(path: &Path) -> Result<(), OutputError> {
    for above in path.ancestors().skip(1) {
        let folder = if above.as_os_str().is_empty() {
            Path::new(".")
        } else {
            above
        };
        match std::fs::metadata(folder) {
            Ok(m) if m.is_dir() => return probe(path, folder),
            Ok(_) => {
                return Err(OutputError::FileOnPath {
                    path: path.to_path_buf(),
                    file: folder.to_path_buf(),
                })
            }
            // Not there (it will be created), or below a file (found further up).
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotADirectory => {}
            Err(source) => {
                return Err(OutputError::Unwritable {
                    path: path.to_path_buf(),
                    folder: folder.to_path_buf(),
                    source,
                })
            }
        }
    }
    Ok(())
}

/// Whether a file can be created in `folder`: by creating one and removing it (the one test
/// that answers for permissions, access lists and read-only mounts alike).
fn probe(path: &Path, folder: &Path) -> Result<(), OutputError> {
    let unwritable = |source| OutputError::Unwritable {
        path: path.to_path_buf(),
        folder: folder.to_path_buf(),
        source,
    };
    let probe = folder.join(format!(".tactile-probe-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(unwritable)?;
    std::fs::remove_file(&probe).map_err(unwritable)
}

/// `path` made absolute with every link resolved, whether or not it exists yet: the nearest
/// existing ancestor canonicalised, the rest appended.
fn resolve(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    match (path.parent(), path.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() {
                Path::new(".")
            } else {
                parent
            };
            resolve(parent).join(name)
        }
        _ => path.to_path_buf(),
    }
}

/// Where one output goes: the process's standard output, a path written as it is (not a
/// regular file: a device, a FIFO, another stream of this process), or a regular file (there or
/// not yet, through any links) written whole.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Sink {
    /// `-` or `/dev/stdout`: the standard output as the shell set it up.
    Stdout,
    /// A path that is not a regular file, opened and written to as it is: never replaced.
    AsIs(PathBuf),
    /// A regular file (or one to create): written to a temporary file beside the file a link
    /// names, then renamed over it, so that a link stays a link.
    Whole(PathBuf),
}

impl Sink {
    /// The sink `path` names (the module's rule).
    pub fn of(path: &Path) -> Self {
        if path.as_os_str() == "-" || path == Path::new("/dev/stdout") {
            return Self::Stdout;
        }
        let stream = std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir());
        if stream || names_a_stream(path) {
            Self::AsIs(path.to_path_buf())
        } else {
            Self::Whole(path.to_path_buf())
        }
    }
}

/// Whether `path`, or a link it goes through, names one of this process's streams by its
/// descriptor (`/dev/fd/N`, `/dev/stderr`, `/proc/self/fd/N`): such a path resolves to the
/// file behind the descriptor, which must be written through the descriptor, not replaced.
fn names_a_stream(path: &Path) -> bool {
    let mut at = path.to_path_buf();
    for _ in 0..40 {
        let s = at.to_string_lossy();
        if s.starts_with("/dev/fd/")
            || s.starts_with("/dev/std")
            || (s.starts_with("/proc/") && s.contains("/fd/"))
        {
            return true;
        }
        match std::fs::read_link(&at) {
            Ok(next) => at = at.parent().map_or(next.clone(), |p| p.join(&next)),
            Err(_) => return false,
        }
    }
    false
}

/// An output that could not be written: the path and why, one line. Its kind is the cause's
/// (a full disk: `StorageFull`), so that the exit code follows it (`sysexit::code_of`).
#[derive(Debug, thiserror::Error)]
#[error("writing {}: {source}", .path.display())]
pub struct WriteError {
    /// The output as the user named it.
    pub path: PathBuf,
    /// Why.
    pub source: std::io::Error,
}

fn failed(path: &Path) -> impl Fn(std::io::Error) -> std::io::Error + '_ {
    move |source| {
        std::io::Error::new(
            source.kind(),
            WriteError {
                path: path.to_path_buf(),
                source,
            },
        )
    }
}

/// Write `bytes` to `path` ([`write_all_whole`] of one file).
pub fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_all_whole(&[(path, bytes)])
}

/// Write the files of one run, each to its [`Sink`]: `-` to the standard output, a path that
/// is not a regular file as it is, a regular file whole (its missing folders created, a
/// temporary file beside it flushed to the disk, then renamed over it; a link written
/// through). Every temporary file is written before any stream, and every stream before the
/// first rename, so that an error leaves no regular file changed. The error names the path
/// that failed (a [`WriteError`] inside the `io::Error`).
pub fn write_all_whole(files: &[(&Path, &[u8])]) -> std::io::Result<()> {
    let mut staged: Vec<(PathBuf, PathBuf)> = Vec::new();
    let unstage = |staged: &[(PathBuf, PathBuf)]| {
        for (tmp, _) in staged {
            let _ = std::fs::remove_file(tmp);
        }
    };
    for &(path, bytes) in files {
        if let Sink::Whole(_) = Sink::of(path) {
            match stage(path, bytes).map_err(failed(path)) {
                Ok(s) => staged.push(s),
                Err(e) => {
                    unstage(&staged);
                    return Err(e);
                }
            }
        }
    }
    for &(path, bytes) in files {
        if let Err(e) = write_stream(&Sink::of(path), bytes).map_err(failed(path)) {
            unstage(&staged);
            return Err(e);
        }
    }
    for (i, (tmp, target)) in staged.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp, target).map_err(failed(target)) {
            unstage(&staged[i..]);
            return Err(e);
        }
    }
    Ok(())
}

/// `bytes` written to a stream sink, as it is: no temporary file, no rename, no truncation of
/// a device or FIFO (a regular file behind a descriptor is truncated first). A regular file's
/// sink writes nothing here.
fn write_stream(sink: &Sink, bytes: &[u8]) -> std::io::Result<()> {
    match sink {
        Sink::Whole(_) => Ok(()),
        Sink::Stdout => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)?;
            out.flush()
        }
        Sink::AsIs(path) => {
            let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .truncate(regular)
                .open(path)?;
            f.write_all(bytes)?;
            f.flush()
        }
    }
}

/// The file `path` names, every link followed (to a file not there yet, for a dangling link), so
/// that the rename replaces the file and keeps the link.
fn link_target(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let mut at = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::read_link(&at) {
            Ok(next) => at = at.parent().map_or(next.clone(), |p| p.join(&next)),
            Err(_) => break,
        }
    }
    at
}

/// `bytes` in a temporary file beside `path`'s target: (the temporary file, the target).
fn stage(path: &Path, bytes: &[u8]) -> std::io::Result<(PathBuf, PathBuf)> {
    let target = link_target(path);
    if let Some(dir) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let name = target
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let tmp = target.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    match written {
        Ok(()) => Ok((tmp, target)),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

#[cfg(test)]
mod tests;
