//! What the data leaves open, said rather than guessed: a turn of the moment scales that
//! crosstalk or the gains would explain alike, gains far off the metadata, and catalogue
//! effects the held-out stretch cannot test.
use sim::effects::EffectKind;

use crate::candidate::{Comparison, MIN_BIC_GAIN};
use crate::fit::Setup;
use crate::output::{EffectReport, Numbers, ParamDetail, Undecided, Verdict};
use crate::select::Selection;
use crate::{params, terms, undecided};

/// The undecided findings of the chosen model (`sel`) with its `effects` and `verdict`, after
/// those the certification sent here (`demoted`); the held-out stretch `heldout` (start, end,
/// s) and the baseline's moment direction `moment_phi` as the protocol step found them.
pub(crate) fn run(
    setup: &Setup,
    sel: &Selection,
    (effects, demoted): (&[EffectReport], Vec<Undecided>),
    verdict: Verdict,
    (heldout, moment_phi): ((f64, f64), Option<f64>),
) -> Vec<Undecided> {
    let details = params::baseline(sel.chosen(), setup.data);
    let mut undecided = undecided_findings(setup, effects, &details, moment_phi);
    undecided.extend(demoted);
    // A structured residual that nothing named explains, and an effect the held-out stretch
    // cannot test would: said, not guessed.
    if effects.is_empty() && verdict != Verdict::NoSignificantMismatch {
        undecided.extend(untestable_findings(sel, heldout));
    }
    undecided
}

/// What the data leaves open: a turn of the moment scales that crosstalk or the gains would
/// explain alike, and gains far off the metadata.
fn undecided_findings(
    setup: &Setup,
    effects: &[EffectReport],
    details: &[ParamDetail],
    moment_phi: Option<f64>,
) -> Vec<Undecided> {
    // A moment read with its sign inverted turns the calibrated moment vector as a rotated
    // chip would; it is found as such, so the turn is not also left undecided.
    let inverted = effects.iter().any(|e| e.name == "inverted_sign");
    let ambiguous = moment_phi
        .filter(|_| setup.used[2] && setup.used[3] && !named(effects, EffectKind::Crosstalk))
        .filter(|_| !inverted)
        .and_then(|phi| undecided::crosstalk_or_gains(details, phi, &setup.fit_bounds));
    // Against a user's simulation an output's scale calibrates the simulation's outputs, which
    // may be off by any factor (its own gains, a sensitivity it assumed): no finding of gains.
    // Nor in another unit than the metadata's volts (`sensor_unit`): a magnetometer's µT have no
    // gain in the metadata to be off from.
    let gains = terms::sanity::gains_off(details)
        .filter(|_| !setup.user_simulation && setup.outputs_in_volts());
    ambiguous.into_iter().chain(gains).collect()
}

/// The catalogue effects that the criterion keeps on the fitting stretch, alone against the
/// baseline, but that the held-out stretch cannot test (`Comparison::untestable`): were one
/// the truth, its held-out gain would not count. Each with its candidate's index and that
/// comparison; the chosen model's own effects are not among them.
pub(crate) fn untestable(sel: &Selection) -> Vec<(usize, Comparison)> {
    let chosen = &sel.chosen().kinds;
    (0..sel.all.len())
        .filter(|&i| sel.all[i].kinds.len() == 1 && !chosen.contains(&sel.all[i].kinds[0]))
        .filter(|&i| sel.admissible_alone(i))
        .map(|i| (i, sel.all[i].compare(sel.base())))
        .filter(|(_, cmp)| cmp.untestable())
        .collect()
}

/// Each [`untestable`] effect, undecided: what the fitting stretch says of it and why the
/// held-out stretch cannot, and which recording would decide.
///
/// Only the effects the criterion cannot tell from the best of them (within `MIN_BIC_GAIN`):
/// the fitting stretch decides between them, though not whether the best is there.
fn untestable_findings(sel: &Selection, heldout: (f64, f64)) -> Vec<Undecided> {
    let all = untestable(sel);
    let best = all
        .iter()
        .map(|&(i, _)| sel.all[i].bic)
        .fold(f64::INFINITY, f64::min);
    all.into_iter()
        .filter(|&(i, _)| sel.all[i].bic <= best + MIN_BIC_GAIN)
        .map(|(i, cmp)| {
            let c = &sel.all[i];
            let kind = c.kinds[0];
            let mut params = Numbers::default();
            for (_, details) in params::effects(c, sel.base().model.setup.data) {
                for p in details {
                    params.push(&p.name, p.value);
                }
            }
            Undecided {
                effects: vec![kind.name().into()],
                calibration: Vec::new(),
                params,
                reason: format!(
                    "{} fits the fitting stretch (BIC {:.0} below the baseline's), but the held-out stretch ({:.1}-{:.1} s) cannot test it: were it the truth, it would lower the held-out misfit there by {:.1} (noise units), and the test needs more than {:.1}. A recording that shows its signature again after the stretch it is fitted on (another press and release) would decide",
                    kind.name(),
                    cmp.bic_gain,
                    heldout.0,
                    heldout.1,
                    cmp.heldout_reach,
                    cmp.heldout_needed
                ),
            }
        })
        .collect()
}

/// Whether `effects` names `kind`.
fn named(effects: &[EffectReport], kind: EffectKind) -> bool {
    effects.iter().any(|e| e.name == kind.name())
}
