//! Speed targets of issue 8, as ratios against their limits measured in this run (not timed
//! asserts): reading a 300 s, 1 kHz recording (limit 1 s) and diagnosing it (limit 10 s).
//! Run: `cargo test --release -p host --test diagnosis_speed -- --ignored --nocapture`.

use std::time::Instant;

use host::diagnosis::baseline::{BaselineParams, FrontEnd};
use host::diagnosis::standin::HertzContact;
use host::diagnosis::synth::{simulate, Noise, SimSpec};
use sim::effects::Effect;

#[test]
#[ignore = "speed study: run with --release --ignored --nocapture"]
fn read_and_diagnose_300_s_at_1_khz() {
    let hw = hardware::Params::load_default().unwrap();
    let opt = host::diagnosis::Options::from_hardware(&hw, false).unwrap();
    let fingertip = HertzContact {
        radius_mm: 20.0,
        poisson: opt.poisson,
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        lever_mm: opt.lever_mm,
    };
    let spec = SimSpec {
        fingertip: &fingertip,
        front_end: FrontEnd::from_hardware(&hw).unwrap(),
        baseline: BaselineParams::nominal(1.0e5),
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::CompressionTest {
            recovery_s: 45.0,
            ..Default::default()
        },
        peak_loads_n: vec![60.0, 45.0, 30.0],
        effects: vec![
            Effect::from_spec("viscoelastic_relaxation:tau_s=4,fraction=0.3").unwrap(),
            Effect::from_spec("highpass_coupling:tau_s=40").unwrap(),
        ],
        noise: Noise {
            load_n: 0.02,
            volts: [2e-3; 3],
            temp_c: 0.02,
        },
        seed: 1,
        ambient_c: 25.0,
        warm_up_rise_c: 5.0,
        source: "speed study".into(),
    };
    let rec = simulate(&spec);
    let seconds = rec.channels.t_s.last().unwrap();
    let path = std::env::temp_dir().join(format!("tactile-speed-{}.csv", std::process::id()));
    rec.write_to(std::fs::File::create(&path).unwrap()).unwrap();
    let t = Instant::now();
    let back = host::recording::read(&path).unwrap();
    let read_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let d = host::diagnosis::diagnose(&back, "speed", &opt).unwrap();
    let diag_s = t.elapsed().as_secs_f64();
    std::fs::remove_file(&path).ok();
    println!("recording: {seconds:.0} s, {} rows", back.channels.len());
    println!("read:     {read_s:.3} s = {:.2} of the 1 s limit", read_s);
    println!(
        "diagnose: {diag_s:.2} s = {:.2} of the 10 s limit ({} threads)",
        diag_s / 10.0,
        rayon::current_num_threads()
    );
    println!(
        "found: {:?}",
        d.report.effects.iter().map(|e| &e.name).collect::<Vec<_>>()
    );
}
