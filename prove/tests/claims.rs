//! The claims scan (issue 46): a small proof writes every answer it makes
//! (`prove::ANSWERS_ENV`), and each JSON written is read back and held to diagnosis-v1's rules
//! for what is reported (amendment 2026-11-28): every effect with its `evidence_values`, a
//! criterion that falls (`bic_gain > 0`), a held-out misfit that falls, a held-out test that
//! passes after the false-discovery control (`q_value <= 0.05`), every `inclusion` at least
//! 0.5, no parameter within its own standard error of zero; and at least 95 % of the
//! parameters with an uncertainty. `/work/shared/tools/check-claims`'s rules, in Rust. One
//! recording per catalogue effect and one without, 500 Hz: a few minutes on 2 cores.

use std::path::Path;

use prove::{run, Plan, ANSWERS_ENV};
use serde_json::Value;

/// What is wrong with one effect of an answer, in words; empty when nothing is.
fn problems(e: &Value) -> Vec<String> {
    let mut why = Vec::new();
    let num = |v: &Value, k: &str| v.get(k).and_then(Value::as_f64);
    let Some(ev) = e.get("evidence_values") else {
        // The calibration's sanity findings are no term of the model: nothing to test held out.
        if e["catalogue"] == Value::Bool(false) && e.get("parameters").is_none() {
            return why;
        }
        return vec!["no evidence_values".into()];
    };
    match num(ev, "bic_gain") {
        Some(b) if b > 0.0 => {}
        b => why.push(format!("bic_gain {b:?}")),
    }
    match (
        num(ev, "heldout_rmse_with"),
        num(ev, "heldout_rmse_without"),
    ) {
        (Some(a), Some(b)) if a < b => {}
        x => why.push(format!("held-out with, without {x:?}")),
    }
    match num(ev, "q_value") {
        Some(q) if q <= 0.05 => {}
        q => why.push(format!("q_value {q:?}")),
    }
    for (k, v) in e
        .get("inclusion")
        .and_then(Value::as_object)
        .into_iter()
        .flatten()
    {
        if v.as_f64().is_some_and(|v| v < 0.5) {
            why.push(format!("inclusion of {k} {v}"));
        }
    }
    for p in e["parameters"].as_array().into_iter().flatten() {
        if let (Some(v), Some(se)) = (num(p, "value"), num(p, "stderr")) {
            if v.abs() < se && p["at_bound"] != Value::Bool(true) {
                why.push(format!("{} = {v} within its error {se}", p["name"]));
            }
        }
    }
    why
}

/// Every effect of every answer below `dir`: the effects failing a rule, and how many
/// parameters there are and how many carry an uncertainty.
fn scan(dir: &Path) -> (Vec<String>, usize, usize, usize) {
    let (mut bad, mut files, mut n, mut with) = (Vec::new(), 0, 0, 0);
    for entry in std::fs::read_dir(dir).expect("the answers' folder") {
        let path = entry.expect("an entry").path();
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let doc: Value = serde_json::from_str(&text).expect("an answer is JSON");
        files += 1;
        for e in doc["effects"].as_array().into_iter().flatten() {
            let why = problems(e);
            if !why.is_empty() {
                bad.push(format!(
                    "{}: {}: {}",
                    path.display(),
                    e["name"],
                    why.join("; ")
                ));
            }
            for p in e["parameters"].as_array().into_iter().flatten() {
                n += 1;
                let has = |k: &str| p.get(k).and_then(Value::as_f64).is_some();
                with += usize::from(has("stderr") || (has("ci_low") && has("ci_high")));
            }
        }
    }
    (bad, files, n, with)
}

#[test]
fn every_answer_of_a_proof_certifies_its_claims() {
    let hw = hardware::Params::load_default().expect("hardware/ loads");
    let plan = Plan {
        seed: 2026,
        sample_rate_hz: 500.0,
        no_effect: 1,
        per_effect: 1,
        radius_mm: hw.fingertip.radius_mm,
        options: diagnosis::Options::from_hardware(&hw).unwrap(),
        readout: baseline::Readout::from_hardware(&hw).unwrap(),
    };
    let cases = plan.generate().expect("FE tables");
    let dir = std::env::temp_dir().join(format!("tactile-claims-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::env::set_var(ANSWERS_ENV, &dir);
    let scores = run(&cases, &plan.options);
    let (bad, files, n, with) = scan(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(files, scores.len(), "one answer written per recording");
    println!(
        "{} answers, parameters with an uncertainty {with}/{n}",
        files
    );
    assert!(
        bad.is_empty(),
        "effects failing their own test:\n{}",
        bad.join("\n")
    );
    assert!(
        with as f64 >= 0.95 * n as f64,
        "parameters with an uncertainty: {with} of {n}"
    );
}
