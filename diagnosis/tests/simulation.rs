//! The user's own simulation as the baseline (`docs/simulation-format.md`): a simulation off by
//! constant factors changes only the calibration, in either form; an effect it lacks is named;
//! channels it lacks are not compared; and a simulation that cannot be the recording's baseline
//! is refused in one line naming the file and the field, with the usual exit codes.
//!
//! The lab's model is a closed form (no FE), so every diagnosis here takes a second or two.

use std::path::{Path, PathBuf};

use baseline::synth::{simulate, Noise, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout, UnitResponse};
use diagnosis::output::{Report, Verdict};
use diagnosis::simulation::Simulations;
use diagnosis::{diagnose, BaselineSource, DataError, Options};
use recording::Recording;
use sim::effects::{Effect, EffectKind};
use sysexit::ExitStatus;

/// The modulus the recordings are made at, Pa.
const E_REC: f64 = 1.0e5;

/// A lab's lumped fingertip: F = 0.9 d^1.8 N at `E_REC` (d in mm), outputs of 0.015, 0.010 and
/// -0.006 V per newton at the recording's gains, the moments' arm growing 5 % per mm.
struct Lumped {
    per_newton: [f64; 3],
}

impl FingertipResponse for Lumped {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let d = rod_mm.max(0.0);
        let f = 0.9 * d.powf(1.8) / E_REC;
        let arm = 1.0 + 0.05 * d;
        let c = self.per_newton;
        UnitResponse {
            force_n: f,
            chip: [c[0] * f, c[1] * f * arm, c[2] * f * arm],
        }
    }
}

fn readout() -> Readout {
    Readout::from_hardware(&hardware::Params::load_default().expect("hardware")).expect("readout")
}

fn lumped() -> Lumped {
    let per_newton = readout()
        .signal
        .chip_loads([0.015, 0.010, -0.006])
        .expect("invertible");
    Lumped { per_newton }
}

fn spec<'a>(model: &'a Lumped, base: BaselineParams, rate_hz: f64) -> SimSpec<'a> {
    SimSpec {
        fingertip: model,
        readout: readout(),
        baseline: base,
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::RodSchedule {
            sample_rate_hz: rate_hz,
            recovery_s: 30.0,
            ..Default::default()
        },
        peak_loads_n: vec![40.0, 25.0],
        effects: Vec::new(),
        noise: Noise::default(),
        seed: 3,
        ambient_c: 24.0,
        warm_up_rise_c: 0.0,
        ambient_swing: None,
        source: "lab".into(),
    }
}

/// The recording: the lab's model with a gel and outputs the lab did not know, offsets, noise
/// and `effects`.
fn recording(model: &Lumped, effects: Vec<Effect>) -> Recording {
    let base = BaselineParams {
        scale: [1.1, 0.92, 0.92],
        offset: [0.03, 0.01, -0.004, 0.002],
        ..BaselineParams::nominal(E_REC)
    };
    simulate(&SimSpec {
        effects,
        noise: Noise {
            load_n: 0.02,
            volts: [2e-3; 3],
            temp_c: 0.02,
        },
        ..spec(model, base, 100.0)
    })
}

fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-sim-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The lab's simulated test at modulus `e_pa`, `rate_hz`, its clock `shift_s` ahead of the
/// recording's, outputs at the bridges (gains 1), `lacks` empty; at the recording's peaks, or
/// another protocol's.
fn write_test(path: &Path, model: &Lumped, e_pa: f64, lacks: [bool; 4], peaks: &[f64]) {
    let mut s = spec(model, BaselineParams::nominal(e_pa), 40.0);
    // The same rod path as the recording's: turning where the recording's gel turned.
    let turns: Vec<f64> = peaks
        .iter()
        .map(|&l| baseline::synth::rod_at(&spec(model, BaselineParams::nominal(E_REC), 40.0), l))
        .collect();
    let history = s.test.rod_history(&turns);
    s.readout.signal.gain = [1.0; 3];
    let mut rec = baseline::synth::simulate_path(&s, history);
    rec.temp_c = None;
    rec.channels.t_s.iter_mut().for_each(|t| *t += 2.5);
    for (c, lack) in lacks.iter().enumerate() {
        if *lack {
            let col = [
                &mut rec.channels.load_n,
                &mut rec.channels.fz_v,
                &mut rec.channels.mx_v,
                &mut rec.channels.my_v,
            ];
            col.into_iter()
                .nth(c)
                .unwrap()
                .iter_mut()
                .for_each(|v| *v = f64::NAN);
        }
    }
    rec.write_to(std::fs::File::create(path).unwrap()).unwrap();
}

/// The lab's static response at modulus `e_pa`, a row every 0.1 mm up to `to_mm`, with the
/// columns `columns` (of load_N, fz_V, mx_V, my_V) and `extra` metadata lines.
fn write_table(path: &Path, model: &Lumped, e_pa: f64, to_mm: f64, columns: &[usize], extra: &str) {
    let r = readout();
    let names = ["load_N", "fz_V", "mx_V", "my_V"];
    let header: Vec<&str> = columns.iter().map(|&c| names[c]).collect();
    let mut text = format!(
        "# format = tactile-response/1\n# source = lumped test model\n{extra}rod_mm,{}\n",
        header.join(",")
    );
    let rows = (to_mm / 0.1).ceil() as usize + 1;
    for k in 0..rows {
        let d = k as f64 * 0.1;
        let u = model.unit_response(d);
        let v = r.volts(u.chip.map(|x| x * e_pa));
        let all = [u.force_n * e_pa, v[0], v[1], v[2]];
        let values: Vec<String> = columns.iter().map(|&c| format!("{}", all[c])).collect();
        text.push_str(&format!("{d},{}\n", values.join(",")));
    }
    std::fs::write(path, text).unwrap();
}

fn against(rec: &Recording, sim: &Path) -> Result<Report, DataError> {
    let opt = Options {
        baseline: BaselineSource::Simulation(Simulations::one(sim)),
        ..Options::from_hardware(&hardware::Params::load_default().unwrap()).unwrap()
    };
    diagnose(rec, "rec.csv", &opt).map(|d| d.report)
}

fn largest_rod(rec: &Recording) -> f64 {
    rec.channels.rod_mm.iter().cloned().fold(0.0, f64::max)
}

/// A simulation off by constant factors (a gel 30 % stiffer, outputs given at the bridges)
/// changes only the calibration, in either form: nothing named, the load scale their ratio.
#[test]
fn a_constant_factor_is_calibration_only() {
    let (model, d) = (lumped(), dir("factor"));
    let rec = recording(&model, Vec::new());
    let table = d.join("table.csv");
    write_table(
        &table,
        &model,
        1.3 * E_REC,
        largest_rod(&rec) + 0.2,
        &[0, 1, 2, 3],
        "",
    );
    let test = d.join("test.csv");
    write_test(&test, &model, 0.8 * E_REC, [false; 4], &[40.0, 25.0]);
    for (sim, scale, form) in [
        (&table, 1.0 / 1.3, "static_response"),
        (&test, 1.0 / 0.8, "simulated_test"),
    ] {
        let r = against(&rec, sim).unwrap();
        assert_eq!(r.verdict, Verdict::NoSignificantMismatch, "{form}");
        assert!(r.effects.is_empty() && r.undecided.is_empty(), "{form}");
        let got = r.baseline.params.get("load_scale").unwrap();
        assert!((got / scale - 1.0).abs() < 0.01, "{form}: {got} vs {scale}");
        assert!(r.baseline.params.get("youngs_modulus_Pa").is_none());
        assert!(r.baseline.params.get("force_exponent_shift").is_none());
        let s = r.baseline.simulation.as_ref().unwrap();
        assert_eq!(s.form, form);
        assert!(s.not_compared.is_empty(), "{:?}", s.not_compared);
    }
    let r = against(&rec, &test).unwrap();
    let s = r.baseline.simulation.unwrap();
    let shift = s
        .alignment
        .iter()
        .find(|(k, _)| k == "time_shift_s")
        .unwrap()
        .1;
    assert!((shift - 2.5).abs() < 1e-3, "{shift}");
    assert!(
        s.outputs_at.contains("gains [1.0, 1.0, 1.0]"),
        "{}",
        s.outputs_at
    );
}

/// The physics the simulation leaves out is named with its parameters; the channels it does
/// not model are not compared, and the output says so.
#[test]
fn what_the_simulation_lacks_is_named_and_its_missing_channels_are_not_compared() {
    let (model, d) = (lumped(), dir("lacks"));
    let relaxation = EffectKind::ViscoelasticRelaxation.with_params(&[3.0, 0.25]);
    let rec = recording(&model, vec![relaxation]);
    let table = d.join("no-moments.csv");
    write_table(&table, &model, E_REC, largest_rod(&rec) + 0.2, &[0, 1], "");
    let r = against(&rec, &table).unwrap();
    let names: Vec<&str> = r.effects.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["viscoelastic_relaxation"], "{:?}", r.effects);
    let tau = r.effects[0].params.get("tau_s").unwrap();
    assert!((tau / 3.0 - 1.0).abs() < 0.1, "{tau}");
    let s = r.baseline.simulation.as_ref().unwrap();
    let not: Vec<&str> = s.not_compared.iter().map(|(c, _)| c.as_str()).collect();
    assert_eq!(not, ["mx_V", "my_V"]);
    assert_eq!(s.channels, ["load_N", "fz_V"]);
    assert!(r.baseline.rmse.get("mx_V").is_none() && r.baseline.rmse.get("fz_V").is_some());
    // `baseline.rmse` is in each channel's unit: per its recorded range, its mean is the
    // dimensionless `fit.rmse_before` (were it already per range, this mean would be far off).
    let whole = rec.without_gaps();
    let per_range: Vec<f64> = s
        .channels
        .iter()
        .map(|c| {
            let y = whole.column(c).unwrap();
            let lo = y.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            r.baseline.rmse.get(c).unwrap() / (hi - lo)
        })
        .collect();
    let mean = per_range.iter().sum::<f64>() / per_range.len() as f64;
    assert!(
        (mean / r.fit.rmse_before - 1.0).abs() < 1e-9,
        "{mean} per range against fit.rmse_before {}",
        r.fit.rmse_before
    );
}

/// A static shape is named against a simulation without the load, as with one: where the
/// baseline models no load, the outputs' own levels say which samples are loaded (the span the
/// threshold reads them over had been empty, so any bend was taken as the calibration's).
#[test]
fn a_bridge_nonlinearity_is_named_against_a_simulation_without_the_load() {
    let (model, d) = (lumped(), dir("shape"));
    let bend = EffectKind::BridgeNonlinearity.with_params(&[0.25]);
    let rec = recording(&model, vec![bend]);
    let table = d.join("outputs.csv");
    write_table(
        &table,
        &model,
        E_REC,
        largest_rod(&rec) + 0.2,
        &[1, 2, 3],
        "",
    );
    let r = against(&rec, &table).unwrap();
    let names: Vec<&str> = r.effects.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["bridge_nonlinearity"], "{:?}", r.candidates);
    let q = r.effects[0].params.get("quadratic").unwrap();
    assert!((q / 0.25 - 1.0).abs() < 0.1, "{q}");
}

/// The one line a refused simulation gives, and its exit code.
fn refused(rec: &Recording, sim: &Path) -> (String, u8) {
    let e = against(rec, sim).expect_err("refused");
    (e.to_string(), e.exit_code())
}

#[test]
fn another_protocol_a_short_table_and_another_jig_are_refused() {
    let (model, d) = (lumped(), dir("refused"));
    let rec = recording(&model, Vec::new());
    let other = d.join("other-protocol.csv");
    write_test(&other, &model, E_REC, [false; 4], &[30.0, 25.0]);
    let (line, code) = refused(&rec, &other);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("other-protocol.csv")
            && line.contains("`rod_mm`")
            && line.contains("another protocol"),
        "{line}"
    );
    let short = d.join("short.csv");
    write_table(
        &short,
        &model,
        E_REC,
        0.7 * largest_rod(&rec),
        &[0, 1, 2, 3],
        "",
    );
    let (line, code) = refused(&rec, &short);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("short.csv") && line.contains("does not cover the recorded travel"),
        "{line}"
    );
    let jig = d.join("jig.csv");
    write_table(
        &jig,
        &model,
        E_REC,
        largest_rod(&rec) + 0.2,
        &[0, 1],
        "# contact_angle_deg = 0\n",
    );
    let (line, code) = refused(&rec, &jig);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("jig.csv") && line.contains("`contact_angle_deg` = 0"),
        "{line}"
    );
}

#[test]
fn columns_that_do_not_match_are_refused_by_name() {
    let (model, d) = (lumped(), dir("columns"));
    let rec = recording(&model, Vec::new());
    let misspelt = d.join("misspelt.csv");
    std::fs::write(
        &misspelt,
        "# format = tactile-response/1\nrod_mm,force_N\n0,0\n1,1\n",
    )
    .unwrap();
    let (line, code) = refused(&rec, &misspelt);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("misspelt.csv: line 2") && line.contains("`force_N`"),
        "{line}"
    );
    let headless = d.join("no-fz.csv");
    std::fs::write(
        &headless,
        "# format = tactile-recording/1\n# sample_rate_hz = 10\n# contact_angle_deg = 20\n\
         # azimuth_deg = 60\n# fingertip_radius_mm = 20\n# gain_fz = 1\n# gain_mx = 1\n\
         # gain_my = 1\n# excitation_V = 3.3\nt_s,rod_mm,load_N,mx_V,my_V\n0,0,0,0,0\n",
    )
    .unwrap();
    let (line, code) = refused(&rec, &headless);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("no-fz.csv") && line.contains("fz_V"),
        "{line}"
    );
    // A test of the material alone against a simulation of the outputs alone: nothing to
    // compare.
    let mut material = rec.clone();
    for c in [
        &mut material.channels.fz_v,
        &mut material.channels.mx_v,
        &mut material.channels.my_v,
    ] {
        c.iter_mut().for_each(|v| *v = f64::NAN);
    }
    let outputs = d.join("outputs-only.csv");
    write_table(
        &outputs,
        &model,
        E_REC,
        largest_rod(&rec) + 0.2,
        &[1, 2, 3],
        "",
    );
    let (line, code) = refused(&material, &outputs);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("outputs-only.csv") && line.contains("no channel in common"),
        "{line}"
    );
}

#[test]
fn a_missing_simulation_is_a_missing_input() {
    let rec = recording(&lumped(), Vec::new());
    let gone = dir("missing").join("gone.csv");
    let (line, code) = refused(&rec, &gone);
    assert_eq!(code, sysexit::NO_INPUT);
    assert!(line.contains("gone.csv"), "{line}");
    let wrong = dir("missing").join("wrong-format.csv");
    std::fs::write(&wrong, "# format = something/2\nrod_mm\n0\n").unwrap();
    let (line, code) = refused(&rec, &wrong);
    assert_eq!(code, sysexit::DATA);
    assert!(
        line.contains("wrong-format.csv") && line.contains("`format`"),
        "{line}"
    );
}
