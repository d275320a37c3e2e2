//! Regime detection on synthetic rigs: every protocol the issue lists (staircases, single ramps,
//! triangles, sinusoids over a preload, starts in contact, no rest), read by rods with noise,
//! quantisation, encoder back-steps and servo overshoot, at 10 Hz to 5 kHz.

use crate::regimes::{self, HeldoutKind, Protocol, Regime, Segment};
use baseline::synth::Gaussian;

const RATES_HZ: [f64; 4] = [10.0, 100.0, 1000.0, 5000.0];

/// How the rig reads its rod.
#[derive(Clone, Copy)]
struct Rig {
    rate_hz: f64,
    /// Encoder quantum, mm (0: none).
    quantum_mm: f64,
    /// White reading noise, mm.
    noise_mm: f64,
    /// Chance per sample of a one-sample back-step of `backstep_mm`.
    backstep_chance: f64,
    backstep_mm: f64,
    /// Overshoot at the end of each move, as a share of its travel, settling over 0.3 s.
    overshoot: f64,
}

impl Rig {
    /// A clean rod at `rate_hz`.
    fn clean(rate_hz: f64) -> Self {
        Self {
            rate_hz,
            quantum_mm: 0.0,
            noise_mm: 0.0,
            backstep_chance: 0.0,
            backstep_mm: 0.0,
            overshoot: 0.0,
        }
    }

    /// A real encoder: 0.1 um quantum, one back-step in 200 samples, 0.9 % overshoot.
    fn encoder(rate_hz: f64) -> Self {
        Self {
            quantum_mm: 1e-4,
            backstep_chance: 0.005,
            backstep_mm: 1e-4,
            overshoot: 0.009,
            ..Self::clean(rate_hz)
        }
    }

    /// The rod read along `path` from `start_mm`: each entry (duration s, end mm) a straight
    /// move (a hold when the end equals the level before).
    fn read(&self, start_mm: f64, path: &[(f64, f64)], seed: u64) -> (Vec<f64>, Vec<f64>) {
        let exact = |t: f64| {
            let (mut t0, mut level, mut settle) = (0.0, start_mm, 0.0);
            let mut move_end: Option<f64> = None;
            for &(dur, to) in path {
                if t < t0 + dur {
                    let x = level + (to - level) * (t - t0) / dur;
                    return x + move_end.map_or(0.0, |e| overshoot(t - e, settle));
                }
                if to != level {
                    settle = self.overshoot * (to - level);
                    move_end = Some(t0 + dur);
                }
                t0 += dur;
                level = to;
            }
            level + move_end.map_or(0.0, |e| overshoot(t - e, settle))
        };
        let total: f64 = path.iter().map(|p| p.0).sum();
        let n = (total * self.rate_hz) as usize + 1;
        let mut g = Gaussian::new(seed);
        let t: Vec<f64> = (0..n).map(|k| k as f64 / self.rate_hz).collect();
        let rod = t
            .iter()
            .map(|&t| {
                let mut x = exact(t) + self.noise_mm * g.normal();
                if self.quantum_mm > 0.0 {
                    x = (x / self.quantum_mm).round() * self.quantum_mm;
                }
                if g.uniform() < self.backstep_chance {
                    x -= self.backstep_mm;
                }
                x
            })
            .collect();
        (t, rod)
    }
}

/// Overshoot `size` (mm) `dt` s after a move ends: rises to its peak at 0.3 s, settles after.
fn overshoot(dt: f64, size: f64) -> f64 {
    let u = dt / 0.3;
    size * u * (1.0 - u).exp()
}

fn count(segs: &[Segment], r: Regime) -> usize {
    segs.iter().filter(|s| s.regime == r).count()
}

fn summary(t: &[f64], rod: &[f64], load: Option<&[f64]>, segs: &[Segment]) -> String {
    let list: Vec<String> = segs
        .iter()
        .map(|s| {
            format!(
                "{}@{:.1}-{:.1}s(c{})",
                s.regime.name(),
                t[s.start],
                t[s.end - 1],
                s.cycle
            )
        })
        .collect();
    format!(
        "{} | {:?}",
        list.join(" "),
        regimes::protocol(t, rod, load, segs)
    )
}

/// Detect and summarise.
fn run(t: &[f64], rod: &[f64], load: Option<&[f64]>) -> (Vec<Segment>, Protocol, String) {
    let (_, segs) = regimes::detect_with_load(t, rod, load);
    let p = regimes::protocol(t, rod, load, &segs);
    let text = summary(t, rod, load, &segs);
    (segs, p, text)
}

#[test]
fn staircase_of_three_ramps_and_holds_is_one_cycle() {
    // Three 40 um steps at 2 um/s, each held 40 s: Static_data.txt's protocol, faster.
    let path = [
        (5.0, 0.0),
        (20.0, 0.04),
        (40.0, 0.04),
        (20.0, 0.08),
        (40.0, 0.08),
        (20.0, 0.12),
        (40.0, 0.12),
    ];
    for rate in RATES_HZ {
        let (t, rod) = Rig::encoder(rate).read(0.0, &path, 1);
        let (segs, p, text) = run(&t, &rod, None);
        assert_eq!(
            (p.loadings, p.holds, p.releases, p.cycles),
            (3, 3, 0, 1),
            "{rate} Hz: {text}"
        );
        assert_eq!(count(&segs, Regime::Rest), 1, "{rate} Hz: {text}");
        assert_eq!(p.heldout_kind, HeldoutKind::EndOfHold);
        // The last third of the last hold (145..185 s), give or take the overshoot's settling,
        // but no less than the last tenth of the record.
        let expected = (145.0 + 40.0 * 2.0 / 3.0_f64).min(185.0 - 18.5);
        assert!((p.heldout.0 - expected).abs() < 1.5, "{rate} Hz: {text}");
        assert!(p.separates_rate_effects && !p.has_unloading);
    }
}

#[test]
fn slow_quantised_ramp_with_back_steps_is_one_loading() {
    // 1 um steps read at 0.5 um/s (two seconds per step), 0.1 um back-steps.
    for rate in RATES_HZ {
        let rig = Rig {
            quantum_mm: 1e-3,
            backstep_chance: 0.01,
            backstep_mm: 1e-4,
            ..Rig::clean(rate)
        };
        let (t, rod) = rig.read(0.0, &[(10.0, 0.0), (100.0, 0.05), (60.0, 0.05)], 2);
        let (_, p, text) = run(&t, &rod, None);
        assert_eq!(
            (p.loadings, p.holds, p.releases, p.cycles),
            (1, 1, 0, 1),
            "{rate} Hz: {text}"
        );
    }
}

#[test]
fn single_ramp_with_nothing_after_cannot_separate_rate_effects() {
    for rate in RATES_HZ {
        let (t, rod) = Rig::encoder(rate).read(0.0, &[(5.0, 0.0), (30.0, 0.2)], 3);
        let (_, p, text) = run(&t, &rod, None);
        assert_eq!(
            (p.loadings, p.holds, p.releases),
            (1, 0, 0),
            "{rate} Hz: {text}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::EndOfRamp, "{text}");
        assert!(!p.separates_rate_effects, "{text}");
        // The last third of the ramp, and never less than the last tenth of the record.
        assert!(p.heldout.0 > 20.0 && p.heldout.0 < 31.5, "{text}");
    }
}

#[test]
fn overshoot_at_the_end_of_a_ramp_is_not_a_release() {
    for rate in RATES_HZ {
        for noise_mm in [0.0, 2e-4] {
            let rig = Rig {
                noise_mm,
                ..Rig::encoder(rate)
            };
            let path = [(2.0, 0.0), (1.0, 0.2), (100.0, 0.2)];
            let (t, rod) = rig.read(0.0, &path, 4);
            let (_, p, text) = run(&t, &rod, None);
            assert_eq!(
                (p.loadings, p.holds, p.releases),
                (1, 1, 0),
                "{rate} Hz, noise {noise_mm}: {text}"
            );
        }
    }
}

#[test]
fn ramp_hold_release_recovery_holds_out_release_and_recovery() {
    for rate in RATES_HZ {
        let path = [
            (2.0, 0.0),
            (10.0, 0.5),
            (20.0, 0.5),
            (1.0, 0.0),
            (40.0, 0.0),
        ];
        let (t, rod) = Rig::encoder(rate).read(0.0, &path, 5);
        let (segs, p, text) = run(&t, &rod, None);
        let order: Vec<Regime> = segs.iter().map(|s| s.regime).collect();
        use Regime::*;
        assert_eq!(
            order,
            [Rest, Loading, Hold, Release, Recovery],
            "{rate} Hz: {text}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::ReleaseAndRecovery);
        // The release is at 32 s, before the middle (36.5 s): the calibration keeps half.
        assert!((p.heldout.0 - 36.5).abs() < 0.2, "{text}");
        assert!(
            p.has_rate_change,
            "a release 10x faster than the loading: {text}"
        );
    }
}

#[test]
fn repeated_triangles_without_holds_are_cycles() {
    for rate in RATES_HZ {
        let mut path = vec![(2.0, 0.0)];
        for _ in 0..5 {
            path.extend([(4.0, 0.3), (4.0, 0.0)]);
        }
        let rig = Rig {
            noise_mm: 5e-4,
            ..Rig::encoder(rate)
        };
        let (t, rod) = rig.read(0.0, &path, 6);
        let (_, p, text) = run(&t, &rod, None);
        assert_eq!(
            (p.loadings, p.holds, p.releases, p.cycles),
            (5, 0, 5, 5),
            "{rate} Hz: {text}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::LastCycle);
        assert!((p.heldout.0 - 34.0).abs() < 0.5, "{text}");
        assert!(!p.has_rate_change && !p.separates_rate_effects, "{text}");
    }
}

/// A load that follows the rod from its contact point with a power law, over a preload.
fn load_of(rod: &[f64], contact_mm: f64, preload_n: f64) -> Vec<f64> {
    let mut g = Gaussian::new(9);
    rod.iter()
        .map(|&x| preload_n + 400.0 * (x - contact_mm).max(0.0).powf(1.5) + 1e-3 * g.normal())
        .collect()
}

#[test]
fn a_start_in_contact_is_a_hold_and_no_rest_is_a_loading() {
    for rate in RATES_HZ {
        // The rod's zero far from contact, a preload: still 5 s, press in, hold.
        let path = [(5.0, -3.0), (10.0, -2.9), (40.0, -2.9)];
        let (t, rod) = Rig::encoder(rate).read(-3.0, &path, 7);
        let load = load_of(&rod, -3.05, 0.0);
        let (segs, p, text) = run(&t, &rod, Some(&load));
        assert_eq!(segs[0].regime, Regime::Hold, "{rate} Hz: {text}");
        assert!(p.starts_in_contact, "{text}");
        // The same rod with the load at zero until contact after 3 s of travel: a rest.
        let free = load_of(&rod, -2.97, 0.0);
        let (segs, p, text) = run(&t, &rod, Some(&free));
        assert_eq!(segs[0].regime, Regime::Rest, "{rate} Hz: {text}");
        assert!(!p.starts_in_contact, "{text}");
        // A load-cell offset with the rod still clear is no contact either.
        let offset: Vec<f64> = free.iter().map(|l| l + 0.5).collect();
        let (segs, _, text) = run(&t, &rod, Some(&offset));
        assert_eq!(segs[0].regime, Regime::Rest, "{rate} Hz: {text}");
        // No rest at all: the record starts moving.
        let (t, rod) = Rig::encoder(rate).read(-3.0, &path[1..], 8);
        let (segs, p, text) = run(&t, &rod, Some(&load_of(&rod, -3.05, 0.0)));
        assert_eq!(segs[0].regime, Regime::Loading, "{rate} Hz: {text}");
        assert_eq!((p.loadings, p.holds), (1, 1), "{text}");
    }
}

/// `cycles` periods of a sinusoid of `amp_mm` at `f_hz` from its midpoint, after `t0` s.
fn sine(t: &[f64], t0: f64, f_hz: f64, amp_mm: f64) -> Vec<f64> {
    t.iter()
        .map(|&t| amp_mm * (2.0 * std::f64::consts::PI * f_hz * (t - t0).max(0.0)).sin())
        .collect()
}

#[test]
fn sinusoids_over_a_preload_give_one_cycle_per_period() {
    // Dynamic_data.txt: 47 um at 0.2 Hz, quantised to 0.1 um, from a still start.
    for rate in [10.0, 100.0, 1000.0] {
        let n = (52.0 * rate) as usize;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
        let mut g = Gaussian::new(10);
        let rod: Vec<f64> = sine(&t, 2.0, 0.2, 0.047)
            .iter()
            .map(|x| ((x + 2e-5 * g.normal()) / 1e-4).round() * 1e-4)
            .collect();
        let load = load_of(&rod, -1.0, 190.0);
        let (segs, p, text) = run(&t, &rod, Some(&load));
        assert_eq!((p.holds, p.releases), (0, 10), "{rate} Hz: {text}");
        assert!((10..=11).contains(&p.cycles), "{rate} Hz: {text}");
        assert_eq!(p.heldout_kind, HeldoutKind::LastCycle);
        // Each leg spans about half a period.
        let legs = segs
            .iter()
            .filter(|s| matches!(s.regime, Regime::Loading | Regime::Release));
        for s in legs.skip(1).take(18) {
            let d = t[s.end - 1] - t[s.start];
            assert!((d - 2.5).abs() < 0.3, "{rate} Hz leg of {d} s: {text}");
        }
        assert!(!p.has_rate_change, "{text}");
    }
}

#[test]
fn sinusoids_at_two_frequencies_are_a_rate_change() {
    let rate = 100.0;
    let n = (40.0 * rate) as usize;
    let t: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
    let slow = sine(&t, 0.0, 0.2, 0.047);
    let fast = sine(&t, 20.0, 1.0, 0.047);
    let rod: Vec<f64> = (0..n)
        .map(|k| if t[k] < 20.0 { slow[k] } else { fast[k] })
        .collect();
    let (_, p, text) = run(&t, &rod, None);
    assert!(p.has_rate_change && p.separates_rate_effects, "{text}");
    assert!(p.cycles >= 20, "{text}");
}

#[test]
fn the_standard_simulated_test_at_every_rate() {
    for rate in RATES_HZ {
        let h = sim::compression::RodSchedule {
            sample_rate_hz: rate,
            ..Default::default()
        }
        .rod_history(&[1.5, 1.0]);
        let (segs, p, text) = run(&h.t_s, &h.rod_mm, None);
        let order: Vec<(Regime, usize)> = segs.iter().map(|s| (s.regime, s.cycle)).collect();
        use Regime::*;
        assert_eq!(
            order,
            [
                (Rest, 0),
                (Loading, 0),
                (Hold, 0),
                (Release, 0),
                (Recovery, 0),
                (Loading, 1),
                (Hold, 1),
                (Release, 1),
                (Recovery, 1)
            ],
            "{rate} Hz: {text}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::LastCycle);
    }
}

#[test]
fn bad_input_gives_a_clear_outcome_without_panic() {
    let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
    let cases: [(&str, Vec<f64>, Vec<f64>); 5] = [
        ("empty", vec![], vec![]),
        ("one sample", vec![0.0], vec![1.0]),
        ("constant rod", t.clone(), vec![0.3; 100]),
        ("all NaN", t.clone(), vec![f64::NAN; 100]),
        (
            "unsorted time",
            t.iter().rev().cloned().collect(),
            t.clone(),
        ),
    ];
    for (what, t, rod) in cases {
        let (regimes, segs) = regimes::detect(&t, &rod);
        assert_eq!(regimes.len(), t.len(), "{what}");
        assert!(segs.iter().all(|s| s.regime == Regime::Rest), "{what}");
        let (a, b) = regimes::heldout_window(&t, &segs);
        assert!(a <= b, "{what}: {a} {b}");
    }
    // NaNs inside a ramp are carried over, the ramp is still found.
    let mut rod: Vec<f64> = t.iter().map(|&t| (t - 0.2).clamp(0.0, 0.6)).collect();
    rod[50] = f64::NAN;
    let (_, segs) = regimes::detect(&t, &rod);
    assert_eq!(count(&segs, Regime::Loading), 1);
    // Lengths that differ.
    let (_, segs) = regimes::detect(&t, &rod[..10]);
    assert_eq!(segs.len(), 1);
}
