//! `summary.html`: one self-contained page (inline SVG, no script, no link) with the session's
//! table and, per parameter, its value ± standard error across the recordings: does the
//! relaxation tau drift from test to test?

use std::fmt::Write as _;

use super::plot::{parameter_svg, Point};
use super::table::{lookup, parameters, table, Cell};
use super::Row;

/// The text of `summary.html` for `rows`.
pub fn summary(rows: &[Row]) -> String {
    let bad = rows.iter().filter(|r| r.outcome.is_err()).count();
    let mut html = String::new();
    let _ = write!(
        html,
        "<!doctype html><meta charset=utf-8><title>tactile diagnose: session of {n}</title>\
         <style>body{{font-family:sans-serif;margin:1em}}table{{border-collapse:collapse;font-size:90%}}\
         td,th{{padding:2px 6px;border-bottom:1px solid #ddd;text-align:right;white-space:nowrap}}\
         td:first-child,th:first-child,td:last-child{{text-align:left}}.error{{color:#b00}}\
         .wide{{overflow-x:auto}}</style>\
         <h1>Session of {n} recordings</h1><p>{ok} analysed, {bad} could not be.</p>",
        n = rows.len(),
        ok = rows.len() - bad,
    );
    html.push_str("<h2>Recordings</h2>");
    table_html(&mut html, rows);
    html.push_str("<h2>Parameters across the session</h2>");
    for (title, svg) in plots(rows) {
        let _ = write!(html, "<h3>{}</h3>", esc(&title));
        match svg {
            Ok(svg) => html.push_str(&svg),
            Err(e) => {
                let _ = write!(html, "<p class=error>plot failed: {}</p>", esc(&e));
            }
        }
    }
    html
}

fn table_html(html: &mut String, rows: &[Row]) {
    let t = table(rows);
    html.push_str("<div class=wide><table><tr>");
    for h in &t.header {
        let _ = write!(html, "<th>{}</th>", esc(h));
    }
    html.push_str("</tr>");
    for (row, cells) in rows.iter().zip(&t.rows) {
        let class = if row.outcome.is_err() {
            " class=error"
        } else {
            ""
        };
        let _ = write!(html, "<tr{class}>");
        for c in cells {
            let text = match c {
                Cell::Text(s) => esc(s),
                Cell::Num(v) if v.is_finite() => significant(*v),
                Cell::Num(_) | Cell::Empty => String::new(),
            };
            let _ = write!(html, "<td>{text}</td>");
        }
        html.push_str("</tr>");
    }
    html.push_str("</table></div>");
}

/// One plot per parameter: the baseline's modulus, then each effect parameter of the table.
fn plots(rows: &[Row]) -> Vec<(String, Result<String, String>)> {
    let labels: Vec<String> = rows.iter().map(|r| r.stem.clone()).collect();
    let modulus: Vec<Option<Point>> = rows
        .iter()
        .map(|r| {
            let o = r.outcome.as_ref().ok()?;
            o.modulus_pa.is_finite().then_some((o.modulus_pa, None))
        })
        .collect();
    let mut out = vec![(
        "baseline: youngs_modulus_Pa".to_string(),
        parameter_svg(&labels, &modulus, &axis_title("youngs_modulus_Pa")),
    )];
    let scale: Vec<Option<Point>> = rows
        .iter()
        .map(|r| r.outcome.as_ref().ok()?.load_scale.map(|v| (v, None)))
        .collect();
    if scale.iter().any(Option::is_some) {
        out.push((
            "baseline: load_scale (a user's simulation)".to_string(),
            parameter_svg(&labels, &scale, &axis_title("load_scale")),
        ));
    }
    for col in parameters(rows) {
        let points: Vec<Option<Point>> = rows
            .iter()
            .map(|r| lookup(r.outcome.as_ref().ok()?, &col))
            .collect();
        let svg = parameter_svg(&labels, &points, &axis_title(&col.1));
        out.push((format!("{}: {}", col.0, col.1), svg));
    }
    out
}

/// `v` to four significant digits, in plain notation where that stays short.
fn significant(v: f64) -> String {
    let magnitude = v.abs();
    if magnitude == 0.0 {
        return "0".to_string();
    }
    if (1e-3..1e6).contains(&magnitude) {
        let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// The y axis title of a parameter: its name and the unit its suffix names.
fn axis_title(param: &str) -> String {
    let unit = [
        ("_Pa", "Pa"),
        ("_s", "s"),
        ("_V", "V"),
        ("_deg", "deg"),
        ("_hz", "Hz"),
        ("_N", "N"),
    ]
    .iter()
    .find(|(suffix, _)| param.ends_with(suffix))
    .map_or("1", |(_, unit)| unit);
    format!("{param} [{unit}]")
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_titles_carry_the_unit_of_the_suffix() {
        assert_eq!(axis_title("tau_s"), "tau_s [s]");
        assert_eq!(axis_title("youngs_modulus_Pa"), "youngs_modulus_Pa [Pa]");
        assert_eq!(axis_title("freq_hz"), "freq_hz [Hz]");
        assert_eq!(axis_title("fraction"), "fraction [1]");
    }

    #[test]
    fn table_numbers_keep_four_significant_digits() {
        assert_eq!(significant(74294.909), "74295");
        assert_eq!(significant(2.0586714), "2.059");
        assert_eq!(significant(0.0042454), "0.004245");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(3.2e-7), "3.200e-7");
    }
}
