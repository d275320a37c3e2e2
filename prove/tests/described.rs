//! The described physics: each generator puts in what its truth says (fast, in the test run),
//! the scoring reads the contract's keys, and, `--ignored`, the blind scores of both groups
//! against the acceptance bar at seeds 2026 and 7:
//! `cargo test --release -p prove --test described -- --ignored --nocapture`
//! (the same figures as `tactile prove --categories`).

use baseline::synth::{rod_at, simulate_path, Noise, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout, UnitResponse};
use prove::categories::described::{self, Group, Injection, Physics, Target, Truth};
use prove::categories::TestShape;
use prove::reported::ReportedEffect;
use prove::{run, Plan};
use recording::Recording;
use sim::compression::RodHistory;

/// A fingertip with a closed form: F = 1e-6 N/Pa (d / mm)^2, chip loads in proportion.
struct Square;

impl FingertipResponse for Square {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let f = 1e-6 * rod_mm.max(0.0).powi(2);
        UnitResponse {
            force_n: f,
            chip: [-0.1 * f, 1e-4 * f, -0.5e-4 * f],
        }
    }
}

const NOISE: Noise = Noise {
    load_n: 0.02,
    volts: [2e-3; 3],
    temp_c: 0.02,
};

fn spec(fingertip: &dyn FingertipResponse, swing: Option<(f64, f64)>) -> SimSpec<'_> {
    let hw = hardware::Params::load_default().expect("hardware");
    SimSpec {
        fingertip,
        readout: Readout::from_hardware(&hw).expect("front end"),
        baseline: BaselineParams::nominal(1.0e5),
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::RodSchedule {
            sample_rate_hz: 100.0,
            ..Default::default()
        },
        peak_loads_n: vec![60.0, 40.0],
        effects: Vec::new(),
        noise: NOISE,
        seed: 5,
        ambient_c: 24.0,
        warm_up_rise_c: 0.0,
        ambient_swing: swing,
        source: "test".into(),
    }
}

fn history(s: &SimSpec, protocol: TestShape) -> RodHistory {
    match protocol.waypoints(s, [60.0, 40.0]) {
        Some(w) => RodHistory::from_waypoints(s.test.sample_rate_hz, &w),
        None => {
            let turns: Vec<f64> = s.peak_loads_n.iter().map(|&l| rod_at(s, l)).collect();
            s.test.rod_history(&turns)
        }
    }
}

/// The recording without and with `physics` on `target` (same noise), and its truth.
fn pair(physics: Physics, target: Target, protocol: TestShape, alone: bool) -> Injected {
    pair_with(physics, target, protocol, alone, false, None)
}

struct Injected {
    plain: Recording,
    rec: Recording,
    truth: Truth,
}

fn pair_with(
    physics: Physics,
    target: Target,
    protocol: TestShape,
    alone: bool,
    alternate: bool,
    speed_mm_per_min: Option<f64>,
) -> Injected {
    let inj = Injection {
        physics,
        target,
        alternate,
        material_alone: alone,
    };
    let mut s = spec(&Square, inj.ambient_swing(1));
    if let Some(v) = speed_mm_per_min {
        s.test.speed_mm_per_min = v;
    }
    let h = history(&s, protocol);
    let plain = simulate_path(&s, h.clone());
    let (rec, truth) = inj.record(&s, h);
    Injected { plain, rec, truth }
}

fn param(t: &Truth, key: &str) -> f64 {
    t.params
        .iter()
        .find(|(k, _)| *k == key)
        .unwrap_or_else(|| panic!("{key} in {:?}", t.params))
        .1
}

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// Mean frequency of a sinusoid from its zero crossings, Hz.
fn crossing_freq_hz(t: &[f64], x: &[f64]) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let crossings = x
        .windows(2)
        .filter(|w| (w[0] - mean).signum() != (w[1] - mean).signum())
        .count();
    crossings as f64 / 2.0 / (t[t.len() - 1] - t[0])
}

#[test]
fn an_offset_step_is_there_at_its_time_with_its_size() {
    let x = pair(Physics::OffsetStep, Target::Mx, TestShape::Standard, false);
    let (t_step, size) = (param(&x.truth, "t_step_s"), param(&x.truth, "size"));
    assert!(size.abs() >= 15.0 * NOISE.volts[1], "{size}");
    let d = diff(&x.rec.channels.mx_v, &x.plain.channels.mx_v);
    for (t, d) in x.rec.channels.t_s.iter().zip(&d) {
        let want = if *t >= t_step { size } else { 0.0 };
        assert!((d - want).abs() < 1e-12, "at {t}: {d} vs {want}");
    }
    assert_eq!(x.rec.channels.fz_v, x.plain.channels.fz_v);
    assert_eq!(x.rec.channels.load_n, x.plain.channels.load_n);
    assert_eq!(x.truth.stages, ["electronics"]);
    assert_eq!(x.truth.channels, ["mx_V"]);
}

#[test]
fn a_stuck_channel_reads_zero_or_its_last_value_from_mid_hold() {
    let x = pair(
        Physics::StuckChannel,
        Target::My,
        TestShape::LongHold,
        false,
    );
    let from = param(&x.truth, "from_s");
    let c = &x.rec.channels;
    let i = c.t_s.iter().position(|&t| t >= from).unwrap();
    // Mid-hold: the rod is held at its top around that time.
    assert!((c.rod_mm[i] - c.rod_mm[i - 200]).abs() < 1e-9);
    assert!((c.rod_mm[i] - c.rod_mm[i + 200]).abs() < 1e-9);
    assert!(c.my_v[i..].iter().all(|v| v.abs() < 6.0 * NOISE.volts[2]));
    assert_eq!(c.my_v[..i], x.plain.channels.my_v[..i]);
    assert!(x.plain.channels.my_v[i].abs() > 10.0 * NOISE.volts[2]);

    let y = pair_with(
        Physics::StuckChannel,
        Target::My,
        TestShape::Standard,
        false,
        true,
        None,
    );
    let from = param(&y.truth, "from_s");
    let c = &y.rec.channels;
    let i = c.t_s.iter().position(|&t| t >= from).unwrap();
    assert!(c.my_v[i..].iter().all(|&v| v == c.my_v[i]));
}

#[test]
fn a_dead_sensor_reads_noise_while_the_load_moves() {
    let x = pair(
        Physics::DeadSensor,
        Target::Outputs,
        TestShape::Standard,
        false,
    );
    let c = &x.rec.channels;
    for ch in [&c.fz_v, &c.mx_v, &c.my_v] {
        let rms = (ch.iter().map(|v| v * v).sum::<f64>() / ch.len() as f64).sqrt();
        assert!((rms / NOISE.volts[0] - 1.0).abs() < 0.1, "{rms}");
    }
    assert!(c.load_n.iter().cloned().fold(0.0, f64::max) > 50.0);
    assert_eq!(x.truth.channels, ["fz_V", "mx_V", "my_V"]);
}

#[test]
fn a_flipped_sign_flips_one_moment() {
    let x = pair(Physics::SignFlip, Target::Mx, TestShape::Standard, false);
    let c = &x.rec.channels;
    assert!(c
        .mx_v
        .iter()
        .zip(&x.plain.channels.mx_v)
        .all(|(a, b)| a == &-b));
    assert_eq!(c.my_v, x.plain.channels.my_v);
}

/// The load on a ramp of speed `v` over the same travel's load without the term.
fn ratio_at_speed(x: &Injected, speed_mm_per_min: f64) -> f64 {
    let c = &x.rec.channels;
    let mut ratios = Vec::new();
    for i in 1..c.t_s.len() - 1 {
        let v = 60.0 * (c.rod_mm[i + 1] - c.rod_mm[i - 1]) / (c.t_s[i + 1] - c.t_s[i - 1]);
        let plain = x.plain.channels.load_n[i];
        if (v / speed_mm_per_min - 1.0).abs() < 1e-6 && plain > 10.0 {
            ratios.push(c.load_n[i] / plain);
        }
    }
    assert!(!ratios.is_empty());
    ratios.iter().sum::<f64>() / ratios.len() as f64
}

#[test]
fn the_rate_law_grows_the_load_with_a_power_of_the_speed_on_the_material_alone() {
    let x = pair(
        Physics::RateDependentLoad,
        Target::Load,
        TestShape::SpeedDecade,
        true,
    );
    let (a, m) = (param(&x.truth, "a"), param(&x.truth, "m"));
    // SpeedDecade loads at 6 and 60 mm/min (0.3 and 3 times the 20 mm/min of the schedule).
    let fast = ratio_at_speed(&x, 60.0);
    let slow = ratio_at_speed(&x, 6.0);
    assert!((fast - (1.0 + a)).abs() < 0.01, "{fast} vs {}", 1.0 + a);
    assert!((slow - (1.0 + a * 0.1f64.powf(m))).abs() < 0.01, "{slow}");
    assert!(x.rec.channels.fz_v.iter().all(|v| v.is_nan()));
    assert!(x.rec.temp_c.is_none());
    assert_eq!(x.rec.channels.rod_mm, x.plain.channels.rod_mm);
    assert!(x.truth.channels_also.is_empty(), "no outputs to follow");
}

#[test]
fn the_span_follows_the_temperature() {
    let x = pair(
        Physics::SpanFollowsTemperature,
        Target::Outputs,
        TestShape::Standard,
        false,
    );
    let beta = param(&x.truth, "beta_per_C");
    let c = &x.rec.channels;
    let temp = x.rec.temp_c.as_ref().unwrap();
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..c.t_s.len() {
        let p = x.plain.channels.fz_v[i];
        if p.abs() > 0.2 {
            let dt = temp[i] - temp[0];
            num += (c.fz_v[i] / p - 1.0) * dt;
            den += dt * dt;
        }
    }
    assert!(
        (num / den / beta - 1.0).abs() < 0.05,
        "{} vs {beta}",
        num / den
    );
    let swing = temp.iter().cloned().fold(f64::MIN, f64::max) - temp[0];
    assert!(swing > 1.5, "the temperature swings: {swing}");
}

/// The least-squares ratio of `a` to `b`.
fn stats_ratio(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(a, b)| a * b).sum();
    let den: f64 = b.iter().map(|b| b * b).sum();
    num / den
}

/// A sinusoid of the truth's frequency and amplitude added to `column` and nothing else.
fn line_is_there(x: &Injected, column: &str, amplitude_key: &str) {
    let get = |r: &Recording| r.column(column).unwrap().to_vec();
    let d = diff(&get(&x.rec), &get(&x.plain));
    let amplitude = param(&x.truth, amplitude_key);
    let peak = d.iter().cloned().fold(0.0, |m: f64, v| m.max(v.abs()));
    assert!(
        (peak / amplitude - 1.0).abs() < 0.05,
        "{peak} vs {amplitude}"
    );
    let f = crossing_freq_hz(&x.rec.channels.t_s, &d);
    let want = param(&x.truth, "freq_hz");
    assert!((f / want - 1.0).abs() < 0.1, "{f} vs {want}");
}

#[test]
fn lines_sit_at_their_frequency_on_their_channel() {
    let x = pair(
        Physics::FrameVibration,
        Target::Load,
        TestShape::Standard,
        false,
    );
    line_is_there(&x, "load_N", "amplitude");
    // The frame moves the force, so Fz follows the load's line by its swing per newton.
    let d_load = diff(&x.rec.channels.load_n, &x.plain.channels.load_n);
    let d_fz = diff(&x.rec.channels.fz_v, &x.plain.channels.fz_v);
    let ratio = stats_ratio(&d_fz, &d_load);
    let (load, fz) = (&x.plain.channels.load_n, &x.plain.channels.fz_v);
    let peak = (0..load.len())
        .max_by(|&a, &b| load[a].total_cmp(&load[b]))
        .unwrap();
    let swing = (fz[peak] - fz[0]) / (load[peak] - load[0]);
    assert!((ratio / swing - 1.0).abs() < 0.05, "{ratio} vs {swing}");
    let f = param(&x.truth, "freq_hz");
    assert!((2.5..=4.5).contains(&f));

    let x = pair(
        Physics::LineNotMains,
        Target::Fz,
        TestShape::Standard,
        false,
    );
    line_is_there(&x, "fz_V", "amplitude");
    let f = param(&x.truth, "freq_hz");
    assert!([50.0, 60.0]
        .iter()
        .all(|m| (f - m).abs() > 5.0 && (f - m / 2.0).abs() > 1.0));

    let x = pair(Physics::Wander, Target::My, TestShape::Standard, false);
    let f = param(&x.truth, "freq_hz");
    assert!((0.03..=0.07).contains(&f));
    let d = diff(&x.rec.channels.my_v, &x.plain.channels.my_v);
    let peak = d.iter().cloned().fold(0.0, |m: f64, v| m.max(v.abs()));
    assert!(peak > 10.0 * NOISE.volts[2] * 0.9);

    let x = pair(
        Physics::MainsOnLoadCell,
        Target::Load,
        TestShape::Standard,
        false,
    );
    let f = param(&x.truth, "freq_hz");
    assert!((f - 50.0).abs() <= 0.1 || (f - 60.0).abs() <= 0.1);
    assert_eq!(x.truth.catalogue_name, Some("mains_interference"));
}

#[test]
fn a_permanent_set_lowers_the_load_after_the_first_release() {
    let x = pair(
        Physics::PermanentSet,
        Target::Load,
        TestShape::Standard,
        false,
    );
    let from = param(&x.truth, "from_s");
    let c = &x.rec.channels;
    let i = c.t_s.iter().position(|&t| t >= from).unwrap();
    assert_eq!(c.load_n[..i], x.plain.channels.load_n[..i]);
    let second_peak = |r: &Recording| {
        r.channels.load_n[i + 100..]
            .iter()
            .cloned()
            .fold(0.0, f64::max)
    };
    let (with, without) = (second_peak(&x.rec), second_peak(&x.plain));
    // F = k d^2: the set s lowers the peak by (1 - s / d)^2.
    assert!(with < 0.95 * without, "{with} vs {without}");
    // The outputs follow the load through the model's chain.
    let fz_peak = |r: &Recording| {
        r.channels.fz_v[i + 100..]
            .iter()
            .cloned()
            .fold(0.0, |m: f64, v| m.max(v.abs()))
    };
    assert!(fz_peak(&x.rec) < 0.97 * fz_peak(&x.plain));
}

#[test]
fn the_sensing_element_keeps_a_set_and_creeps_back() {
    let x = pair(
        Physics::SensingElementSet,
        Target::Outputs,
        TestShape::LongHold,
        false,
    );
    let c = &x.rec.channels;
    let d = diff(&c.fz_v, &x.plain.channels.fz_v);
    let release = c
        .rod_mm
        .iter()
        .rposition(|&r| r > c.rod_mm[0] + 1e-9)
        .unwrap();
    let after = |s: f64| {
        let i = c.t_s.iter().position(|&t| t >= c.t_s[release] + s).unwrap();
        d[i]
    };
    assert!(after(2.0).abs() > 5.0 * NOISE.volts[0], "{}", after(2.0));
    assert!(after(30.0).abs() < after(2.0).abs(), "creeps back");
    assert_eq!(c.load_n, x.plain.channels.load_n, "the load does not");
}

/// Load at the start of the hold, its least and its last value in the hold.
fn hold_profile(r: &Recording) -> (f64, f64, f64) {
    let c = &r.channels;
    let top = c.rod_mm.iter().cloned().fold(f64::MIN, f64::max);
    let held: Vec<usize> = (0..c.t_s.len())
        .filter(|&i| (c.rod_mm[i] - top).abs() < 1e-9)
        .collect();
    let f: Vec<f64> = held.iter().map(|&i| c.load_n[i]).collect();
    (
        f[0],
        f.iter().cloned().fold(f64::MAX, f64::min),
        f[f.len() - 1],
    )
}

#[test]
fn the_tendon_relaxes_then_recovers_load() {
    // A ramp of 15 s (the Square fingertip's 24 mm at 100 mm/min), the tendon's own.
    let x = pair_with(
        Physics::TendonRecovery,
        Target::Load,
        TestShape::HoldToEnd,
        true,
        false,
        Some(100.0),
    );
    let (first, least, last) = hold_profile(&x.rec);
    assert!(least < 0.85 * first, "relaxes: {least} vs {first}");
    assert!(
        last > least + 10.0 * NOISE.load_n,
        "recovers: {last} vs {least}"
    );
}

#[test]
fn the_sensing_element_relaxes_more_than_the_load() {
    let x = pair_with(
        Physics::SensingElementRelaxation,
        Target::Outputs,
        TestShape::LongHold,
        false,
        false,
        Some(100.0),
    );
    let c = &x.rec.channels;
    let top = c.rod_mm.iter().cloned().fold(f64::MIN, f64::max);
    let held: Vec<usize> = (0..c.t_s.len())
        .filter(|&i| (c.rod_mm[i] - top).abs() < 1e-9)
        .collect();
    let (a, b) = (held[0], held[held.len() - 1]);
    let load = 1.0 - c.load_n[b] / c.load_n[a];
    let fz = 1.0 - (c.fz_v[b] - c.fz_v[0]) / (c.fz_v[a] - c.fz_v[0]);
    assert!((0.01..0.1).contains(&load), "load relaxes {load}");
    assert!(fz > load + 0.05, "outputs relax {fz}, load {load}");
    assert_eq!(x.truth.stages, ["transducer"]);
}

#[test]
fn the_load_cell_clips_in_both_cycles_and_the_material_alone_stiffens() {
    let x = pair(
        Physics::SaturationOnLoadCell,
        Target::Load,
        TestShape::Standard,
        false,
    );
    let limit = param(&x.truth, "limit_N");
    let c = &x.rec.channels;
    assert!(c.load_n.iter().all(|&f| f <= limit));
    let release = c.t_s.len() / 2;
    let clipped = |r: std::ops::Range<usize>| c.load_n[r].iter().filter(|&&f| f == limit).count();
    let first = c
        .rod_mm
        .iter()
        .position(|&r| r == c.rod_mm.iter().cloned().fold(f64::MIN, f64::max))
        .unwrap();
    assert!(
        clipped(0..first + 1) > 0 && clipped(first + 1..c.t_s.len()) > 0,
        "{release}"
    );

    let x = pair(
        Physics::StiffeningAlone,
        Target::Load,
        TestShape::Standard,
        true,
    );
    let p = param(&x.truth, "exponent");
    let peak = x.plain.channels.load_n.iter().cloned().fold(0.0, f64::max);
    let half = x
        .plain
        .channels
        .load_n
        .iter()
        .position(|&f| f > 0.5 * peak)
        .unwrap();
    let ratio = x.rec.channels.load_n[half] / peak;
    let want = (x.plain.channels.load_n[half] / peak).powf(p);
    assert!((ratio - want).abs() < 0.01, "{ratio} vs {want}");
}

#[test]
fn every_kind_has_its_stage_and_the_groups_their_kinds() {
    let specs = described::specs();
    let kinds = |g: Group| {
        let mut k: Vec<Physics> = specs
            .iter()
            .filter_map(|(_, s)| s.injection)
            .map(|i| i.physics)
            .filter(|p| p.group() == g)
            .collect();
        k.dedup();
        k
    };
    assert!(kinds(Group::OutOfCatalogue).len() >= 8);
    let alone = specs
        .iter()
        .filter(|(_, s)| s.injection.unwrap().material_alone)
        .count();
    let other = specs
        .iter()
        .filter(|(_, s)| s.other_family.is_some())
        .count();
    let with = specs.iter().filter(|(_, s)| !s.kinds.is_empty()).count();
    assert!(
        alone >= 8 && other >= 8 && with >= 5,
        "{alone} {other} {with}"
    );
}

fn effect(name: &str, stage: &str, channels: &[&str], depends: Option<&[&str]>) -> ReportedEffect {
    ReportedEffect {
        name: name.into(),
        stage: Some(stage.into()),
        channels: channels.iter().map(|c| c.to_string()).collect(),
        catalogue: depends.map(|_| false),
        depends_on: depends.map(|d| d.iter().map(|c| c.to_string()).collect()),
        form: None,
    }
}

#[test]
fn the_judge_reads_stage_channels_and_dependence() {
    let x = pair(Physics::OffsetStep, Target::Mx, TestShape::Standard, false);
    let right = effect("offset_step", "electronics", &["mx_V"], Some(&["time"]));
    assert!(described::judge(&x.truth, std::slice::from_ref(&right)).right);
    let wrong_stage = effect("offset_step", "transducer", &["mx_V"], Some(&["time"]));
    let wrong_dep = effect("offset_step", "electronics", &["mx_V"], Some(&["load_N"]));
    let wrong_channel = effect(
        "offset_step",
        "electronics",
        &["mx_V", "my_V"],
        Some(&["time"]),
    );
    for e in [wrong_stage, wrong_dep, wrong_channel] {
        assert!(!described::judge(&x.truth, &[e]).right);
    }
    let named = effect("thermal_drift", "electronics", &["mx_V"], None);
    let j = described::judge(&x.truth, &[right, named]);
    assert!(j.right);
    assert_eq!(j.claimed, ["thermal_drift"]);

    // A material term may list the outputs that follow the load.
    let x = pair(
        Physics::PermanentSet,
        Target::Load,
        TestShape::Standard,
        false,
    );
    let e = effect(
        "permanent_set",
        "material",
        &["load_N", "fz_V", "mx_V", "my_V"],
        Some(&["rod_mm", "time"]),
    );
    assert!(described::judge(&x.truth, &[e]).right);

    // Today's report has no `stage`: read from its JSON, nothing is described.
    let json = serde_json::json!({"effects": [{"name": "thermal_drift", "channels": ["mx_V"]}]});
    let effects = ReportedEffect::all(&json);
    assert!(effects[0].is_catalogue() && effects[0].stage.is_none());
    assert!(!described::judge(&x.truth, &effects).right);
}

fn plan(seed: u64) -> Plan {
    let hw = hardware::Params::load_default().expect("hardware");
    Plan {
        seed,
        sample_rate_hz: 500.0,
        no_effect: 0,
        per_effect: 0,
        radius_mm: hw.fingertip.radius_mm,
        options: diagnosis::Options::from_hardware(&hw).expect("options"),
        readout: Readout::from_hardware(&hw).expect("front end"),
    }
}

/// The acceptance bar of both groups at seeds 2026 and 7, blind: the truth only scores.
#[test]
#[ignore = "slow: ~100 recordings diagnosed; run with --release"]
fn described_physics_passes_blind() {
    let mut pass = true;
    for seed in [2026, 7] {
        let plan = plan(seed);
        let (labels, cases) = plan.generate_described().expect("FE tables");
        let scores = run(&cases, &plan.options);
        println!("seed {seed}\n{}", described::table(&labels, &scores));
        pass &= described::all_pass(&labels, &scores);
    }
    assert!(pass, "see the tables above");
}
