//! The static response (`tactile-response/1`, `docs/simulation-format.md`): rod travel -> load
//! and outputs, one row per travel, driven along the recorded rod path as the FE tables are.

use std::path::Path;

use recording::Meta;

use super::curve::Curve;
use super::{channels, Aligned, Angles, Front, Samples, SimulationError};

/// A static response table as read.
pub(crate) struct Table {
    angles: Angles,
    /// The gains and excitation its outputs are given at, where it says.
    gain: [Option<f64>; 3],
    excitation_v: Option<f64>,
    rod_mm: Vec<f64>,
    /// load_N, fz_V, mx_V, my_V; `None` where not simulated.
    columns: [Option<Vec<f64>>; 4],
}

impl Table {
    /// The travels the table gives, mm.
    pub(crate) fn rod_mm(&self) -> &[f64] {
        &self.rod_mm
    }
}

/// Read and check the table at `path`.
pub(crate) fn read(path: &Path) -> Result<Table, SimulationError> {
    let bytes = std::fs::read(path).map_err(|source| SimulationError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = super::utf8(path, &bytes, 1)?;
    let err = |line: usize, what: String| SimulationError::Table {
        path: path.to_path_buf(),
        line,
        what,
    };
    let mut meta = MetaLines::default();
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (header_line, header) = loop {
        let Some((no, line)) = lines.next() else {
            return Err(err(0, "no header line (`rod_mm,load_N,...`)".into()));
        };
        let line = line.trim().trim_start_matches('\u{feff}');
        if line.is_empty() {
            continue;
        }
        match line.strip_prefix('#') {
            Some(comment) => meta.push(no, comment).map_err(|w| err(no, w))?,
            None => break (no, line),
        }
    };
    let names = header_columns(header).map_err(|w| err(header_line, w))?;
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut row_lines = Vec::new();
    for (no, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != names.len() {
            let what = format!("{} fields, the header has {}", fields.len(), names.len());
            return Err(err(no, what));
        }
        for ((field, name), column) in fields.iter().zip(&names).zip(values.iter_mut()) {
            let v = number(field).ok_or_else(|| {
                err(
                    no,
                    format!("column `{name}`: `{}` is not a number", field.trim()),
                )
            })?;
            column.push(v);
        }
        row_lines.push(no);
    }
    let lines = Lines {
        header: header_line,
        rows: row_lines,
    };
    Table::of_columns(&names, values, &meta, &|i, w| err(lines.of(i), w))
}

/// Where the header and each data row are in the file (1-based lines).
struct Lines {
    header: usize,
    rows: Vec<usize>,
}

impl Lines {
    /// The line of data row `i` (0-based), the header's for `usize::MAX`.
    fn of(&self, i: usize) -> usize {
        self.rows.get(i).copied().unwrap_or(self.header)
    }
}

/// A field: a finite number, or NaN for an empty one (`nan` too).
fn number(field: &str) -> Option<f64> {
    let f = field.trim();
    if f.is_empty() || f.eq_ignore_ascii_case("nan") {
        return Some(f64::NAN);
    }
    f.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The header's column names, checked: `rod_mm` and the value columns only, each once.
fn header_columns(header: &str) -> Result<Vec<String>, String> {
    let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            return Err(format!("column `{n}` is given twice"));
        }
        if n != "rod_mm" && !channels().contains(&n.as_str()) {
            return Err(format!(
                "column `{n}` is not one of rod_mm, {} (a static response's columns)",
                channels().join(", ")
            ));
        }
    }
    if !names.iter().any(|n| n == "rod_mm") {
        return Err(
            "no column `rod_mm`: a static response is a function of the rod's travel".into(),
        );
    }
    Ok(names)
}

/// The metadata lines of a table, typed where the format types them.
#[derive(Default)]
struct MetaLines {
    seen: Vec<(String, usize)>,
    angles: Angles,
    gain: [Option<f64>; 3],
    excitation_v: Option<f64>,
}

impl MetaLines {
    /// One `# key = value` line (a comment without `=` is ignored).
    fn push(&mut self, line: usize, comment: &str) -> Result<(), String> {
        let Some((k, v)) = comment.split_once('=') else {
            return Ok(());
        };
        let (key, value) = (k.trim(), v.trim());
        if let Some((_, first)) = self.seen.iter().find(|(k, _)| k == key) {
            return Err(format!(
                "metadata `{key}` is given again (first on line {first})"
            ));
        }
        self.seen.push((key.to_string(), line));
        let num = |positive: bool| -> Result<Option<f64>, String> {
            match value.parse::<f64>() {
                Ok(x) if x.is_finite() && (!positive || x > 0.0) => Ok(Some(x)),
                _ => Err(format!(
                    "metadata `{key}` = `{value}` is not a {}number",
                    if positive { "positive " } else { "" }
                )),
            }
        };
        match key {
            "contact_angle_deg" => self.angles.contact_angle_deg = num(false)?,
            "azimuth_deg" => self.angles.azimuth_deg = num(false)?,
            "fingertip_radius_mm" => self.angles.fingertip_radius_mm = num(true)?,
            "gain_fz" => self.gain[0] = num(true)?,
            "gain_mx" => self.gain[1] = num(true)?,
            "gain_my" => self.gain[2] = num(true)?,
            "excitation_V" => self.excitation_v = num(true)?,
            _ => {}
        }
        Ok(())
    }
}

impl Table {
    /// The table of the parsed `values` (one vector per header column), checked: `rod_mm`
    /// given on every row and increasing, each other column given on every row or on none;
    /// `err(i, what)` names data row `i` (`usize::MAX`: the header).
    fn of_columns(
        names: &[String],
        values: Vec<Vec<f64>>,
        meta: &MetaLines,
        err: &dyn Fn(usize, String) -> SimulationError,
    ) -> Result<Self, SimulationError> {
        let rows = values.first().map_or(0, Vec::len);
        if rows < 2 {
            let what = format!("{rows} data rows: a response needs at least 2");
            return Err(err(usize::MAX, what));
        }
        let at = |name: &str| names.iter().position(|n| n == name);
        let rod = values[at("rod_mm").expect("checked")].clone();
        if let Some(i) = rod.iter().position(|d| d.is_nan()) {
            let what = "column `rod_mm` is empty here: every row is at a travel".to_string();
            return Err(err(i, what));
        }
        for (i, w) in rod.windows(2).enumerate() {
            if w[1] <= w[0] {
                let what = format!(
                    "column `rod_mm` must increase from row to row: {} after {}",
                    w[1], w[0]
                );
                return Err(err(i + 1, what));
            }
        }
        let mut columns: [Option<Vec<f64>>; 4] = Default::default();
        for (c, name) in channels().iter().enumerate() {
            let Some(j) = at(name) else { continue };
            let v = &values[j];
            if v.iter().all(|x| x.is_nan()) {
                continue;
            }
            if let Some(i) = v.iter().position(|x| x.is_nan()) {
                let what = format!(
                    "column `{name}` is empty here but not on other rows: a table has no gaps (leave the whole column empty if it is not simulated)"
                );
                return Err(err(i, what));
            }
            columns[c] = Some(v.clone());
        }
        Ok(Self {
            angles: meta.angles,
            gain: meta.gain,
            excitation_v: meta.excitation_v,
            rod_mm: rod,
            columns,
        })
    }

    pub fn angles(&self) -> Angles {
        self.angles
    }

    /// The front end its outputs are given at: its own gains and excitation where it says,
    /// else the recording's.
    pub fn front(&self, rec: &Meta) -> Front {
        let rec_gain = [rec.gain_fz, rec.gain_mx, rec.gain_my];
        Front {
            gain: std::array::from_fn(|k| self.gain[k].unwrap_or(rec_gain[k])),
            excitation_v: self.excitation_v.unwrap_or(rec.excitation_v),
        }
    }

    /// The table driven along the recorded rod path: each column at each full-rate travel.
    /// It must span the recorded travel, from first contact (or the recording's least travel,
    /// where it starts in contact) to the largest, within half a percent of the largest.
    pub fn drive(&self, path: &Path, at: Samples) -> Result<Aligned, SimulationError> {
        let rod = at.rod_mm;
        let lo = rod.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = rod.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let tol = TRAVEL_TOLERANCE * hi.abs();
        let (first, last) = (self.rod_mm[0], self.rod_mm[self.rod_mm.len() - 1]);
        let needs_from = lo.max(0.0);
        if first > needs_from + tol || last < hi - tol {
            return Err(SimulationError::Travel {
                path: path.to_path_buf(),
                covers_mm: (first, last),
                needs_mm: (needs_from, hi),
            });
        }
        let columns = self.columns.clone().map(|c| {
            c.map(|y| {
                let curve = Curve::new(self.rod_mm.clone(), y);
                rod.iter().map(|&d| curve.at_extending(d)).collect()
            })
        });
        let held = if lo < first {
            format!("; below {first} mm (the rod out of contact) its first row's values")
        } else {
            String::new()
        };
        let alignment = vec![
            ("rows".into(), self.rod_mm.len() as f64),
            ("rod_from_mm".into(), first),
            ("rod_to_mm".into(), last),
        ];
        Ok(Aligned {
            columns,
            aligned: format!(
                "driven along the recorded rod path: its {} rows from {first} to {last} mm interpolated (monotone cubic in the travel) at each of the recording's {} samples{held}",
                self.rod_mm.len(),
                rod.len()
            ),
            alignment,
        })
    }
}

/// A table may stop this share of the largest recorded travel short of it (continued along its
/// end slope there): an FE run stopped at the nominal peak, a rod overshooting by a few
/// micrometres.
const TRAVEL_TOLERANCE: f64 = 0.005;
