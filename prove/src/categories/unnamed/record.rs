//! One recording of the group: the kind put in at its stage, and its truth.

use sim::compression::RodHistory;

use super::channels::{self, Ctx};
use super::signal::copy;
use super::{material, truth, Hidden, Kind, Truth};
use baseline::synth::{simulate_path, Gaussian, Noise, SimSpec};
use recording::Recording;

impl Hidden {
    /// The temperature swing (amplitude °C, period s) the simulation needs, if any: the
    /// modulus's kind needs the temperature to move.
    pub fn ambient_swing(&self, seed: u64) -> Option<(f64, f64)> {
        (self.kind == Some(Kind::ModulusFollowsTemperature)).then(|| {
            let mut g = Gaussian::new(seed ^ 0x0DD_7E4D);
            let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
            (u(2.0, 4.0), u(60.0, 120.0))
        })
    }

    /// Simulate `spec` along `history` with the kind in, and what a right answer says. The
    /// noise is the simulation's own (the same with and without the kind).
    pub fn record(&self, spec: &SimSpec, history: RodHistory) -> (Recording, Truth) {
        let mut g = Gaussian::new(spec.seed ^ 0x0B11_4D5E_ED0F_0A11);
        let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
        let mut truth = truth::of(self);
        if let Some((amplitude_c, period_s)) = spec.ambient_swing {
            truth.params.push(("swing_C", amplitude_c));
            truth.params.push(("swing_period_s", period_s));
        }
        let quiet = SimSpec {
            noise: Noise::default(),
            ..copy(spec)
        };
        let clean = simulate_path(&quiet, history.clone());
        let travel = material::travel(self, spec, &history, &clean, &mut u, &mut truth.params);
        let mut rec = simulate_path(
            spec,
            RodHistory {
                t_s: history.t_s.clone(),
                rod_mm: travel,
            },
        );
        rec.channels.rod_mm = history.rod_mm.clone();
        let ctx = Ctx {
            clean: &clean,
            history: &history,
            noise: spec.noise,
            speed_mm_per_min: spec.test.speed_mm_per_min,
        };
        channels::apply(self, &mut rec, &ctx, &mut u, &mut truth.params);
        if self.material_alone {
            let c = &mut rec.channels;
            for ch in [&mut c.fz_v, &mut c.mx_v, &mut c.my_v] {
                ch.iter_mut().for_each(|x| *x = f64::NAN);
            }
            if self.kind != Some(Kind::ModulusFollowsTemperature) {
                rec.temp_c = None;
            }
        }
        (rec, truth)
    }
}
