//! Parameter tables: value ± uncertainty with units and sensible digits, the bounds the fit was
//! allowed, and a visible flag where a value ended on one.

use figures::number::measurement;

use super::page::esc;
use crate::output::{Numbers, ParamDetail};

/// One row of a parameter table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub name: String,
    /// `6.08 ± 0.31 s`, or `≥ 200 s (at bound)`.
    pub value: String,
    /// `0.1 … 200 s`, when known.
    pub bounds: String,
    pub at_bound: bool,
    pub note: String,
}

/// The unit a parameter's name announces by its suffix (`tau_s` -> `s`); dimensionless
/// otherwise. Only for parameters that come without a [`ParamDetail`].
pub fn unit_from_name(name: &str) -> &'static str {
    const SUFFIXES: [(&str, &str); 9] = [
        ("_s", "s"),
        ("_V", "V"),
        ("_Pa", "Pa"),
        ("_hz", "Hz"),
        ("_Hz", "Hz"),
        ("_N", "N"),
        ("_deg", "deg"),
        ("_mm", "mm"),
        ("_C", "°C"),
    ];
    SUFFIXES
        .iter()
        .find(|(suffix, _)| name.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

/// A row from a full parameter description: a value on a bound reads as the bound it may lie
/// beyond ("≥ 200 s (at bound)"), since the data did not resolve it inside.
pub fn detail_row(p: &ParamDetail) -> Row {
    // A dimensionless number ("1") takes no unit and no SI prefix: 0.30, not 300 m1.
    let unit = if p.unit == "1" { "" } else { p.unit.as_str() };
    let bound = |v: f64| measurement(v, None, unit);
    let value = if p.at_bound {
        let upper = (p.value - p.upper).abs() <= (p.value - p.lower).abs();
        let (sign, b) = if upper {
            ("≥", p.upper)
        } else {
            ("≤", p.lower)
        };
        format!("{sign} {} (at bound)", bound(b))
    } else if let (None, Some(lo), Some(hi)) = (p.stderr, p.ci_low, p.ci_high) {
        format!(
            "{} (95 % interval {} … {})",
            measurement(p.value, None, unit),
            measurement(lo, None, unit),
            measurement(hi, None, unit)
        )
    } else {
        measurement(p.value, p.stderr, unit)
    };
    let bounds = if p.lower.is_finite() || p.upper.is_finite() {
        format!(
            "{} … {}",
            finite_or(p.lower, "−∞", bound),
            finite_or(p.upper, "∞", bound)
        )
    } else {
        String::new()
    };
    Row {
        name: p.name.clone(),
        value,
        bounds,
        at_bound: p.at_bound,
        note: p.note.clone().unwrap_or_default(),
    }
}

fn finite_or(v: f64, infinite: &str, f: impl Fn(f64) -> String) -> String {
    if v.is_finite() {
        f(v)
    } else {
        infinite.to_string()
    }
}

/// Rows from `details` when the fit filled them, else from the contract's `params` and
/// `param_stderr` with units from the names.
pub fn rows(details: &[ParamDetail], params: &Numbers, stderr: Option<&Numbers>) -> Vec<Row> {
    if !details.is_empty() {
        return details.iter().map(detail_row).collect();
    }
    params
        .0
        .iter()
        .map(|(name, v)| Row {
            name: name.clone(),
            value: measurement(*v, stderr.and_then(|s| s.get(name)), unit_from_name(name)),
            bounds: String::new(),
            at_bound: false,
            note: String::new(),
        })
        .collect()
}

/// An HTML table of `rows`; the bounds and note columns only when some row has them.
pub fn table(rows: &[Row]) -> String {
    let with_bounds = rows.iter().any(|r| !r.bounds.is_empty());
    let with_notes = rows.iter().any(|r| !r.note.is_empty() || r.at_bound);
    let mut h = String::from("<table class=params><tr><th>parameter</th><th>value</th>");
    if with_bounds {
        h.push_str("<th>allowed</th>");
    }
    if with_notes {
        h.push_str("<th>note</th>");
    }
    h.push_str("</tr>");
    for r in rows {
        let class = if r.at_bound { " class=at-bound" } else { "" };
        h.push_str(&format!(
            "<tr{class}><td><code>{}</code></td><td class=num>{}</td>",
            esc(&r.name),
            esc(&r.value)
        ));
        if with_bounds {
            h.push_str(&format!("<td class=num>{}</td>", esc(&r.bounds)));
        }
        if with_notes {
            let note = match (r.at_bound, r.note.is_empty()) {
                (true, true) => "on a bound: the data did not resolve it".to_string(),
                _ => r.note.clone(),
            };
            h.push_str(&format!("<td>{}</td>", esc(&note)));
        }
        h.push_str("</tr>");
    }
    h.push_str("</table>");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn detail(value: f64, at_bound: bool) -> ParamDetail {
        ParamDetail {
            name: "tau_s".into(),
            value,
            stderr: Some(0.3138),
            ci_low: None,
            ci_high: None,
            unit: "s".into(),
            lower: 0.1,
            upper: 200.0,
            at_bound,
            note: None,
        }
    }

    #[test]
    fn values_carry_units_digits_and_bound_flags() {
        let r = detail_row(&detail(6.0803, false));
        assert_eq!(
            (r.value.as_str(), r.bounds.as_str()),
            ("6.08 ± 0.31 s", "100 ms … 200 s")
        );
        let r = detail_row(&detail(200.0, true));
        assert_eq!(r.value, "≥ 200 s (at bound)");
        assert!(table(&[r]).contains("class=at-bound"));
        let fraction = ParamDetail {
            unit: "1".into(),
            ..detail(0.299_725, false)
        };
        let r = detail_row(&ParamDetail {
            stderr: Some(4e-5),
            ..fraction
        });
        assert_eq!(r.value, "0.299725 ± 0.000040");
    }

    #[test]
    fn without_details_units_come_from_the_names() {
        assert_eq!(unit_from_name("amplitude_V"), "V");
        assert_eq!(unit_from_name("youngs_modulus_Pa"), "Pa");
        assert_eq!(unit_from_name("fraction"), "");
        let mut p = Numbers::default();
        p.push("amplitude_V", 0.030_014);
        p.push("fraction", 0.299_95);
        let mut se = Numbers::default();
        se.push("amplitude_V", 1.73e-5);
        let r = rows(&[], &p, Some(&se));
        assert_eq!(r[0].value, "30.014 ± 0.017 mV");
        assert_eq!(r[1].value, "0.300");
    }
}
