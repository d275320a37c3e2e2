//! The session page's words where the browser test's session has none: an angle law, a
//! contradicted sensitivity, something undecided, no leave-one-out row, markup in the data.

use super::html::report_html;
use super::output::*;
use super::SessionDiagnosis;
use crate::output::{EffectReport, Numbers, Stage, Undecided, Verdict};

fn angle_law() -> SharedEffect {
    let mut params = Numbers::default();
    params.push("ratio", 1.114);
    SharedEffect {
        effect: EffectReport {
            name: "angle_dependence".into(),
            stage: Stage::Transducer,
            channels: vec!["fz_V".into()],
            params,
            param_stderr: Numbers::default(),
            evidence: "one sensitivity of fz_V fits each test alone but none fits all".into(),
            catalogue: true,
            depends_on: None,
            form: None,
            inclusion: None,
            parameters: Vec::new(),
            evidence_values: None,
        },
        channel_param: Some("fz_V".into()),
        recordings: None,
    }
}

fn session() -> SessionDiagnosis {
    let report = SessionReport {
        format: FORMAT,
        verdict: Verdict::PartiallyExplained,
        summary: String::new(),
        recordings: vec![
            RecordingRow {
                file: "a.csv".into(),
                verdict: Some(Verdict::Explained),
                effects: Some(Vec::new()),
                fit: None,
                protocol: None,
                remains: None,
                error: None,
            },
            RecordingRow {
                file: "a<b>.csv".into(),
                verdict: None,
                effects: None,
                fit: None,
                protocol: None,
                remains: None,
                error: Some("a<b>.csv line 3: `x` is not a number".into()),
            },
        ],
        shared: vec![angle_law()],
        validation: Validation {
            leave_one_out: Vec::new(),
            note: Some("one recording: nothing to leave out".into()),
        },
        undecided: vec![Undecided {
            effects: vec!["gain_error".into()],
            calibration: vec!["scale_mx".into()],
            params: Numbers::default(),
            reason: "one azimuth cannot tell them apart.".into(),
        }],
        protocols: Protocols {
            contact_angles_deg: vec![10.0, 30.0],
            ..Protocols::default()
        },
        contradicted: vec![Contradiction {
            parameter: "scale_my".into(),
            values: vec![("a.csv".into(), 0.93), ("b.csv".into(), 1.08)],
            evidence: "the sensor or its mounting changed between tests".into(),
        }],
        candidates: Vec::new(),
        seconds: 1.5,
    };
    SessionDiagnosis {
        report,
        singles: vec![("a<b>.csv".into(), Err("not a recording".into()))],
        plots: vec![None],
    }
}

#[test]
fn the_page_says_in_words_what_the_json_holds() {
    let h = report_html(&session());
    assert!(h.contains("the sensitivity of Fz follows the contact angle unlike the model"));
    assert!(h.contains("Angle dependence of Fz.</b>"), "{h}");
    assert!(h.contains("is 1.11."), "the ratio");
    assert!(h.contains("0.930 in a.csv and 1.08 in b.csv: the sensor or its mounting"));
    assert!(h.contains(
        "Gain error or the calibration (scale_mx)</b>: one azimuth cannot tell them apart.</li>"
    ));
    assert!(h.contains("<p>one recording: nothing to leave out</p>"));
    assert!(h.contains("No recording could be left out"));
    assert!(h.contains("<td colspan=6 class=error>a&lt;b&gt;.csv line 3"));
    assert!(!h.contains("a<b>"), "data taken as markup");
    assert!(!h.contains("..") && !h.contains("<a ") && !h.contains("<script"));
    // No figure can be drawn: no bars without rows, no channels without a diagnosis.
    assert_eq!(h.matches("<svg").count(), 0);
}

/// A session of three recordings sharing a relaxation: `a.csv` and `b.csv` explained, `c.csv`
/// where the session's model still misses Fz in the hold, and a file that failed.
fn partial() -> SessionReport {
    use crate::localise::Mismatch;
    let fit = |before: f64, after: f64| crate::output::Fit {
        rmse_before: before,
        rmse_after: after,
        heldout: crate::output::Heldout {
            t_start_s: 90.0,
            t_end_s: 180.0,
            rmse_before: before,
            rmse_after: after,
        },
    };
    let row = |file: &str, verdict: Verdict, remains: Option<Remaining>| RecordingRow {
        file: file.into(),
        verdict: Some(verdict),
        effects: Some(Vec::new()),
        fit: Some(fit(0.02, 0.002)),
        protocol: None,
        remains,
        error: None,
    };
    let remains = Remaining {
        windows: vec![Mismatch {
            channel: "fz_V",
            t_start_s: 30.0,
            t_end_s: 42.0,
            regime: "hold",
            rms: 0.0012,
            share: 0.55,
        }],
        character: "a slow drift on Fz".into(),
        channels: vec!["Fz (RMS 1.2 mV, 0.8 % of its range): a slow drift.".into()],
    };
    let mut relaxation = angle_law();
    relaxation.effect.name = "viscoelastic_relaxation".into();
    relaxation.channel_param = None;
    let loo = |file: &str, before: f64, after: f64, change: Change| LeaveOneOut {
        file: file.into(),
        rmse_before: before,
        rmse_after: after,
        change,
    };
    SessionReport {
        format: FORMAT,
        verdict: Verdict::PartiallyExplained,
        summary: String::new(),
        recordings: vec![
            row("a.csv", Verdict::Explained, None),
            row("b.csv", Verdict::Explained, None),
            RecordingRow {
                file: "bad.csv".into(),
                verdict: None,
                effects: None,
                fit: None,
                protocol: None,
                remains: None,
                error: Some("day2/bad.csv line 3: `x` is not a number".into()),
            },
            row("c.csv", Verdict::PartiallyExplained, Some(remains)),
        ],
        shared: vec![relaxation],
        validation: Validation {
            leave_one_out: vec![
                loo("a.csv", 0.02, 0.002, Change::Better),
                loo("b.csv", 0.02, 0.002, Change::Better),
                loo("c.csv", 0.004, 0.003999, Change::NoChange),
            ],
            note: None,
        },
        undecided: Vec::new(),
        protocols: Protocols::default(),
        contradicted: Vec::new(),
        candidates: Vec::new(),
        seconds: 2.0,
    }
}

#[test]
fn the_headline_says_what_is_explained_what_is_not_and_which_file_failed() {
    let r = partial();
    let s = super::headline::sentence(&r);
    // The failure first: which file, and why.
    assert!(
        s.starts_with(
            "1 of 4 files could not be analysed (day2/bad.csv line 3: `x` is not a number); \
             the session is diagnosed from the other 3. "
        ),
        "{s}"
    );
    // The verdict as the JSON spells it, what acts, where the model leaves noise and where not.
    assert!(
        s.contains(
            "Session partially explained: viscoelastic relaxation is shared by all 3 recordings."
        ),
        "{s}"
    );
    assert!(
        s.contains(
            "What the session's model leaves is noise in a.csv and b.csv but not in c.csv, \
             where it still misses Fz during the hold at 30–42 s (RMS 1.20 mV, 55 % of what it \
             leaves); its residual shows a slow drift on Fz."
        ),
        "{s}"
    );
    // A change within the noise is no change.
    assert!(
        s.contains("2 of 3 held-out stretches fit better than with their own baseline, 1 fits the same within its noise"),
        "{s}"
    );
    // The page leads with the same words, the failure set apart and the box not green.
    let d = SessionDiagnosis {
        report: SessionReport {
            summary: s.clone(),
            ..r
        },
        singles: Vec::new(),
        plots: Vec::new(),
    };
    let h = report_html(&d);
    assert!(h.contains("<p id=verdict class='verdict partially_explained failed'><span class=failure>1 of 4 files could not be analysed (day2/bad.csv line 3: `x` is not a number); the session is diagnosed from the other 3.</span> Session partially explained"), "{h}");
    // The recordings' table says where c.csv is still missed.
    assert!(h.contains("partially explained<br><small class=remains>still misses Fz during the hold at 30–42 s</small>"), "{h}");
    assert!(h.contains("<td class=same>no change</td>"), "{h}");
}

#[test]
fn several_recordings_left_are_each_named_with_where_the_model_misses_most() {
    let mut r = partial();
    r.verdict = Verdict::Unexplained;
    for i in [0, 1] {
        r.recordings[i].verdict = Some(Verdict::Unexplained);
        r.recordings[i].remains = r.recordings[3].remains.clone();
    }
    let s = super::headline::sentence(&r);
    assert!(
        s.contains(
            "what the session's model leaves is not noise in a.csv (Fz during the hold at \
             30–42 s), b.csv (Fz during the hold at 30–42 s) and c.csv (Fz during the hold at \
             30–42 s)."
        ),
        "{s}"
    );
}

#[test]
fn an_explained_session_with_a_failed_file_does_not_read_as_all_well() {
    let mut r = partial();
    r.verdict = Verdict::Explained;
    r.recordings[3] = RecordingRow {
        verdict: Some(Verdict::Explained),
        remains: None,
        ..r.recordings[0].clone()
    };
    r.recordings[3].file = "c.csv".into();
    let s = super::headline::sentence(&r);
    assert!(
        s.starts_with("1 of 4 files could not be analysed (day2/bad.csv"),
        "{s}"
    );
    assert!(s.contains("Session explained: viscoelastic relaxation is shared by all 3 recordings; what the session's model leaves is noise in every recording."), "{s}");
    let h = report_html(&SessionDiagnosis {
        report: r,
        singles: Vec::new(),
        plots: Vec::new(),
    });
    assert!(h.contains("class='verdict explained failed'"), "{h}");
}

#[test]
fn an_angle_law_is_a_shared_effect_on_the_page_as_in_the_json() {
    let h = report_html(&session());
    let shared = &h[h.find("<h2 id=shared>").unwrap()..h.find("<h2 id=sensitivities>").unwrap()];
    assert!(!shared.contains("None"), "{shared}");
    assert!(
        shared.contains("<td>Angle dependence</td><td>transducer</td><td>fz_V</td>"),
        "{shared}"
    );
    assert!(shared.contains("<code>channel</code> = fz_V"), "{shared}");
}

#[test]
fn evidence_reads_in_shares_and_ratios_of_the_rms_misfit() {
    use super::search::Gain;
    let gain = |heldout: f64, before: f64| Gain {
        bic: 60_795.0,
        heldout,
        needed: 0.005 * before,
        before,
        reach: 1.0,
        across: false,
    };
    // Chi-square 7 650 000 -> 2 340: RMS 57 times lower; the margin half a percent of the
    // chi-square, a quarter of the RMS.
    let w = gain(7_647_660.0, 7_650_000.0).words("without it");
    assert_eq!(w, "BIC \u{2212}60\u{2009}795 vs without it, held-out RMS misfit 57 times lower (0.25 % counts)");
    let w = gain(0.36 * 1000.0, 1000.0).words("shared");
    assert!(
        w.ends_with("held-out RMS misfit 20 % lower (0.25 % counts)"),
        "{w}"
    );
    let w = gain(-0.44 * 1000.0, 1000.0).words("shared");
    assert!(
        w.ends_with("held-out RMS misfit 20 % higher (0.25 % counts)"),
        "{w}"
    );
    assert!(!w.contains("000"), "a chi-square sum in the words: {w}");
}

/// A session whose model shares no effect: the summary and the page say that nothing
/// transfers, and neither calls the leave-one-out evidence of transfer (`session-v1.md`, "What
/// transfers"). The same session sharing a relaxation says neither.
#[test]
fn a_session_that_shares_nothing_says_that_nothing_transfers() {
    let shares = partial();
    let mut none = partial();
    none.shared.clear();
    for (r, nothing) in [(shares, false), (none, true)] {
        let s = super::headline::sentence(&r);
        let d = SessionDiagnosis {
            report: SessionReport {
                summary: s.clone(),
                ..r
            },
            singles: Vec::new(),
            plots: Vec::new(),
        };
        let h = report_html(&d);
        let says = "these tests share no physics the others can predict";
        assert_eq!(s.contains(says), nothing, "{s}");
        assert_eq!(h.matches(says).count(), if nothing { 2 } else { 0 }, "{h}");
        assert_eq!(
            h.contains("evidence that the physics found transfers"),
            !nothing,
            "{h}"
        );
    }
}

/// The header names each protocol's distinct values, or where there are many their range:
/// never one value standing for several (a session at 14.7, 16.2 and 16.8 mm/min had read
/// "rod speeds 14.7 mm/min").
#[test]
fn the_header_shows_each_protocol_or_the_range() {
    let mut r = partial();
    r.protocols.rod_speeds_mm_per_min = vec![14.7, 16.2, 16.8];
    r.protocols.azimuths_deg = vec![0.0, 15.0, 30.0, 45.0, 60.0, 90.0];
    let d = SessionDiagnosis {
        report: r,
        singles: Vec::new(),
        plots: Vec::new(),
    };
    let h = report_html(&d);
    assert!(
        h.contains("azimuths 0–90°; rod speeds 14.7, 16.2, 16.8 mm/min"),
        "{h}"
    );
}
