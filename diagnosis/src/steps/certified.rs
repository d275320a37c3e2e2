//! The certification of what the answer reports (`crate::certify`: the contract's rules, the
//! held-out test and the false-discovery control), with the verdict of what is left.
use crate::certify;
use crate::data::Data;
use crate::output::{EffectReport, Undecided, Verdict};
use crate::steps::effects::Found;
use crate::steps::full_rate::FullRate;
use crate::steps::verdict;

/// The effects that pass the certification, the verdict, and what went to `undecided`. Where
/// an effect went, the fit is the model's without it, and the verdict is no `explained` by an
/// effect the answer no longer reports.
pub(crate) fn run(
    data: &Data,
    full: &mut FullRate,
    found: Vec<Found>,
    white_after: bool,
) -> (Vec<EffectReport>, Verdict, Vec<Undecided>) {
    let certified = certify::certify(data, full.masks(), &full.model, found);
    let effects = certified.effects;
    let mut verdict = verdict::run(!effects.is_empty(), white_after, full.fit.rmse_before);
    if certified.demoted {
        full.refit(data, &certified.model);
        if verdict == Verdict::Explained {
            verdict = Verdict::PartiallyExplained;
        }
        if effects.is_empty() {
            verdict = Verdict::Unexplained;
        }
    }
    (effects, verdict, certified.undecided)
}
