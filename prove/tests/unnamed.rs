//! Physics nobody named: each generator changes the channels its truth names and no other, by
//! its law, deterministically per seed; the truth table is complete; the scoring reads the
//! contract's keys; and, `--ignored`, the group blind at seeds 2026 and 7 against its bar:
//! `cargo test --release -p prove --test unnamed -- --ignored --nocapture`
//! (the same table as `tactile prove --categories --unnamed-only`).

use baseline::synth::{rod_at, Noise, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout, UnitResponse};
use prove::categories::unnamed::{self, Hidden, Kind, On, Truth};
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

const COLUMNS: [&str; 4] = ["load_N", "fz_V", "mx_V", "my_V"];

fn spec(swing: Option<(f64, f64)>, seed: u64) -> SimSpec<'static> {
    let hw = hardware::Params::load_default().expect("hardware");
    SimSpec {
        fingertip: &Square,
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
        seed,
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

/// The recording with nothing hidden and with `hidden` (same noise, same temperature), and the
/// truth.
struct Injected {
    plain: Recording,
    rec: Recording,
    truth: Truth,
}

fn inject(hidden: Hidden, protocol: TestShape, seed: u64) -> Injected {
    let s = spec(hidden.ambient_swing(seed), seed);
    let h = history(&s, protocol);
    let null = Hidden {
        kind: None,
        ..hidden
    };
    let (plain, _) = null.record(&s, h.clone());
    let (rec, truth) = hidden.record(&s, h);
    Injected { plain, rec, truth }
}

fn hidden(kind: Kind, on: On, alone: bool) -> Hidden {
    Hidden {
        kind: Some(kind),
        on,
        material_alone: alone,
    }
}

fn col<'a>(r: &'a Recording, name: &str) -> &'a [f64] {
    r.column(name).expect("column")
}

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// The largest change of a column (none where both are not measured).
fn largest_change(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m: f64, (x, y)| {
        if x.is_nan() && y.is_nan() {
            m
        } else {
            m.max((x - y).abs())
        }
    })
}

fn sigma(column: &str) -> f64 {
    if column == "load_N" {
        NOISE.load_n
    } else {
        NOISE.volts[0]
    }
}

fn param(t: &Truth, key: &str) -> f64 {
    t.param(key)
        .unwrap_or_else(|| panic!("{key} in {:?}", t.params))
}

/// Every recording of the group with physics, generated on the closed-form fingertip.
fn every_variant() -> Vec<(String, Hidden, Injected)> {
    unnamed::specs()
        .into_iter()
        .filter_map(|(label, cs)| {
            let h = cs.unnamed.expect("a hidden kind or a null");
            h.kind?;
            Some((label, h, inject(h, cs.protocol, 11)))
        })
        .collect()
}

#[test]
fn each_kind_changes_its_channels_and_no_other() {
    for (label, h, x) in every_variant() {
        let kind = h.kind.unwrap();
        let mut expected = x.truth.channels.clone();
        if kind.is_material() && !h.material_alone {
            expected.extend(["fz_V", "mx_V", "my_V"]);
        }
        for c in COLUMNS {
            let d = largest_change(col(&x.rec, c), col(&x.plain, c));
            if expected.contains(&c) {
                assert!(d > 10.0 * sigma(c), "{label}: {c} changes by {d} only");
            } else {
                assert_eq!(d, 0.0, "{label}: {c} must not change");
            }
        }
        assert_eq!(x.rec.channels.rod_mm, x.plain.channels.rod_mm, "{label}");
        assert_eq!(x.rec.channels.t_s, x.plain.channels.t_s, "{label}");
        let outputs_measured = !x.rec.channels.fz_v.iter().all(|v| v.is_nan());
        assert_eq!(outputs_measured, !h.material_alone, "{label}");
    }
}

#[test]
fn a_material_kind_moves_the_outputs_with_the_load() {
    for (label, h, x) in every_variant() {
        if !h.kind.unwrap().is_material() || h.material_alone {
            continue;
        }
        // The closed-form fingertip's outputs are linear in the load: each output's change is
        // its swing per newton times the load's change.
        let load = &x.plain.channels.load_n;
        let top = (0..load.len())
            .max_by(|&a, &b| load[a].total_cmp(&load[b]))
            .unwrap();
        let d_load = diff(&x.rec.channels.load_n, load);
        for c in ["fz_V", "mx_V", "my_V"] {
            let v = col(&x.plain, c);
            let per_newton = (v[top] - v[0]) / (load[top] - load[0]);
            let d = diff(col(&x.rec, c), v);
            let off = d
                .iter()
                .zip(&d_load)
                .map(|(d, l)| (d - per_newton * l).abs())
                .fold(0.0, f64::max);
            let size = d.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            assert!(off < 0.02 * size, "{label}: {c} off by {off} of {size}");
        }
    }
}

#[test]
fn the_truth_table_is_complete() {
    const VOCABULARY: [&str; 11] = [
        "time",
        "rod_mm",
        "rod_speed",
        "load_N",
        "load_rate",
        "temp_C",
        "fz_V",
        "mx_V",
        "my_V",
        "time_since_change",
        "load_history",
    ];
    let specs = unnamed::specs();
    let mut kinds_seen = Vec::new();
    for (label, h, x) in every_variant() {
        let t = &x.truth;
        assert_eq!(t.kind, h.kind, "{label}");
        assert!(!t.stages.is_empty(), "{label}");
        assert!(t
            .stages
            .iter()
            .all(|s| ["material", "transducer", "electronics"].contains(s)));
        assert!(!t.channels.is_empty(), "{label}");
        assert!(!t.depends_any.is_empty(), "{label}");
        assert!(t.depends_any.iter().all(|q| t.depends_allowed.contains(q)));
        for list in [&t.depends_any, &t.depends_allowed, &t.channels] {
            let mut sorted = list.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(
                sorted.len(),
                list.len(),
                "{label}: {list:?} names a quantity twice"
            );
        }
        assert!(t.depends_allowed.iter().all(|q| VOCABULARY.contains(q)));
        assert!(!t.params.is_empty(), "{label}: parameters drawn");
        if h.material_alone {
            assert!(t.channels_also.is_empty(), "{label}: no outputs to follow");
            assert!(t.channels.iter().all(|c| *c == "load_N"), "{label}");
        }
        kinds_seen.push(h.kind.unwrap());
    }
    for kind in Kind::ALL {
        let n = kinds_seen.iter().filter(|&&k| k == kind).count();
        assert!(n >= 2, "{}: {n} recordings", kind.name());
    }
    assert!(Kind::ALL.len() >= 10);
    // Material alone, several channels, one channel; nulls on the protocols and fingertips of
    // the kinds; two presses or a staircase everywhere; 200 Hz to 1 kHz.
    let hidden: Vec<&Hidden> = specs
        .iter()
        .filter_map(|(_, s)| s.unnamed.as_ref())
        .collect();
    let with =
        |f: &dyn Fn(&Hidden) -> bool| hidden.iter().filter(|h| h.kind.is_some() && f(h)).count();
    assert!(with(&|h| h.material_alone) >= 6);
    assert!(with(&|h| h.on.columns().len() >= 2) >= 6);
    assert!(with(&|h| !h.material_alone && h.on.columns().len() == 1 && h.on != On::Load) >= 6);
    let nulls: Vec<_> = specs
        .iter()
        .filter(|(_, s)| s.unnamed.is_some_and(|h| h.kind.is_none()))
        .collect();
    assert!(nulls.len() >= 4);
    for (_, s) in &specs {
        assert!(
            nulls.iter().any(|(_, n)| n.protocol == s.protocol),
            "{:?}",
            s.protocol
        );
        let rate = s.sample_rate_hz.unwrap();
        assert!((200.0..=1000.0).contains(&rate));
        assert!(matches!(
            s.protocol,
            TestShape::Standard
                | TestShape::Staircase
                | TestShape::Triangles
                | TestShape::SpeedDecade
                | TestShape::StartInContact
        ));
    }
    for other in [None, Some(true), Some(false)] {
        assert!(
            nulls.iter().any(|(_, n)| n.other_family == other)
                || other == Some(true) && nulls.iter().any(|(_, n)| n.other_family.is_some())
        );
        assert!(specs.iter().any(|(_, s)| s.other_family == other));
    }
}

#[test]
fn the_generator_is_deterministic_per_seed() {
    let h = hidden(Kind::GainDroop, On::Fz, false);
    let a = inject(h, TestShape::Standard, 3);
    let b = inject(h, TestShape::Standard, 3);
    let c = inject(h, TestShape::Standard, 4);
    assert_eq!(a.rec.channels.fz_v, b.rec.channels.fz_v);
    assert_eq!(a.truth, b.truth);
    assert_ne!(param(&a.truth, "g"), param(&c.truth, "g"));
    let h = hidden(Kind::ModulusFollowsTemperature, On::Load, true);
    let a = inject(h, TestShape::Staircase, 3);
    let b = inject(h, TestShape::Staircase, 3);
    assert_eq!(a.rec.channels.load_n, b.rec.channels.load_n);
    assert_eq!(a.rec.temp_c, b.rec.temp_c);
}

/// Least-squares slope of y on x.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn the_modulus_follows_the_temperature_with_the_material_alone() {
    let x = inject(
        hidden(Kind::ModulusFollowsTemperature, On::Load, true),
        TestShape::Standard,
        5,
    );
    let kappa = param(&x.truth, "kappa_per_C");
    let temp = x.rec.temp_c.as_ref().expect("the temperature is kept");
    let (mut dt, mut ratio) = (Vec::new(), Vec::new());
    for i in 0..temp.len() {
        let p = x.plain.channels.load_n[i];
        if p > 10.0 {
            dt.push(temp[i] - temp[0]);
            ratio.push(x.rec.channels.load_n[i] / p - 1.0);
        }
    }
    let k = -slope(&dt, &ratio);
    assert!((k / kappa - 1.0).abs() < 0.05, "{k} vs {kappa}");
}

#[test]
fn the_gel_softens_with_the_work_done_on_it() {
    let x = inject(
        hidden(Kind::WorkSoftening, On::Load, false),
        TestShape::Triangles,
        5,
    );
    let c = param(&x.truth, "c");
    let r = &x.rec.channels;
    let p = &x.plain.channels;
    // The first press's peak loses c (its own work is W_1), later presses more, up to 2c.
    let ranges = press_ranges(&r.rod_mm);
    assert_eq!(ranges.len(), 3);
    let peak = |x: &[f64], k: usize| x[ranges[k].clone()].iter().cloned().fold(0.0, f64::max);
    let lost: Vec<f64> = (0..3)
        .map(|k| 1.0 - peak(&r.load_n, k) / peak(&p.load_n, k))
        .collect();
    assert!(lost[0] > 0.3 * c && lost[0] < 1.05 * c, "{lost:?} vs {c}");
    assert!(
        lost[1] > lost[0] && lost[2] > lost[1] && lost[2] < 2.0 * c,
        "{lost:?}"
    );
}

/// The presses: runs where the rod is a tenth of its range in.
fn press_ranges(rod: &[f64]) -> Vec<std::ops::Range<usize>> {
    let lo = rod.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = rod.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let mut out = Vec::new();
    let mut start = None;
    for (i, &x) in rod.iter().enumerate() {
        let inside = x > lo + 0.1 * (hi - lo);
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push(s..i);
                start = None;
            }
            _ => {}
        }
    }
    out
}

#[test]
fn the_rigs_zero_moves_the_gel_in_time() {
    let x = inject(
        hidden(Kind::RigZeroDrift, On::Load, false),
        TestShape::Standard,
        5,
    );
    let (z, tau) = (param(&x.truth, "z_mm"), param(&x.truth, "tau_s"));
    assert!(z.abs() <= 0.4 && z != 0.0);
    // F = 0.1 d^2: the gel at d + z(t).
    let c = &x.rec.channels;
    let p = &x.plain.channels;
    for i in (0..c.t_s.len()).step_by(97) {
        if p.load_n[i] > 5.0 {
            let d = (p.load_n[i] / 0.1).sqrt() + z * (1.0 - (-c.t_s[i] / tau).exp());
            let want = 0.1 * d * d;
            let got = c.load_n[i] - (p.load_n[i] - 0.1 * c.rod_mm[i].powi(2));
            assert!((got - want).abs() < 0.01 * want, "{got} vs {want}");
        }
    }
}

#[test]
fn backlash_puts_the_unloading_path_above_the_loading_path() {
    let x = inject(
        hidden(Kind::DriveBacklash, On::Load, true),
        TestShape::Triangles,
        5,
    );
    let b = param(&x.truth, "b_mm");
    let c = &x.rec.channels;
    // At the same encoder travel the tip is b deeper on the way out: a loop a passive
    // material cannot make (its unloading lies below its loading).
    let mid = 0.5 * c.rod_mm.iter().cloned().fold(0.0, f64::max);
    let at = |going_in: bool| {
        let i = (1..c.t_s.len())
            .find(|&i| {
                let v = c.rod_mm[i] - c.rod_mm[i - 1];
                (if going_in { v > 0.0 } else { v < 0.0 }) && (c.rod_mm[i] - mid).abs() < 0.01
            })
            .unwrap();
        c.load_n[i]
    };
    let (up, down) = (at(true), at(false));
    let want = 0.1 * ((mid + b / 2.0).powi(2) - (mid - b / 2.0).powi(2));
    assert!(
        ((down - up) / want - 1.0).abs() < 0.1,
        "{down} - {up} vs {want}"
    );
}

#[test]
fn the_load_train_rings_after_the_pull_back() {
    let x = inject(
        hidden(Kind::RigRinging, On::Load, false),
        TestShape::Standard,
        5,
    );
    let f = param(&x.truth, "freq_hz");
    let c = &x.rec.channels;
    let d = diff(&c.load_n, &x.plain.channels.load_n);
    // The largest swing is where the rod starts back, at most a F_peak.
    let i = (0..d.len())
        .max_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
        .unwrap();
    let release = (1..c.t_s.len())
        .find(|&k| c.rod_mm[k] < c.rod_mm[k - 1] - 1e-9)
        .unwrap();
    assert!(c.t_s[i] >= c.t_s[release] - 0.02 && c.t_s[i] < c.t_s[release] + 1.0 / f);
    let peak = x.plain.channels.load_n.iter().cloned().fold(0.0, f64::max);
    assert!(d[i].abs() <= param(&x.truth, "a") * peak * 1.01);
    // Before the first stop nothing rings.
    let top = (1..c.t_s.len())
        .find(|&k| (c.rod_mm[k] - c.rod_mm[k - 1]).abs() < 1e-12 && c.rod_mm[k] > 1.0)
        .unwrap();
    assert!(d[..top - 1].iter().all(|v| v.abs() < 1e-9));
}

#[test]
fn the_pillar_takes_no_load_below_the_gap() {
    let x = inject(
        hidden(Kind::PillarGap, On::Outputs, false),
        TestShape::Standard,
        5,
    );
    let gap = param(&x.truth, "gap_N");
    let (c, p) = (&x.rec.channels, &x.plain.channels);
    // F = 0.1 d^2 without noise; the driven part read off the noisy plain recording, so the
    // noise's share of it is the tolerance.
    for i in 0..c.t_s.len() {
        let f = 0.1 * c.rod_mm[i].max(0.0).powi(2);
        let driven = p.fz_v[i] - p.fz_v[0];
        let kept = if f > gap { 1.0 - gap / f } else { 0.0 };
        let off = c.fz_v[i] - p.fz_v[i] - driven * (kept - 1.0);
        assert!(off.abs() < 10.0 * NOISE.volts[0], "{off} at {i}");
        if f < gap {
            // The pillar takes nothing: the output reads its rest, and noise.
            assert!((c.fz_v[i] - c.fz_v[0]).abs() < 10.0 * NOISE.volts[0]);
        }
    }
}

#[test]
fn the_moments_turn_with_the_load_and_keep_their_size() {
    let x = inject(
        hidden(Kind::MomentAxisTurning, On::Moments, false),
        TestShape::Standard,
        5,
    );
    let (c, p) = (&x.rec.channels, &x.plain.channels);
    let (at, _) = p
        .load_n
        .iter()
        .enumerate()
        .fold((0, 0.0), |m, (i, &f)| if f > m.1 { (i, f) } else { m });
    let size = |mx: f64, my: f64| (mx - p.mx_v[0]).hypot(my - p.my_v[0]);
    // The noise-free size is kept by a turn; the noisy samples differ by the noise's turn only.
    let before = size(p.mx_v[at], p.my_v[at]);
    let after = size(c.mx_v[at], c.my_v[at]);
    assert!((after / before - 1.0).abs() < 0.01, "{after} vs {before}");
    let turned = ((c.my_v[at] - p.my_v[0]).atan2(c.mx_v[at] - p.mx_v[0])
        - (p.my_v[at] - p.my_v[0]).atan2(p.mx_v[at] - p.mx_v[0]))
    .to_degrees();
    let want = param(&x.truth, "theta_max_deg");
    assert!((turned - want).abs() < 0.5, "{turned} vs {want}");
}

#[test]
fn the_supply_sags_in_proportion_to_time() {
    let x = inject(
        hidden(Kind::SupplySag, On::Outputs, false),
        TestShape::Standard,
        5,
    );
    let s = param(&x.truth, "sag");
    let (c, p) = (&x.rec.channels, &x.plain.channels);
    let end = c.t_s[c.t_s.len() - 1];
    let top = (0..p.fz_v.len())
        .max_by(|&a, &b| p.fz_v[a].abs().total_cmp(&p.fz_v[b].abs()))
        .unwrap();
    let lost = 1.0 - c.fz_v[top] / p.fz_v[top];
    assert!((lost / (s * c.t_s[top] / end) - 1.0).abs() < 0.05, "{lost}");
}

#[test]
fn the_motor_is_picked_up_while_the_rod_moves_even_out_of_contact() {
    let x = inject(
        hidden(Kind::MotorPickup, On::Fz, false),
        TestShape::Standard,
        5,
    );
    let a = param(&x.truth, "a");
    let (c, p) = (&x.rec.channels, &x.plain.channels);
    let d = diff(&c.fz_v, &p.fz_v);
    // At rest: nothing; approaching, out of contact: a tanh(1); pulling back: -a tanh(30).
    assert!(d[10].abs() < 1e-12);
    let approach = c.rod_mm.iter().position(|&r| r > -0.25).unwrap();
    assert!(p.load_n[approach] < 0.1);
    assert!(
        (d[approach] - a * 1f64.tanh()).abs() < 1e-9,
        "{}",
        d[approach]
    );
    let back = (1..c.t_s.len())
        .find(|&k| c.rod_mm[k] < c.rod_mm[k - 1] - 1e-9)
        .unwrap();
    assert!((d[back + 1] + a * 30f64.tanh()).abs() < 1e-9);
}

#[test]
fn the_load_cell_creeps_and_reads_after_the_rod_has_left() {
    let x = inject(
        hidden(Kind::LoadCellCreep, On::Load, false),
        TestShape::Standard,
        5,
    );
    let c = param(&x.truth, "c");
    let ch = &x.rec.channels;
    let d = diff(&ch.load_n, &x.plain.channels.load_n);
    let out = (1..ch.t_s.len())
        .find(|&k| ch.rod_mm[k] < 0.0 && ch.rod_mm[k - 1] >= 0.0)
        .unwrap();
    let peak = x.plain.channels.load_n.iter().cloned().fold(0.0, f64::max);
    assert!(
        d[out + 10] > 0.2 * c * peak,
        "reads {} with the rod out",
        d[out + 10]
    );
    assert!(d.iter().all(|&v| v >= -1e-12 && v <= c * peak * 1.001));
}

#[test]
fn the_reading_wraps_round_in_every_press() {
    let x = inject(
        hidden(Kind::CounterWrap, On::Fz, false),
        TestShape::Standard,
        5,
    );
    let limit = param(&x.truth, "limit");
    let c = &x.rec.channels;
    assert!(c.fz_v.iter().all(|v| v.abs() <= limit + 1e-12));
    let jumps: Vec<usize> = (1..c.t_s.len())
        .filter(|&k| (c.fz_v[k] - c.fz_v[k - 1]).abs() > limit)
        .collect();
    // Up and down through the wrap, in each of the two presses.
    assert!(jumps.len() >= 4, "{jumps:?}");
}

#[test]
fn the_amplifier_droops_with_its_own_output() {
    let x = inject(
        hidden(Kind::GainDroop, On::My, false),
        TestShape::Staircase,
        5,
    );
    let g = param(&x.truth, "g");
    let (c, p) = (&x.rec.channels, &x.plain.channels);
    let lost: Vec<f64> = (0..c.t_s.len())
        .filter(|&i| p.my_v[i].abs() > 0.05)
        .map(|i| 1.0 - c.my_v[i] / p.my_v[i])
        .collect();
    assert!(lost.iter().all(|&l| l > -0.05 && l < g + 0.05), "{g}");
    // It droops more the longer the output is held high.
    assert!(lost[lost.len() - 1] > lost[0] + 0.2 * g);
}

fn effect(stage: &str, channels: &[&str], depends: &[&str], catalogue: bool) -> ReportedEffect {
    ReportedEffect {
        name: "a_term".into(),
        stage: Some(stage.into()),
        channels: channels.iter().map(|c| c.to_string()).collect(),
        catalogue: (!catalogue).then_some(false),
        depends_on: Some(depends.iter().map(|c| c.to_string()).collect()),
        form: None,
    }
}

#[test]
fn the_judge_reads_stage_channels_dependence_and_the_held_out_stretch() {
    let x = inject(
        hidden(Kind::LoadCellCreep, On::Load, false),
        TestShape::Standard,
        5,
    );
    let t = &x.truth;
    let right = effect("electronics", &["load_N"], &["load_history"], false);
    assert!(unnamed::judge(t, std::slice::from_ref(&right), 0.1, 0.05).right);
    assert!(
        !unnamed::judge(t, std::slice::from_ref(&right), 0.1, 0.1).right,
        "held out"
    );
    for wrong in [
        effect("material", &["load_N"], &["load_history"], false),
        effect("electronics", &["load_N", "fz_V"], &["load_history"], false),
        effect("electronics", &["load_N"], &["rod_mm"], false),
        effect(
            "electronics",
            &["load_N"],
            &["load_history", "temp_C"],
            false,
        ),
        effect("electronics", &["load_N"], &["load_history"], true),
    ] {
        assert!(!unnamed::judge(t, &[wrong], 0.1, 0.05).right);
    }
    let named = effect("material", &["load_N"], &[], true);
    let j = unnamed::judge(t, &[right, named], 0.1, 0.05);
    assert!(j.right && j.claimed == ["a_term"]);

    // A material term may list the outputs that follow the load.
    let x = inject(
        hidden(Kind::RigZeroDrift, On::Load, false),
        TestShape::Standard,
        5,
    );
    let e = effect(
        "material",
        &["load_N", "fz_V", "mx_V", "my_V"],
        &["time", "rod_mm"],
        false,
    );
    assert!(unnamed::judge(&x.truth, &[e], 0.1, 0.05).right);

    // A null recording: any effect is a false alarm.
    let x = inject(
        Hidden {
            kind: None,
            on: On::Outputs,
            material_alone: false,
        },
        TestShape::Standard,
        5,
    );
    let e = effect("electronics", &["fz_V"], &["time"], false);
    assert!(unnamed::judge(&x.truth, &[e], 0.1, 0.05).false_alarm);
    assert!(!unnamed::judge(&x.truth, &[], 0.1, 0.1).false_alarm);
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

/// The group's bar at seeds 2026 and 7, blind: the truth only scores. Expected to fail until
/// the diagnosis's discovery step describes these kinds; do not weaken it.
#[test]
#[ignore = "slow: ~80 recordings diagnosed; run with --release"]
fn physics_nobody_named_passes_blind() {
    let mut pass = true;
    for seed in [2026, 7] {
        let plan = plan(seed);
        let (labels, cases) = plan.generate_unnamed().expect("FE tables");
        let scores = run(&cases, &plan.options);
        println!("seed {seed}\n{}", unnamed::table(&labels, &scores));
        pass &= unnamed::totals(&labels, &scores).passes();
    }
    assert!(pass, "see the tables above");
}
