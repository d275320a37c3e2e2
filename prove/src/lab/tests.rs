//! The lab category's designs and judge, without the FE or the diagnosis.

use serde_json::json;
use sim::effects::{Effect, EffectKind};

use super::design::{draw, Family, LabKind, Own, SessionDesign, TestDesign};
use super::score::{contract_gaps, judge, Truth};

fn designs(seed: u64, kind: LabKind, n: usize) -> Vec<SessionDesign> {
    (0..n)
        .map(|j| draw(seed, 500.0, 100 + j, kind, j))
        .collect()
}

/// What a test's settings are, without what is set anew for every test (the jig's mounting
/// error, the noise's seed) and its own effect.
fn settings(t: &TestDesign) -> TestDesign {
    TestDesign {
        azimuth_shift_deg: 0.0,
        seed: 0,
        own: None,
        ..t.clone()
    }
}

/// The settings in which tests `a` and `b` differ, by name.
fn differ(a: &TestDesign, b: &TestDesign) -> Vec<&'static str> {
    let mut d = Vec::new();
    let (a, b) = (settings(a), settings(b));
    if a.contact_angle_deg != b.contact_angle_deg {
        d.push("angle");
    }
    if a.azimuth_deg != b.azimuth_deg {
        d.push("azimuth");
    }
    if a.speed_mm_per_min != b.speed_mm_per_min {
        d.push("speed");
    }
    if a.sample_rate_hz != b.sample_rate_hz {
        d.push("rate");
    }
    if a.gain_factor != b.gain_factor {
        d.push("gains");
    }
    if a.excitation_factor != b.excitation_factor {
        d.push("excitation");
    }
    if a.peaks_n != b.peaks_n {
        d.push("peaks");
    }
    d
}

/// Every pair of a session's tests differs in exactly `allowed` (or a subset, for repeats).
fn only_differ_in(d: &SessionDesign, allowed: &[&str]) {
    for (i, a) in d.tests.iter().enumerate() {
        for b in &d.tests[i + 1..] {
            let diff = differ(a, b);
            assert!(!diff.is_empty(), "session {}: two tests alike", d.id);
            assert!(
                diff.iter().all(|x| allowed.contains(x)),
                "session {} ({:?}): tests differ in {diff:?}, allowed {allowed:?}",
                d.id,
                d.kind
            );
        }
    }
}

fn kinds(effects: &[Effect]) -> Vec<EffectKind> {
    let mut k: Vec<EffectKind> = effects.iter().map(Effect::kind).collect();
    k.sort();
    k
}

#[test]
fn a_design_is_the_same_for_the_same_seed_and_another_for_another() {
    for kind in LabKind::ALL {
        for j in 0..4 {
            let a = draw(7, 500.0, 3, kind, j);
            assert_eq!(a, draw(7, 500.0, 3, kind, j));
            assert_ne!(a, draw(8, 500.0, 3, kind, j), "{kind:?} {j}");
            assert_ne!(
                a,
                draw(7, 500.0, 4, kind, j),
                "{kind:?} {j}: the id seeds it"
            );
        }
    }
}

#[test]
fn mixed_sessions_share_two_effects_and_one_test_has_its_own() {
    let all = designs(11, LabKind::Mixed, 12);
    for d in &all {
        assert_eq!(d.tests.len(), 4);
        assert_eq!(d.shared.len(), 2, "session {}", d.id);
        assert_ne!(d.shared[0].kind(), d.shared[1].kind());
        let own: Vec<&TestDesign> = d.tests.iter().filter(|t| t.own.is_some()).collect();
        assert_eq!(
            own.len(),
            1,
            "session {}: one test with its own effect",
            d.id
        );
        // A drift never sits under an AC coupling.
        let coupled = d
            .shared
            .iter()
            .any(|e| e.kind() == EffectKind::HighpassCoupling);
        assert!(!(coupled && matches!(own[0].own, Some(Own::Drift(_)))));
        only_differ_in(d, &["angle", "azimuth", "speed"]);
        // One setting steps; the others are the session's.
        let varied = ["angle", "azimuth", "speed"]
            .iter()
            .filter(|s| differ(&d.tests[0], &d.tests[3]).contains(s))
            .count();
        assert_eq!(varied, 1, "session {}", d.id);
    }
    // Every own kind, every shared pair's effects, both fingertips occur.
    let owns: Vec<EffectKind> = all
        .iter()
        .flat_map(|d| d.tests.iter().filter_map(|t| t.own.map(Own::kind)))
        .collect();
    for k in [
        EffectKind::ThermalDrift,
        EffectKind::MainsInterference,
        EffectKind::AmplifierSaturation,
    ] {
        assert!(owns.contains(&k), "{}", k.name());
    }
    assert!(all.iter().any(|d| d.family == Family::Ours));
    assert!(all.iter().any(|d| d.family != Family::Ours));
}

#[test]
fn null_sessions_hide_nothing_on_another_models_fingertip() {
    for d in designs(12, LabKind::NullOther, 6) {
        assert!(d.shared.is_empty());
        assert!(d.tests.iter().all(|t| t.own.is_none()));
        assert!(matches!(d.family, Family::Other { .. }));
        assert!((3..=4).contains(&d.tests.len()));
        only_differ_in(&d, &["angle", "azimuth", "speed"]);
    }
}

#[test]
fn friction_is_pressed_inclined_at_speeds_a_decade_apart() {
    for d in designs(13, LabKind::FrictionSpeeds, 4) {
        assert_eq!(kinds(&d.shared), [EffectKind::ContactFriction]);
        let speeds: Vec<f64> = d.tests.iter().map(|t| t.speed_mm_per_min).collect();
        assert_eq!(speeds, [6.0, 20.0, 60.0]);
        assert!(d.tests.iter().all(|t| t.contact_angle_deg >= 20.0));
        assert!(d.tests.iter().all(|t| t.own.is_none()));
        only_differ_in(&d, &["speed"]);
    }
}

#[test]
fn hysteresis_or_relaxation_hides_one_of_the_two_across_speeds() {
    let all = designs(14, LabKind::HysteresisOrRelaxation, 4);
    for d in &all {
        assert_eq!(d.shared.len(), 1);
        assert!(d.tests.iter().all(|t| t.own.is_none()));
        only_differ_in(d, &["speed"]);
    }
    let hidden: Vec<EffectKind> = all.iter().map(|d| d.shared[0].kind()).collect();
    assert!(hidden.contains(&EffectKind::Hysteresis));
    assert!(hidden.contains(&EffectKind::ViscoelasticRelaxation));
    // Each effect on both fingertips within four sessions.
    for k in [EffectKind::Hysteresis, EffectKind::ViscoelasticRelaxation] {
        let families: Vec<bool> = all
            .iter()
            .filter(|d| d.shared[0].kind() == k)
            .map(|d| d.family == Family::Ours)
            .collect();
        assert!(
            families.contains(&true) && families.contains(&false),
            "{}",
            k.name()
        );
    }
}

#[test]
fn rates_and_gains_differ_between_tests_and_nothing_else_but_azimuth() {
    for d in designs(15, LabKind::RatesAndGains, 4) {
        assert!(d.shared.len() <= 1);
        let rates: Vec<f64> = d.tests.iter().map(|t| t.sample_rate_hz).collect();
        assert_eq!(rates, [500.0, 250.0, 1000.0]);
        only_differ_in(&d, &["azimuth", "rate", "gains", "excitation"]);
    }
}

#[test]
fn mains_is_not_hidden_where_the_rate_cannot_show_it() {
    for j in 0..12 {
        let d = draw(16, 100.0, j, LabKind::Mixed, j);
        assert!(d
            .tests
            .iter()
            .all(|t| !matches!(t.own, Some(Own::Mains(_)))));
    }
}

fn effect(kind: EffectKind, p: &[f64]) -> Effect {
    kind.with_params(p)
}

fn truth() -> Truth {
    Truth {
        shared: vec![
            effect(EffectKind::Crosstalk, &[10.0]),
            effect(EffectKind::ViscoelasticRelaxation, &[5.0, 0.2]),
        ],
        own: vec![
            ("a.csv".into(), vec![]),
            (
                "b.csv".into(),
                vec![effect(EffectKind::ThermalDrift, &[0.05, 40.0])],
            ),
            ("c.csv".into(), vec![]),
        ],
    }
}

fn row(file: &str, effects: serde_json::Value) -> serde_json::Value {
    json!({ "file": file, "verdict": "explained", "effects": effects })
}

fn report(shared: serde_json::Value, b_effects: serde_json::Value) -> serde_json::Value {
    json!({
        "format": "tactile-session-diagnosis/1",
        "verdict": "explained",
        "recordings": [row("a.csv", json!([])), row("b.csv", b_effects), row("c.csv", json!([]))],
        "shared": shared,
        "validation": { "leave_one_out": [
            { "file": "a.csv", "rmse_before": 0.1, "rmse_after": 0.05 },
            { "file": "b.csv", "rmse_before": 0.1, "rmse_after": 0.03 } ] },
        "undecided": [],
        "contradicted": []
    })
}

fn right_shared() -> serde_json::Value {
    json!([
        { "name": "crosstalk", "params": { "angle_deg": 10.5 } },
        { "name": "viscoelastic_relaxation", "params": { "tau_s": 5.5, "fraction": 0.2 },
          "recordings": ["c.csv", "a.csv", "b.csv"] }
    ])
}

fn drift(amplitude: f64) -> serde_json::Value {
    json!([{ "name": "thermal_drift", "params": { "amplitude_V": amplitude, "tau_s": 40.0 } }])
}

#[test]
fn the_judge_wants_each_name_in_its_place_and_nothing_else() {
    let j = judge(
        LabKind::Mixed,
        &truth(),
        &report(right_shared(), drift(0.052)),
    );
    assert!(j.right, "{j:?}");
    assert_eq!(j.recordings_right, 3);
    assert!(j.false_alarms.is_empty());
    assert_eq!(j.params_within(0.2), 3);
    assert!((j.loo_ratio.unwrap() - 0.4).abs() < 1e-12);
    assert!(j.contract_gaps.is_empty(), "{:?}", j.contract_gaps);

    // The own effect shared instead: wrong, no false alarm (it was hidden).
    let mut shared = right_shared();
    shared
        .as_array_mut()
        .unwrap()
        .push(json!({ "name": "thermal_drift", "params": { "amplitude_V": 0.05, "tau_s": 40.0 } }));
    let j = judge(LabKind::Mixed, &truth(), &report(shared, json!([])));
    assert!(!j.right && j.false_alarms.is_empty());
    assert_eq!(j.recordings_right, 0);

    // A shared effect over only some recordings: wrong there.
    let partial = json!([
        { "name": "crosstalk", "params": { "angle_deg": 10.0 }, "recordings": ["a.csv", "b.csv"] },
        { "name": "viscoelastic_relaxation", "params": { "tau_s": 5.0, "fraction": 0.2 } }
    ]);
    let j = judge(LabKind::Mixed, &truth(), &report(partial, drift(0.05)));
    assert!(!j.right);
    assert_eq!(j.recordings_right, 2);

    // A described term beside the drift: a false alarm.
    let more = json!([
        { "name": "thermal_drift", "params": { "amplitude_V": 0.05, "tau_s": 40.0 } },
        { "name": "offset_step", "catalogue": false, "params": {} }
    ]);
    let j = judge(LabKind::Mixed, &truth(), &report(right_shared(), more));
    assert!(!j.right);
    assert_eq!(j.false_alarms, ["offset_step@b.csv"]);
    assert_eq!(j.recordings_right, 2);
}

#[test]
fn on_a_null_session_any_name_is_a_false_alarm_and_an_error_is_wrong() {
    let null = Truth {
        shared: vec![],
        own: ["a.csv", "b.csv", "c.csv"]
            .map(|f| (f.to_string(), vec![]))
            .to_vec(),
    };
    let quiet = report(json!([]), json!([]));
    let j = judge(LabKind::NullOther, &null, &quiet);
    assert!(j.right && j.false_alarms.is_empty() && j.param_errors.is_empty());
    let loud = report(
        json!([{ "name": "crosstalk", "params": { "angle_deg": 2.0 } }]),
        json!([]),
    );
    let j = judge(LabKind::NullOther, &null, &loud);
    assert!(!j.right);
    assert_eq!(j.false_alarms, ["crosstalk@shared"]);
    let mut failed = quiet.clone();
    failed["recordings"][1] = json!({ "file": "b.csv", "error": "b.csv line 3: bad" });
    let j = judge(LabKind::NullOther, &null, &failed);
    assert!(!j.right);
    assert_eq!(j.recordings_right, 2);
    assert!(!judge(LabKind::NullOther, &null, &serde_json::Value::Null).right);
}

#[test]
fn friction_is_right_only_with_mu_within_20_percent() {
    let t = Truth {
        shared: vec![effect(EffectKind::ContactFriction, &[0.1])],
        own: ["a.csv", "b.csv", "c.csv"]
            .map(|f| (f.to_string(), vec![]))
            .to_vec(),
    };
    let with = |mu: f64| {
        report(
            json!([{ "name": "contact_friction", "params": { "mu": mu } }]),
            json!([]),
        )
    };
    assert!(judge(LabKind::FrictionSpeeds, &t, &with(0.115)).right);
    assert!(!judge(LabKind::FrictionSpeeds, &t, &with(0.125)).right);
    // Elsewhere the parameter is a figure, not part of right.
    assert!(judge(LabKind::HysteresisOrRelaxation, &t, &with(0.125)).right);
}

#[test]
fn a_report_without_a_key_the_contract_requires_is_named_for_it() {
    let mut r = report(json!([]), json!([]));
    assert!(contract_gaps(&r).is_empty());
    r.as_object_mut().unwrap().remove("contradicted");
    r["format"] = json!("tactile-diagnosis/1");
    r["validation"] = json!({});
    assert_eq!(
        contract_gaps(&r),
        ["format", "contradicted", "validation.leave_one_out"]
    );
    assert!(contract_gaps(&serde_json::Value::Null).len() >= 6);
}

#[test]
fn the_table_counts_per_kind_and_states_the_bar() {
    let score = |kind: LabKind, report: serde_json::Value| super::LabScore {
        id: 0,
        kind,
        judgement: judge(kind, &truth(), &report),
        report: Some(report),
        failure: None,
        seconds: 10.0,
    };
    let mut without = report(right_shared(), json!([]));
    without.as_object_mut().unwrap().remove("contradicted");
    let scores = [
        score(LabKind::Mixed, report(right_shared(), drift(0.05))),
        score(LabKind::Mixed, without),
    ];
    let t = super::table(&scores);
    assert!(
        t.contains("| mixed: two shared, one test's own | 1/2 | 5/6 | 0/2 | 5/6 | 0.400 | 10 |"),
        "{t}"
    );
    assert!(t.contains("| **all** | 1/2 |"), "{t}");
    assert!(
        t.contains("requires (not scored): 1 of 2 (`contradicted`)"),
        "{t}"
    );
    assert!(t.contains("right 50 % (need >= 90 %), sessions with a false alarm 0 (need 0). FAIL"));
}
