//! The emulated sensor as one chain of the project's models, each stage callable alone:
//!
//! load history ([`crate::load`]) -> gel traction on the package top -> pillar ([`crate::pillar`])
//! -> chip loads Fz, Mx, My -> the bridges' signal ([`crate::forward`], the forward model
//! `tactile simulate` and the diagnosis use too: beam stresses, piezoresistor ΔR/R, bridges) ->
//! each bridge channel's circuit around its operating point: the chip's unloaded arms with this
//! board's mismatch, the trim-DAC injection, two amplifier stages with their rails, anti-alias
//! RC DC gain (`crate::frontend`) -> noise -> volts at the ADS131M04's four inputs, channel 3
//! the TMP235 ([`crate::temperature`]). As an [`AnalogInput`] and [`TrimInput`] the chain feeds
//! the register-level ADC emulation ([`crate::ads131m04`]) and follows the trim DAC the firmware
//! writes, so the firmware's real drivers run against it.
//!
//! Effects of the catalogue (`crate::effects`, `docs/diagnosis-format.md`) are off by
//! default; [`Chain::with_effects`] switches a set on. Their operators need a run's whole history
//! (peak-normalised, hysteretic), so the run is computed once on a time grid: the chip loads go
//! through the mechanical effects, the resulting offset-cut signal volts through the electrical
//! ones and the rails; what the effects add is stored per grid point and added to the live chain,
//! which keeps following the trim DAC.
//!
//! Time: conversion `n` happens at `t0 + (n - n0) T`; when the firmware changes the data rate,
//! the owner calls [`Chain::retime`] so the load history keeps running in seconds.
//! Dynamics are quasi-static: the amplifiers' (3.5 kHz) and the RC's (16 kHz) bandwidths are far
//! above the signal, so only their DC gains enter.

use chip::{ChipParams, Load};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::ads131m04::trim_dac::TrimInput;
use crate::ads131m04::AnalogInput;
use crate::forward::SignalPath;
use crate::frontend::{FrontEnd, CHANNELS};
use crate::load::{Contact, LoadHistory};
use crate::pillar::Pillar;
use crate::temperature::WarmUp;

/// The chain could not be built from `hardware/`.
#[derive(Debug)]
#[non_exhaustive]
pub enum ChainError {
    /// `chip.toml` holds a value the chip model cannot represent.
    Chip(chip::from_hardware::FromHardwareError),
}

impl std::fmt::Display for ChainError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Chip(e) => write!(f, "chip model: {e}"),
        }
    }
}

impl std::error::Error for ChainError {}

/// Conversion index to time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    index0: u64,
    t0_s: f64,
    period_s: f64,
}

impl Clock {
    pub fn new(period_s: f64) -> Self {
        Self {
            index0: 0,
            t0_s: 0.0,
            period_s,
        }
    }

    /// Time of conversion `index`.
    pub fn time_s(&self, index: u64) -> f64 {
        self.t0_s + (index as f64 - self.index0 as f64) * self.period_s
    }

    /// From conversion `index` on, conversions are `period_s` apart.
    pub fn retime(&mut self, index: u64, period_s: f64) {
        self.t0_s = self.time_s(index);
        self.index0 = index;
        self.period_s = period_s;
    }
}

/// Gaussian noise at the ADC inputs: the front end's (referred to the bridge, times the gain)
/// and the converter's own, added in quadrature per channel.
struct Noise {
    rng: ChaCha8Rng,
    rms_v: [f64; 4],
}

impl Noise {
    /// A standard normal draw (Box-Muller).
    fn normal(&mut self) -> f64 {
        let u1: f64 = 1.0 - self.rng.random::<f64>();
        let u2: f64 = self.rng.random::<f64>();
        libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(2.0 * core::f64::consts::PI * u2)
    }
}

/// The whole emulated sensor.
pub struct Chain<H> {
    pub chip: ChipParams,
    pub front_end: FrontEnd,
    /// Chip loads to the bridges' signal and its volts: the one forward model.
    pub signal: SignalPath,
    pub pillar: Pillar,
    pub warmup: WarmUp,
    pub history: H,
    pub clock: Clock,
    /// Trim-DAC codes of the three bridge channels (MCP4728 A..C).
    pub dac_codes: [u32; CHANNELS],
    noise: Option<Noise>,
    effects: Option<EffectRun>,
}

/// A run with effects, on a grid `t = k dt`: the load cell's reading and the volts the effects
/// add to each bridge channel.
struct EffectRun {
    dt_s: f64,
    load_n: Vec<f64>,
    added_v: [Vec<f64>; CHANNELS],
}

impl EffectRun {
    fn at(&self, series: &[f64], t_s: f64) -> f64 {
        let x = (t_s / self.dt_s).max(0.0);
        let k = x.floor() as usize;
        match (series.get(k), series.get(k + 1)) {
            (Some(a), Some(b)) => a + (b - a) * (x - k as f64),
            (Some(a), None) => *a,
            _ => series.last().copied().unwrap_or(0.0),
        }
    }
}

impl<H: LoadHistory> Chain<H> {
    /// The chain of `hardware/`, noise off, trim DAC at mid code, converting at the ADC's
    /// configured rate from t = 0.
    pub fn from_params(p: &hardware::Params, history: H) -> Result<Self, ChainError> {
        let front_end = FrontEnd::from_params(p);
        let mid = front_end.channels[0].trim.codes() / 2;
        let chip = ChipParams::try_from(&p.chip).map_err(ChainError::Chip)?;
        Ok(Self {
            signal: SignalPath::from_front_end(&chip, &front_end),
            chip,
            clock: Clock::new(1.0 / front_end.adc.data_rate_hz),
            front_end,
            pillar: Pillar::from_params(p),
            warmup: WarmUp::from_params(p),
            history,
            dac_codes: [mid; CHANNELS],
            noise: None,
            effects: None,
        })
    }

    /// Switch the noise on, drawn from a generator seeded with `seed` (reproducible runs).
    pub fn with_noise(mut self, seed: u64) -> Self {
        self.noise = Some(Noise {
            rng: ChaCha8Rng::seed_from_u64(seed),
            rms_v: self.noise_rms_v(),
        });
        self
    }

    /// Switch the catalogue's `effects` on for a run of `duration_s` on a grid of `dt_s` (after
    /// it, the last point holds). `contact_angle_deg` is the load's inclination (contact
    /// friction depends on it). Computed at the current trim codes; the effects' share does not
    /// depend on them (the front end is linear around its operating point).
    pub fn with_effects(
        mut self,
        effects: &crate::effects::EffectSet,
        contact_angle_deg: f64,
        duration_s: f64,
        dt_s: f64,
    ) -> Self {
        self.effects = None;
        let n = (duration_s / dt_s).ceil() as usize + 1;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * dt_s).collect();
        let mut load_n: Vec<f64> = t.iter().map(|&t| self.contact(t).load_n).collect();
        let loads: Vec<Load> = t.iter().map(|&t| self.chip_load(t)).collect();
        let mut chip: [Vec<f64>; 3] =
            core::array::from_fn(|i| loads.iter().map(|l| l.to_array()[i]).collect());
        let clean: Vec<[f64; CHANNELS]> = loads.iter().map(|&l| self.signal_v(l)).collect();
        effects.apply_mechanical(&t, &mut load_n, &mut chip, contact_angle_deg);
        let mut volts: [Vec<f64>; CHANNELS] = core::array::from_fn(|_| Vec::with_capacity(n));
        let [fz, mx, my] = &chip;
        for ((&fz, &mx), &my) in fz.iter().zip(mx).zip(my) {
            let v = self.signal_v(Load::new(fz, mx, my));
            volts
                .iter_mut()
                .zip(v)
                .for_each(|(series, x)| series.push(x));
        }
        effects.apply_electrical(&t, &mut volts);
        effects.apply_saturation(&mut volts);
        let added_v = core::array::from_fn(|i| (0..n).map(|k| volts[i][k] - clean[k][i]).collect());
        self.effects = Some(EffectRun {
            dt_s,
            load_n,
            added_v,
        });
        self
    }

    /// The load cell's reading at `t_s`, with the gel's effects when switched on.
    pub fn load_n(&self, t_s: f64) -> f64 {
        match &self.effects {
            Some(run) => run.at(&run.load_n, t_s),
            None => self.contact(t_s).load_n,
        }
    }

    /// Offset-cut volts at the ADC inputs for a chip load: the forward model's
    /// ([`SignalPath::volts`]), what [`Self::truth_v`] reads inside the rails.
    pub fn signal_v(&self, load: Load) -> [f64; CHANNELS] {
        self.signal.volts(load.to_array())
    }

    /// Noise at each ADC input, V rms, at the ADC's configured data rate.
    pub fn noise_rms_v(&self) -> [f64; 4] {
        let adc = &self.front_end.adc;
        core::array::from_fn(|ch| match self.front_end.channels.get(ch) {
            Some(c) => libm::hypot(
                c.noise_rms_v(adc.data_rate_hz) * c.gain(),
                adc.noise_rms_v[ch],
            ),
            None => adc.noise_rms_v[ch],
        })
    }

    /// Stage 1: the contact at `t_s`.
    pub fn contact(&self, t_s: f64) -> Contact {
        self.history.contact(t_s)
    }

    /// Stage 2: the load on the chip at `t_s`, through the pillar.
    pub fn chip_load(&self, t_s: f64) -> Load {
        self.pillar
            .chip_load(&self.chip, self.contact(t_s).traction)
    }

    /// Stage 3: the bridges' signal at their terminals for a chip load (the forward model).
    pub fn bridge_v(&self, load: Load) -> [f64; CHANNELS] {
        self.signal.bridge_v(load.to_array())
    }

    /// The chip's bridge arms (Fz, Mx, My) under `load`, exact, in the front end's R1..R4 order;
    /// unloaded, the operating point the signal rides on.
    pub fn arms_ohm(&self, load: Load) -> [[f64; 4]; CHANNELS] {
        core::array::from_fn(|i| {
            let [ul, ll, ur, lr] =
                chip::bridge::arm_resistances_ohm(&self.chip, &self.chip.bridges[i], load);
            // frontend::CHIP_ARM_ORDER: upper_right, lower_right, upper_left, lower_left.
            [ur, lr, ul, ll]
        })
    }

    /// Stage 4: noise-free volts at the ADC inputs of the three bridge channels with the
    /// bridges' signal `bridge_v` on the chip's unloaded arms (this board's mismatch, the trim at
    /// [`Self::dac_codes`], amplifiers with their rails, RC).
    pub fn adc_input_v(&self, bridge_v: [f64; CHANNELS]) -> [f64; CHANNELS] {
        let mid = self.front_end.mid_v();
        let arms = self.arms_ohm(Load::default());
        core::array::from_fn(|i| {
            let channel = &self.front_end.channels[i];
            channel.adc_input_v_for_arms(arms[i], bridge_v[i], self.dac_codes[i], mid)
        })
    }

    /// Stage 4': the temperature channel's volts at `t_s`.
    pub fn temperature_v(&self, t_s: f64) -> f64 {
        self.warmup.sensor_v(&self.front_end.temperature, t_s)
    }

    /// Noise-free volts at the four ADC inputs at `t_s` (effects included when on).
    pub fn clean_v(&self, t_s: f64) -> [f64; 4] {
        let mut bridges = self.adc_input_v(self.bridge_v(self.chip_load(t_s)));
        if let Some(run) = &self.effects {
            (0..CHANNELS).for_each(|i| bridges[i] += run.at(&run.added_v[i], t_s));
        }
        [bridges[0], bridges[1], bridges[2], self.temperature_v(t_s)]
    }

    /// The ground truth after the offset cut: the bridge channels' noise-free volts minus their
    /// volts unloaded at the same trim codes (what a perfect tare removes).
    pub fn truth_v(&self, t_s: f64) -> [f64; CHANNELS] {
        let loaded = self.clean_v(t_s);
        let rest = self.adc_input_v([0.0; CHANNELS]);
        core::array::from_fn(|i| loaded[i] - rest[i])
    }

    /// Volts at the four inputs at `t_s` with noise, if switched on (advances the generator).
    pub fn volts(&mut self, t_s: f64) -> [f64; 4] {
        let mut v = self.clean_v(t_s);
        if let Some(noise) = &mut self.noise {
            for (ch, x) in v.iter_mut().enumerate() {
                *x += noise.rms_v[ch] * noise.normal();
            }
        }
        v
    }

    /// From conversion `index` on the ADC converts every `period_s` (a data-rate change).
    pub fn retime(&mut self, index: u64, period_s: f64) {
        self.clock.retime(index, period_s);
    }
}

impl<H: LoadHistory> AnalogInput for Chain<H> {
    fn sample_v(&mut self, index: u64) -> [f32; 4] {
        self.volts(self.clock.time_s(index)).map(|v| v as f32)
    }
}

impl<H> TrimInput for Chain<H> {
    /// DAC channels A..C trim the bridges; channel D makes VMID from its EEPROM code, which the
    /// firmware must not change, so writes to it do not move the emulated reference.
    fn set_trim(&mut self, channel: usize, code: u16) {
        if let Some(c) = self.dac_codes.get_mut(channel) {
            *c = u32::from(code);
        }
    }
}
