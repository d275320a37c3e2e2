//! A session whose sensing element creeps where the load does not: each output's load-driven
//! part relaxes by 17 % with tau = 15 s in every test, at three peak loads. Each recording's own
//! diagnosis places the relaxation at the transducer; the session, which searches each
//! catalogue effect at its own stage, must keep it there and not hand it to the gel (a shared
//! `viscoelastic_relaxation` at the material, which also relaxes the load, had taken it at
//! tau = 494 s, fraction 0.99 at its bound, with a gain 43 % off and a held-out misfit worse
//! than the baseline's).

use baseline::standard_test::{simulate_standard_test, SimulateOptions};
use recording::Recording;

/// The creep: each output less `fraction` of a first-order lag (tau) of its load-driven part.
fn creep(rec: &mut Recording, fraction: f64, tau_s: f64) {
    let t = rec.channels.t_s.clone();
    let ch = &mut rec.channels;
    for v in [&mut ch.fz_v, &mut ch.mx_v, &mut ch.my_v] {
        let v0 = v[0];
        let mut lagged = 0.0;
        for k in 0..v.len() {
            if k > 0 {
                let a = 1.0 - (-(t[k] - t[k - 1]) / tau_s).exp();
                lagged += a * (v[k] - v0 - lagged);
            }
            v[k] -= fraction * lagged;
        }
    }
}

#[test]
fn a_sensing_element_that_creeps_stays_at_the_transducer_in_a_session() {
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let inputs = [32.0, 39.0, 46.0]
        .iter()
        .enumerate()
        .map(|(i, &peak)| {
            let mut rec = simulate_standard_test(
                &SimulateOptions {
                    rate_hz: Some(250.0),
                    noise_v: 2e-3,
                    noise_load_n: 0.02,
                    seed: i as u64 + 1,
                    ..SimulateOptions::new(20.0, 60.0, peak)
                },
                &hw,
            )
            .unwrap();
            creep(&mut rec, 0.17, 15.0);
            (format!("creep{i}.csv"), Ok(rec))
        })
        .collect();
    let r = diagnosis::joint::diagnose_recordings(inputs, &opt)
        .expect("the session is analysed")
        .report;
    let shared: Vec<(&str, &str)> = r
        .shared
        .iter()
        .map(|s| (s.effect.name.as_str(), s.effect.stage.name()))
        .collect();
    assert!(shared.is_empty(), "{shared:?}");
    // Nothing the session cannot separate; a recording's own term that its held-out stretch
    // did not certify (diagnosis-v1, 2026-11-28) is listed as such, not reported.
    assert!(
        r.undecided
            .iter()
            .all(|u| u.reason.contains("not certified")),
        "{:?}",
        r.undecided
    );
    for row in &r.recordings {
        let effects: Vec<_> = row.effects.iter().flatten().collect();
        let at: Vec<(&str, &str)> = effects
            .iter()
            .map(|e| (e.name.as_str(), e.stage.name()))
            .collect();
        // The creep at the transducer, each recording's own: the library's relaxation of the
        // outputs, or the discovery's output term in the load's memory (L - h_tau(L)), which
        // is the creep's own form and fits it better than the library's exponential does.
        assert_eq!(at.len(), 1, "{}: {at:?}", row.file);
        assert_eq!(at[0].1, "transducer", "{}: {at:?}", row.file);
        let e = effects[0];
        if e.catalogue {
            assert_eq!(e.name, "viscoelastic_relaxation", "{}", row.file);
            let fraction = e.params.get("fraction").unwrap();
            assert!(
                (fraction - 0.17).abs() < 0.2 * 0.17,
                "{}: {fraction}",
                row.file
            );
        } else {
            assert_eq!(
                e.depends_on.as_deref(),
                Some(&["load_history".to_string()][..])
            );
            assert_eq!(e.channels, ["fz_V", "mx_V", "my_V"], "{}", row.file);
            let tau = e
                .params
                .0
                .iter()
                .find(|(k, _)| k.starts_with("tau"))
                .map(|p| p.1);
            assert!(
                tau.is_some_and(|t| (15.0 / 1.5..15.0 * 1.5).contains(&t)),
                "{}: {:?}",
                row.file,
                e.params
            );
        }
        let held = &row.fit.as_ref().expect("analysed").heldout;
        assert!(
            held.rmse_after <= 0.5 * held.rmse_before,
            "{}: {held:?}",
            row.file
        );
    }
    // The creep is each recording's own, so no shared physics predicts it in a test left out,
    // and nothing is shared that could predict one worse than its own baseline
    // (`session-v1.md`). (With the library's relaxation held, the left-out tests were predicted
    // twice as well; the discovered term, at a time constant of 19.5 s against the creep's 15,
    // leaves each test a share of the creep that the session gives a scale per recording, and
    // one test left out is predicted worse through that scale.)
    assert!(r.shared.is_empty());
}
