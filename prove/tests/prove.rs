//! The proof as a test: 44 generated recordings with concealed effects, diagnosed
//! blind, must meet the acceptance figures. About a minute of CPU on 2 cores (500 Hz recordings).

use prove::{markdown, run, Plan, Summary};

#[test]
fn concealed_effects_are_found_blind() {
    let hw = hardware::Params::load_default().expect("hardware/ loads");
    let plan = Plan {
        seed: 8,
        sample_rate_hz: 500.0,
        no_effect: 6,
        per_effect: 3,
        radius_mm: hw.fingertip.radius_mm,
        options: diagnosis::Options::from_hardware(&hw).unwrap(),
        readout: baseline::Readout::from_hardware(&hw).unwrap(),
    };
    let cases = plan.generate().expect("FE tables");
    assert!(cases.len() >= 40);
    for kind in sim::effects::EffectKind::ALL {
        assert!(
            cases
                .iter()
                .filter(|c| c.truth.iter().any(|e| e.kind() == kind))
                .count()
                >= 3,
            "{}",
            kind.name()
        );
    }
    let scores = run(&cases, &plan.options);
    let s = Summary::of(&scores);
    println!("{}", markdown(&scores, &s));
    assert!(
        s.correct_share >= 0.9,
        "effect set right in {:.0} %",
        100.0 * s.correct_share
    );
    assert_eq!(s.false_alarms, 0, "false alarms on no-effect recordings");
    // No reported effect may make the held-out misfit worse than the calibrated baseline's.
    for x in scores.iter().filter(|x| !x.found.is_empty()) {
        assert!(
            x.heldout_after <= x.heldout_before,
            "case {}: {:?} held-out RMSE {} -> {}",
            x.id,
            x.found,
            x.heldout_before,
            x.heldout_after
        );
    }
    assert!(
        s.primary_within_20 >= 0.8,
        "primary parameter within 20 % in {:.0} %",
        100.0 * s.primary_within_20
    );
    assert!(
        s.heldout_ratio_mean <= 0.5,
        "held-out RMSE after/before {:.3}",
        s.heldout_ratio_mean
    );
}
