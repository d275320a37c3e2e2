//! `tactile simulate` and the emulated sensor produce the same volts for the same load history,
//! through the same code: the simulator (`baseline::synth::simulate`, also the proof's
//! generator and, with the calibrated parameters, the diagnosis's baseline) and the emulator
//! (`sim::chain::Chain`, what the firmware reads in the HIL tests) both turn chip loads into volts
//! with `sim::forward::SignalPath`. One load history drives both, with two catalogue effects on
//! (one on the gel, one on the electronics); the emulator's noise-free volts after the offset cut
//! (`Chain::truth_v`: through its circuit, before noise and quantisation) must equal the
//! simulated recording's to rounding.

use baseline::synth::{simulate, Noise, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout, UnitResponse};
use sim::chain::Chain;
use sim::compression::RodSchedule;
use sim::effects::Effect;
use sim::load::{Contact, Table};
use sim::pillar::{Pillar, Traction};

const YOUNGS_MODULUS_PA: f64 = 1.2e5;
const CONTACT_ANGLE_DEG: f64 = 20.0;
const AZIMUTH_DEG: f64 = 60.0;

/// A fingertip whose gel presses on the package top with a traction growing as d^1.5 along a
/// tilted direction (per pascal of modulus), reaching the chip through the pillar as in the
/// emulator.
struct TiltedHertz {
    chip: chip::ChipParams,
    pillar: Pillar,
}

impl TiltedHertz {
    /// Traction on the package top per pascal of gel modulus at rod travel `rod_mm`.
    fn traction_per_pa(rod_mm: f64) -> Traction {
        let s = 0.05 * rod_mm.max(0.0).powf(1.5);
        let (theta, phi) = (CONTACT_ANGLE_DEG.to_radians(), AZIMUTH_DEG.to_radians());
        Traction {
            tx_pa: s * theta.sin() * phi.cos(),
            ty_pa: s * theta.sin() * phi.sin(),
            tz_pa: s * theta.cos(),
        }
    }

    /// Rod force per pascal of gel modulus.
    fn force_per_pa(rod_mm: f64) -> f64 {
        4.0e-5 * rod_mm.max(0.0).powf(1.5)
    }
}

impl FingertipResponse for TiltedHertz {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        UnitResponse {
            force_n: Self::force_per_pa(rod_mm),
            chip: self
                .pillar
                .chip_load(&self.chip, Self::traction_per_pa(rod_mm))
                .to_array(),
        }
    }
}

fn scaled(t: Traction, k: f64) -> Traction {
    Traction {
        tx_pa: t.tx_pa * k,
        ty_pa: t.ty_pa * k,
        tz_pa: t.tz_pa * k,
    }
}

#[test]
fn simulate_and_the_emulator_give_the_same_volts() {
    let hw = hardware::Params::load_default().expect("hardware/ loads");
    let tip = TiltedHertz {
        chip: chip::ChipParams::try_from(&hw.chip).unwrap(),
        pillar: Pillar::from_params(&hw),
    };
    let effects = vec![
        Effect::from_spec("viscoelastic_relaxation:tau_s=4,fraction=0.3").unwrap(),
        Effect::from_spec("highpass_coupling:tau_s=25").unwrap(),
    ];
    let rate_hz = 100.0;
    let spec = SimSpec {
        fingertip: &tip,
        readout: Readout::from_hardware(&hw).unwrap(),
        baseline: BaselineParams::nominal(YOUNGS_MODULUS_PA),
        contact_angle_deg: CONTACT_ANGLE_DEG,
        azimuth_deg: AZIMUTH_DEG,
        radius_mm: hw.fingertip.radius_mm,
        test: RodSchedule {
            sample_rate_hz: rate_hz,
            ..Default::default()
        },
        peak_loads_n: vec![40.0, 25.0],
        effects: effects.clone(),
        noise: Noise::default(),
        seed: 1,
        ambient_c: hw.sim.ambient_c,
        warm_up_rise_c: hw.sim.warmup_rise_c,
        ambient_swing: None,
        source: "one forward model".into(),
    };
    let rec = simulate(&spec);
    let c = &rec.channels;

    // The same history as the emulator's load: rod, load cell and the gel's traction at each of
    // the recording's samples.
    let rows = (0..c.len())
        .map(|k| {
            let rod_mm = c.rod_mm[k];
            let contact = Contact {
                rod_mm,
                load_n: TiltedHertz::force_per_pa(rod_mm) * YOUNGS_MODULUS_PA,
                traction: scaled(TiltedHertz::traction_per_pa(rod_mm), YOUNGS_MODULUS_PA),
            };
            (c.t_s[k], contact)
        })
        .collect();
    let duration_s = c.t_s[c.len() - 1];
    let mut chain = Chain::from_params(&hw, Table::new(rows)).unwrap();
    chain.dac_codes = chain.front_end.null_codes();
    let chain = chain.with_effects(
        &sim::effects::EffectSet::new(effects),
        CONTACT_ANGLE_DEG,
        duration_s,
        1.0 / rate_hz,
    );

    let simulated = [&c.fz_v, &c.mx_v, &c.my_v];
    for (ch, volts) in simulated.iter().enumerate() {
        let peak = volts.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            peak > 0.02,
            "channel {ch} peaks at {peak} V: too small to compare"
        );
        let worst = (0..c.len())
            .map(|k| (chain.truth_v(c.t_s[k])[ch] - volts[k]).abs())
            .fold(0.0f64, f64::max);
        eprintln!(
            "channel {ch}: worst difference {:.1e} of the peak",
            worst / peak
        );
        assert!(
            worst <= 1e-12 * peak,
            "channel {ch}: emulator and simulate differ by {worst:e} V of a {peak} V peak"
        );
    }
    // The load cell too, through the gel's effects on both sides.
    let worst_load = (0..c.len())
        .map(|k| (chain.load_n(c.t_s[k]) - c.load_n[k]).abs())
        .fold(0.0f64, f64::max);
    assert!(
        worst_load <= 1e-12 * 40.0,
        "load differs by {worst_load:e} N"
    );
}
