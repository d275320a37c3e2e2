//! The two amplifier stages: an instrumentation amplifier (INA333) and a non-inverting op-amp
//! stage (OPA333), both referenced to VMID and limited by their rail-to-rail outputs.
//!
//! The same equations as the behavioural models of `hardware/spice/frontend.cir`.

/// Softplus `sp(z) = k ln(1 + e^(z/k))`, written so that the exponential never overflows.
fn softplus(z: f64, knee_v: f64) -> f64 {
    z.max(0.0) + knee_v * libm::log1p(libm::exp(-z.abs() / knee_v))
}

/// An output that follows `x` and rounds off into `[lo, hi]` over `knee_v`:
/// `clip(x) = x - sp(x - hi) + sp(lo - x)`.
pub fn clip(x: f64, lo: f64, hi: f64, knee_v: f64) -> f64 {
    x - softplus(x - hi, knee_v) + softplus(lo - x, knee_v)
}

/// How close a rail-to-rail output gets to its supply rails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Output {
    pub supply_v: f64,
    pub swing_from_rail_v: f64,
    pub knee_v: f64,
}

impl Output {
    /// Lowest and highest output, `[swing, supply - swing]`.
    pub fn limits_v(&self) -> (f64, f64) {
        (
            self.swing_from_rail_v,
            self.supply_v - self.swing_from_rail_v,
        )
    }

    fn drive(&self, x: f64) -> f64 {
        let (lo, hi) = self.limits_v();
        clip(x, lo, hi, self.knee_v)
    }
}

/// First stage: `out = ref + G1 (v_in + V_os)`, `G1 = 1 + R_int / R_G`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InAmp {
    pub internal_ohm: f64,
    pub gain_resistor_ohm: f64,
    pub offset_v: f64,
    pub gbw_hz: f64,
    pub input_noise_v_per_rthz: f64,
    pub output_noise_v_per_rthz: f64,
    pub output: Output,
}

impl InAmp {
    pub fn gain(&self) -> f64 {
        1.0 + self.internal_ohm / self.gain_resistor_ohm
    }

    /// Output for the differential input `v_in` with REF at `ref_v`.
    pub fn output_v(&self, v_in: f64, ref_v: f64) -> f64 {
        self.output
            .drive(ref_v + self.gain() * (v_in + self.offset_v))
    }

    /// Closed-loop bandwidth `GBW / G1`.
    pub fn bandwidth_hz(&self) -> f64 {
        self.gbw_hz / self.gain()
    }

    /// Noise density referred to the input: input stage and output stage / G1.
    pub fn noise_v_per_rthz(&self) -> f64 {
        libm::hypot(
            self.input_noise_v_per_rthz,
            self.output_noise_v_per_rthz / self.gain(),
        )
    }
}

/// Second stage: non-inverting around VMID, `G2 = 1 + R_f / R_g`, finite open-loop gain A0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GainStage {
    pub feedback_ohm: f64,
    pub ground_ohm: f64,
    pub open_loop_gain: f64,
    pub gbw_hz: f64,
    pub input_noise_v_per_rthz: f64,
    pub output: Output,
}

impl GainStage {
    /// Noise gain `1 + R_f / R_g` (the ideal closed-loop gain).
    pub fn noise_gain(&self) -> f64 {
        1.0 + self.feedback_ohm / self.ground_ohm
    }

    /// Closed-loop gain with the finite open-loop gain: `G2 / (1 + G2 / A0)`.
    pub fn gain(&self) -> f64 {
        let g = self.noise_gain();
        g / (1.0 + g / self.open_loop_gain)
    }

    /// Output for input `v_in` with the gain network's foot at `mid_v`.
    pub fn output_v(&self, v_in: f64, mid_v: f64) -> f64 {
        self.output.drive(mid_v + self.gain() * (v_in - mid_v))
    }

    /// Closed-loop bandwidth `GBW / noise gain`.
    pub fn bandwidth_hz(&self) -> f64 {
        self.gbw_hz / self.noise_gain()
    }

    /// Input-referred noise density: the op amp and the thermal noise of `R_f || R_g`.
    pub fn noise_v_per_rthz(&self, temperature_k: f64) -> f64 {
        let r_par = self.feedback_ohm * self.ground_ohm / (self.feedback_ohm + self.ground_ohm);
        let e = self.input_noise_v_per_rthz;
        libm::sqrt(e * e + super::noise::thermal_v2_per_hz(r_par, temperature_k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OUT: Output = Output {
        supply_v: 3.3,
        swing_from_rail_v: 0.05,
        knee_v: 0.005,
    };

    #[test]
    fn clip_is_the_identity_well_inside_and_the_limit_well_outside() {
        assert!((clip(1.0, 0.05, 3.25, 0.005) - 1.0).abs() < 1e-15);
        assert!((clip(10.0, 0.05, 3.25, 0.005) - 3.25).abs() < 1e-12);
        assert!((clip(-10.0, 0.05, 3.25, 0.005) - 0.05).abs() < 1e-12);
        // At the corner the softplus gives k ln 2 below the limit.
        assert!(
            (clip(3.25, 0.05, 3.25, 0.005) - (3.25 - 0.005 * core::f64::consts::LN_2)).abs()
                < 1e-12
        );
    }

    #[test]
    fn inamp_gain_follows_the_datasheet_equation() {
        let a = InAmp {
            internal_ohm: 100.0e3,
            gain_resistor_ohm: 1010.0,
            offset_v: 10.0e-6,
            gbw_hz: 350.0e3,
            input_noise_v_per_rthz: 50.0e-9,
            output_noise_v_per_rthz: 200.0e-9,
            output: OUT,
        };
        let g = 1.0 + 100.0e3 / 1010.0;
        assert!((a.output_v(1.0e-3, 1.65) - (1.65 + g * 1.01e-3)).abs() < 1e-12);
        assert!((a.noise_v_per_rthz() - libm::hypot(50.0e-9, 200.0e-9 / g)).abs() < 1e-18);
    }

    #[test]
    fn gain_stage_loses_g_over_a0() {
        let s = GainStage {
            feedback_ohm: 29.1e3,
            ground_ohm: 1.0e3,
            open_loop_gain: 1.0e6,
            gbw_hz: 350.0e3,
            input_noise_v_per_rthz: 55.0e-9,
            output: OUT,
        };
        assert!((s.gain() - 30.1 / (1.0 + 30.1e-6)).abs() < 1e-12);
        assert!((s.output_v(1.66, 1.65) - (1.65 + s.gain() * 0.01)).abs() < 1e-12);
        assert!((s.output_v(2.0, 1.65) - 3.25).abs() < 1e-9);
    }
}
