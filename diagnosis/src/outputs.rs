//! Where a diagnosis writes: every output path checked before any work, and every file written
//! whole.
//!
//! The rule for folders (`docs/bad-input.md`): an output's missing folders are created when it
//! is written, for `--json`, `--report` and `--out-dir` alike. Before any work, the nearest
//! folder that exists on each output's path must be a folder this process can write into
//! (something on the path that is a file fails at once, naming it), the output itself must
//! not be a folder, two outputs of one run must not be one file, and no output may be one of
//! the recordings read, which writing it would destroy.
//!
//! Each file is written to a temporary file beside it and renamed over it ([`write_whole`],
//! [`write_all_whole`]): a run that fails or is killed leaves either the old file or the new
//! one, never a half-written one.

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
/// `inputs`, before any work (the module's rule).
pub fn check(files: &[&Path], folders: &[&Path], inputs: &[PathBuf]) -> Result<(), OutputError> {
    for &file in files {
        if std::fs::metadata(file).is_ok_and(|m| m.is_dir()) {
            return Err(OutputError::IsFolder(file.to_path_buf()));
        }
        writable_folder_above(file)?;
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
        let at = resolve(file);
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

/// Write `bytes` to `path` whole: its missing folders created, the bytes into a temporary file
/// beside it, flushed to the disk, then renamed over it. A link is written through, to the
/// file it names.
pub fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_all_whole(&[(path, bytes)])
}

/// [`write_whole`] for the files of one run together: every temporary file written before
/// the first is renamed, so that an error leaves none of them changed.
pub fn write_all_whole(files: &[(&Path, &[u8])]) -> std::io::Result<()> {
    let mut staged: Vec<(PathBuf, PathBuf)> = Vec::new();
    for &(path, bytes) in files {
        match stage(path, bytes) {
            Ok(s) => staged.push(s),
            Err(e) => {
                for (tmp, _) in &staged {
                    let _ = std::fs::remove_file(tmp);
                }
                return Err(e);
            }
        }
    }
    for (i, (tmp, target)) in staged.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp, target) {
            for (tmp, _) in &staged[i..] {
                let _ = std::fs::remove_file(tmp);
            }
            return Err(e);
        }
    }
    Ok(())
}

/// `bytes` in a temporary file beside `path`'s target: (the temporary file, the target).
fn stage(path: &Path, bytes: &[u8]) -> std::io::Result<(PathBuf, PathBuf)> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
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
