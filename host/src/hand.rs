//! A hand file: which sensor is which finger, for `tactile log --hand hand.toml`.
//!
//! ```toml
//! # Fingers in the order they are shown; a name maps to a USB serial number or a port path.
//! [fingers]
//! thumb = "serial:TT0001"
//! index = "/dev/serial/by-id/usb-tactile_TT0002-if00"
//! ```
//!
//! Names become file names (`OUT-<finger>.csv`) and MCAP topics (`/tactile/<finger>/…`), so
//! they are letters, digits, `_` and `-`. Every error names the file, its line and the field.

use std::path::{Path, PathBuf};

use crate::device::PortSpec;
use crate::logger::FileError;

/// One finger of the hand.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finger {
    pub name: String,
    pub port: PortSpec,
}

/// Most fingers in one hand file: sixteen fingertips with room to spare, and a bound on what
/// one process opens.
pub const MAX_FINGERS: usize = 32;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct HandFile {
    fingers: toml::Table,
}

/// Read and check `path`.
pub fn load(path: &Path) -> Result<Vec<Finger>, FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::Open {
        path: path.to_path_buf(),
        source: e,
    })?;
    parse(path, &text)
}

/// Parse a hand file's `text`; `path` names it in errors.
pub fn parse(path: &Path, text: &str) -> Result<Vec<Finger>, FileError> {
    let bad = |line: usize, field: &str, why: String| FileError::Malformed {
        path: path.to_path_buf(),
        line,
        field: field.to_string(),
        why,
    };
    let file: HandFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| line_of(text, s.start));
        bad(line, "fingers", e.message().to_string())
    })?;
    let mut fingers: Vec<(usize, Finger)> = Vec::new();
    // In the order of the file (the table is sorted by name), so that errors and the hand's
    // order follow what the user wrote.
    let mut entries: Vec<(usize, &String, &toml::Value)> = file
        .fingers
        .iter()
        .map(|(name, value)| (key_line(text, name), name, value))
        .collect();
    entries.sort_by_key(|(line, _, _)| *line);
    for (line, name, value) in entries {
        let field = format!("fingers.{name}");
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(bad(
                line,
                &field,
                "a finger's name is letters, digits, _ and - (it names files and topics)".into(),
            ));
        }
        let Some(port) = value.as_str().map(str::trim) else {
            return Err(bad(
                line,
                &field,
                format!(
                    "expected a port string (\"serial:SN\" or a path), found {}",
                    value.type_str()
                ),
            ));
        };
        if port.is_empty() || port == "serial:" {
            return Err(bad(line, &field, "empty port".into()));
        }
        let port = PortSpec::parse(port);
        if let Some((_, other)) = fingers.iter().find(|(_, f)| f.port == port) {
            let why = format!("{} is already finger {}", port.label(), other.name);
            return Err(bad(line, &field, why));
        }
        fingers.push((
            line,
            Finger {
                name: name.clone(),
                port,
            },
        ));
    }
    if fingers.is_empty() || fingers.len() > MAX_FINGERS {
        let why = format!("{} fingers; a hand has 1 to {MAX_FINGERS}", fingers.len());
        return Err(bad(key_line(text, "fingers"), "fingers", why));
    }
    Ok(fingers.into_iter().map(|(_, f)| f).collect())
}

/// 1-based line of byte `at`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

/// The line where `key` is defined (`key =` or `[key]`, quoted or not), 0 if not found.
fn key_line(text: &str, key: &str) -> usize {
    text.lines()
        .position(|l| {
            let l = l.trim_start();
            let k = l.split(['=', ']']).next().unwrap_or("");
            let k = k.trim().trim_start_matches('[').trim_matches('"').trim();
            k == key
        })
        .map_or(0, |i| i + 1)
}

/// The CSV of finger `name` beside `out`: `OUT-<name>.csv`.
pub fn finger_csv(out: &Path, name: &str) -> PathBuf {
    crate::logger::per_sensor_path(out, name, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<Vec<Finger>, String> {
        parse(Path::new("hand.toml"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn fingers_in_file_order() {
        let h = p("[fingers]\nthumb = \"serial:A1\"\nindex = \"/dev/ttyACM3\"\n").unwrap();
        assert_eq!(h[0].name, "thumb");
        assert_eq!(h[0].port, PortSpec::Serial("A1".into()));
        assert_eq!(h[1].port, PortSpec::Path("/dev/ttyACM3".into()));
        assert_eq!(
            finger_csv(Path::new("out/rec.csv"), "index"),
            Path::new("out/rec-index.csv")
        );
    }

    #[test]
    fn errors_name_file_line_and_field() {
        let e = p("[fingers]\nthumb = \"/dev/a\"\nring = 3\n").unwrap_err();
        assert!(
            e.starts_with("hand.toml:3: field fingers.ring: expected a port"),
            "{e}"
        );
        let e = p("[fingers]\nthumb = \"/dev/a\"\nindex = \"/dev/a\"\n").unwrap_err();
        assert!(
            e.contains(":3: field fingers.index: /dev/a is already finger thumb"),
            "{e}"
        );
        let e = p("[fingers]\n\"little finger\" = \"/dev/a\"\n").unwrap_err();
        assert!(
            e.contains(":2: field fingers.little finger: a finger's name"),
            "{e}"
        );
        let e = p("[fingers]\n").unwrap_err();
        assert!(e.contains(":1: field fingers: 0 fingers"), "{e}");
        let e = p("[finger]\nthumb = \"/dev/a\"\n").unwrap_err();
        assert!(
            e.starts_with("hand.toml:1: field fingers: unknown field"),
            "{e}"
        );
        let e = p("[fingers]\nthumb = \"/dev/a\n").unwrap_err();
        assert!(e.starts_with("hand.toml:2: "), "{e}");
    }
}
