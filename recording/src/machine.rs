//! The test machine's export: time, rod travel and load, one row per sample, as a CSV with one
//! header line naming a time, a rod-position and a load column (common spellings accepted) and
//! `#` comment lines anywhere. `tactile simulate --machine-csv` writes it, and `tactile log
//! --reference` reads it and merges rod and load into a recording (the `rod_mm` and `load_N`
//! columns of `docs/recording-format.md`).

use std::fmt;
use std::io::Write;
use std::path::Path;

use crate::Limits;

/// A test machine's export: time in s, rod travel in mm, load in N, time increasing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MachineExport {
    /// Machine time, s, strictly increasing.
    pub t_s: Vec<f64>,
    /// Rod travel, mm.
    pub rod_mm: Vec<f64>,
    /// Load on the rod, N.
    pub load_n: Vec<f64>,
}

/// Spellings of the time column, compared without case.
pub const TIME_NAMES: [&str; 4] = ["t_s", "time_s", "time", "t"];
/// Spellings of the rod-position column, compared without case.
pub const ROD_NAMES: [&str; 5] = [
    "rod_mm",
    "position_mm",
    "displacement_mm",
    "rod",
    "position",
];
/// Spellings of the load column, compared without case.
pub const LOAD_NAMES: [&str; 5] = ["load_N", "force_N", "load", "force", "load_n"];

/// Why a machine export was refused. The message names the file, and the line and field where
/// there is one.
#[derive(Debug)]
#[non_exhaustive]
pub enum MachineExportError {
    /// The file could not be opened or read.
    Io {
        /// The file.
        path: String,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The file is bigger than the reader holds in memory (it is read whole).
    TooLarge {
        /// The file.
        path: String,
        /// Its size.
        bytes: u64,
        /// The reader's limit.
        limit_bytes: u64,
    },
    /// The file breaks the layout at this line and field.
    Malformed {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// The column, or what was expected there in parentheses.
        field: String,
        /// What is wrong.
        why: String,
    },
    /// An importer's option that cannot be used as given (no file is at fault).
    Usage {
        /// The option, as the command line spells it.
        option: String,
        /// What is wrong.
        why: String,
    },
}

impl fmt::Display for MachineExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{path}: {source}"),
            Self::TooLarge {
                path,
                bytes,
                limit_bytes,
            } => write!(
                f,
                "{path}: {bytes} bytes is over the {limit_bytes}-byte limit of this reader \
                 (a reference export is read whole)"
            ),
            Self::Malformed {
                path,
                line,
                field,
                why,
            } => write!(f, "{path}:{line}: field {field}: {why}"),
            Self::Usage { option, why } => write!(f, "{option}: {why}"),
        }
    }
}

impl std::error::Error for MachineExportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl MachineExportError {
    /// The operating system's reason when the file could not be opened or read; `None` when it
    /// was read and refused.
    pub fn io_kind(&self) -> Option<std::io::ErrorKind> {
        match self {
            Self::Io { source, .. } => Some(source.kind()),
            _ => None,
        }
    }
}

/// An export that could not be read is a missing or forbidden input; one that was read and
/// refused is bad data; an option that cannot be used is a usage error.
impl sysexit::ExitStatus for MachineExportError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Usage { .. } => sysexit::USAGE,
            _ => self.io_kind().map_or(sysexit::DATA, sysexit::of_input),
        }
    }
}

/// The path as named in errors and the bytes of the file at `path`, refused when larger than
/// [`Limits::DEFAULT`]`.max_bytes` (checked before reading).
pub(crate) fn read_bounded(path: &Path) -> Result<(String, Vec<u8>), MachineExportError> {
    let name = path.display().to_string();
    let io = |source| MachineExportError::Io {
        path: name.clone(),
        source,
    };
    let bytes = std::fs::metadata(path).map_err(io)?.len();
    let limit_bytes = Limits::DEFAULT.max_bytes;
    if bytes > limit_bytes {
        return Err(MachineExportError::TooLarge {
            path: name,
            bytes,
            limit_bytes,
        });
    }
    let raw = std::fs::read(path).map_err(io)?;
    Ok((name, raw))
}

/// Read the export at `path` (at most [`Limits::DEFAULT`]`.max_bytes`, read whole).
pub fn read(path: &Path) -> Result<MachineExport, MachineExportError> {
    let (name, raw) = read_bounded(path)?;
    match std::str::from_utf8(&raw) {
        Ok(text) => parse_named(text, &name),
        Err(e) => Err(MachineExportError::Malformed {
            line: raw[..e.valid_up_to()]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1,
            path: name,
            field: "(text)".into(),
            why: "not UTF-8 (UTF-16, Latin-1 or binary?): save the export as UTF-8".into(),
        }),
    }
}

/// Parse an export already in memory (errors name it `<input>`).
pub fn parse(text: &str) -> Result<MachineExport, MachineExportError> {
    parse_named(text, "<input>")
}

fn parse_named(text: &str, path: &str) -> Result<MachineExport, MachineExportError> {
    let bad = |line, field: &str, why: String| MachineExportError::Malformed {
        path: path.to_string(),
        line,
        field: field.into(),
        why,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty());
    let (hline, header) = lines
        .next()
        .ok_or_else(|| bad(1, "(header)", "no header line".into()))?;
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_owned()).collect();
    let need = |names: &[&str], what: &str| {
        find(&columns, names)
            .ok_or_else(|| bad(hline, what, format!("no column named one of {names:?}")))
    };
    let at = [
        need(&TIME_NAMES, "time")?,
        need(&ROD_NAMES, "rod position")?,
        need(&LOAD_NAMES, "load")?,
    ];
    let mut export = MachineExport::default();
    for (n, line) in lines {
        let fields: Vec<&str> = line.split(',').collect();
        let [t, rod, load] = at.map(|i| {
            let s = fields.get(i).map_or("", |s| s.trim());
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(n, &columns[i], format!("not a number: {s:?}")))
        });
        let t = t?;
        if export.t_s.last().is_some_and(|last| t <= *last) {
            return Err(bad(n, &columns[at[0]], "time does not increase".into()));
        }
        export.t_s.push(t);
        export.rod_mm.push(rod?);
        export.load_n.push(load?);
    }
    if export.t_s.len() < 2 {
        return Err(bad(hline, "(rows)", "fewer than two rows".into()));
    }
    Ok(export)
}

fn find(columns: &[String], names: &[&str]) -> Option<usize> {
    columns
        .iter()
        .position(|c| names.iter().any(|n| c.eq_ignore_ascii_case(n)))
}

impl MachineExport {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Write the export as `t_s,rod_mm,load_N` rows (what [`read`] accepts).
    pub fn write_to<W: Write>(&self, out: W) -> std::io::Result<()> {
        let mut out = std::io::BufWriter::new(out);
        writeln!(out, "t_s,rod_mm,load_N")?;
        for i in 0..self.len() {
            writeln!(out, "{},{},{}", self.t_s[i], self.rod_mm[i], self.load_n[i])?;
        }
        out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_common_spellings_and_skips_comments() {
        let m = parse("# Mach-1\nTime,Position_mm,Force_N\n0,0,0\n# pause\n0.5,1,2\n").unwrap();
        assert_eq!(m.t_s, [0.0, 0.5]);
        assert_eq!(m.rod_mm, [0.0, 1.0]);
        assert_eq!(m.load_n, [0.0, 2.0]);
    }

    #[test]
    fn refusals_name_line_and_field() {
        let e = parse("t_s,rod_mm,load_N\n0,0,0\n0,1,1\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "<input>:3: field t_s: time does not increase"
        );
        let e = parse("t_s,rod_mm\n0,0\n").unwrap_err();
        assert!(e.to_string().contains(":1: field load:"), "{e}");
        let e = parse("t_s,rod_mm,load_N\n0,0,x\n1,1,1\n").unwrap_err();
        assert!(
            e.to_string().contains(":2: field load_N: not a number"),
            "{e}"
        );
        let e = parse("t_s,rod_mm,load_N\n0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("fewer than two rows"), "{e}");
    }

    #[test]
    fn written_exports_read_back() {
        let m = MachineExport {
            t_s: vec![0.0, 0.002, 0.004],
            rod_mm: vec![0.0, 0.1, 0.25],
            load_n: vec![0.0, 1.5, 3.0],
        };
        let mut buf = Vec::new();
        m.write_to(&mut buf).unwrap();
        assert_eq!(parse(std::str::from_utf8(&buf).unwrap()).unwrap(), m);
    }
}
