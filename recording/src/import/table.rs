//! A delimited text log, the one reader of every CSV-like import: lines to skip, `#` comment
//! lines and blank lines ignored, a header line or none, the delimiter given or detected, and
//! columns chosen by header name or 1-based position. Each number read names its line and
//! column when it is refused.

use std::str::FromStr;

use super::bad;
use crate::machine::MachineExportError;

/// A column chosen by its header name (without case) or by its 1-based index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ColumnRef {
    /// The header's name for it.
    Name(String),
    /// 1-based position in the row.
    Index(usize),
}

impl FromStr for ColumnRef {
    type Err = std::convert::Infallible;
    /// Digits are an index, anything else a name.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim().parse::<usize>() {
            Ok(i) => ColumnRef::Index(i),
            Err(_) => ColumnRef::Name(s.trim().to_string()),
        })
    }
}

impl std::fmt::Display for ColumnRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ColumnRef::Name(n) => f.write_str(n),
            ColumnRef::Index(i) => write!(f, "column {i}"),
        }
    }
}

/// Whether the first line read is a header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Header {
    /// A header if one of its fields is not a number.
    #[default]
    Auto,
    /// Always a header.
    Yes,
    /// No header: every line is a row, columns are named `column N`.
    No,
}

/// What separates the fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delimiter {
    /// One character (`,`, `;`, tab, …).
    Char(char),
    /// Runs of spaces or tabs.
    Whitespace,
}

impl FromStr for Delimiter {
    type Err = String;
    /// `tab`, `space` (any run of blanks), or one character.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "tab" | "\\t" => Ok(Self::Char('\t')),
            "space" | "whitespace" => Ok(Self::Whitespace),
            _ => {
                let mut chars = s.chars();
                match (chars.next(), chars.next()) {
                    (Some(c), None) => Ok(Self::Char(c)),
                    _ => Err(format!(
                        "{s:?}: a delimiter is one character, `tab` or `space`"
                    )),
                }
            }
        }
    }
}

/// How to read the lines of a log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TableOptions {
    /// The delimiter; `None` detects it from the first line read: the most frequent of tab,
    /// semicolon and comma, or blanks where there is none of them.
    pub delimiter: Option<Delimiter>,
    /// Whether the first line read is a header.
    pub header: Header,
    /// Lines to skip at the top of the file (an instrument's preamble).
    pub skip_rows: usize,
}

/// The delimiter of a line: the most frequent of tab, semicolon and comma; blanks if none.
pub fn detect_delimiter(line: &str) -> Delimiter {
    let best = ['\t', ';', ',']
        .into_iter()
        .max_by_key(|d| line.matches(*d).count())
        .unwrap_or(',');
    if line.contains(best) {
        Delimiter::Char(best)
    } else {
        Delimiter::Whitespace
    }
}

fn split(line: &str, d: Delimiter) -> Vec<&str> {
    match d {
        Delimiter::Char(c) => line.split(c).map(str::trim).collect(),
        Delimiter::Whitespace => line.split_whitespace().collect(),
    }
}

/// A log's lines split into fields, with its column names.
#[derive(Debug, Clone)]
pub struct Table<'a> {
    path: &'a str,
    names: Vec<String>,
    /// The header's line, or the first row's where there is no header.
    header_line: usize,
    /// 1-based line and fields of each row.
    rows: Vec<(usize, Vec<&'a str>)>,
}

impl<'a> Table<'a> {
    /// Split `text` (the file `path`, named in errors). At least one row is required.
    pub fn parse(
        text: &'a str,
        path: &'a str,
        opt: &TableOptions,
    ) -> Result<Self, MachineExportError> {
        let mut lines = text
            .lines()
            .enumerate()
            .skip(opt.skip_rows)
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'))
            .peekable();
        let &(first_line, first) = lines
            .peek()
            .ok_or_else(|| bad(path, opt.skip_rows + 1, "(header)", "no header line or row"))?;
        let delimiter = opt.delimiter.unwrap_or_else(|| detect_delimiter(first));
        let is_header = match opt.header {
            Header::Yes => true,
            Header::No => false,
            Header::Auto => split(first, delimiter)
                .iter()
                .any(|f| !f.is_empty() && f.parse::<f64>().is_err()),
        };
        let names: Vec<String> = if is_header {
            lines.next();
            split(first, delimiter)
                .into_iter()
                .map(str::to_string)
                .collect()
        } else {
            let n = split(first, delimiter).len();
            (1..=n).map(|i| format!("column {i}")).collect()
        };
        let rows: Vec<(usize, Vec<&str>)> =
            lines.map(|(no, l)| (no, split(l, delimiter))).collect();
        if rows.is_empty() {
            return Err(bad(path, first_line, "(rows)", "no data rows"));
        }
        Ok(Self {
            path,
            names,
            header_line: first_line,
            rows,
        })
    }

    /// The file, as named in errors.
    pub fn path(&self) -> &str {
        self.path
    }

    /// Rows read.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether there is no row (never, for a table [`Table::parse`] accepted).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The header's line, or the first row's where there is no header.
    pub fn header_line(&self) -> usize {
        self.header_line
    }

    /// The 1-based line of row `i`.
    pub fn line(&self, i: usize) -> usize {
        self.rows[i].0
    }

    /// The name of column `k` (0-based): its header's, or `column N`.
    pub fn name(&self, k: usize) -> String {
        self.names
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("column {}", k + 1))
    }

    /// The 0-based position of column `c`, or an error at the header naming it.
    pub fn column(&self, c: &ColumnRef) -> Result<usize, MachineExportError> {
        let found = match c {
            ColumnRef::Index(i) => (*i >= 1 && *i <= self.names.len()).then(|| i - 1),
            ColumnRef::Name(n) => self.names.iter().position(|h| h.eq_ignore_ascii_case(n)),
        };
        found.ok_or_else(|| {
            let have = if matches!(c, ColumnRef::Index(_)) {
                format!("the first line has {} fields", self.names.len())
            } else {
                format!("columns: {}", self.names.join(", "))
            };
            bad(
                self.path,
                self.header_line,
                &c.to_string(),
                format!("no such column ({have})"),
            )
        })
    }

    /// Column `k` of every row times `factor`; an empty field, `nan` or a field equal to
    /// `missing` is `NaN` (no reading). A row too short for the column, or a field that is not
    /// a number, is refused naming its line.
    pub fn values(
        &self,
        k: usize,
        factor: f64,
        missing: Option<f64>,
    ) -> Result<Vec<f64>, MachineExportError> {
        self.rows
            .iter()
            .map(|(no, fields)| {
                let text = fields.get(k).ok_or_else(|| {
                    let why = format!("the row has {} fields", fields.len());
                    bad(self.path, *no, &self.name(k), why)
                })?;
                if text.is_empty() || text.eq_ignore_ascii_case("nan") {
                    return Ok(f64::NAN);
                }
                let v = super::number(self.path, *no, &self.name(k), text)?;
                Ok(if missing == Some(v) {
                    f64::NAN
                } else {
                    v * factor
                })
            })
            .collect()
    }

    /// Column `k` as times (× `factor` to s): every row has one, and they never decrease.
    pub fn times(&self, k: usize, factor: f64) -> Result<Vec<f64>, MachineExportError> {
        let t = self.values(k, factor, None)?;
        for (i, w) in t.windows(2).enumerate() {
            let why = if w[1].is_nan() {
                "no time on this row".to_string()
            } else if w[1] < w[0] {
                format!("time decreases (from {} to {})", w[0], w[1])
            } else {
                continue;
            };
            return Err(bad(self.path, self.line(i + 1), &self.name(k), why));
        }
        if t[0].is_nan() {
            return Err(bad(
                self.path,
                self.line(0),
                &self.name(k),
                "no time on this row",
            ));
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opt(header: Header) -> TableOptions {
        TableOptions {
            header,
            ..Default::default()
        }
    }

    #[test]
    fn header_is_detected_and_columns_found_by_name_or_index() {
        let t = Table::parse("# note\nTime;Z\n1;2\n\n3;4\n", "a.csv", &opt(Header::Auto)).unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t.column(&"z".parse().unwrap()).unwrap(), 1);
        assert_eq!(t.column(&"1".parse().unwrap()).unwrap(), 0);
        assert_eq!(t.line(1), 5);
        let t = Table::parse("1,2\n3,-1\n", "b.csv", &opt(Header::Auto)).unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t.name(1), "column 2");
        let v = t.values(1, 10.0, Some(-1.0)).unwrap();
        assert_eq!(v[0], 20.0);
        assert!(v[1].is_nan());
        let t = Table::parse("1  2\n3\t4\n", "c.txt", &opt(Header::No)).unwrap();
        assert_eq!(t.values(1, 1.0, None).unwrap(), vec![2.0, 4.0]);
    }

    #[test]
    fn bad_fields_and_times_name_the_line_and_column() {
        let t = Table::parse("1,2\n3,x\n2,5,\n4\n", "b.csv", &opt(Header::No)).unwrap();
        let e = |r: Result<Vec<f64>, MachineExportError>| r.unwrap_err().to_string();
        assert!(e(t.values(1, 1.0, None)).contains("b.csv:2: field column 2: not a number"));
        assert!(e(t.times(0, 1.0)).contains("b.csv:3: field column 1: time decreases"));
        let short = Table::parse("1,2\n3\n", "s.csv", &opt(Header::No)).unwrap();
        let msg = e(short.values(1, 1.0, None));
        assert!(
            msg.contains("s.csv:2: field column 2: the row has 1 fields"),
            "{msg}"
        );
        let msg = t.column(&"7".parse().unwrap()).unwrap_err().to_string();
        assert!(
            msg.contains("b.csv:1: field column 7: no such column"),
            "{msg}"
        );
        let msg = Table::parse("x\n", "h.csv", &opt(Header::Yes))
            .unwrap_err()
            .to_string();
        assert!(msg.contains("h.csv:1: field (rows)"), "{msg}");
    }
}
