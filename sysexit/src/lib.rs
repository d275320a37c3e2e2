//! Exit codes after BSD sysexits, so scripts can tell a bad file from a missing port, and the
//! trait by which each error type says which one it deserves, in the crate that defines it.
//!
//! A command line wraps a library's error with [`Coded`] where it meets it
//! ([`ResultExt::coded`]); the code then travels with the error through any context that is
//! added on top, and [`code_of`] finds it in the chain without knowing the library's types.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

use std::error::Error;
use std::fmt;

/// Internal error: a bug or a state the program did not expect.
pub const SOFTWARE: u8 = 70;
/// Bad command-line arguments.
pub const USAGE: u8 = 64;
/// An input file or device answer that breaks its format.
pub const DATA: u8 = 65;
/// An input file or port that is not there.
pub const NO_INPUT: u8 = 66;
/// A device that is busy, gone or silent.
pub const UNAVAILABLE: u8 = 69;
/// Any other I/O error.
pub const IO: u8 = 74;
/// An output file could not be created or written.
pub const CANT_CREATE: u8 = 73;
/// Permission denied on a file or port.
pub const NO_PERM: u8 = 77;
/// The device answered but refused or spoke another protocol version.
pub const PROTOCOL: u8 = 76;

/// Something that knows which exit code it deserves.
pub trait ExitStatus {
    /// The sysexits code the process ends with.
    fn exit_code(&self) -> u8;
}

/// An I/O error on an input: missing, forbidden, or any other failure.
impl ExitStatus for std::io::Error {
    fn exit_code(&self) -> u8 {
        of_input(self.kind())
    }
}

/// The code for an input that could not be opened or read for reason `kind`.
pub fn of_input(kind: std::io::ErrorKind) -> u8 {
    match kind {
        std::io::ErrorKind::NotFound => NO_INPUT,
        std::io::ErrorKind::PermissionDenied => NO_PERM,
        _ => IO,
    }
}

/// An error with the exit code its type chose. It shows and chains exactly as the error it
/// holds: its message is the error's and its source the error's source, so a chain printed
/// with `": "` between causes says each cause once.
pub struct Coded {
    code: u8,
    error: Box<dyn Error + Send + Sync + 'static>,
}

impl Coded {
    /// `error` with the code it asks for.
    pub fn new<E: ExitStatus + Error + Send + Sync + 'static>(error: E) -> Self {
        Self {
            code: error.exit_code(),
            error: Box::new(error),
        }
    }

    /// The exit code.
    pub fn code(&self) -> u8 {
        self.code
    }
}

impl fmt::Debug for Coded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&self.error, f)
    }
}

impl fmt::Display for Coded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.error, f)
    }
}

impl Error for Coded {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        self.error.source()
    }
}

/// [`Coded`] for results: `library_call().coded()?`.
pub trait ResultExt<T> {
    /// The error, if any, with its exit code attached.
    fn coded(self) -> Result<T, Coded>;
}

impl<T, E: ExitStatus + Error + Send + Sync + 'static> ResultExt<T> for Result<T, E> {
    fn coded(self) -> Result<T, Coded> {
        self.map_err(Coded::new)
    }
}

/// An error the program has already told the user about, line by line (a batch's bad
/// recordings): the caller only ends the process with `code`.
#[derive(Debug)]
pub struct Reported {
    /// The sysexits code the process ends with.
    pub code: u8,
    /// What happened, in one line, for a caller that prints it anyway.
    pub what: String,
}

impl fmt::Display for Reported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.what)
    }
}

impl Error for Reported {}

/// The first exit code chosen in `chain` (outermost first): a [`Coded`] error's, a
/// [`Reported`] one's, or an I/O error's kind. `None` where no cause chose one.
pub fn code_of<'a>(chain: impl IntoIterator<Item = &'a (dyn Error + 'static)>) -> Option<u8> {
    chain.into_iter().find_map(|cause| {
        if let Some(c) = cause.downcast_ref::<Coded>() {
            Some(c.code)
        } else if let Some(r) = cause.downcast_ref::<Reported>() {
            Some(r.code)
        } else {
            cause
                .downcast_ref::<std::io::Error>()
                .map(|io| of_input(io.kind()))
        }
    })
}

/// `err` and its sources, outermost first.
pub fn causes<'a>(
    err: &'a (dyn Error + 'static),
) -> impl Iterator<Item = &'a (dyn Error + 'static)> {
    let mut next = Some(err);
    std::iter::from_fn(move || {
        let this = next?;
        next = this.source();
        Some(this)
    })
}

/// The error and its causes on one line, joined by `": "`. A cause that a message already
/// quotes (an error type that prints its source and also returns it) is said once.
pub fn one_line<'a>(chain: impl IntoIterator<Item = &'a (dyn Error + 'static)>) -> String {
    let mut line = String::new();
    for cause in chain {
        let text = cause.to_string();
        if line.ends_with(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug)]
    struct Outer(std::io::Error);
    impl fmt::Display for Outer {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("reading rec.csv")
        }
    }
    impl Error for Outer {
        fn source(&self) -> Option<&(dyn Error + 'static)> {
            Some(&self.0)
        }
    }
    impl ExitStatus for Outer {
        fn exit_code(&self) -> u8 {
            DATA
        }
    }

    fn chain<'a>(e: &'a (dyn Error + 'static)) -> Vec<&'a (dyn Error + 'static)> {
        causes(e).collect()
    }

    #[test]
    fn a_coded_error_keeps_its_message_and_its_causes_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        let coded = Coded::new(Outer(io));
        let text: Vec<String> = chain(&coded).iter().map(|e| e.to_string()).collect();
        assert_eq!(text, ["reading rec.csv", "gone"]);
        // The type's own choice wins over the io kind further down.
        assert_eq!(code_of(chain(&coded)), Some(DATA));
    }

    #[test]
    fn a_cause_the_message_already_quotes_is_said_once() {
        #[derive(Debug)]
        struct Quoting(std::io::Error);
        impl fmt::Display for Quoting {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "/nonexistent: {}", self.0)
            }
        }
        impl Error for Quoting {
            fn source(&self) -> Option<&(dyn Error + 'static)> {
                Some(&self.0)
            }
        }
        let e = Quoting(std::io::Error::new(std::io::ErrorKind::NotFound, "gone"));
        assert_eq!(one_line(chain(&e)), "/nonexistent: gone");
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        assert_eq!(one_line(chain(&Outer(io))), "reading rec.csv: gone");
    }

    #[test]
    fn an_uncoded_io_error_is_read_by_its_kind() {
        let io = std::io::Error::new(std::io::ErrorKind::PermissionDenied, "no");
        assert_eq!(code_of(chain(&io)), Some(NO_PERM));
        let reported = Reported {
            code: DATA,
            what: "2 bad".into(),
        };
        assert_eq!(code_of(chain(&reported)), Some(DATA));
    }
}
