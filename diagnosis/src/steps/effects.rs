//! The effects a diagnosis reports, gathered from the steps that found them.
use crate::data::Data;
use crate::evidence;
use crate::output::EffectReport;
use crate::select::Selection;
use crate::steps::full_rate::FullRate;
use crate::terms;

/// The effects to report: the chosen catalogue effects, the mains lines on the outputs and on
/// the load cell, and what was described beyond the catalogue.
pub(crate) fn run(
    sel: &Selection,
    full: &FullRate,
    described: Vec<EffectReport>,
    data: &Data,
) -> Vec<EffectReport> {
    let mut effects = evidence::effect_reports(sel, data);
    effects.extend(
        full.mains
            .as_ref()
            .map(|line| evidence::mains_report(line, data)),
    );
    effects.extend(
        full.load_mains
            .as_ref()
            .map(|line| evidence::load_mains_report(line, data)),
    );
    effects.extend(terms::report::fast_lines(&full.fast));
    effects.extend(described);
    effects
}
