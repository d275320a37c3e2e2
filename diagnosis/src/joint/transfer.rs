//! No shared effect that does not transfer (`session-v1.md`): a shared effect is physics the
//! recordings have in common, so with it a recording left out must be predicted at least as
//! well as by its own baseline. Where the leave-one-out predicts one worse, each shared effect is
//! tried per recording instead; the move that leaves fewest recordings predicted worse is kept,
//! until none is, or no move helps. An angle law is a per-recording scale, never shared, and
//! is not touched here (its left-out prediction extrapolates a sensitivity the baseline fits).

use super::distinct_kinds;
use super::loo::leave_one_out;
use super::output::{Change, Validation};
use super::search::Search;
use super::{Members, Outcome};

/// `outcome` and its leave-one-out `loo`, with the shared effects that do not transfer fitted
/// per recording.
pub(super) fn transferring(
    m: &Members,
    mut outcome: Outcome,
    mut loo: Validation,
) -> (Outcome, Validation) {
    let mut search = Search {
        setups: m.setups.clone(),
        tried: std::mem::take(&mut outcome.tried),
    };
    while worse(&loo) > 0 {
        let cur = &outcome.fitted;
        let best = distinct_kinds(cur.layout.shared.clone())
            .into_iter()
            .map(|k| {
                let f = search.fit(cur.layout.per_recording(k), cur);
                let v = leave_one_out(m, &f);
                (k, f, v)
            })
            .min_by_key(|(_, _, v)| worse(v));
        let Some((kind, f, v)) = best.filter(|(_, _, v)| worse(v) < worse(&loo)) else {
            break;
        };
        let reason = format!(
            "{} per recording: shared, it predicted {} of {} recordings left out worse than \
             their own baselines ({} with it per recording)",
            kind.name(),
            worse(&loo),
            loo.leave_one_out.len(),
            worse(&v)
        );
        search.record(&f, true, reason);
        outcome.gains.retain(|(k, _)| *k != kind);
        outcome.fitted = f;
        loo = v;
    }
    outcome.tried = search.tried;
    (outcome, loo)
}

/// How many recordings left out are predicted worse than by their own baselines.
fn worse(v: &Validation) -> usize {
    v.leave_one_out
        .iter()
        .filter(|r| r.change == Change::Worse)
        .count()
}
