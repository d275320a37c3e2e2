//! Strict reading of one TOML file: every key read is checked for presence, type and range, and
//! every key left unread is reported as unknown (with the nearest known key, to catch typos).

use std::collections::BTreeSet;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use crate::{ParamError, ParamErrorKind};

/// Reads typed values out of one parsed file, remembering which keys it was asked for.
pub struct Reader {
    file: PathBuf,
    table: toml::Table,
    read: BTreeSet<String>,
    errors: Vec<ParamError>,
}

impl Reader {
    /// Parse `text` (the contents of `file`).
    pub fn parse(file: &Path, text: &str) -> Result<Self, ParamError> {
        let table = text.parse::<toml::Table>().map_err(|e| ParamError {
            file: file.to_path_buf(),
            key: String::new(),
            kind: ParamErrorKind::Syntax(e.message().to_string()),
        })?;
        Ok(Self {
            file: file.to_path_buf(),
            table,
            read: BTreeSet::new(),
            errors: Vec::new(),
        })
    }

    /// Open and parse `file`.
    pub fn open(file: &Path) -> Result<Self, ParamError> {
        let text = std::fs::read_to_string(file).map_err(|e| ParamError {
            file: file.to_path_buf(),
            key: String::new(),
            kind: ParamErrorKind::Io(e.to_string()),
        })?;
        Self::parse(file, &text)
    }

    fn lookup(&mut self, key: &str) -> Option<&toml::Value> {
        self.read.insert(key.to_string());
        let mut parts = key.split('.');
        let first = parts.next()?;
        let mut value = self.table.get(first)?;
        for part in parts {
            value = value.as_table()?.get(part)?;
        }
        Some(value)
    }

    fn fail(&mut self, key: &str, kind: ParamErrorKind) {
        self.errors.push(ParamError {
            file: self.file.clone(),
            key: key.to_string(),
            kind,
        });
    }

    /// A real number (integers accepted) within `range`, in the unit the key's name carries.
    /// On error records it and returns the range's lower end so reading can go on.
    pub fn f64(&mut self, key: &str, range: RangeInclusive<f64>) -> f64 {
        let value = match self.lookup(key) {
            None => {
                self.fail(key, ParamErrorKind::Missing);
                return *range.start();
            }
            Some(toml::Value::Float(v)) => *v,
            Some(toml::Value::Integer(v)) => *v as f64,
            Some(_) => {
                self.fail(
                    key,
                    ParamErrorKind::WrongType {
                        expected: "a number",
                    },
                );
                return *range.start();
            }
        };
        if !range.contains(&value) {
            let (min, max) = (*range.start(), *range.end());
            self.fail(key, ParamErrorKind::OutOfRange { value, min, max });
            return min;
        }
        value
    }

    /// An integer within `range`.
    pub fn int(&mut self, key: &str, range: RangeInclusive<i64>) -> i64 {
        let value = match self.lookup(key) {
            None => {
                self.fail(key, ParamErrorKind::Missing);
                return *range.start();
            }
            Some(toml::Value::Integer(v)) => *v,
            Some(_) => {
                self.fail(
                    key,
                    ParamErrorKind::WrongType {
                        expected: "an integer",
                    },
                );
                return *range.start();
            }
        };
        if !range.contains(&value) {
            let (min, max) = (*range.start() as f64, *range.end() as f64);
            self.fail(
                key,
                ParamErrorKind::OutOfRange {
                    value: value as f64,
                    min,
                    max,
                },
            );
            return *range.start();
        }
        value
    }

    /// A string that must be one of `allowed`.
    pub fn choice(&mut self, key: &str, allowed: &[&'static str]) -> &'static str {
        let found = match self.lookup(key) {
            None => {
                self.fail(key, ParamErrorKind::Missing);
                return allowed[0];
            }
            Some(toml::Value::String(s)) => s.clone(),
            Some(_) => {
                self.fail(
                    key,
                    ParamErrorKind::WrongType {
                        expected: "a string",
                    },
                );
                return allowed[0];
            }
        };
        match allowed.iter().find(|a| **a == found) {
            Some(a) => a,
            None => {
                self.fail(
                    key,
                    ParamErrorKind::NotOneOf {
                        found,
                        allowed: allowed.join(", "),
                    },
                );
                allowed[0]
            }
        }
    }

    /// A free-text string (a part number, a note).
    pub fn string(&mut self, key: &str) -> String {
        match self.lookup(key) {
            Some(toml::Value::String(s)) => s.clone(),
            None => {
                self.fail(key, ParamErrorKind::Missing);
                String::new()
            }
            Some(_) => {
                self.fail(
                    key,
                    ParamErrorKind::WrongType {
                        expected: "a string",
                    },
                );
                String::new()
            }
        }
    }

    /// A fixed-length array of numbers, each within `range`.
    pub fn f64_array<const N: usize>(&mut self, key: &str, range: RangeInclusive<f64>) -> [f64; N] {
        let items: Option<Vec<toml::Value>> = self
            .lookup(key)
            .map(|v| v.as_array().cloned().unwrap_or_default());
        let Some(items) = items else {
            self.fail(key, ParamErrorKind::Missing);
            return [*range.start(); N];
        };
        if items.len() != N {
            self.fail(
                key,
                ParamErrorKind::WrongLength {
                    expected: N,
                    found: items.len(),
                },
            );
            return [*range.start(); N];
        }
        let mut out = [*range.start(); N];
        for (i, item) in items.iter().enumerate() {
            let element = format!("{key}[{i}]");
            let value = match item {
                toml::Value::Float(v) => *v,
                toml::Value::Integer(v) => *v as f64,
                _ => {
                    self.fail(
                        &element,
                        ParamErrorKind::WrongType {
                            expected: "a number",
                        },
                    );
                    continue;
                }
            };
            if range.contains(&value) {
                out[i] = value;
            } else {
                let (min, max) = (*range.start(), *range.end());
                self.fail(&element, ParamErrorKind::OutOfRange { value, min, max });
            }
        }
        out
    }

    /// Record a rule that spans several keys (e.g. `a < b`) as broken, against `key`.
    pub fn reject(&mut self, key: &str, why: impl Into<String>) {
        self.fail(key, ParamErrorKind::Invalid(why.into()));
    }

    /// Report every key present in the file that no reader asked for, then every error found.
    pub fn finish(mut self) -> Result<(), Vec<ParamError>> {
        let mut present = Vec::new();
        collect_keys(&self.table, "", &mut present);
        let known: Vec<String> = self.read.iter().cloned().collect();
        for key in present {
            if !self.read.contains(&key) {
                let suggestion = nearest(&key, &known);
                self.fail(&key, ParamErrorKind::Unknown { suggestion });
            }
        }
        if self.errors.is_empty() {
            Ok(())
        } else {
            Err(self.errors)
        }
    }
}

fn collect_keys(table: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in table {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => collect_keys(t, &key, out),
            _ => out.push(key),
        }
    }
}

/// The known key closest to `key` by edit distance, if it is close enough to be a typo.
fn nearest(key: &str, known: &[String]) -> Option<String> {
    known
        .iter()
        .map(|k| (levenshtein(key, k), k))
        .filter(|(d, k)| *d <= 3.max(k.len() / 4))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k.clone())
}

fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let cost = usize::from(ca != *cb);
            cur.push((prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}
