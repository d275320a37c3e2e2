//! A channel found frozen (`stuck_channel`) reads nothing of the sensor from then on: the
//! catalogue is fitted again without those samples (`Data::frozen_from`), so that its effects
//! are chosen on what the sensor did, and that diagnosis is kept when it finds the freeze it
//! was fitted without (a frozen Fz had the catalogue bend a lag, a power of the rod speed and
//! a relaxation at the transducer to follow it).
use crate::data::Data;
use crate::outcome::Diagnosis;
use crate::prepared::Prepared;
use crate::steps::Rerun;
use crate::terms;

/// Refits without a frozen channel's samples before the freeze found is taken as it was first
/// found: each moves the freeze towards where the channel's own calibration puts it.
const MAX_FREEZE_REFITS: usize = 3;

/// Whether `b` finds the freezes `a` found: the same channels, each from the same time to
/// within two samples of the fitting series (a freeze found elsewhere once the catalogue no
/// longer follows it is not the one the refit was for).
fn same_freeze(data: &Data, a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
    let t = &data.fit.t_s;
    let step_s = (t[t.len() - 1] - t[0]) / (t.len().max(2) - 1) as f64;
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 2.0 * step_s)
}

/// The channels `terms` found frozen, each with the time it froze.
pub(crate) fn frozen_channels(terms: &[terms::Term]) -> Vec<(usize, f64)> {
    terms
        .iter()
        .filter(|t| t.kind == terms::TermKind::StuckChannel)
        .map(|t| (t.channel, t.shape[0]))
        .collect()
}

/// `d`, or where it found channels `frozen`, the diagnosis fitted without what they read after
/// they froze: fitted so, the model follows the channel's own calibration, and the freeze may
/// show where it began. Refitted until the freeze it finds is the one it was fitted without (a
/// fixed point), or kept as first found.
pub(crate) fn refitted(
    prepared: &mut Prepared,
    mut d: Diagnosis,
    mut frozen: Vec<(usize, f64)>,
    once: &Rerun,
) -> Diagnosis {
    for _ in 0..MAX_FREEZE_REFITS {
        if frozen.is_empty() {
            break;
        }
        prepared.frozen.clone_from(&frozen);
        let (again, still) = once(prepared);
        if same_freeze(&prepared.data, &frozen, &still) {
            d = again;
            break;
        }
        frozen = still;
    }
    d
}
