//! No shared effect that does not transfer (`session-v1.md`): a shared effect is physics the
//! recordings have in common, so with it a recording left out must be predicted at least as
//! well as by its own baseline. Where the leave-one-out predicts one worse, the shared effect to
//! blame is the one without which fewest recordings are predicted worse (fewer than with it); it
//! is fitted per recording instead, until no recording is predicted worse or none is to blame.
//! An angle law is a per-recording scale, never shared, and is not touched here (its left-out
//! prediction extrapolates a sensitivity the baseline fits).

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
        // The shared effect to blame: the one without which the session predicts fewest
        // recordings worse. A left-out recording that is predicted worse without it too is
        // not its doing (its own calibration's, or another effect's), and it stays shared.
        let blamed = distinct_kinds(cur.layout.shared.clone())
            .into_iter()
            .map(|k| {
                let mut layout = cur.layout.clone();
                layout.shared.retain(|&s| s != k);
                (k, worse(&leave_one_out(m, &search.fit(layout, cur))))
            })
            .filter(|&(_, w)| w < worse(&loo))
            .min_by_key(|&(_, w)| w);
        let Some((kind, _)) = blamed else {
            break;
        };
        let f = search.fit(cur.layout.per_recording(kind), cur);
        let v = leave_one_out(m, &f);
        let reason = format!(
            "{} per recording: shared, it predicted {} of {} recordings left out worse than \
             their own baselines ({} without it)",
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
