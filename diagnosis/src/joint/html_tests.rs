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
        },
        channel_param: Some("fz_V".into()),
        recordings: None,
    }
}

fn session() -> SessionDiagnosis {
    let report = SessionReport {
        format: FORMAT,
        verdict: Verdict::PartiallyExplained,
        recordings: vec![RecordingRow {
            file: "a<b>.csv".into(),
            verdict: None,
            effects: None,
            fit: None,
            protocol: None,
            error: Some("a<b>.csv line 3: `x` is not a number".into()),
        }],
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
    assert!(h.contains("no recording could be left out"));
    assert!(h.contains("<td colspan=6 class=error>a&lt;b&gt;.csv line 3"));
    assert!(!h.contains("a<b>"), "data taken as markup");
    assert!(!h.contains("..") && !h.contains("<a ") && !h.contains("<script"));
    // No figure can be drawn: no bars without rows, no channels without a diagnosis.
    assert_eq!(h.matches("<svg").count(), 0);
}
