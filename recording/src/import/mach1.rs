//! The Biomomentum Mach-1 text export: `<INFO>` … `<END INFO>`, then per test a header such as
//! `<Stress Relaxation>` with `key:<TAB>value` lines, `<DATA>`, one tab-separated column header
//! (`Time, s`, `Position (z), mm`, `Fz, gf` or `Fz, N`, …), rows, `<divider>` between ramps and
//! `<END DATA>`.
//!
//! Mapping (`docs/recording-format.md`, "Importing"): rod travel is `Position (z)` minus its
//! first value in the block (positions grow into the sample); the load is the compressive force
//! in N: `Fz` for a single-axis cell (compression reads positive), `-Fz` for a multiple-axis
//! cell (compression reads negative); gf and kgf are converted with standard gravity.

use super::{bad, number};
use crate::machine::{MachineExport, MachineExportError};

pub use super::units::N_PER_KGF;

/// One test block of a Mach-1 export.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// 1-based index among the file's test blocks.
    pub index: usize,
    /// The test's type, e.g. `Stress Relaxation`.
    pub kind: String,
    /// 1-based line of the block's `<…>` header.
    pub line: usize,
    /// Time, s, continuous across dividers.
    pub t_s: Vec<f64>,
    /// `Position (z)`, mm.
    pub position_mm: Vec<f64>,
    /// Compressive load, N.
    pub load_n: Vec<f64>,
}

impl Block {
    /// Rows in the block.
    pub fn rows(&self) -> usize {
        self.t_s.len()
    }

    /// Time from the first row to the last, s.
    pub fn duration_s(&self) -> f64 {
        match (self.t_s.first(), self.t_s.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// The block as time from its start, rod travel from its first position, load.
    pub fn to_export(&self) -> MachineExport {
        let t0 = self.t_s.first().copied().unwrap_or(0.0);
        let z0 = self.position_mm.first().copied().unwrap_or(0.0);
        MachineExport {
            t_s: self.t_s.iter().map(|t| t - t0).collect(),
            rod_mm: self.position_mm.iter().map(|z| z - z0).collect(),
            load_n: self.load_n.clone(),
        }
    }
}

/// Where the parser is.
enum State {
    /// Between blocks, or in `<INFO>` or a test header.
    Outside,
    /// Expecting the column header after `<DATA>`.
    Header,
    /// In the rows.
    Rows(Columns),
}

/// The columns the import uses and how to read the load.
#[derive(Clone)]
struct Columns {
    names: Vec<String>,
    time: usize,
    position: usize,
    fz: usize,
    /// N per unit of `Fz`, with the sign that makes compression positive.
    n_per_unit: f64,
    /// Time added to rows after a divider that restarts the clock.
    offset_s: f64,
}

/// The instrument an export names in its `<INFO>` block, where it does: the system's serial
/// and the load cell's name (which carries its serial), e.g. `Mach-1 MA0561076c, load cell
/// 25kg SN:1886652`.
pub fn identity(text: &str) -> Option<String> {
    let mut info = text
        .lines()
        .map(|l| l.trim_end_matches('\r'))
        .skip_while(|l| l.trim() != "<INFO>")
        .take_while(|l| l.trim() != "<END INFO>");
    let mut system = None;
    let mut cell = None;
    for line in info.by_ref() {
        let Some((key, value)) = line.split_once(':') else {
            continue;
        };
        let value = value.trim();
        match key.trim() {
            "Mach-1 System S/N" if !value.is_empty() => system = Some(value.to_string()),
            "Load Cell Name" if !value.is_empty() => cell = Some(value.to_string()),
            _ => {}
        }
    }
    match (system, cell) {
        (Some(s), Some(c)) => Some(format!("Mach-1 {s}, load cell {c}")),
        (Some(s), None) => Some(format!("Mach-1 {s}")),
        (None, Some(c)) => Some(format!("Mach-1, load cell {c}")),
        (None, None) => None,
    }
}

/// Parse a whole export already in memory; `path` names it in errors.
pub fn parse(text: &str, path: &str) -> Result<Vec<Block>, MachineExportError> {
    let mut blocks: Vec<Block> = Vec::new();
    let mut state = State::Outside;
    let mut multi_axis = false;
    let mut open_test: Option<usize> = None;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        last_line = no;
        let line = raw.trim_end_matches('\r');
        if line.trim().is_empty() {
            continue;
        }
        state = match state {
            State::Rows(cols) => rows_line(line, no, path, cols, blocks.last_mut())?,
            State::Header => State::Rows(header(line, no, path, multi_axis)?),
            State::Outside => {
                outside_line(line, no, path, &mut open_test, &mut blocks, &mut multi_axis)?
            }
        };
    }
    finish(state, open_test, blocks, path, last_line)
}

/// A line outside `<DATA>`: a tag opens a test block or its data; `Load Cell Type` sets the
/// sign of the load.
fn outside_line(
    line: &str,
    no: usize,
    path: &str,
    open_test: &mut Option<usize>,
    blocks: &mut Vec<Block>,
    multi_axis: &mut bool,
) -> Result<State, MachineExportError> {
    let Some(kind) = line
        .trim()
        .strip_prefix('<')
        .and_then(|l| l.strip_suffix('>'))
    else {
        if let Some(v) = line.strip_prefix("Load Cell Type:") {
            *multi_axis = v.trim().to_ascii_lowercase().starts_with("multi");
        }
        return Ok(State::Outside);
    };
    if let Some(start) = *open_test {
        if kind != "DATA" && kind != "INFO" && kind != "END INFO" {
            return Err(bad(path, start, "<DATA>", "test block has no <DATA>"));
        }
    }
    match kind {
        "DATA" => {
            if open_test.take().is_none() {
                return Err(bad(path, no, "<DATA>", "no test header before it"));
            }
            Ok(State::Header)
        }
        "INFO" | "END INFO" | "Mach-1 File" => Ok(State::Outside),
        "END DATA" | "divider" => Err(bad(path, no, kind, "outside a <DATA> section")),
        _ => {
            *open_test = Some(no);
            blocks.push(Block {
                index: blocks.len() + 1,
                kind: kind.to_string(),
                line: no,
                t_s: Vec::new(),
                position_mm: Vec::new(),
                load_n: Vec::new(),
            });
            Ok(State::Outside)
        }
    }
}

/// The end of the file: every block closed and holding rows.
fn finish(
    state: State,
    open_test: Option<usize>,
    blocks: Vec<Block>,
    path: &str,
    last_line: usize,
) -> Result<Vec<Block>, MachineExportError> {
    if !matches!(state, State::Outside) {
        return Err(bad(
            path,
            last_line,
            "<END DATA>",
            "file ends inside <DATA>: truncated?",
        ));
    }
    if let Some(start) = open_test {
        return Err(bad(path, start, "<DATA>", "test block has no <DATA>"));
    }
    if blocks.is_empty() {
        return Err(bad(
            path,
            1,
            "(test block)",
            "no test block: not a Mach-1 export?",
        ));
    }
    if let Some(b) = blocks.iter().find(|b| b.rows() < 2) {
        return Err(bad(path, b.line, &b.kind, "fewer than two data rows"));
    }
    Ok(blocks)
}

/// The column header after `<DATA>`: find time, `Position (z)` and `Fz` and the load's unit.
fn header(
    line: &str,
    no: usize,
    path: &str,
    multi_axis: bool,
) -> Result<Columns, MachineExportError> {
    let names: Vec<String> = line.split('\t').map(|s| s.trim().to_string()).collect();
    let find = |prefix: &str| {
        names
            .iter()
            .position(|n| n.starts_with(prefix))
            .ok_or_else(|| bad(path, no, prefix, format!("no column `{prefix}, <unit>`")))
    };
    let (time, position, fz) = (find("Time")?, find("Position (z)")?, find("Fz")?);
    let unit = names[fz].split_once(',').map_or("", |(_, u)| u.trim());
    let per_unit = match unit {
        "N" => 1.0,
        "gf" => N_PER_KGF * 1e-3,
        "kgf" => N_PER_KGF,
        "kN" => 1e3,
        other => {
            return Err(bad(
                path,
                no,
                &names[fz],
                format!("unknown force unit {other:?}"),
            ))
        }
    };
    let sign = if multi_axis || names.iter().any(|n| n.starts_with("Fx")) {
        -1.0
    } else {
        1.0
    };
    Ok(Columns {
        time,
        position,
        fz,
        n_per_unit: sign * per_unit,
        offset_s: 0.0,
        names,
    })
}

/// One line inside `<DATA>`: a row, a `<divider>` or `<END DATA>`.
fn rows_line(
    line: &str,
    no: usize,
    path: &str,
    mut cols: Columns,
    block: Option<&mut Block>,
) -> Result<State, MachineExportError> {
    let block = block.ok_or_else(|| bad(path, no, "<DATA>", "rows outside a test block"))?;
    match line.trim() {
        "<END DATA>" => return Ok(State::Outside),
        "<divider>" => return Ok(State::Rows(cols)),
        l if l.starts_with('<') => {
            return Err(bad(
                path,
                no,
                l,
                "tag inside <DATA> before <END DATA>: truncated block?",
            ))
        }
        _ => {}
    }
    let fields: Vec<&str> = line.split('\t').collect();
    let field = |k: usize| -> Result<f64, MachineExportError> {
        let text = fields.get(k).copied().unwrap_or("");
        number(path, no, &cols.names[k], text)
    };
    let (t, z, f) = (field(cols.time)?, field(cols.position)?, field(cols.fz)?);
    let mut t_s = t + cols.offset_s;
    if let Some(&last) = block.t_s.last() {
        if t_s < last {
            let n = block.t_s.len();
            let step = if n > 1 { last - block.t_s[n - 2] } else { 0.0 };
            cols.offset_s += last - t_s + step.max(0.0);
            t_s = t + cols.offset_s;
        }
    }
    block.t_s.push(t_s);
    block.position_mm.push(z);
    block.load_n.push(f * cols.n_per_unit);
    Ok(State::Rows(cols))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_identity_is_the_system_and_load_cell_serials_where_the_info_gives_them() {
        let info = "<Mach-1 File>\r\n<INFO>\r\nMach-1 System S/N:\tMA0561076c\r\n\
                    Load Cell Name:\t25kg SN:1886652\r\n<END INFO>\r\n<Sinusoid>\r\n";
        assert_eq!(
            identity(info).as_deref(),
            Some("Mach-1 MA0561076c, load cell 25kg SN:1886652")
        );
        assert_eq!(identity(HAYES), None);
    }

    const HAYES: &str = "<Mach-1 File>\r\n<INFO>\r\nLoad Cell Type:\tSingle-axis\r\n<END INFO>\r\n\
<Stress Relaxation>\r\nVelocity, mm/s:\t0.2794\r\n<DATA>\r\n\
Time, s\tPosition (z), mm\tPosition (x), mm\tFz, gf\r\n\
0.00\t-2.7942\t0\t0.0\r\n0.01\t-2.7900\t0\t1.0\r\n<divider>\r\n0.02\t-2.7800\t0\t2.0\r\n<END DATA>\r\n";

    const SIX_AXIS: &str = "<INFO>\nLoad Cell Type:\tMultiple-axis\n<END INFO>\n<Stress Relaxation>\n<DATA>\n\
Time, s\tPosition (z), mm\tFx, N\tFy, N\tFz, N\tTx, N-mm\n\
0.0\t0.1574\t0\t0\t-0.25\t1\n0.01\t0.1600\t0\t0\t-0.30\t1\n<divider>\n0.0\t0.17\t0\t0\t-0.4\t1\n<END DATA>\n";

    #[test]
    fn single_axis_gf_is_converted_and_rod_starts_at_zero() {
        let b = &parse(HAYES, "h.txt").unwrap()[0];
        assert_eq!(b.kind, "Stress Relaxation");
        assert_eq!(b.rows(), 3);
        let e = b.to_export();
        assert!((e.rod_mm[2] - 0.0142).abs() < 1e-12);
        assert!((e.load_n[2] - 2.0 * 9.80665e-3).abs() < 1e-12);
    }

    #[test]
    fn six_axis_compression_is_negative_fz_and_time_continues_after_a_divider() {
        let b = &parse(SIX_AXIS, "s.txt").unwrap()[0];
        assert_eq!(b.load_n, vec![0.25, 0.30, 0.4]);
        assert!((b.t_s[2] - 0.02).abs() < 1e-12, "{:?}", b.t_s);
    }

    #[test]
    fn bad_input_names_the_line_and_field() {
        let cases = [
            (HAYES.replace("<END DATA>\r\n", ""), ":12: field <END DATA>"),
            (HAYES.replace("<DATA>\r\n", ""), ":5: field <DATA>"),
            (
                HAYES.replace("0.01\t-2.7900", "0.01\tx"),
                ":10: field Position (z), mm: not a number",
            ),
            (
                HAYES.replace("Fz, gf", "Fz, lbf"),
                ":8: field Fz, lbf: unknown force unit",
            ),
            (HAYES.replace("Fz, gf", "Load"), ":8: field Fz:"),
            ("hello\n".to_string(), ":1: field (test block)"),
        ];
        for (text, want) in cases {
            let e = parse(&text, "f.txt").unwrap_err().to_string();
            assert!(e.starts_with("f.txt") && e.contains(want), "{want}: {e}");
        }
    }
}
