//! No shared effect that does not transfer (`session-v1.md`): a relaxation in two of three
//! tests, none in the third. Whatever the session shares, no recording left out may be
//! predicted worse than by its own baseline, and the test without a relaxation is not given a
//! shared one.

use baseline::standard_test::{simulate_standard_test, SimulateOptions};
use diagnosis::joint::output::Change;

#[test]
fn a_shared_effect_predicts_no_left_out_recording_worse_than_its_own_baseline() {
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let inputs = [(32.0, true), (39.0, true), (46.0, false)]
        .iter()
        .enumerate()
        .map(|(i, &(peak, relaxes))| {
            let effects = if relaxes {
                vec!["viscoelastic_relaxation:tau_s=4,fraction=0.3".to_string()]
            } else {
                Vec::new()
            };
            let rec = simulate_standard_test(
                &SimulateOptions {
                    rate_hz: Some(250.0),
                    noise_v: 2e-3,
                    noise_load_n: 0.02,
                    seed: i as u64 + 1,
                    effects,
                    ..SimulateOptions::new(20.0, 60.0, peak)
                },
                &hw,
            )
            .unwrap();
            (format!("rec{i}.csv"), Ok(rec))
        })
        .collect();
    let r = diagnosis::joint::diagnose_recordings(inputs, &opt)
        .expect("the session is analysed")
        .report;
    for row in &r.validation.leave_one_out {
        assert_ne!(row.change, Change::Worse, "{}: {row:?}", row.file);
    }
    // The test without a relaxation is not given a shared one.
    let plain = &r.recordings[2].file;
    let shared_relaxation = r.shared.iter().any(|s| {
        s.effect.name == "viscoelastic_relaxation"
            && s.recordings.as_ref().is_none_or(|f| f.contains(plain))
    });
    assert!(!shared_relaxation, "{:?}", r.shared);
}
