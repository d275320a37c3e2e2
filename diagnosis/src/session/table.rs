//! The summary's table, shared by `summary.csv` and `summary.html`: one row per recording, one
//! column pair (value, standard error) per effect parameter found anywhere in the session.

use sim::effects::EffectKind;

use super::{Outcome, Row};

/// A cell: text, a number, or nothing (an effect this recording does not have).
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    Text(String),
    Num(f64),
    Empty,
}

/// A parameter tracked across the session: (effect, parameter name).
pub type Column = (String, String);

/// The session's table.
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<Cell>>,
}

/// The effect parameters found in any recording, in catalogue order (then by name), once each:
/// the columns of the table and the session plots.
pub fn parameters(rows: &[Row]) -> Vec<Column> {
    let mut cols: Vec<Column> = rows
        .iter()
        .filter_map(|r| r.outcome.as_ref().ok())
        .flat_map(|o| o.effects.iter())
        .map(|p| (p.effect.clone(), p.name.clone()))
        .collect();
    let rank = |name: &str| {
        EffectKind::ALL
            .iter()
            .position(|k| k.name() == name)
            .unwrap_or(usize::MAX)
    };
    cols.sort_by(|a, b| rank(&a.0).cmp(&rank(&b.0)).then_with(|| a.cmp(b)));
    cols.dedup();
    cols
}

/// The value and standard error of parameter `col` in `o`, if it has that effect.
pub fn lookup(o: &Outcome, col: &Column) -> Option<(f64, Option<f64>)> {
    o.effects
        .iter()
        .find(|p| p.effect == col.0 && p.name == col.1)
        .map(|p| (p.value, p.stderr))
}

/// Build the table of `rows`.
pub fn table(rows: &[Row]) -> Table {
    let params = parameters(rows);
    let mut header: Vec<String> = ["file", "status", "verdict", "effects", "youngs_modulus_Pa"]
        .map(String::from)
        .to_vec();
    // Against users' simulations the baseline's level is a load scale: its column only then.
    let scaled = rows
        .iter()
        .any(|r| r.outcome.as_ref().is_ok_and(|o| o.load_scale.is_some()));
    if scaled {
        header.push("load_scale".into());
    }
    for (effect, name) in &params {
        header.push(format!("{effect}.{name}"));
        header.push(format!("{effect}.{name}_stderr"));
    }
    header.extend(
        [
            "heldout_rmse_before",
            "heldout_rmse_after",
            "seconds",
            "error",
        ]
        .map(String::from),
    );
    let rows = rows.iter().map(|r| cells(r, &params, scaled)).collect();
    Table { header, rows }
}

fn cells(r: &Row, params: &[Column], scaled: bool) -> Vec<Cell> {
    let text = |s: &str| Cell::Text(s.to_string());
    let mut c = vec![text(&r.file)];
    match &r.outcome {
        Ok(o) => {
            let names: Vec<&str> = o.effects.iter().map(|p| p.effect.as_str()).collect();
            c.extend([
                text("ok"),
                text(&o.verdict),
                text(&names.join("+")),
                Cell::Num(o.modulus_pa),
            ]);
            if scaled {
                c.push(o.load_scale.map_or(Cell::Empty, Cell::Num));
            }
            for col in params {
                let (value, se) = match lookup(o, col) {
                    Some((v, se)) => (Cell::Num(v), se.map_or(Cell::Empty, Cell::Num)),
                    None => (Cell::Empty, Cell::Empty),
                };
                c.extend([value, se]);
            }
            let (before, after) = o.heldout_rmse;
            c.extend([Cell::Num(before), Cell::Num(after)]);
            c.extend([Cell::Num(r.seconds), Cell::Empty]);
        }
        Err(e) => {
            c.push(text("error"));
            let level = 1 + usize::from(scaled);
            c.extend(std::iter::repeat_n(
                Cell::Empty,
                2 + level + 2 * params.len() + 2,
            ));
            c.extend([Cell::Num(r.seconds), text(e)]);
        }
    }
    c
}
