//! The other stretch held out: when nothing fitted to the start of the recording explains what
//! its end shows (`unexplained`), the physics may act only in the end (a connector knocked
//! late, a channel that freezes in the last cycle). The stretches are swapped, the end fitted
//! and the start held out, and that diagnosis is kept when it finds what acts: it passed the
//! same two tests, on the other stretch.
use crate::output::Verdict;
use crate::prepared::Prepared;
use crate::steps::{Pass, Rerun};

/// `first`, or the diagnosis with the start of the recording held out where `first` is
/// unexplained and that one finds effects. The recording keeps its stretches swapped either way.
pub(crate) fn run(prepared: &mut Prepared, first: Pass, once: &Rerun) -> Pass {
    if first.0.report.verdict != Verdict::Unexplained {
        return first;
    }
    prepared.stretches.swap(&prepared.data.fit.t_s);
    let swapped = once(prepared);
    if swapped.0.report.effects.is_empty() {
        first
    } else {
        swapped
    }
}
