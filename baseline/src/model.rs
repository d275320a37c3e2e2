//! The baseline model of a compression test: what the project predicts with no catalogue effect.
//!
//! rod travel -> [`FingertipResponse`] (probe force and chip loads per unit gel modulus; the
//! neo-Hookean response scales linearly with E at fixed geometry) -> x E, force-law warp,
//! azimuth correction -> chip loads -> volts at the ADC inputs through the emulated sensor's own
//! signal path (`sim::forward`, inside [`Readout`]) -> x the calibrated sensitivity scales,
//! plus offsets. The calibrated parameters ([`BaselineParams`]) are adjustments around that one
//! forward model; the catalogue effects of `sim::effects` slot in between (mechanical on loads,
//! electrical on volts); see [`evaluate`].

use sim::effects::EffectSet;
use sim::forward::SignalPath;

use crate::map_by_load::MapByLoad;
use crate::response::{FingertipResponse, UnitResponse};

/// From chip loads to the volts at the ADC inputs: the emulated sensor's signal path (the one
/// forward model, [`SignalPath`]) with the recording's gains and excitation, and the firmware's
/// smoother when the recording says it was on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readout {
    /// Chip loads to volts at the ADC inputs.
    pub signal: SignalPath,
    /// Time constant of the firmware's first-order smoother y += alpha (x - y), if it is on:
    /// tau = dt / ln(1 / (1 - alpha)) (see [`smoother_tau_s`]).
    pub smoother_tau_s: Option<f64>,
}

/// The smoother `y[k] = y[k-1] + alpha (x[k] - y[k-1])` at `sample_rate_hz` as a first-order
/// low-pass: its step response e^{-k ln(1/(1-alpha))} gives tau = dt / ln(1 / (1 - alpha)).
pub fn smoother_tau_s(alpha: f64, sample_rate_hz: f64) -> Option<f64> {
    (alpha > 0.0 && alpha < 1.0).then(|| 1.0 / sample_rate_hz / (1.0 / (1.0 - alpha)).ln())
}

impl Readout {
    /// The chip of `hardware/chip.toml` (its sensitivity matrix per volt of its excitation);
    /// gains and excitation as given (the recording's metadata when diagnosing).
    pub fn from_chip(
        hw: &hardware::Params,
        gain: [f64; 3],
        excitation_v: f64,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        let chip = chip::ChipParams::try_from(&hw.chip)?;
        Ok(Self {
            signal: SignalPath::from_chip(&chip, gain, excitation_v),
            smoother_tau_s: None,
        })
    }

    /// Everything from `hardware/`: the emulated sensor's own signal path (the chip's
    /// sensitivities, the amplifier chains' DC gains, the bridge excitation), smoother off.
    pub fn from_hardware(
        hw: &hardware::Params,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        Ok(Self {
            signal: SignalPath::from_params(hw)?,
            smoother_tau_s: None,
        })
    }

    /// The volts at the ADC inputs for chip loads `chip` [Fz N, Mx N·m, My N·m].
    pub fn volts(&self, chip: [f64; 3]) -> [f64; 3] {
        self.signal.volts(chip)
    }

    /// [`Self::volts`] with the calibrated sensitivity scales of `p`.
    pub fn scaled_volts(&self, chip: [f64; 3], p: &BaselineParams) -> [f64; 3] {
        let v = self.volts(chip);
        let scale = p.scales();
        std::array::from_fn(|b| v[b] * scale[b])
    }
}

/// The baseline's free parameters, calibrated by the diagnosis within the bounds of
/// `hardware/fit-bounds.toml`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineParams {
    pub youngs_modulus_pa: f64,
    /// Change of the force–indentation exponent against the fingertip model's own.
    pub exponent_shift: f64,
    /// Curvature of ln F against ln(rod travel): a force law whose local exponent itself changes
    /// with indentation (finite thickness, contact growth), F ~ (d/d_max)^(shift + k ln(d/d_max)).
    pub exponent_curvature: f64,
    /// Sensitivity scales of the Fz, Mx and My channels against the nominal front end (each
    /// output's own gain: a recording's metadata gains may each be wrong).
    pub scale: [f64; 3],
    /// ln F added at 60 %, 30 % and 10 % of the largest travel ([`WARP_KNOTS`]), interpolated
    /// linearly in ln(travel) and zero at the largest travel and at 1 %: a contact law whose
    /// local exponent wanders in ways no smooth power captures (another gel, another model).
    pub force_warp: [f64; 3],
    /// The contact law between the FE's (0) and the power law of the travel that best matches
    /// it over 10-100 % of the largest travel (1): another law need not show the FE's features.
    pub force_law_blend: f64,
    /// Each output's map between the FE's (0) and one linear in the load (1): the FE's own
    /// departure from proportional, r(F) = (chip / F) / (chip / F)_max, raised to 1 - b.
    pub map_blend: [f64; 3],
    /// Where the outputs' maps are read ([`crate::map_by_load`]): at the FE's load at that travel
    /// (0: the outputs follow the travel) or at the calibrated law's (1: they follow the load).
    pub map_load_share: f64,
    /// ln of the load the outputs' maps follow over the FE's at the largest travel
    /// ([`crate::map_by_load`]): another law's level, where the modulus moved the load alone.
    pub map_load_level: f64,
    /// Rotation of the moment vector, deg: the jig's mounting error. Data only (the proof's
    /// truth); the fit leaves it at 0, since in a one-direction test the two moment scales
    /// carry the same rotation.
    pub azimuth_shift_deg: f64,
    /// Offsets of load_N, fz_V, mx_V, my_V.
    pub offset: [f64; 4],
}

impl BaselineParams {
    /// The sensitivity scales of the three output channels [Fz, Mx, My].
    pub fn scales(&self) -> [f64; 3] {
        self.scale
    }

    /// The nominal model at modulus `youngs_modulus_pa`: no deviation, no offset.
    pub fn nominal(youngs_modulus_pa: f64) -> Self {
        Self {
            youngs_modulus_pa,
            exponent_shift: 0.0,
            exponent_curvature: 0.0,
            scale: [1.0; 3],
            force_warp: [0.0; 3],
            force_law_blend: 0.0,
            map_blend: [0.0; 3],
            map_load_share: 0.0,
            map_load_level: 0.0,
            azimuth_shift_deg: 0.0,
            offset: [0.0; 4],
        }
    }
}

/// ln of the smallest relative rod travel (and load) the force-law warps distinguish.
const MIN_LN_REL_ROD: f64 = -4.605_170_185_988_091; // ln(0.01)

/// Relative travels d / d_max of the force warp's knots, largest first.
pub const WARP_KNOTS: [f64; 3] = [0.6, 0.3, 0.1];

/// Where ln(d / d_max) = `l` lies among the force warp's knots: the interval j (between knot
/// j - 1 and j, counting the largest travel as knot 0 and 1 % as knot 4) and the fraction t
/// along it; `None` at or beyond either end, where the warp is 0. Fixed by the rod, so found
/// once per drive rather than in every evaluation.
fn warp_interval(l: f64) -> Option<(usize, f64)> {
    if l >= 0.0 || l <= MIN_LN_REL_ROD {
        return None;
    }
    let x = [
        0.0,
        WARP_KNOTS[0].ln(),
        WARP_KNOTS[1].ln(),
        WARP_KNOTS[2].ln(),
        MIN_LN_REL_ROD,
    ];
    let j = (1..5).find(|&j| l >= x[j]).unwrap_or(4);
    Some((j, (l - x[j - 1]) / (x[j] - x[j - 1])))
}

/// The force warp with knot values `w` on interval `at` ([`warp_interval`]): linear between the
/// knots in ln(travel), 0 at the largest travel (the modulus sets the level there) and at 1 %.
fn force_warp(w: &[f64; 3], at: Option<(usize, f64)>) -> f64 {
    let Some((j, t)) = at.filter(|_| *w != [0.0; 3]) else {
        return 0.0;
    };
    let y = [0.0, w[0], w[1], w[2], 0.0];
    y[j - 1] + t * (y[j] - y[j - 1])
}

/// The drive of one evaluation: a time base and the unit response at each time.
///
/// Everything but the time and the temperature is a function of the rod's travel (and the
/// response there), and a test's rod stands still most of the time (holds, rests, the encoder's
/// quanta): the drive keeps one `AtTravel` per run of equal samples and each sample's run.
/// An hour at 1 kHz held 144 bytes a sample (540 MB) before; now 12 and its runs.
#[derive(Debug, Clone)]
pub struct Drive {
    pub t_s: Vec<f64>,
    /// The run ([`Drive::at`]) of each sample.
    run: Vec<u32>,
    /// What the drive knows at each run's travel.
    at: Vec<AtTravel>,
    /// The outputs' maps against the load, to read them at another load ([`MapByLoad`]).
    map_by_load: std::sync::Arc<MapByLoad>,
    /// Measured temperature at each time, for a drift regressed on it.
    pub temp_c: Option<Vec<f64>>,
}

/// The drive at one travel: the unit response and what the calibration's laws read there.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AtTravel {
    unit: UnitResponse,
    /// ln(rod / rod_max) where in contact (for the exponent shift), 0 elsewhere.
    ln_rel_rod: f64,
    /// Where ln(rod / rod_max) lies among the force warp's knots ([`warp_interval`]).
    warp_at: Option<(usize, f64)>,
    /// ln of the power law matching the fingertip's force less ln of its force, in contact
    /// ([`matching_power_law`]): the force-law blend's direction.
    to_power_law: f64,
    /// ln r(F) of each output: the FE's departure from an output linear in the load, relative to
    /// full load (for the outputs' map blend), 0 out of contact.
    ln_map_departure: [f64; 3],
    /// ln of the fingertip's force per Pa in contact (the load its maps are read at), else
    /// `None`; and the table's maps there.
    ln_unit_force: Option<f64>,
    map_at_own_load: [f64; 3],
}

impl AtTravel {
    /// ln of the calibrated force over the fingertip's own here: the same law as
    /// [`Drive::contact_shape_basis`] (linear in those parameters), evaluated directly.
    fn ln_force_warp(&self, p: &BaselineParams) -> f64 {
        let l = self.ln_rel_rod;
        p.exponent_shift * l
            + p.exponent_curvature * l * l
            + force_warp(&p.force_warp, self.warp_at)
            + p.force_law_blend * self.to_power_law
    }

    /// The factors of the three outputs here that give them their calibrated maps: the
    /// FE's departure r raised to 1 - b (the map blend), read at the load of
    /// [`crate::map_by_load`] (`warp`: ln of the calibrated force over the fingertip's own).
    fn map_factors(&self, map_by_load: &MapByLoad, p: &BaselineParams, warp: f64) -> [f64; 3] {
        let moved = match self.ln_unit_force {
            Some(x) if p.map_load_share != 0.0 || p.map_load_level != 0.0 => {
                let x = x + p.map_load_share * warp + p.map_load_level;
                Some(map_by_load.at(x))
            }
            _ => None,
        };
        std::array::from_fn(|k| {
            let b = p.map_blend[k];
            let mut e = -b * self.ln_map_departure[k];
            if let Some(m) = moved {
                e += (1.0 - b) * (m[k] - self.map_at_own_load[k]);
            }
            if e != 0.0 {
                e.exp()
            } else {
                1.0
            }
        })
    }

    /// The calibrated load and chip loads here (before the mechanical effects), with the
    /// moments turned by the azimuth shift (`sin`, `cos`).
    fn calibrated(
        &self,
        map_by_load: &MapByLoad,
        p: &BaselineParams,
        (s, c): (f64, f64),
    ) -> [f64; 4] {
        let u = &self.unit;
        let warp = self.ln_force_warp(p);
        let w = p.youngs_modulus_pa * if warp != 0.0 { warp.exp() } else { 1.0 };
        let share = self.map_factors(map_by_load, p, warp);
        let (mx, my) = (u.chip[1] * w * share[1], u.chip[2] * w * share[2]);
        [
            u.force_n * w,
            u.chip[0] * w * share[0],
            mx * c - my * s,
            mx * s + my * c,
        ]
    }
}

/// The runs of samples `0..n` over which `same(i - 1, i)` holds: each sample's run, and each
/// run's first sample.
fn runs(n: usize, same: impl Fn(usize, usize) -> bool) -> (Vec<u32>, Vec<usize>) {
    let mut run = Vec::with_capacity(n);
    let mut first = Vec::new();
    for i in 0..n {
        if i == 0 || !same(i - 1, i) {
            first.push(i);
        }
        // A drive of more than 2^32 runs would be 300 GB of them.
        run.push(u32::try_from(first.len() - 1).expect("fewer than 2^32 runs"));
    }
    (run, first)
}

impl Drive {
    pub fn new(model: &dyn FingertipResponse, t_s: Vec<f64>, rod_mm: &[f64]) -> Self {
        let rod_max = rod_mm.iter().cloned().fold(0.0, f64::max);
        let law = matching_power_law(model, rod_max);
        // Equal travels, bit for bit, have one response: it is looked up once per run.
        let (run, first) = runs(rod_mm.len(), |i, j| {
            rod_mm[i].to_bits() == rod_mm[j].to_bits()
        });
        let rods: Vec<f64> = first.iter().map(|&i| rod_mm[i]).collect();
        let (unit, power) = rods
            .iter()
            .map(|&d| (model.unit_response(d), law.force(d)))
            .unzip();
        let map = MapByLoad::new(model, rod_max);
        Self::with_runs(t_s, (run, &rods), rod_max, (unit, power), map)
    }

    /// The drive of block means: the response averaged over each block's full-rate travels
    /// `full_rod_mm[a..b]` (`bounds`), as the recorded block means are. The response at the
    /// block's mean travel would differ by F'' var(d) / 2, on a fast ramp's blocks many times
    /// the noise of their means (the force is convex in the travel).
    pub fn over_blocks(
        model: &dyn FingertipResponse,
        t_s: Vec<f64>,
        rod_mm: &[f64],
        full_rod_mm: &[f64],
        bounds: &[(usize, usize)],
    ) -> Self {
        let rod_max = full_rod_mm.iter().cloned().fold(0.0, f64::max);
        let law = matching_power_law(model, rod_max);
        let (unit, power) = bounds
            .iter()
            .map(|&(a, b)| {
                let n = (b - a).max(1) as f64;
                let sum = full_rod_mm[a..b].iter().fold([0.0; 5], |mut acc, &d| {
                    let u = model.unit_response(d);
                    acc[0] += u.force_n;
                    (0..3).for_each(|k| acc[k + 1] += u.chip[k]);
                    acc[4] += law.force(d);
                    acc
                });
                let unit = UnitResponse {
                    force_n: sum[0] / n,
                    chip: [sum[1] / n, sum[2] / n, sum[3] / n],
                };
                (unit, sum[4] / n)
            })
            .unzip();
        let map = MapByLoad::new(model, rod_max);
        Self::with_units(t_s, rod_mm, rod_max, unit, power, map)
    }

    /// The drive of a response given sample by sample (`unit[i]` at `t_s[i]`, `rod_mm[i]`): a
    /// simulation of the test in time, or a table already driven along the rod. It has no law
    /// of the travel behind it, so the contact law's shape and the outputs' maps read at another
    /// load have nothing to act on: a calibration of such a drive holds them at 0 (the force-law
    /// blend's target is the response itself, the maps read at another load are its own).
    pub fn of_samples(t_s: Vec<f64>, rod_mm: &[f64], unit: Vec<UnitResponse>) -> Self {
        assert_eq!(unit.len(), rod_mm.len(), "one response per sample");
        let rod_max = rod_mm.iter().cloned().fold(0.0, f64::max);
        let power = unit.iter().map(|u| u.force_n).collect();
        Self::with_units(t_s, rod_mm, rod_max, unit, power, MapByLoad::none())
    }

    /// [`Drive::of_samples`] on block means: the full-rate responses `full_unit` averaged over
    /// each block `bounds` (as the recorded block means are, [`Drive::over_blocks`]).
    pub fn over_blocks_of_samples(
        t_s: Vec<f64>,
        rod_mm: &[f64],
        full_unit: &[UnitResponse],
        bounds: &[(usize, usize)],
    ) -> Self {
        let unit = bounds
            .iter()
            .map(|&(a, b)| {
                let n = (b - a).max(1) as f64;
                let sum = full_unit[a..b].iter().fold([0.0; 4], |mut acc, u| {
                    acc[0] += u.force_n;
                    (0..3).for_each(|k| acc[k + 1] += u.chip[k]);
                    acc
                });
                UnitResponse {
                    force_n: sum[0] / n,
                    chip: [sum[1] / n, sum[2] / n, sum[3] / n],
                }
            })
            .collect();
        Self::of_samples(t_s, rod_mm, unit)
    }

    /// `power`: the matching power law's force per Pa at each sample (block means for a drive
    /// of blocks), the force-law blend's target.
    fn with_units(
        t_s: Vec<f64>,
        rod_mm: &[f64],
        rod_max: f64,
        unit: Vec<UnitResponse>,
        power: Vec<f64>,
        map_by_load: MapByLoad,
    ) -> Self {
        let (run, first) = runs(rod_mm.len(), |i, j| {
            rod_mm[i].to_bits() == rod_mm[j].to_bits()
                && unit[i] == unit[j]
                && power[i].to_bits() == power[j].to_bits()
        });
        let rods: Vec<f64> = first.iter().map(|&i| rod_mm[i]).collect();
        let unit = first.iter().map(|&i| unit[i]).collect();
        let power = first.iter().map(|&i| power[i]).collect();
        Self::with_runs(t_s, (run, &rods), rod_max, (unit, power), map_by_load)
    }

    /// The drive of samples in runs (`run`, each sample's), with each run's travel, unit
    /// response and matching power law's force per Pa.
    fn with_runs(
        t_s: Vec<f64>,
        (run, rod_mm): (Vec<u32>, &[f64]),
        rod_max: f64,
        (unit, power): (Vec<UnitResponse>, Vec<f64>),
        map_by_load: MapByLoad,
    ) -> Self {
        let departure = map_departure(&unit);
        let at = rod_mm
            .iter()
            .zip(unit)
            .zip(power)
            .zip(departure)
            .map(|(((&d, u), p), ln_map_departure)| {
                // Frozen below 1 % of the largest travel: the warp must stay bounded as d -> 0
                // (a positive curvature would otherwise blow up at travels of 1e-16 mm).
                let ln_rel_rod = if d > 0.0 && rod_max > 0.0 {
                    (d / rod_max).ln().max(MIN_LN_REL_ROD)
                } else {
                    0.0
                };
                let ln_unit_force = (u.force_n > 0.0).then(|| u.force_n.ln());
                AtTravel {
                    unit: u,
                    ln_rel_rod,
                    warp_at: warp_interval(ln_rel_rod),
                    to_power_law: if u.force_n > 0.0 && p > 0.0 {
                        p.ln() - u.force_n.ln()
                    } else {
                        0.0
                    },
                    ln_map_departure,
                    ln_unit_force,
                    map_at_own_load: ln_unit_force.map_or([0.0; 3], |x| map_by_load.at(x)),
                }
            })
            .collect();
        Self {
            t_s,
            run,
            at,
            map_by_load: std::sync::Arc::new(map_by_load),
            temp_c: None,
        }
    }

    /// What the drive knows at sample `i`'s travel.
    fn at(&self, i: usize) -> &AtTravel {
        &self.at[self.run[i] as usize]
    }

    /// The unit response at sample `i`.
    pub fn unit(&self, i: usize) -> &UnitResponse {
        &self.at(i).unit
    }

    /// The unit response at each sample, in order.
    pub fn units(&self) -> impl Iterator<Item = &UnitResponse> + '_ {
        self.run.iter().map(|&r| &self.at[r as usize].unit)
    }

    /// ln r of each output at sample `i`: the FE's departure from an output linear in the
    /// load, relative to full load; 0 out of contact.
    pub fn ln_map_departure(&self, i: usize) -> [f64; 3] {
        self.at(i).ln_map_departure
    }

    /// The same drive with the temperature measured at each of its times.
    pub fn with_temperature(self, temp_c: Option<Vec<f64>>) -> Self {
        Self { temp_c, ..self }
    }

    /// How ln F at sample `i` moves with each of the contact law's shape parameters, in their
    /// order in the fit's vector: exponent shift, curvature, the warp's knots, the force-law
    /// blend. `None` out of contact.
    pub fn contact_shape_basis(&self, i: usize) -> Option<[f64; 6]> {
        let a = self.at(i);
        let l = a.ln_rel_rod;
        if l == 0.0 && a.unit.force_n <= 0.0 {
            return None;
        }
        let knot = |j: usize| {
            let mut w = [0.0; 3];
            w[j] = 1.0;
            force_warp(&w, a.warp_at)
        };
        Some([l, l * l, knot(0), knot(1), knot(2), a.to_power_law])
    }

    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }
}

/// A power law of the travel, F = exp(a) (d / d_max)^b per Pa.
#[derive(Debug, Clone, Copy)]
struct PowerLaw {
    a: f64,
    b: f64,
    rod_max: f64,
}

impl PowerLaw {
    fn force(&self, rod_mm: f64) -> f64 {
        if rod_mm > 0.0 && self.rod_max > 0.0 {
            (self.a + self.b * (rod_mm / self.rod_max).ln()).exp()
        } else {
            0.0
        }
    }
}

/// The power law closest to `model`'s force over 10-100 % of `rod_max` (least squares in
/// ln F at 19 travels even in ln d). Found from the model and the largest travel alone, so the
/// fit's block drive and the full-rate drive blend towards the same law.
fn matching_power_law(model: &dyn FingertipResponse, rod_max: f64) -> PowerLaw {
    let points: Vec<(f64, f64)> = (0..19)
        .map(|k| -std::f64::consts::LN_10 * k as f64 / 18.0)
        .filter_map(|l| {
            let f = model.unit_response(rod_max * l.exp()).force_n;
            (f > 0.0).then(|| (l, f.ln()))
        })
        .collect();
    let n = points.len() as f64;
    if n < 2.0 {
        return PowerLaw {
            a: 0.0,
            b: 0.0,
            rod_max: 0.0,
        };
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.0 / n, y + p.1 / n));
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    PowerLaw {
        a: my - b * mx,
        b,
        rod_max,
    }
}

/// Largest |ln r| of an output's departure from linear: beyond a decade the ratio is of two
/// numbers near zero (a moment at no inclination), not a map.
const MAX_LN_DEPARTURE: f64 = std::f64::consts::LN_10;

/// ln r(F) = ln[(chip / F) / (chip / F) at the largest load] of each output at each sample in
/// contact, 0 out of it. The table interpolates chip / F itself and holds it below its first
/// point, so the ratio stays a map down to the lightest touch; cut off at 1 % of the largest
/// load, as it once was, the outputs of a model linear in the load kept the FE's map there.
fn map_departure(unit: &[UnitResponse]) -> Vec<[f64; 3]> {
    let Some(top) = unit.iter().max_by(|a, b| a.force_n.total_cmp(&b.force_n)) else {
        return Vec::new();
    };
    unit.iter()
        .map(|u| {
            std::array::from_fn(|k| {
                let (r, r_top) = (u.chip[k] / u.force_n, top.chip[k] / top.force_n);
                let ratio = r / r_top;
                if u.force_n > 0.0 && ratio > 0.0 && ratio.is_finite() {
                    ratio.ln().clamp(-MAX_LN_DEPARTURE, MAX_LN_DEPARTURE)
                } else {
                    0.0
                }
            })
        })
        .collect()
}

/// Model output: load and the three output voltages on the drive's time base.
#[derive(Debug, Clone, PartialEq)]
pub struct Outputs {
    pub load_n: Vec<f64>,
    pub volts: [Vec<f64>; 3],
}

impl Outputs {
    /// Channel `c` in contract order load_N, fz_V, mx_V, my_V.
    pub fn channel(&self, c: usize) -> &[f64] {
        if c == 0 {
            &self.load_n
        } else {
            &self.volts[c - 1]
        }
    }
}

/// A hook on the output volts just ahead of the amplifier rails.
pub type RailHook<'h> = &'h mut dyn FnMut(&mut [Vec<f64>; 3]);

/// Run the baseline with `chain` switched on. `before_rails` is called on the volts after the
/// offsets and before saturation (the simulator adds its noise there).
pub fn evaluate(
    drive: &Drive,
    readout: &Readout,
    p: &BaselineParams,
    chain: &EffectSet,
    contact_angle_deg: f64,
    before_rails: Option<RailHook>,
) -> Outputs {
    let n = drive.len();
    let mut load = Vec::with_capacity(n);
    let mut chip: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(n));
    let (s, c) = p.azimuth_shift_deg.to_radians().sin_cos();
    // Once per run of equal travels, then spread over its samples.
    let at: Vec<[f64; 4]> = drive
        .at
        .iter()
        .map(|a| a.calibrated(&drive.map_by_load, p, (s, c)))
        .collect();
    for &r in &drive.run {
        let v = &at[r as usize];
        load.push(v[0]);
        chip.iter_mut().zip(&v[1..]).for_each(|(x, &v)| x.push(v));
    }
    chain.apply_mechanical(&drive.t_s, &mut load, &mut chip, contact_angle_deg);
    let mut volts: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(n));
    let [fz, mx, my] = &chip;
    for ((&a, &b), &c) in fz.iter().zip(mx).zip(my) {
        let v = readout.scaled_volts([a, b, c], p);
        volts.iter_mut().zip(v).for_each(|(out, v)| out.push(v));
    }
    chain.apply_electrical_at(&drive.t_s, drive.temp_c.as_deref(), &mut volts);
    load.iter_mut().for_each(|f| *f += p.offset[0]);
    for (out, offset) in volts.iter_mut().zip(&p.offset[1..]) {
        out.iter_mut().for_each(|v| *v += offset);
    }
    if let Some(f) = before_rails {
        f(&mut volts);
    }
    chain.apply_saturation(&mut volts);
    if let Some(tau_s) = readout.smoother_tau_s {
        // Low-pass = input minus its high-pass, integrated exactly on any time base.
        let hp = sim::effects::HighpassCoupling { tau_s };
        for v in volts.iter_mut() {
            let mut h = v.clone();
            hp.apply(&drive.t_s, &mut h);
            v.iter_mut().zip(h).for_each(|(x, h)| *x -= h);
        }
    }
    Outputs {
        load_n: load,
        volts,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::Linear;

    /// The recursive smoother and its continuous equivalent agree on a step.
    #[test]
    fn smoother_time_constant() {
        let (alpha, rate) = (0.2, 1000.0);
        let tau = smoother_tau_s(alpha, rate).unwrap();
        let mut y = 0.0;
        for _ in 0..10 {
            y += alpha * (1.0 - y);
        }
        assert!((y - (1.0 - (-10.0 / rate / tau).exp())).abs() < 1e-12);
    }

    #[test]
    fn outputs_scale_linearly_with_modulus() {
        let fe = Readout {
            signal: SignalPath {
                sensitivity_per_v: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                gain: [2.0, 3.0, 3.0],
                excitation_v: 1.5,
            },
            smoother_tau_s: None,
        };
        let drive = Drive::new(&Linear, vec![0.0, 1.0, 2.0], &[0.0, 1.0, 2.0]);
        let chain = EffectSet::default();
        let a = evaluate(
            &drive,
            &fe,
            &BaselineParams::nominal(1.0),
            &chain,
            20.0,
            None,
        );
        let b = evaluate(
            &drive,
            &fe,
            &BaselineParams::nominal(2.0),
            &chain,
            20.0,
            None,
        );
        assert_eq!(a.volts[0], vec![0.0, 3.0, 6.0]);
        assert_eq!(b.volts[1], vec![0.0, -9.0, -18.0]);
        assert_eq!(b.load_n[2], 4.0);
    }

    /// A drive of per-sample responses evaluates as the model's own at the nominal shape, and
    /// its block drive averages the samples of each block.
    #[test]
    fn a_drive_of_samples_reads_each_sample_and_averages_blocks() {
        let readout = Readout {
            signal: SignalPath {
                sensitivity_per_v: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                gain: [2.0, 3.0, 3.0],
                excitation_v: 1.5,
            },
            smoother_tau_s: None,
        };
        let (t, rod) = (vec![0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 3.0]);
        let units: Vec<UnitResponse> = rod.iter().map(|&d| Linear.unit_response(d)).collect();
        let p = BaselineParams::nominal(2.0);
        let chain = EffectSet::default();
        let of = evaluate(
            &Drive::of_samples(t.clone(), &rod, units.clone()),
            &readout,
            &p,
            &chain,
            20.0,
            None,
        );
        let ours = evaluate(
            &Drive::new(&Linear, t, &rod),
            &readout,
            &p,
            &chain,
            20.0,
            None,
        );
        assert_eq!(of, ours);
        let blocks =
            Drive::over_blocks_of_samples(vec![0.5, 2.5], &[0.5, 2.5], &units, &[(0, 2), (2, 4)]);
        assert_eq!(blocks.unit(1).force_n, 2.5);
        assert_eq!(blocks.unit(0).chip[1], -0.5);
    }
}
