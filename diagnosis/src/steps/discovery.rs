//! The discovery step's gate and its joint fit: the catalogue refitted without what the
//! discovery step found until the two agree ([`with_discovery_refitted`]), and the diagnosis
//! without the discovery step where its terms do not predict the held-out stretch
//! ([`without_unsupported_discovery`]). Each runs the diagnosis again (`once`) on the recording
//! as it leaves it.
use crate::outcome::Diagnosis;
use crate::output::EffectReport;
use crate::prepared::Prepared;
use crate::steps::Rerun;

/// `d`, or where its discovered terms leave the held-out stretch predicted worse than by the
/// baseline (the contract's RMSE, at the full rate: the terms passed their test on the fitting
/// series' blocks), the diagnosis without the discovery step. Only what the held-out stretch
/// supports is reported.
pub(crate) fn without_unsupported_discovery(
    prepared: &mut Prepared,
    d: Diagnosis,
    once: &Rerun,
) -> Diagnosis {
    let held = &d.report.fit.heldout;
    let discovered = d.report.effects.iter().any(|e| e.is_discovered());
    if !discovered || held.rmse_after <= held.rmse_before {
        return d;
    }
    prepared.discovered = None;
    prepared.without_discovery = true;
    once(prepared).0
}

/// Refits of the catalogue without what the discovery step found before it is taken as found.
const MAX_DISCOVERY_REFITS: usize = 2;

/// `d` again with the catalogue fitted without its discovered terms, until the terms found
/// again are the ones it was fitted without (the same channels and features), or as first
/// found when the refit loses them. The calibration fitted to the whole recording had bent
/// towards what the model lacked: a discovered term fitted beside it takes up the bend too
/// (a softening in time came with a function of the travel), and the refit removes it. It
/// is the universal differential equation's joint fit, done by alternation: the model with
/// the unknown block fitted, then the block on what the model leaves.
pub(crate) fn with_discovery_refitted(
    prepared: &mut Prepared,
    mut d: Diagnosis,
    once: &Rerun,
) -> Diagnosis {
    for _ in 0..MAX_DISCOVERY_REFITS {
        let Some(parts) = d.discovered.clone() else {
            break;
        };
        let before = discovered_names(&d.report.effects);
        prepared.discovered = Some(parts);
        let (again, _) = once(prepared);
        let after = discovered_names(&again.report.effects);
        // The refit is kept only where it still discovers and predicts the held-out stretch
        // no worse: an alternation that wandered (a calibration bent around a wrong term) is
        // not a better joint fit.
        let held = |d: &Diagnosis| d.report.fit.heldout.rmse_after;
        if after.is_empty() || held(&again) > held(&d) {
            break;
        }
        d = with_baseline_of(again, &d);
        if after == before {
            break;
        }
    }
    prepared.discovered = None;
    d
}

/// `again` with the baseline of `first`: the baseline is the one calibrated to the recording
/// itself (the contract's `rmse_before`, where it misses and its page), not the one fitted
/// without the discovered terms.
fn with_baseline_of(mut again: Diagnosis, first: &Diagnosis) -> Diagnosis {
    let (r, f) = (&mut again.report, &first.report);
    r.baseline = f.baseline.clone();
    r.mismatches = f.mismatches.clone();
    r.localisation = f.localisation.clone();
    r.fit.rmse_before = f.fit.rmse_before;
    r.fit.heldout.rmse_before = f.fit.heldout.rmse_before;
    again.plots.baseline = first.plots.baseline.clone();
    again
}

/// The names and channels of the discovered effects of a report, sorted.
fn discovered_names(effects: &[EffectReport]) -> Vec<(String, Vec<String>)> {
    let mut v: Vec<(String, Vec<String>)> = effects
        .iter()
        .filter(|e| e.inclusion.is_some())
        .map(|e| (e.name.clone(), e.channels.clone()))
        .collect();
    v.sort();
    v
}
