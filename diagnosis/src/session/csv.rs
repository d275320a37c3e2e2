//! `summary.csv`: the session's table as RFC 4180 CSV (CRLF line ends; a field with a comma,
//! quote or line end quoted, its quotes doubled). Numbers are written in full (shortest text
//! that reads back to the same f64); a number that could not be computed is an empty field.

use super::table::{table, Cell};
use super::Row;

/// The text of `summary.csv` for `rows`.
pub fn summary(rows: &[Row]) -> String {
    let t = table(rows);
    let mut out = String::new();
    line(&mut out, t.header.iter().map(|h| field(h)));
    for row in &t.rows {
        line(&mut out, row.iter().map(cell));
    }
    out
}

fn line(out: &mut String, fields: impl Iterator<Item = String>) {
    let fields: Vec<String> = fields.collect();
    out.push_str(&fields.join(","));
    out.push_str("\r\n");
}

fn cell(c: &Cell) -> String {
    match c {
        Cell::Text(s) => field(s),
        Cell::Num(v) if v.is_finite() => v.to_string(),
        Cell::Num(_) | Cell::Empty => String::new(),
    }
}

/// One field, quoted when RFC 4180 requires it.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_commas_quotes_and_line_ends_are_quoted() {
        assert_eq!(field("plain.csv"), "plain.csv");
        assert_eq!(field("a,b"), "\"a,b\"");
        assert_eq!(field("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(field("two\nlines"), "\"two\nlines\"");
        assert_eq!(cell(&Cell::Num(f64::NAN)), "");
        assert_eq!(cell(&Cell::Num(0.25)), "0.25");
    }
}
