//! The last step: the diagnosis of one recording put together from what the steps found,
//! OUT.json's content ([`Report`]) and the report's plots ([`PlotData`]).
use crate::candidate::Candidate;
use crate::mains::{self, Line};
use crate::outcome::{Diagnosis, PlotData};
use crate::output::{
    Baseline, EffectReport, Localisation, Numbers, Report, Undecided, Verdict, FORMAT,
};
use crate::params;
use crate::prepared::Prepared;
use crate::select::Selection;
use crate::steps::described::Model;
use crate::steps::full_rate::FullRate;
use crate::steps::residual::Localised;

/// What the steps found, in the order they found it.
pub(crate) struct Found<'f, 's, 'a> {
    /// The catalogue's selection, its choice as the described model left it.
    pub sel: &'f Selection<'s, 'a>,
    pub model: Model,
    pub local: Localised,
    pub full: FullRate,
    pub effects: Vec<EffectReport>,
    pub verdict: Verdict,
    pub undecided: Vec<Undecided>,
}

/// The diagnosis of `prepared` (called `name` in OUT.json) from what the steps `found`, with
/// the channels compared (`used`).
pub(crate) fn run(prepared: &Prepared, name: &str, used: [bool; 4], found: Found) -> Diagnosis {
    let Found {
        sel,
        model,
        local,
        full,
        effects,
        verdict,
        undecided,
    } = found;
    let (data, base) = (&prepared.data, sel.base());
    let report = Report {
        format: FORMAT,
        recording: name.to_string(),
        verdict,
        baseline: Baseline {
            params: baseline_params(base),
            rmse: full.baseline_rmse,
            parameters: params::baseline(base, data),
            simulation: prepared.simulation.clone(),
            sensor_unit: prepared.meta.get("sensor_unit").map(str::to_string),
        },
        mismatches: local.mismatches,
        effects,
        undecided,
        fit: full.fit,
        localisation: Localisation {
            channels: local.channels,
            lines: prominent_lines(full.baseline_line.as_ref()),
        },
        candidates: sel.reports(),
        seconds: 0.0,
    };
    let plots = PlotData {
        // At the fitting rate a mains line averages out over whole periods, so the improved
        // model plotted there is the slow model alone.
        improved: local.chosen,
        terms: model.described.curves,
        ..PlotData::of(data, local.baseline, &prepared.stretches, used)
    };
    Diagnosis {
        report,
        plots,
        at_stage: model.described.at_stage,
        discovered: model.described.discovered,
    }
}

/// The lines in the baseline's residual prominent enough to report.
fn prominent_lines(line: Option<&Line>) -> Vec<(f64, f64, f64)> {
    line.iter()
        .filter(|l| l.prominence > mains::MIN_LINE_PROMINENCE)
        .map(|l| (l.freq_hz, l.amplitude(), l.prominence))
        .collect()
}

fn baseline_params(base: &Candidate) -> Numbers {
    let mut n = Numbers::default();
    for (name, value) in params::baseline_values(base) {
        n.push(name, value);
    }
    n
}
