//! Temperature next to the chip (the TMP235 on ADC channel 3): the lab's air plus the
//! electronics' warm-up from power-up, a first-order thermal system
//! `T(t) = T_amb + ΔT (1 - e^(-t/τ))`, and the sensor's output `V = V_0 + S T`.

use crate::frontend::TempSensor;

/// Warm-up of the temperature near the chip after power-up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarmUp {
    /// Air temperature T_amb.
    pub ambient_c: f64,
    /// Final rise ΔT from the board's own dissipation.
    pub rise_c: f64,
    /// Thermal time constant τ.
    pub tau_s: f64,
}

impl WarmUp {
    /// Temperature `t_s` seconds after power-up (the ambient before it).
    pub fn temperature_c(&self, t_s: f64) -> f64 {
        if t_s <= 0.0 {
            return self.ambient_c;
        }
        self.ambient_c + self.rise_c * (1.0 - libm::exp(-t_s / self.tau_s))
    }

    /// The sensor's output voltage at `t_s`.
    pub fn sensor_v(&self, sensor: &TempSensor, t_s: f64) -> f64 {
        sensor.output_v(self.temperature_c(t_s))
    }
}

#[cfg(feature = "std")]
impl WarmUp {
    /// From `hardware/sim.toml`.
    pub fn from_params(p: &hardware::Params) -> Self {
        Self {
            ambient_c: p.sim.ambient_c,
            rise_c: p.sim.warmup_rise_c,
            tau_s: p.sim.warmup_tau_s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: WarmUp = WarmUp {
        ambient_c: 23.0,
        rise_c: 2.0,
        tau_s: 600.0,
    };

    #[test]
    fn reaches_63_percent_of_the_rise_after_one_time_constant() {
        // By hand: 23 + 2 (1 - 1/e) = 24.26424 degC.
        assert_eq!(W.temperature_c(0.0), 23.0);
        assert!((W.temperature_c(600.0) - 24.264_241).abs() < 1e-6);
        assert!((W.temperature_c(1.0e6) - 25.0).abs() < 1e-12);
    }

    #[test]
    fn tmp235_reads_750_mv_at_25_degc() {
        // TMP235 datasheet: 500 mV at 0 degC, 10 mV/degC.
        let s = TempSensor {
            offset_v: 0.5,
            slope_v_per_c: 0.01,
        };
        let settled = WarmUp {
            ambient_c: 25.0,
            rise_c: 0.0,
            tau_s: 1.0,
        };
        assert!((settled.sensor_v(&s, 10.0) - 0.75).abs() < 1e-12);
    }
}
