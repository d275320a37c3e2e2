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
    let file: toml::Table = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| line_of(text, s.start));
        let why = e.message().to_string();
        // The key the error is at, where its line defines one (`fingers.thumb`); a line
        // without a key is named by its number alone.
        match field_at(text, line) {
            Some(field) => bad(line, &field, why),
            None => FileError::Syntax {
                path: path.to_path_buf(),
                line,
                why,
            },
        }
    })?;
    if let Some(other) = file.keys().find(|k| *k != "fingers") {
        let why = "not part of a hand file, which is one [fingers] table".to_string();
        return Err(bad(key_line(text, other).max(1), other, why));
    }
    let Some(table) = file.get("fingers") else {
        let why = "missing: a hand file is a [fingers] table of name = \"port\" lines".to_string();
        return Err(bad(1, "fingers", why));
    };
    let Some(table) = table.as_table() else {
        let why = format!("expected a table [fingers], found {}", table.type_str());
        return Err(bad(key_line(text, "fingers").max(1), "fingers", why));
    };
    let mut fingers: Vec<(usize, Finger)> = Vec::new();
    // In the order of the file (the table is sorted by name), so that errors and the hand's
    // order follow what the user wrote.
    let mut entries: Vec<(usize, &String, &toml::Value)> = table
        .iter()
        .map(|(name, value)| (key_line(text, name), name, value))
        .collect();
    entries.sort_by_key(|(line, _, _)| *line);
    for (line, name, value) in entries {
        let finger =
            finger(name, value).map_err(|why| bad(line, &format!("fingers.{name}"), why))?;
        if let Some((_, other)) = fingers
            .iter()
            .find(|(_, f)| same_port(&f.port, &finger.port))
        {
            let why = format!(
                "{} is already finger {}",
                one_port(&finger.port, &other.port),
                other.name
            );
            return Err(bad(line, &format!("fingers.{name}"), why));
        }
        fingers.push((line, finger));
    }
    if fingers.is_empty() || fingers.len() > MAX_FINGERS {
        let why = format!("{} fingers; a hand has 1 to {MAX_FINGERS}", fingers.len());
        return Err(bad(key_line(text, "fingers"), "fingers", why));
    }
    Ok(fingers.into_iter().map(|(_, f)| f).collect())
}

/// The finger `name = value`, or why not.
fn finger(name: &str, value: &toml::Value) -> Result<Finger, String> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(
            "a finger's name is letters, digits, _ and - (it names files and topics)".into(),
        );
    }
    let Some(port) = value.as_str().map(str::trim) else {
        return Err(format!(
            "expected a port string (\"serial:SN\" or a path), found {}",
            value.type_str()
        ));
    };
    if port.is_empty() || port == "serial:" {
        return Err("empty port".into());
    }
    Ok(Finger {
        name: name.to_string(),
        port: PortSpec::parse(port),
    })
}

/// Whether two ports are one: one serial number, or one device however its path reaches it
/// (a udev symlink and its target, `./` or `..` on the way).
fn same_port(a: &PortSpec, b: &PortSpec) -> bool {
    match (a, b) {
        (PortSpec::Path(x), PortSpec::Path(y)) => canonical(x) == canonical(y),
        _ => a == b,
    }
}

/// `port` named for the message that it is taken: with the device both paths lead to, where
/// they differ (`/dev/serial/by-id/… (/dev/ttyACM0)`).
fn one_port(port: &PortSpec, taken: &PortSpec) -> String {
    match (port, taken) {
        (PortSpec::Path(x), PortSpec::Path(y)) if x != y => {
            format!("{} ({})", x.display(), canonical(x).display())
        }
        _ => port.label(),
    }
}

/// The path with every link resolved, or as written where it cannot be (a port not there yet:
/// opening it will say so).
fn canonical(p: &Path) -> PathBuf {
    std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf())
}

/// The dotted key that line `line` (1-based) of a TOML text defines: its table's header name on
/// a header line, else the key before `=` under the last header above; `None` on a blank or
/// comment line.
fn field_at(text: &str, line: usize) -> Option<String> {
    let mut table = String::new();
    for (i, l) in text.lines().enumerate().take(line) {
        let l = l.trim();
        let here = i + 1 == line;
        if l.starts_with('[') {
            table = l
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
                .trim_matches('"')
                .to_string();
            if here {
                return Some(table);
            }
        } else if here {
            let key = l.split('=').next().unwrap_or("").trim().trim_matches('"');
            if key.is_empty() || key.starts_with('#') {
                return None;
            }
            return Some(if table.is_empty() {
                key.to_string()
            } else {
                format!("{table}.{key}")
            });
        }
    }
    None
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
    }

    /// Each TOML error names the field and line it is at, not `fingers` whatever it was.
    #[test]
    fn toml_errors_name_their_own_field_and_line() {
        let cases = [
            // A table that is not the hand's.
            (
                "[finger]\nthumb = \"/dev/a\"\n",
                "hand.toml:1: field finger: not part of a hand file",
            ),
            (
                "[fingers]\nthumb = \"/dev/a\"\n[options]\nrate = 1\n",
                "hand.toml:3: field options: not part of a hand file",
            ),
            // Syntax at a finger's line: that finger.
            (
                "[fingers]\nthumb = \"/dev/a\"\nindex = \"/dev/b\n",
                "hand.toml:3: field fingers.index: ",
            ),
            (
                "[fingers]\nthumb = \"/dev/a\"\nthumb = \"/dev/b\"\n",
                "hand.toml:3: field fingers.thumb: ",
            ),
            ("# a hand\n", "hand.toml:1: field fingers: missing"),
            (
                "fingers = 3\n",
                "hand.toml:1: field fingers: expected a table [fingers], found integer",
            ),
        ];
        for (text, says) in cases {
            let e = p(text).unwrap_err();
            assert!(e.starts_with(says), "{text:?}: {e}");
        }
        // A line with no key at all is named by its number alone.
        let e = p("[fingers]\nthumb = \"/dev/a\"\n= \"/dev/b\"\n").unwrap_err();
        assert!(e.starts_with("hand.toml:3: "), "{e}");
        assert!(!e.contains("field fingers:"), "{e}");
    }

    /// One port written twice, once through a symlink: the second finger is refused in the
    /// file, not met later as a busy port.
    #[test]
    fn a_port_and_a_link_to_it_are_one_port() {
        let dir = std::env::temp_dir().join(format!("tactile-hand-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let port = dir.join("ttyACM0");
        std::fs::write(&port, "").unwrap();
        let link = dir.join("by-id-thumb");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&port, &link).unwrap();
        let text = format!(
            "[fingers]\nthumb = \"{}\"\nindex = \"{}\"\n",
            port.display(),
            link.display()
        );
        let e = p(&text).unwrap_err();
        assert!(
            e.starts_with(&format!(
                "hand.toml:3: field fingers.index: {} ({}) is already finger thumb",
                link.display(),
                std::fs::canonicalize(&port).unwrap().display()
            )),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
