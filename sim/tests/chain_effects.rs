//! Effects of the catalogue switched on in the chain: off by default, and when on, the chain's
//! output moves in the direction the catalogue's signature says (the per-effect signatures at
//! signal level are tested in `sim::effects`).

use sim::chain::Chain;
use sim::effects::{self, Effect, Stiffening, ThermalDrift, ViscoelasticRelaxation};
use sim::load::ForceSchedule;

fn chain() -> Chain<ForceSchedule> {
    let p = hardware::Params::load_default().unwrap();
    // 45 N at 20 deg (inside the ADC range), sped up 40x: the run is over in about 1.7 s.
    let mut p45 = p.clone();
    p45.fingertip.test.peak_load_n = 45.0;
    let mut c = Chain::from_params(&p45, ForceSchedule::from_params(&p45, 0.5, 40.0)).unwrap();
    c.dac_codes = c.front_end.null_codes();
    c
}

fn with(effect: Effect) -> Chain<ForceSchedule> {
    chain().with_effects(&effects::EffectSet::new(vec![effect]), 20.0, 4.0, 1.0e-3)
}

#[test]
fn no_effect_leaves_the_chain_unchanged() {
    let plain = chain();
    let none = chain().with_effects(&effects::EffectSet::default(), 20.0, 4.0, 1.0e-3);
    for t in [0.3, 1.0, 1.5, 2.0, 3.0] {
        let (a, b) = (plain.truth_v(t), none.truth_v(t));
        for ch in 0..3 {
            assert!((a[ch] - b[ch]).abs() < 1e-12, "t {t} ch {ch}");
        }
        assert_eq!(plain.load_n(t), none.load_n(t));
    }
}

#[test]
fn thermal_drift_raises_every_channel_at_rest() {
    // Before contact the plain chain reads 0; with a +20 mV warm-up drift of tau 0.5 s it reads
    // 20 mV (1 - e^-1) at t = 0.5 s (before the rod touches), on every channel.
    let c = with(Effect::ThermalDrift(ThermalDrift {
        amplitude_v: 0.02,
        tau_s: 0.5,
    }));
    for (ch, v) in c.truth_v(0.5).into_iter().enumerate() {
        assert!(
            (v - 0.02 * (1.0 - (-1.0f64).exp())).abs() < 1e-6,
            "ch {ch}: {v}"
        );
    }
}

#[test]
fn stiffening_lowers_the_output_below_the_peak_only() {
    let plain = chain();
    let stiff = with(Effect::Stiffening(Stiffening { exponent: 1.5 }));
    let h = plain.history;
    let up = h.peak_travel_m() / h.rod_speed_m_per_s;
    let (mid, peak) = (h.start_s + up * 0.6, h.start_s + up + h.hold_s / 2.0);
    for ch in 0..3 {
        let (p, s) = (plain.truth_v(mid)[ch], stiff.truth_v(mid)[ch]);
        assert!(
            s.abs() < 0.9 * p.abs() && s * p > 0.0,
            "ch {ch}: {s} vs {p} mid-ramp"
        );
        let (p, s) = (plain.truth_v(peak)[ch], stiff.truth_v(peak)[ch]);
        assert!(
            (s - p).abs() < 1e-3 * p.abs(),
            "ch {ch}: {s} vs {p} at the peak"
        );
    }
}

#[test]
fn viscoelastic_relaxation_leaves_a_slow_tail_after_the_return() {
    // After the fast return the plain chain is back at 0 at once; with relaxation a residual is
    // left that recovers over tau (sensor-facts, observation 3).
    let plain = chain();
    let visco = with(Effect::ViscoelasticRelaxation(ViscoelasticRelaxation {
        tau_s: 0.5,
        fraction: 0.3,
    }));
    let after = plain.history.end_s() + 0.1;
    assert!(plain.truth_v(after)[0].abs() < 1e-9);
    let v = visco.truth_v(after)[0];
    let later = visco.truth_v(after + 1.5)[0];
    assert!(v.abs() > 1e-3, "a tail is left: {v}");
    assert!(later.abs() < 0.2 * v.abs(), "and it decays: {v} -> {later}");
}
