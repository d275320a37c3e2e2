//! Library errors as Python exceptions carrying the line `tactile` prints (without its
//! `tactile: error:` prefix): the error and its causes on one line ([`sysexit::one_line`], as
//! `tactile::cli::report` prints an `anyhow` chain). The classes are defined in `tactile/_errors.py`.

use std::error::Error;

use pyo3::PyErr;

pyo3::import_exception!(tactile._errors, TactileDataError);
pyo3::import_exception!(tactile._errors, TactileFileError);

/// The message of `err` and of each of its sources, on one line.
fn chain(err: &(dyn Error + 'static)) -> String {
    sysexit::one_line(sysexit::causes(err))
}

/// Whether the operating system refused a file somewhere in `err`'s chain.
fn is_io(err: &(dyn Error + 'static)) -> bool {
    let mut cause = Some(err);
    while let Some(e) = cause {
        if e.is::<std::io::Error>() {
            return true;
        }
        cause = e.source();
    }
    false
}

/// `err` as the exception for its kind, its message after `context` as the command line's
/// `.context()` would put it.
pub fn raise(context: Option<&str>, err: &(dyn Error + 'static)) -> PyErr {
    let line = match context {
        Some(c) => format!("{c}: {}", chain(err)),
        None => chain(err),
    };
    if is_io(err) {
        TactileFileError::new_err(line)
    } else {
        TactileDataError::new_err(line)
    }
}

/// An error of the conversion itself (a DataFrame that cannot be a recording).
pub fn data(line: String) -> PyErr {
    TactileDataError::new_err(line)
}

/// The file error `err` met on `path`, with the command's context for it (`creating`,
/// `writing`).
pub fn file(context: &str, path: &std::path::Path, err: &std::io::Error) -> PyErr {
    TactileFileError::new_err(format!("{context} {}: {err}", path.display()))
}
