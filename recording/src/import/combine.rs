//! An output column made of a sensor's columns: one column, or a signed sum or linear
//! combination of them, written `4`, `-4+7+10-13+16`, `0.5*Bx1 - 0.5*Bx2`.

use std::str::FromStr;

use super::table::{ColumnRef, Table};
use crate::machine::MachineExportError;

/// A linear combination of columns: `sum(coefficient × column)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Combination {
    /// The text it was read from, trimmed (the metadata records it).
    pub text: String,
    /// Each term's coefficient and column.
    pub terms: Vec<(f64, ColumnRef)>,
}

impl FromStr for Combination {
    type Err = String;
    /// Terms joined by `+` or `-` (a leading sign allowed), each `column` or
    /// `coefficient*column`; a column is a 1-based index or a header name (without `+`, `-`
    /// or `*`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let mut terms = Vec::new();
        for (sign, term) in split_terms(s) {
            let (coef, column) = match term.split_once('*') {
                Some((c, col)) => {
                    let c: f64 = c
                        .trim()
                        .parse()
                        .ok()
                        .filter(|c: &f64| c.is_finite())
                        .ok_or_else(|| {
                            format!("{s:?}: {:?} is not a number before `*`", c.trim())
                        })?;
                    (c, col.trim())
                }
                None => (1.0, term.trim()),
            };
            if column.is_empty() || column.contains('*') {
                return Err(format!(
                    "{s:?}: a term is `column` or `coefficient*column` (e.g. `-4+7`, `0.5*3`)"
                ));
            }
            let column = column.parse().unwrap_or_else(|e| match e {});
            if column == ColumnRef::Index(0) {
                return Err(format!("{s:?}: columns are counted from 1"));
            }
            terms.push((sign * coef, column));
        }
        Ok(Self {
            text: s.trim().to_string(),
            terms,
        })
    }
}

/// The terms of `s` with their signs: split at each `+` or `-` that is not the sign of a
/// number's exponent (`1e-3`).
fn split_terms(s: &str) -> Vec<(f64, &str)> {
    let bytes = s.as_bytes();
    let mut out = Vec::new();
    let (mut sign, mut start) = (1.0, 0);
    for (i, &b) in bytes.iter().enumerate() {
        if b != b'+' && b != b'-' {
            continue;
        }
        let exponent = i >= 2
            && matches!(bytes[i - 1], b'e' | b'E')
            && (bytes[i - 2].is_ascii_digit() || bytes[i - 2] == b'.');
        if exponent {
            continue;
        }
        if !s[start..i].trim().is_empty() {
            out.push((sign, &s[start..i]));
        } else if !out.is_empty() || start != 0 {
            // Two signs in a row (`4+-7`) or a sign after nothing but another sign.
            out.push((sign, ""));
        }
        sign = if b == b'-' { -1.0 } else { 1.0 };
        start = i + 1;
    }
    out.push((sign, &s[start..]));
    out
}

impl Combination {
    /// The combination on every row of `table`, times `scale`; `NaN` on a row where one of its
    /// columns has no reading.
    pub fn evaluate(&self, table: &Table, scale: f64) -> Result<Vec<f64>, MachineExportError> {
        let mut sum = vec![0.0; table.len()];
        for (coef, column) in &self.terms {
            let values = table.values(table.column(column)?, 1.0, None)?;
            for (s, v) in sum.iter_mut().zip(values) {
                *s += coef * v;
            }
        }
        Ok(sum.into_iter().map(|s| s * scale).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::super::table::{Header, TableOptions};
    use super::*;

    fn c(s: &str) -> Combination {
        s.parse().unwrap()
    }

    #[test]
    fn signed_sums_and_coefficients() {
        let idx = |i| ColumnRef::Index(i);
        assert_eq!(c("4").terms, vec![(1.0, idx(4))]);
        assert_eq!(
            c("-4+7 - 13").terms,
            vec![(-1.0, idx(4)), (1.0, idx(7)), (-1.0, idx(13))]
        );
        assert_eq!(
            c("1e-3*Bz - 2.5*3").terms,
            vec![(1e-3, ColumnRef::Name("Bz".into())), (-2.5, idx(3))]
        );
        for bad in ["", "4+", "4+-7", "x*3", "2*", "0", "3**4"] {
            assert!(bad.parse::<Combination>().is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn evaluates_on_rows_with_gaps() {
        let opt = TableOptions {
            header: Header::Yes,
            ..Default::default()
        };
        let t = Table::parse("t,a,b\n0,1,10\n1,2,\n2,3,30\n", "s.csv", &opt).unwrap();
        let v = c("-a + 0.5*3").evaluate(&t, 2.0).unwrap();
        assert_eq!(v[0], 8.0);
        assert!(v[1].is_nan());
        assert_eq!(v[2], 24.0);
        let e = c("2+9").evaluate(&t, 1.0).unwrap_err().to_string();
        assert!(e.contains("s.csv:1: field column 9: no such column"), "{e}");
    }
}
