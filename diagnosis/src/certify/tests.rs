use super::*;
use crate::output::{Numbers, ParamDetail, Stage};

fn effect(p: f64, bic: f64, held: (f64, f64)) -> EffectReport {
    EffectReport {
        name: "hysteresis".into(),
        stage: Stage::Material,
        channels: vec!["fz_V".into()],
        params: Numbers(vec![("width".into(), 0.02)]),
        param_stderr: Numbers::default(),
        evidence: String::new(),
        catalogue: true,
        depends_on: None,
        form: None,
        inclusion: None,
        parameters: vec![ParamDetail::unbounded("width", 0.02, Some(0.001), "")],
        evidence_values: Some(EvidenceValues {
            bic_gain: bic,
            heldout_rmse_without: held.0,
            heldout_rmse_with: held.1,
            p_value: Some(p),
            q_value: None,
        }),
    }
}

/// Benjamini–Hochberg: the adjusted p-values of a textbook list, monotone in p.
#[test]
fn fdr_control_adjusts_as_benjamini_hochberg() {
    let ps = [0.01, 0.04, 0.03, 0.005];
    let mut v: Vec<(EffectReport, Option<Part>)> = ps
        .iter()
        .map(|&p| (effect(p, 20.0, (0.2, 0.1)), None))
        .collect();
    control_fdr(&mut v);
    let q: Vec<f64> = v
        .iter()
        .map(|(e, _)| e.evidence_values.unwrap().q_value.unwrap())
        .collect();
    // Sorted: 0.005 0.01 0.03 0.04 -> 0.02, 0.02, 0.04, 0.04.
    for (got, want) in q.iter().zip([0.02, 0.04, 0.04, 0.02]) {
        assert!((got - want).abs() < 1e-12, "{q:?}");
    }
}

/// Each of the amendment's rules, alone, sends an effect to `undecided`; one that passes all
/// stays.
#[test]
fn each_rule_of_the_gate_can_fail_an_effect() {
    let passes = |e: &EffectReport| failures(e).is_empty();
    let mut good = effect(0.001, 20.0, (0.2, 0.1));
    good.evidence_values.as_mut().unwrap().q_value = Some(0.004);
    assert!(passes(&good));
    let mut e = good.clone();
    e.evidence_values.as_mut().unwrap().bic_gain = -3.0;
    assert!(!passes(&e));
    let mut e = good.clone();
    e.evidence_values.as_mut().unwrap().heldout_rmse_with = 0.2;
    assert!(!passes(&e));
    let mut e = good.clone();
    e.evidence_values.as_mut().unwrap().q_value = Some(0.2);
    assert!(!passes(&e));
    let mut e = good.clone();
    e.inclusion = Some(Numbers(vec![("v".into(), 0.9), ("t".into(), 0.3)]));
    assert!(!passes(&e));
    let mut e = good.clone();
    e.parameters[0].stderr = Some(0.05);
    assert!(!passes(&e));
    let mut e = good;
    e.parameters[0].stderr = None;
    (e.parameters[0].ci_low, e.parameters[0].ci_high) = (Some(-0.01), Some(0.05));
    assert!(!passes(&e));
    let reason = demoted(&e, &failures(&e)).reason;
    assert!(reason.contains("What would decide"), "{reason}");
}

#[test]
fn numbers_are_printed_to_three_figures() {
    assert_eq!(sig(0.000123456), "0.000123");
    assert_eq!(sig(-41.26), "-41.3");
    assert_eq!(sig(12345.0), "1.23e4");
}
