//! The effects a diagnosis reports, gathered from the steps that found them, each with its
//! part of the model at the full rate, which the certification (`steps::certified`) tests.
use baseline::{Drive, Outputs};

use crate::certify::Part;
use crate::data::Data;
use crate::evidence;
use crate::mains::Line;
use crate::output::EffectReport;
use crate::select::Selection;
use crate::steps::full_rate::FullRate;
use crate::steps::lines::{add_line, LOAD_CELL, OUTPUTS};
use crate::terms;

/// An effect found and its part of the model at the full rate.
pub(crate) type Found = (EffectReport, Option<Part>);

/// The effects to report: the chosen catalogue effects, the mains lines on the outputs and on
/// the load cell, and what was described beyond the catalogue (`described`, with `parts`).
pub(crate) fn run(
    sel: &Selection,
    full: &FullRate,
    (described, parts): (Vec<EffectReport>, Vec<Option<Part>>),
    drive: &Drive,
) -> Vec<Found> {
    let data = sel.base().model.setup.data;
    let catalogue = evidence::effect_reports(sel, data);
    let catalogue_parts = evidence::catalogue_parts(sel, drive, &catalogue);
    let mut effects: Vec<Found> = catalogue
        .into_iter()
        .zip(catalogue_parts.into_iter().map(Some))
        .collect();
    let outputs: Vec<usize> = OUTPUTS.into_iter().filter(|&c| data.modelled(c)).collect();
    if let Some(line) = &full.mains {
        let part = line_part(data, line, &outputs);
        effects.push((evidence::mains_report(line, data), Some(part)));
    }
    if let Some(line) = &full.load_mains {
        let part = line_part(data, line, &LOAD_CELL);
        effects.push((evidence::load_mains_report(line, data), Some(part)));
    }
    for e in terms::report::fast_lines(&full.fast) {
        let f = e.params.get("freq_hz").unwrap_or(f64::NAN);
        let mut part: Part = std::array::from_fn(|_| Vec::new());
        for l in full
            .fast
            .iter()
            .filter(|l| (l.line.freq_hz - f).abs() < 0.01)
        {
            let one = line_part(data, &l.line, &[l.channel]);
            part[l.channel].clone_from(&one[l.channel]);
        }
        effects.push((e, Some(part)));
    }
    effects.extend(described.into_iter().zip(parts));
    effects
}

/// A line on `chans` at the full rate, alone: its part of the model (no part elsewhere).
fn line_part(data: &Data, line: &Line, chans: &[usize]) -> Part {
    let n = data.full.len();
    let zero = Outputs {
        load_n: vec![0.0; n],
        volts: std::array::from_fn(|_| vec![0.0; n]),
    };
    let with = add_line(data, &zero, Some(line), chans);
    std::array::from_fn(|c| {
        if chans.contains(&c) {
            with.channel(c).to_vec()
        } else {
            Vec::new()
        }
    })
}
