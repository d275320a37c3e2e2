//! A session's verdicts (`docs/session-format.md`): each recording's from what the session's
//! model leaves in it, with the rule `tactile-diagnosis/1` gives one recording, and the
//! session's from its recordings'.
//!
//! A recording's own diagnosis is not the session's: it fitted its own effects, which the
//! session may have replaced by shared ones, or by none. Its verdict is therefore read again on
//! the session's model: `explained` when an effect of the session acts on it and the session's
//! model leaves noise there, whatever it said alone (a recording whose own diagnosis was only
//! part of the story had kept `partially_explained` while the session explained it, its row
//! naming nothing left).

use super::output::RecordingRow;
use crate::output::Verdict;

/// A recording's verdict under the session's model. `named`: an effect of the session acts on
/// it (its own, or a shared one); `white`: what the session's model leaves on every compared
/// channel is noise ([`crate::misfit::white`]); `lowered`: the model's held-out misfit is
/// below that of the baseline calibrated to the recording alone.
pub(crate) fn recording(named: bool, white: bool, lowered: bool) -> Verdict {
    match (named, white) {
        (false, true) => Verdict::NoSignificantMismatch,
        (true, true) => Verdict::Explained,
        (true, false) if lowered => Verdict::PartiallyExplained,
        _ => Verdict::Unexplained,
    }
}

/// The session's verdict from its analysed recordings': quiet when every one is quiet (then
/// nothing acts on any); explained when what the session's model leaves is noise in every one;
/// unexplained when it explains none, not even in part; else partially explained.
pub(crate) fn session(rows: &[RecordingRow]) -> Verdict {
    let verdicts: Vec<Verdict> = rows.iter().filter_map(|r| r.verdict).collect();
    let all = |f: &dyn Fn(Verdict) -> bool| verdicts.iter().all(|&v| f(v));
    if all(&|v| v == Verdict::NoSignificantMismatch) {
        Verdict::NoSignificantMismatch
    } else if all(&|v| matches!(v, Verdict::Explained | Verdict::NoSignificantMismatch)) {
        Verdict::Explained
    } else if all(&|v| matches!(v, Verdict::Unexplained | Verdict::NoSignificantMismatch)) {
        Verdict::Unexplained
    } else {
        Verdict::PartiallyExplained
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(v: Verdict) -> RecordingRow {
        RecordingRow {
            file: "r.csv".into(),
            verdict: Some(v),
            effects: Some(Vec::new()),
            fit: None,
            protocol: None,
            remains: None,
            error: None,
        }
    }

    #[test]
    fn a_recording_is_read_on_the_sessions_model() {
        // What a recording said alone does not enter: a shared effect that leaves noise
        // explains it.
        assert_eq!(recording(true, true, false), Verdict::Explained);
        assert_eq!(recording(true, false, true), Verdict::PartiallyExplained);
        assert_eq!(recording(true, false, false), Verdict::Unexplained);
        assert_eq!(
            recording(false, true, false),
            Verdict::NoSignificantMismatch
        );
        assert_eq!(recording(false, false, true), Verdict::Unexplained);
    }

    #[test]
    fn the_session_is_explained_only_where_every_recording_is() {
        use Verdict::*;
        let of = |v: &[Verdict]| session(&v.iter().map(|&v| row(v)).collect::<Vec<_>>());
        assert_eq!(of(&[NoSignificantMismatch; 3]), NoSignificantMismatch);
        assert_eq!(
            of(&[Explained, NoSignificantMismatch, Explained]),
            Explained
        );
        assert_eq!(
            of(&[Explained, PartiallyExplained, Explained]),
            PartiallyExplained
        );
        assert_eq!(of(&[Explained, Unexplained]), PartiallyExplained);
        assert_eq!(of(&[Unexplained, NoSignificantMismatch]), Unexplained);
        // A failed file's row has no verdict and does not count.
        let mut rows = vec![row(Explained)];
        rows.push(RecordingRow {
            verdict: None,
            effects: None,
            error: Some("bad.csv: not a recording".into()),
            ..row(Explained)
        });
        assert_eq!(session(&rows), Explained);
    }
}
