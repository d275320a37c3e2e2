//! `frontend.toml`: bridge mismatch, the trim-DAC offset cut, the two amplifier
//! stages, the anti-alias RC and the temperature sensor. Derived figures (gains, trim range,
//! noise) are computed by the models in `sim::frontend`, not here: this is data.

use std::path::Path;

use crate::{ParamError, Reader};

/// Number of bridge channels: Fz, Mx, My (ADC channels 0, 1, 2).
pub const BRIDGES: usize = 3;

/// The analog front end between the chip and the ADC.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontEnd {
    /// The single analog rail (AVDD) that feeds bridges, DAC, amplifiers and ADC.
    pub supply_v: f64,
    /// MCP4728 channel D code that makes VMID, the common reference.
    pub mid_dac_code: u32,
    pub bridge: Bridge,
    pub trim: Trim,
    pub stage1: InAmp,
    pub stage2: GainStage,
    pub antialias: AntiAlias,
    pub temperature: TempSensor,
}

/// How the chip's three bridges (nominal values in `chip.toml`) differ from nominal.
#[derive(Debug, Clone, PartialEq)]
pub struct Bridge {
    /// Largest fractional mismatch of any arm: sets the worst-case raw offset.
    pub arm_tolerance: f64,
    /// Fractional mismatch of arms [R1, R2, R3, R4] per channel [Fz, Mx, My].
    pub arm_mismatch: [[f64; 4]; BRIDGES],
    /// Noise temperature of the resistors.
    pub temperature_k: f64,
}

/// The trim DAC and its summing resistors into the bridge outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Trim {
    /// DAC resolution.
    pub dac_bits: u32,
    /// Summing resistor from a DAC output to a bridge's positive output node, per channel.
    pub injection_ohm: [f64; BRIDGES],
}

/// The first stage: an instrumentation amplifier per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct InAmp {
    pub part: String,
    /// `G = 1 + internal_ohm / RG`.
    pub internal_ohm: f64,
    /// Gain-setting resistor RG per channel.
    pub gain_resistor_ohm: [f64; BRIDGES],
    pub gbw_hz: f64,
    pub input_noise_v_per_rthz: f64,
    pub output_noise_v_per_rthz: f64,
    pub offset_max_v: f64,
    /// Input offset of each channel's amplifier.
    pub offset_v: [f64; BRIDGES],
    /// Closest approach of the output to either rail.
    pub swing_from_rail_v: f64,
    /// Width of the softplus corner with which the output approaches that limit.
    pub knee_v: f64,
}

/// The second stage: a non-inverting op-amp stage around VMID per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct GainStage {
    pub part: String,
    pub feedback_ohm: [f64; BRIDGES],
    pub ground_ohm: [f64; BRIDGES],
    pub gbw_hz: f64,
    pub open_loop_gain_db: f64,
    pub input_noise_v_per_rthz: f64,
    pub swing_from_rail_v: f64,
    pub knee_v: f64,
}

/// The RC between each second stage and its ADC input pair.
#[derive(Debug, Clone, PartialEq)]
pub struct AntiAlias {
    /// Series resistor in each of the two legs.
    pub series_ohm: f64,
    /// Capacitor across AINxP-AINxN.
    pub diff_cap_f: f64,
    /// Capacitor from each input to ground.
    pub cm_cap_f: f64,
}

/// The analog temperature sensor on ADC channel 3.
#[derive(Debug, Clone, PartialEq)]
pub struct TempSensor {
    pub part: String,
    /// Output at 0 degC.
    pub offset_v: f64,
    pub slope_v_per_c: f64,
}

impl FrontEnd {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let fe = Self::read(&mut r);
        fe.check(&mut r);
        r.finish()?;
        Ok(fe)
    }

    fn read(r: &mut Reader) -> Self {
        let supply_v = r.f64("supply.analog_v", 2.7..=5.5);
        Self {
            supply_v,
            mid_dac_code: r.int("supply.mid_dac_code", 0..=65535) as u32,
            bridge: Bridge {
                arm_tolerance: r.f64("bridge.arm_tolerance", 0.0..=0.05),
                arm_mismatch: [
                    r.f64_array("bridge.arm_mismatch_fz", -0.05..=0.05),
                    r.f64_array("bridge.arm_mismatch_mx", -0.05..=0.05),
                    r.f64_array("bridge.arm_mismatch_my", -0.05..=0.05),
                ],
                temperature_k: r.f64("bridge.temperature_k", 200.0..=400.0),
            },
            trim: Trim {
                dac_bits: r.int("trim.dac_bits", 8..=16) as u32,
                injection_ohm: r.f64_array("trim.injection_ohm", 1.0e3..=100.0e6),
            },
            stage1: InAmp {
                part: r.string("stage1.part"),
                internal_ohm: r.f64("stage1.internal_ohm", 1.0e3..=1.0e6),
                gain_resistor_ohm: r.f64_array("stage1.gain_resistor_ohm", 10.0..=1.0e6),
                gbw_hz: r.f64("stage1.gbw_hz", 1.0e3..=100.0e6),
                input_noise_v_per_rthz: r.f64("stage1.input_noise_v_per_rthz", 0.0..=1.0e-6),
                output_noise_v_per_rthz: r.f64("stage1.output_noise_v_per_rthz", 0.0..=10.0e-6),
                offset_max_v: r.f64("stage1.offset_max_v", 0.0..=10.0e-3),
                offset_v: r.f64_array("stage1.offset_v", -10.0e-3..=10.0e-3),
                swing_from_rail_v: r.f64("stage1.swing_from_rail_v", 0.0..=2.0),
                knee_v: r.f64("stage1.knee_v", 1.0e-5..=0.1),
            },
            stage2: GainStage {
                part: r.string("stage2.part"),
                feedback_ohm: r.f64_array("stage2.feedback_ohm", 0.0..=10.0e6),
                ground_ohm: r.f64_array("stage2.ground_ohm", 10.0..=10.0e6),
                gbw_hz: r.f64("stage2.gbw_hz", 1.0e3..=100.0e6),
                open_loop_gain_db: r.f64("stage2.open_loop_gain_db", 60.0..=180.0),
                input_noise_v_per_rthz: r.f64("stage2.input_noise_v_per_rthz", 0.0..=1.0e-6),
                swing_from_rail_v: r.f64("stage2.swing_from_rail_v", 0.0..=2.0),
                knee_v: r.f64("stage2.knee_v", 1.0e-5..=0.1),
            },
            antialias: AntiAlias {
                series_ohm: r.f64("antialias.series_ohm", 0.0..=100.0e3),
                diff_cap_f: r.f64("antialias.diff_cap_f", 0.0..=10.0e-6),
                cm_cap_f: r.f64("antialias.cm_cap_f", 0.0..=10.0e-6),
            },
            temperature: TempSensor {
                part: r.string("temperature.part"),
                offset_v: r.f64("temperature.offset_v", -1.0..=2.0),
                slope_v_per_c: r.f64("temperature.slope_v_per_c", -0.1..=0.1),
            },
        }
    }

    /// Rules across keys; each has its own test in `tests/frontend_rules.rs`.
    fn check(&self, r: &mut Reader) {
        let full_scale = 1u64 << self.trim.dac_bits;
        if u64::from(self.mid_dac_code) >= full_scale {
            r.reject(
                "supply.mid_dac_code",
                format!("must be below 2^trim.dac_bits = {full_scale}"),
            );
        }
        let names = [
            "bridge.arm_mismatch_fz",
            "bridge.arm_mismatch_mx",
            "bridge.arm_mismatch_my",
        ];
        for (name, arms) in names.iter().zip(&self.bridge.arm_mismatch) {
            if arms.iter().any(|d| d.abs() > self.bridge.arm_tolerance) {
                r.reject(
                    name,
                    "every arm's mismatch must lie within +-bridge.arm_tolerance",
                );
            }
        }
        if self
            .stage1
            .offset_v
            .iter()
            .any(|v| v.abs() > self.stage1.offset_max_v)
        {
            r.reject(
                "stage1.offset_v",
                "every offset must lie within +-stage1.offset_max_v",
            );
        }
        let stages = [
            ("stage1.swing_from_rail_v", self.stage1.swing_from_rail_v),
            ("stage2.swing_from_rail_v", self.stage2.swing_from_rail_v),
        ];
        for (key, swing) in stages {
            if 2.0 * swing >= self.supply_v {
                r.reject(
                    key,
                    "must be below half of supply.analog_v (no output range left)",
                );
            }
        }
        // Mismatched common-mode capacitors turn common-mode noise into a differential error;
        // keeping them a decade below the differential one bounds that (TI SBAA229).
        if self.antialias.cm_cap_f * 10.0 > self.antialias.diff_cap_f {
            r.reject(
                "antialias.cm_cap_f",
                "must be at most a tenth of antialias.diff_cap_f",
            );
        }
    }
}
