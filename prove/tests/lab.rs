//! The lab category of sessions (`tactile prove --sessions --category lab`): its recordings
//! are what their designs say (one sensor, settings differing only where the design steps
//! them, each test's own effect on that test alone, the same recordings for the same seed),
//! and, `--ignored`, the category run blind against issue 41's bar:
//! `cargo test --release -p prove --test lab -- --ignored --nocapture`.

use prove::lab::{self, LabCase, LabKind, Own, SessionDesign, TestDesign};
use prove::Plan;
use recording::Recording;

fn plan(seed: u64, rate_hz: f64) -> Plan {
    let hw = hardware::Params::load_default().expect("hardware/ loads");
    Plan {
        seed,
        sample_rate_hz: rate_hz,
        no_effect: 0,
        per_effect: 0,
        radius_mm: hw.fingertip.radius_mm,
        options: diagnosis::Options::from_hardware(&hw).unwrap(),
        readout: baseline::Readout::from_hardware(&hw).unwrap(),
    }
}

/// The recording's settings as its metadata declares them.
fn declared(r: &Recording) -> [f64; 8] {
    let m = &r.meta;
    [
        m.contact_angle_deg,
        m.azimuth_deg,
        m.rod_speed_mm_per_min.unwrap_or(f64::NAN),
        m.sample_rate_hz,
        m.gain_fz,
        m.gain_mx,
        m.gain_my,
        m.excitation_v,
    ]
}

fn designed(p: &Plan, t: &TestDesign) -> [f64; 8] {
    let g = p.readout.signal.gain;
    [
        t.contact_angle_deg,
        t.azimuth_deg,
        t.speed_mm_per_min,
        t.sample_rate_hz,
        g[0] * t.gain_factor[0],
        g[1] * t.gain_factor[1],
        g[2] * t.gain_factor[2],
        p.readout.signal.excitation_v * t.excitation_factor,
    ]
}

fn span(x: &[f64]) -> f64 {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    hi - lo
}

fn without_own(d: &SessionDesign) -> SessionDesign {
    let mut d = d.clone();
    d.tests.iter_mut().for_each(|t| t.own = None);
    d
}

/// One session's recordings against its design: metadata, one fingertip, and each test's own
/// effect only in that test (the same session without it differs in that recording alone).
fn check(p: &Plan, c: &LabCase) {
    let d = &c.design;
    assert_eq!(c.recordings.len(), d.tests.len());
    for ((name, r), t) in c.recordings.iter().zip(&d.tests) {
        assert_eq!(
            r.meta.fingertip_radius_mm, p.radius_mm,
            "{name}: one fingertip"
        );
        let (got, want) = (declared(r), designed(p, t));
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 1e-9 * w.abs().max(1.0),
                "{name}: {got:?} != {want:?}"
            );
        }
        let temp = r.temp_c.as_deref().expect("temp_C");
        let warm = span(temp) > 3.0;
        assert_eq!(
            warm,
            matches!(t.own, Some(Own::Drift(_))),
            "{name}: only a drift warms"
        );
    }
    let plain = p.lab_case(without_own(d)).expect("FE tables");
    for (i, ((name, r), (_, q))) in c.recordings.iter().zip(&plain.recordings).enumerate() {
        let own = d.tests[i].own;
        let same = r.channels == q.channels;
        assert_eq!(
            same,
            own.is_none(),
            "{name}: differs only by its own effect"
        );
        assert_eq!(c.own[i].len(), usize::from(own.is_some()));
        if let Some(Own::Clip { .. }) = own {
            let limit = c.own[i][0].params()[0];
            let outputs = [&r.channels.fz_v, &r.channels.mx_v, &r.channels.my_v];
            assert!(
                outputs.iter().all(|v| v.iter().all(|x| x.abs() <= limit)),
                "{name}"
            );
            let at_rail = outputs
                .iter()
                .flat_map(|v| v.iter())
                .filter(|x| x.abs() == limit);
            assert!(at_rail.count() > 10, "{name}: it clips");
        }
    }
}

#[test]
fn lab_sessions_are_what_their_designs_say() {
    let p = plan(5, 250.0);
    let cases = p.lab_sessions(1, None).expect("FE tables");
    let kinds: Vec<LabKind> = cases.iter().map(|c| c.design.kind).collect();
    for k in LabKind::ALL {
        assert_eq!(
            kinds.iter().filter(|&&x| x == k).count(),
            k.sessions_per_round()
        );
    }
    for c in &cases {
        check(&p, c);
    }
    // The same seed, the same recordings; one kind alone, the same sessions.
    let again = p.lab_sessions(1, Some(LabKind::FrictionSpeeds)).unwrap();
    let first = cases
        .iter()
        .find(|c| c.design.kind == LabKind::FrictionSpeeds)
        .unwrap();
    assert_eq!(again.len(), 1);
    assert_eq!(again[0].design, first.design);
    for ((a, x), (b, y)) in again[0].recordings.iter().zip(&first.recordings) {
        assert_eq!(a, b);
        assert!(x.channels == y.channels && x.temp_c == y.temp_c, "{a}");
    }
    let other = plan(6, 250.0).lab_designs(1, None);
    assert_ne!(other[0], cases[0].design, "another seed, another session");
}

/// The category blind at the two seeds of `prove/README.md`'s figures (41, chosen before any
/// run, and 7): issue 41's bar at each. Expected to fail until the joint diagnosis is fixed;
/// the bar is not to be lowered.
#[test]
#[ignore = "slow: 2 x 21 sessions diagnosed jointly (~20 min on 2 cores); run with --release"]
fn lab_sessions_meet_the_bar_blind() {
    let mut missed = Vec::new();
    for seed in [41, 7] {
        let p = plan(seed, 500.0);
        let cases = p.lab_sessions(3, None).expect("FE tables");
        let scores = lab::run(&cases, &p.options);
        println!("seed {seed}\n{}", lab::table(&scores));
        println!("{}", lab::details(&scores, &cases));
        let t = lab::Totals::of(&scores);
        if !t.passes() {
            missed.push(format!(
                "seed {seed}: {}/{} sessions right, {} with a false alarm",
                t.right, t.sessions, t.false_alarm_sessions
            ));
        }
    }
    assert!(
        missed.is_empty(),
        "the bar (>= 90 % right, no false alarm): {missed:?}"
    );
}
