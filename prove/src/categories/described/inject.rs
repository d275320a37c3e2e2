//! The generators: each [`Physics`] put into a simulated recording at its stage. A term of the
//! material changes the gel's force along the rod (the simulation runs at an effective travel,
//! so the outputs follow the load through the model's own chain); a term of the transducer or
//! the electronics changes the recorded channels. The physics here is the proof's own.

use sim::compression::RodHistory;
use sim::effects::{Effect, EffectKind};

use super::signal::{first_release, speed_mm_per_min, Ctx};
use super::{terms, Injection, Physics, Truth};
use baseline::synth::{simulate_path, Gaussian, Noise, SimSpec};
use recording::Recording;

/// Reference speed of the rate law, mm/min: the fast loading of the protocols that vary it.
const V_REF_MM_PER_MIN: f64 = 60.0;

impl Injection {
    /// The temperature swing (amplitude °C, period s) the simulation needs, if any.
    pub fn ambient_swing(&self, seed: u64) -> Option<(f64, f64)> {
        (self.physics == Physics::SpanFollowsTemperature).then(|| {
            let mut g = Gaussian::new(seed ^ 0x7E4D_5EED);
            let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
            (u(2.0, 4.0), u(60.0, 120.0))
        })
    }

    /// Simulate `spec` along `history` with the physics in, and what a right answer says.
    pub fn record(&self, spec: &SimSpec, history: RodHistory) -> (Recording, Truth) {
        let mut g = Gaussian::new(spec.seed ^ 0xDE5C_41BE_D0C0_FFEE);
        let mut z = Gaussian::new(spec.seed ^ 0x2E20_5EED);
        let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
        let mut truth = terms::truth(self, spec);
        let mut effects = spec.effects.clone();
        effects.extend(self.extra_effects(&mut u, &mut truth));
        let clean = simulate_path(&respec(spec, Noise::default(), &effects), history.clone());
        let travel = self.effective_travel(&history, spec, &mut u, &mut truth);
        let mut rec = simulate_path(
            &respec(spec, spec.noise, &effects),
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
        };
        terms::apply(self, &mut rec, &ctx, &mut u, &mut || z.normal(), &mut truth);
        if self.material_alone {
            for ch in [
                &mut rec.channels.fz_v,
                &mut rec.channels.mx_v,
                &mut rec.channels.my_v,
            ] {
                ch.iter_mut().for_each(|x| *x = f64::NAN);
            }
            rec.temp_c = None;
        }
        (rec, truth)
    }

    /// Catalogue effects the kind brings with it (through the simulator: the stage it is
    /// scored on is elsewhere).
    fn extra_effects(&self, u: &mut dyn FnMut(f64, f64) -> f64, truth: &mut Truth) -> Vec<Effect> {
        let (tau_s, fraction) = match self.physics {
            // The load relaxes 2-8 %, the outputs the more that `on_channels` adds.
            Physics::SensingElementRelaxation => (u(5.0, 20.0), u(0.03, 0.1)),
            Physics::RelaxationAlone => (u(5.0, 30.0), u(0.15, 0.35)),
            _ => return Vec::new(),
        };
        truth.params.push(("material_tau_s", tau_s));
        truth.params.push(("material_fraction", fraction));
        vec![EffectKind::ViscoelasticRelaxation.with_params(&[tau_s, fraction])]
    }

    /// The rod travel the gel behaves as if pressed to (the true one for all but the material's
    /// terms on a recording with outputs, or where the material's term is a travel's).
    fn effective_travel(
        &self,
        history: &RodHistory,
        spec: &SimSpec,
        u: &mut dyn FnMut(f64, f64) -> f64,
        truth: &mut Truth,
    ) -> Vec<f64> {
        let rod = &history.rod_mm;
        match self.physics {
            Physics::PermanentSet => {
                let peak = rod.iter().cloned().fold(0.0, f64::max);
                let set_mm = u(0.04, 0.1) * peak;
                let from = first_release(rod);
                truth.params.push(("set_mm", set_mm));
                truth.params.push(("from_s", history.t_s[from]));
                let mut d = rod.clone();
                d[from..].iter_mut().for_each(|x| *x -= set_mm);
                d
            }
            Physics::RateDependentLoad => {
                let a = u(0.1, 0.25);
                let m = u(1.5, 2.5);
                truth.params.push(("a", a));
                truth.params.push(("m", m));
                truth.params.push(("v_ref_mm_per_min", V_REF_MM_PER_MIN));
                let v = speed_mm_per_min(&history.t_s, rod);
                let k: Vec<f64> = v
                    .iter()
                    .map(|&v| {
                        (1.0 + a * v.signum() * (v.abs() / V_REF_MM_PER_MIN).powf(m)).max(0.0)
                    })
                    .collect();
                ForceTable::new(spec, rod).scaled_travel(rod, &k)
            }
            _ => rod.clone(),
        }
    }
}

/// `spec` with other noise and effects.
fn respec<'a>(spec: &SimSpec<'a>, noise: Noise, effects: &[Effect]) -> SimSpec<'a> {
    SimSpec {
        fingertip: spec.fingertip,
        readout: spec.readout,
        baseline: spec.baseline,
        contact_angle_deg: spec.contact_angle_deg,
        azimuth_deg: spec.azimuth_deg,
        radius_mm: spec.radius_mm,
        test: spec.test.clone(),
        peak_loads_n: spec.peak_loads_n.clone(),
        effects: effects.to_vec(),
        noise,
        seed: spec.seed,
        ambient_c: spec.ambient_c,
        warm_up_rise_c: spec.warm_up_rise_c,
        ambient_swing: spec.ambient_swing,
        source: spec.source.clone(),
    }
}

/// The gel's unit force along the travel, tabulated to invert it (the force is monotone).
struct ForceTable {
    d_mm: Vec<f64>,
    f: Vec<f64>,
}

impl ForceTable {
    /// From zero to three times the largest travel of `rod_mm`.
    fn new(spec: &SimSpec, rod_mm: &[f64]) -> Self {
        let top = 3.0 * rod_mm.iter().cloned().fold(1e-3, f64::max);
        let n = 4000;
        let d_mm: Vec<f64> = (0..=n).map(|i| top * i as f64 / n as f64).collect();
        let f = d_mm
            .iter()
            .map(|&d| spec.fingertip.unit_response(d).force_n)
            .collect();
        Self { d_mm, f }
    }

    fn force(&self, d: f64) -> f64 {
        sim::effects::interpolate(&self.d_mm, &self.f, d)
    }

    /// The travel where the unit force is `f` (the table's end beyond it).
    fn travel(&self, f: f64) -> f64 {
        let i = self.f.partition_point(|&x| x < f);
        if i == 0 {
            return 0.0;
        }
        if i >= self.f.len() {
            return self.d_mm[self.d_mm.len() - 1];
        }
        let (f0, f1) = (self.f[i - 1], self.f[i]);
        let w = if f1 > f0 { (f - f0) / (f1 - f0) } else { 0.0 };
        self.d_mm[i - 1] + w * (self.d_mm[i] - self.d_mm[i - 1])
    }

    /// The travel at which the gel's force is `k` times its force at each `rod_mm` (out of
    /// contact, the rod's own).
    fn scaled_travel(&self, rod_mm: &[f64], k: &[f64]) -> Vec<f64> {
        rod_mm
            .iter()
            .zip(k)
            .map(|(&d, &k)| {
                let f = self.force(d);
                if d <= 0.0 || f <= 0.0 {
                    d
                } else {
                    self.travel(k * f)
                }
            })
            .collect()
    }
}
