//! `thermal_drift` regressed on the recording's `temp_C`: an offset that follows a warm-up plus
//! a swinging ambient is no exponential, yet it is named and its amplitude recovered, because
//! the model follows the measured temperature.

use baseline::synth::{simulate, Noise, SimSpec};
use baseline::{BaselineParams, Readout};
use sim::effects::Effect;

#[test]
fn drift_following_a_swinging_ambient_is_found_through_temp_c() {
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let fingertip = opt.fe.response(20.0, 20.0, 60.0).unwrap();
    let amplitude_v = 0.06;
    let spec = SimSpec {
        fingertip: &fingertip,
        readout: Readout::from_hardware(&hw).unwrap(),
        baseline: BaselineParams::nominal(1.1e5),
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::RodSchedule {
            sample_rate_hz: 250.0,
            recovery_s: 45.0,
            ..Default::default()
        },
        peak_loads_n: vec![55.0, 35.0],
        effects: vec![Effect::from_spec(&format!(
            "thermal_drift:amplitude_V={amplitude_v},tau_s=50"
        ))
        .unwrap()],
        noise: Noise {
            load_n: 0.02,
            volts: [2e-3; 3],
            temp_c: 0.02,
        },
        seed: 11,
        ambient_c: 24.0,
        warm_up_rise_c: 6.0,
        // A +-1.5 degC swing with a 70 s period: a third of the warm-up's rise.
        ambient_swing: Some((1.5, 70.0)),
        source: "thermal regression test".into(),
    };
    let rec = simulate(&spec);
    let d = diagnosis::diagnose(&rec, "thermal", &opt).unwrap().report;
    let names: Vec<&str> = d.effects.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["thermal_drift"], "{:#?}", d.candidates);
    let found = d.effects[0].params.get("amplitude_V").unwrap();
    assert!(
        (found / amplitude_v - 1.0).abs() < 0.2,
        "amplitude {found} V against {amplitude_v} V"
    );
    let h = &d.fit.heldout;
    assert!(h.rmse_after < 0.5 * h.rmse_before, "{h:?}");
}
