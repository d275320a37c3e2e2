//! Robustness study: recordings whose physics departs from the catalogue operators or from the
//! nominal baseline in ways the diagnosis does not model. Prints what is found; asserts only that
//! nothing is reported on the departures that are not catalogue effects at all.
//! Run: `cargo test --release -p diagnosis --test robustness -- --ignored --nocapture`.

use baseline::fe_response::AngleBlend;
use baseline::synth::{simulate, Gaussian, Noise, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout, UnitResponse};
use recording::Recording;
use sim::effects::Effect;

/// A force law outside the diagnosis's family: the FE response stiffened as if the gel were
/// thinner, F = F_FE (1 + 0.5 (d / R)^2), chip loads in proportion.
struct Thick(AngleBlend);

const RADIUS_MM: f64 = 20.0;

impl FingertipResponse for Thick {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let u = self.0.unit_response(rod_mm);
        let k = 1.0 + 0.5 * (rod_mm.max(0.0) / RADIUS_MM).powi(2);
        UnitResponse {
            force_n: u.force_n * k,
            chip: u.chip.map(|c| c * k),
        }
    }
}

fn recording(effects: &[&str], tweak: impl Fn(&mut SimSpec)) -> (Recording, diagnosis::Options) {
    recording_with(effects, false, tweak)
}

fn recording_with(
    effects: &[&str],
    thick: bool,
    tweak: impl Fn(&mut SimSpec),
) -> (Recording, diagnosis::Options) {
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let fe = opt.fe.response(RADIUS_MM, 20.0, 60.0).unwrap();
    let thick_tip = Thick(fe.clone());
    let fingertip: &dyn FingertipResponse = if thick { &thick_tip } else { &fe };
    let mut spec = SimSpec {
        fingertip,
        readout: Readout::from_hardware(&hw).unwrap(),
        baseline: BaselineParams::nominal(1.0e5),
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::RodSchedule {
            sample_rate_hz: 500.0,
            recovery_s: 45.0,
            ..Default::default()
        },
        peak_loads_n: vec![60.0, 40.0],
        effects: effects
            .iter()
            .map(|s| Effect::from_spec(s).unwrap())
            .collect(),
        noise: Noise {
            load_n: 0.02,
            volts: [2e-3; 3],
            temp_c: 0.02,
        },
        seed: 3,
        ambient_c: 25.0,
        warm_up_rise_c: 5.0,
        ambient_swing: None,
        source: "robustness study".into(),
    };
    tweak(&mut spec);
    let rec = simulate(&spec);
    (rec, opt)
}

fn found(rec: &Recording, opt: &diagnosis::Options, label: &str) -> Vec<String> {
    let d = diagnosis::diagnose(rec, label, opt).unwrap();
    let names: Vec<String> = d
        .report
        .effects
        .iter()
        .map(|e| format!("{} {:?}", e.name, e.params.0))
        .collect();
    println!("{label:55} -> {:?} {:?}", d.report.verdict, names);
    d.report.effects.iter().map(|e| e.name.clone()).collect()
}

/// First-order IIR smoother y += alpha (x - y) on the outputs (the firmware's filter).
fn smooth(rec: &mut Recording, alpha: f64) {
    for ch in [
        &mut rec.channels.fz_v,
        &mut rec.channels.mx_v,
        &mut rec.channels.my_v,
    ] {
        let mut y = ch[0];
        for v in ch.iter_mut() {
            y += alpha * (*v - y);
            *v = y;
        }
    }
}

/// Add AR(1) noise (correlation rho per sample) of standard deviation sigma to the outputs.
fn coloured_noise(rec: &mut Recording, rho: f64, sigma: f64) {
    let mut g = Gaussian::new(99);
    for ch in [
        &mut rec.channels.fz_v,
        &mut rec.channels.mx_v,
        &mut rec.channels.my_v,
    ] {
        let mut e = 0.0;
        for v in ch.iter_mut() {
            e = rho * e + (1.0 - rho * rho).sqrt() * sigma * g.normal();
            *v += e;
        }
    }
}

#[test]
#[ignore = "study: run with --release --ignored --nocapture"]
fn departures_from_the_models() {
    let (rec, opt) = recording(&[], |s| s.readout.signal.sensitivity_per_v[1][1] *= 1.1);
    let mismatched_gain = found(&rec, &opt, "Mx sensitivity 10 % above My (no effect)");
    let (rec, opt) = recording(&[], |s| s.baseline.exponent_shift = 0.25);
    let exponent = found(&rec, &opt, "force exponent 1.75 instead of 1.5 (no effect)");
    let (rec, opt) = recording_with(&[], true, |_| {});
    let thick = found(
        &rec,
        &opt,
        "finite-thickness force law outside the family (no effect)",
    );
    let (rec, opt) = recording_with(
        &["viscoelastic_relaxation:tau_s=4,fraction=0.3"],
        true,
        |_| {},
    );
    found(&rec, &opt, "finite-thickness force law + relaxation");
    let (mut rec, opt) = recording(&[], |_| {});
    smooth(&mut rec, 0.2);
    found(
        &rec,
        &opt,
        "firmware smoother alpha 0.2 at 500 Hz (no effect)",
    );
    let (mut rec, opt) = recording(&[], |_| {});
    coloured_noise(&mut rec, 0.95, 2e-3);
    found(&rec, &opt, "AR(1) noise rho 0.95, 2 mV (no effect)");
    let (rec, opt) = recording(
        &[
            "viscoelastic_relaxation:tau_s=1.5,fraction=0.15",
            "viscoelastic_relaxation:tau_s=20,fraction=0.2",
        ],
        |_| {},
    );
    found(&rec, &opt, "two-term Prony relaxation 1.5 s and 20 s");
    let (rec, opt) = recording(
        &[
            "viscoelastic_relaxation:tau_s=5,fraction=0.3",
            "highpass_coupling:tau_s=40",
            "mains_interference:freq_hz=50,amplitude_V=0.005",
        ],
        |_| {},
    );
    found(
        &rec,
        &opt,
        "three effects: relaxation + AC coupling + mains",
    );
    let (rec, opt) = recording(
        &[
            "stiffening:exponent=1.3",
            "bridge_nonlinearity:quadratic=0.1",
        ],
        |_| {},
    );
    found(&rec, &opt, "stiffening + bridge nonlinearity");
    assert!(
        exponent.is_empty(),
        "a different force exponent is calibration, not an effect"
    );
    assert!(
        thick.is_empty(),
        "a different force law is calibration, not an effect: {thick:?}"
    );
    assert!(mismatched_gain.len() <= 1, "{mismatched_gain:?}");
}

/// A simulation with noise on the outputs but none on the load cell (`tactile simulate
/// --noise-v` alone): the model reproduces the load to the arithmetic's precision, and that
/// residual's structure is not a mismatch, nor may its near-zero residuals inflate the
/// outputs' evidence (the criterion counts only channels that carry noise). It once came back
/// `unexplained`, or with a stuck Fz channel; and with a relaxation, `stiffening` and
/// `amplifier_saturation` (the noiseless load, weighed at a millionth of its range, had
/// outweighed the outputs a hundred-million-fold).
#[test]
fn a_load_without_noise_is_no_mismatch_and_its_relaxation_is_named() {
    let (rec, opt) = recording(&["viscoelastic_relaxation:tau_s=4,fraction=0.3"], |s| {
        s.noise.load_n = 0.0;
        s.peak_loads_n = vec![20.0];
        s.test.sample_rate_hz = 200.0;
    });
    let d = diagnosis::diagnose(&rec, "noiseless load, relaxation", &opt).unwrap();
    let names: Vec<String> = d.report.effects.iter().map(|e| e.name.clone()).collect();
    assert_eq!(names, ["viscoelastic_relaxation"]);
    assert_eq!(d.report.verdict, diagnosis::output::Verdict::Explained);
    for seed in [1, 3] {
        let (rec, opt) = recording(&[], |s| {
            s.noise.load_n = 0.0;
            s.seed = seed;
            s.peak_loads_n = vec![20.0];
            s.test.sample_rate_hz = 200.0;
        });
        let d = diagnosis::diagnose(&rec, "noiseless load", &opt).unwrap();
        assert_eq!(
            d.report.verdict,
            diagnosis::output::Verdict::NoSignificantMismatch,
            "seed {seed}: {:?}",
            d.report
                .effects
                .iter()
                .map(|e| e.name.clone())
                .collect::<Vec<_>>()
        );
    }
}

/// An offset step on Fz in the last cycle, the held-out stretch: nothing fitted to the first
/// cycle can show it, and the recording came back `unexplained`. With the stretches swapped
/// (the end fitted, the start held out) the step is found, and the report says which stretch
/// it held out. A step at the end cannot be tested on a held-out start (diagnosis-v1,
/// 2026-11-28: reported only when the held-out misfit falls with it), so it is either reported
/// or listed in `undecided` with its time and size and the test that would decide.
#[test]
fn a_step_in_the_held_out_stretch_is_found_with_the_stretches_swapped() {
    let (mut rec, opt) = recording(&[], |s| s.peak_loads_n = vec![50.0, 50.0]);
    let ch = &mut rec.channels;
    let t_step_s = ch.t_s[0] + 0.8 * (ch.t_s[ch.t_s.len() - 1] - ch.t_s[0]);
    for (v, t) in ch.fz_v.iter_mut().zip(&ch.t_s) {
        if *t >= t_step_s {
            *v += 0.02;
        }
    }
    let d = diagnosis::diagnose(&rec, "a late offset step on Fz", &opt).unwrap();
    let r = &d.report;
    let names: Vec<_> = r.effects.iter().map(|e| &e.name).collect();
    let reported = r.effects.iter().find(|e| e.name == "offset_step");
    let (t0, size) = match reported {
        Some(step) => {
            assert_eq!(step.channels, ["fz_V"]);
            (step.params.get("t0_s"), step.params.get("step"))
        }
        None => {
            let open = r
                .undecided
                .iter()
                .find(|u| u.effects.iter().any(|e| e == "offset_step"))
                .unwrap_or_else(|| panic!("{names:?}, undecided {:?}", r.undecided));
            assert!(open.reason.contains("would decide"), "{}", open.reason);
            (open.params.get("t0_s"), open.params.get("step"))
        }
    };
    let (t0, size) = (t0.unwrap(), size.unwrap());
    assert!(
        (t0 - t_step_s).abs() < 0.5,
        "{t0} for {t_step_s}: {names:?} {:?} {:?}",
        r.verdict,
        r.fit
    );
    assert!(r.fit.heldout.t_end_s < t_step_s);
    assert!((size - 0.02).abs() < 0.002, "{size}: {names:?}");
    assert!(
        r.fit.heldout.rmse_after <= r.fit.heldout.rmse_before,
        "{names:?} {:?}",
        r.fit
    );
}

/// A test of the material alone (no sensor outputs) whose load cell picks up the mains: the
/// load's line is looked for with the mains' own precondition (the rate), not the outputs'
/// effects' (it had been skipped with them, and nothing was found).
#[test]
fn the_mains_on_a_load_cell_alone_is_named() {
    let (mut rec, opt) = recording(&[], |s| {
        s.peak_loads_n = vec![20.0];
        s.test.sample_rate_hz = 500.0;
    });
    let ch = &mut rec.channels;
    for (f, t) in ch.load_n.iter_mut().zip(&ch.t_s) {
        *f += 0.15 * (std::f64::consts::TAU * 60.0 * t).sin();
    }
    for out in [&mut ch.fz_v, &mut ch.mx_v, &mut ch.my_v] {
        out.iter_mut().for_each(|x| *x = f64::NAN);
    }
    let d = diagnosis::diagnose(&rec, "material alone, mains on the load cell", &opt).unwrap();
    let found: Vec<(String, Vec<String>)> = d
        .report
        .effects
        .iter()
        .map(|e| (e.name.clone(), e.channels.clone()))
        .collect();
    assert_eq!(
        found,
        [("mains_interference".to_string(), vec!["load_N".to_string()])]
    );
}

/// A gel that relaxes, and an Fz output that freezes at `share` of the test (under load in the
/// first press, or at rest between the presses) for the rest of it: its frozen stretches had
/// read as a channel without noise (Fz weighed a million-fold, and no effect passed), and
/// fitted to the frozen samples the catalogue had bent a lag and a relaxation at the transducer
/// to follow them. With the frozen samples left out of the noise and of the catalogue's fit,
/// the relaxation is named on the load and the outputs alike, beside the freeze, and nothing
/// else.
#[test]
fn a_frozen_channel_does_not_hide_the_relaxation_beside_it() {
    for share in [0.17, 0.5] {
        frozen_beside_a_relaxation(share);
    }
}

fn frozen_beside_a_relaxation(share: f64) {
    let (mut rec, opt) = recording(&["viscoelastic_relaxation:tau_s=4,fraction=0.3"], |_| {});
    let ch = &mut rec.channels;
    let t_freeze_s = ch.t_s[0] + share * (ch.t_s[ch.t_s.len() - 1] - ch.t_s[0]);
    let k = ch.t_s.iter().position(|&t| t >= t_freeze_s).unwrap();
    let last = ch.fz_v[k];
    ch.fz_v[k..].iter_mut().for_each(|v| *v = last);
    let d = diagnosis::diagnose(&rec, "a frozen Fz beside a relaxation", &opt).unwrap();
    let found = named(&d);
    let names: Vec<&str> = found.iter().map(|f| f.0).collect();
    assert!(names.contains(&"viscoelastic_relaxation"), "{found:?}");
    let stuck = d.report.effects.iter().find(|e| e.name == "stuck_channel");
    assert_eq!(
        stuck.map(|e| e.channels.as_slice()),
        Some(&["fz_V".to_string()][..]),
        "{share}: {found:?}"
    );
    assert_eq!(names.len(), 2, "{share}: {found:?}");
    // Under load the freeze is found where it began (at rest any time before the next press
    // reads the same).
    let t0 = stuck
        .unwrap()
        .params
        .0
        .iter()
        .find(|(k, _)| k == "t0_s")
        .unwrap()
        .1;
    assert!(t0 <= t_freeze_s + 0.5, "{share}: {t0} for {t_freeze_s}");
    if share < 0.2 {
        assert!((t0 - t_freeze_s).abs() < 0.5, "{t0} for {t_freeze_s}");
    }
}

/// A load cell whose amplifier clips below the peak of both presses: fitted to the clipped
/// samples the calibration had bent the load's law, and the clip came out as a stiffening at
/// the transducer (the outputs grow faster than the load that stopped). The clipped samples,
/// one value held, are left out of the catalogue's fit, and the clip is named on the load cell
/// at its limit, and nothing else.
#[test]
fn a_load_cell_that_clips_is_named_at_its_limit() {
    let (mut rec, opt) = recording(&[], |_| {});
    let limit_n = 30.0;
    rec.channels
        .load_n
        .iter_mut()
        .for_each(|f| *f = f.min(limit_n));
    let d = diagnosis::diagnose(&rec, "a load cell clipping at 30 N", &opt).unwrap();
    let found = named(&d);
    assert_eq!(
        found,
        [("amplifier_saturation", &["load_N".to_string()][..])],
        "{found:?}"
    );
    let limit = d.report.effects[0].params.0[0].1;
    assert!((limit - limit_n).abs() < 0.3, "{limit}");
}

/// The effects of `d`, each by name with its channels.
fn named(d: &diagnosis::Diagnosis) -> Vec<(&str, &[String])> {
    d.report
        .effects
        .iter()
        .map(|e| (e.name.as_str(), e.channels.as_slice()))
        .collect()
}
