//! The calibration problem: the baseline's free parameters plus the parameters of a set of
//! catalogue effects, fitted by least squares to the decimated recording on the fitting stretch.
//!
//! Parameter vector (internal coordinates): ln E, exponent shift, the Fz, Mx and My scales, four
//! offsets, exponent curvature, the force warp's three knots, the three outputs' map blends,
//! the force-law blend, where the outputs' maps are read (load share, level),
//! then each effect's parameters (time constants as ln tau). The baseline's bounds are
//! `hardware/fit-bounds.toml`.
//! Residuals are (recorded - model) / noise level, per channel, so the sum of squares is a
//! chi-square in noise units and channels of any unit mix.

use sim::effects::{EffectKind, EffectSet};

use super::data::{Data, Series};
use super::lm::{self, Problem, Solution};
use super::specs::{effect_specs, spec, ParamSpec};
use baseline::{evaluate, BaselineParams, Drive, Outputs, Readout};

/// Number of baseline parameters at the head of the vector.
pub const N_BASE: usize = 19;
/// Index of the first output scale [Fz, Mx, My] in the parameter vector.
pub const SCALE_AT: usize = 2;
/// Index of the first offset [load, Fz, Mx, My].
pub const OFFSET_AT: usize = 5;
/// Index of the first force-warp knot (`baseline::WARP_KNOTS`).
pub const WARP_AT: usize = 10;
/// Index of the first map blend [Fz, Mx, My].
pub const BLEND_AT: usize = 13;
/// Index of the force-law blend (`BaselineParams::force_law_blend`).
pub const LAW_BLEND_AT: usize = 16;
/// Index of the outputs' map load share, then of its level (`BaselineParams::map_load_share`,
/// `map_load_level`).
pub const MAP_LOAD_AT: usize = 17;

/// The least drop of a fit's BIC worth another iteration (`lm::Options::min_deviance_drop`): a
/// thousandth of the margin that decides an effect ([`crate::candidate::MIN_BIC_GAIN`]). Fits
/// crawling along a flat valley (a time constant traded against a blend), or far from the data
/// while a candidate is tried, otherwise spend half their iterations below it.
pub const MIN_BIC_STEP: f64 = 0.01;

/// Model evaluations so far in this process ([`model_evaluations`]).
static EVALUATIONS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// How many times a recording's model has been evaluated in this process: the work of the
/// fits, counted, for benchmarks on a machine whose clock is shared.
pub fn model_evaluations() -> usize {
    EVALUATIONS.load(std::sync::atomic::Ordering::Relaxed)
}

/// What stays fixed for all fits of one recording.
pub struct Setup<'a> {
    pub data: &'a Data,
    pub drive: Drive,
    /// The baseline is the user's simulation (`crate::simulation`): its modulus is a load
    /// scale, and its contact law and maps are the simulation's, held.
    pub user_simulation: bool,
    pub readout: Readout,
    pub contact_angle_deg: f64,
    /// Samples of the decimated series in the fitting stretch / in the held-out stretch.
    pub fit_mask: Vec<bool>,
    pub heldout_mask: Vec<bool>,
    /// Channels worth comparing (a peak-to-peak range above the noise).
    pub used: [bool; 4],
    /// Whether the residual may be described by the discovery step (off for a diagnosis
    /// whose discovered terms predicted the held-out stretch worse than the baseline).
    pub discover: bool,
    /// A usable measured temperature: `thermal_drift` is then regressed on it, with the
    /// warm-up time constant the temperature shows (see [`super::temperature`]).
    pub thermal: Option<super::temperature::ThermalFit>,
    /// How far the baseline may be calibrated (`hardware/fit-bounds.toml`).
    pub fit_bounds: hardware::FitBounds,
    /// [`initial_baseline`], worked out once ([`Setup::initial_baseline`]).
    pub initial: std::sync::OnceLock<Vec<f64>>,
    /// The unit the outputs hold (the recording's metadata `sensor_unit`, `V` where absent):
    /// the metadata's gains are volts, so in another unit only the data set an output's scale.
    pub sensor_unit: String,
    /// [`scale_reference`], worked out once ([`Setup::scale_reference`]).
    pub scale_reference: std::sync::OnceLock<[f64; 3]>,
}

impl Setup<'_> {
    /// The residuals the criterion counts on the fitting stretch: those of the compared
    /// channels that carry noise. A noiseless channel (a simulation's load cell) is reproduced to
    /// the arithmetic's precision; its residuals, near zero in noise units, would halve the
    /// pooled variance of `n ln(SSE / n)` and so double every other channel's evidence (a
    /// simulated recording without load noise came back with a stuck Fz). All of them where
    /// every compared channel is noiseless.
    pub fn counted_residuals(&self) -> usize {
        let rows = self.fit_mask.iter().filter(|&&m| m).count();
        let channels = |noisy: bool| {
            (0..4)
                .filter(|&c| self.used[c] && (!noisy || !self.data.noiseless[c]))
                .count()
        };
        match channels(true) {
            0 => rows * channels(false),
            n => rows * n,
        }
    }

    /// The starting baseline from the load cell and the outputs ([`initial_baseline`]), worked
    /// out on first use and kept: the baseline's fit and every effect model of a recording that
    /// starts in contact start from it.
    pub fn initial_baseline(&self) -> &[f64] {
        self.initial.get_or_init(|| initial_baseline(self))
    }

    /// Whether the outputs hold volts, the unit of the metadata's gains.
    pub fn outputs_in_volts(&self) -> bool {
        self.sensor_unit == "V"
    }

    /// Each output's scale as its own data set it ([`scale_reference`]), worked out on first
    /// use and kept.
    pub fn scale_reference(&self) -> [f64; 3] {
        *self.scale_reference.get_or_init(|| scale_reference(self))
    }
}

/// A model to fit: the baseline plus `kinds` (mains excluded: it is fitted at full rate).
pub struct Model<'s, 'a> {
    pub setup: &'s Setup<'a>,
    pub kinds: Vec<EffectKind>,
    specs: Vec<ParamSpec>,
    /// Full vector with `None` where free.
    fixed: Vec<Option<f64>>,
    /// Starting points (full vectors) tried besides the product of the specs' starts.
    extra_starts: Vec<Vec<f64>>,
}

impl<'s, 'a> Model<'s, 'a> {
    pub fn new(setup: &'s Setup<'a>, kinds: &[EffectKind], base: &[f64]) -> Self {
        let chip_peak = (1..4)
            .map(|c| sim::effects::peak_abs(&setup.data.fit.y[c]))
            .fold(0.0, f64::max);
        let mut specs = base_specs(setup, base);
        for &k in kinds {
            specs.extend(effect_specs(k, chip_peak));
        }
        // A parameter whose bounds coincide (a calibration switched off in
        // `hardware/fit-bounds.toml`) is held there, not fitted.
        let mut fixed: Vec<Option<f64>> = specs
            .iter()
            .map(|s| (s.lower == s.upper).then_some(s.lower))
            .collect();
        // Regressed on the measured temperature, the drift's time constant is the temperature's.
        if let (Some(th), Some(at)) = (
            setup.thermal,
            param_index(kinds, EffectKind::ThermalDrift, 1),
        ) {
            fixed[at] = Some(th.tau_s.ln());
        }
        for (c, used) in setup.used.iter().enumerate() {
            if !used {
                fixed[OFFSET_AT + c] = Some(0.0);
                // An output not compared has no scale or shape to calibrate.
                if c > 0 {
                    fixed[SCALE_AT + c - 1] = Some(base[SCALE_AT + c - 1]);
                    fixed[BLEND_AT + c - 1] = Some(0.0);
                }
            }
        }
        // With no output compared, nothing reads the outputs' maps.
        if !setup.used[1..].iter().any(|&u| u) {
            fixed[MAP_LOAD_AT] = Some(0.0);
            fixed[MAP_LOAD_AT + 1] = Some(0.0);
        }
        let mut model = Self {
            setup,
            kinds: kinds.to_vec(),
            specs,
            fixed,
            extra_starts: Vec::new(),
        };
        // A recording that starts in contact never shows its unloaded zero: the offsets trade
        // with the contact law over travels never seen, and the baseline this model nests can
        // sit far from where the effects put the law (an offset of -5 N and a bent law took up a
        // relaxation's ramp, and a static shape the rest). So the fit also starts from the load
        // cell's own law, with the effects at their first starts; the better end is kept, so the
        // model still fits no worse than the baseline it nests.
        let starts_in_contact = setup.data.fit.rod_mm.first().is_some_and(|&r| r > 0.0);
        if starts_in_contact && !kinds.is_empty() {
            let mut start: Vec<f64> = model.specs.iter().map(|s| s.starts[0]).collect();
            start[..N_BASE].copy_from_slice(&setup.initial_baseline()[..N_BASE]);
            for (i, v) in start.iter_mut().enumerate().take(N_BASE) {
                *v = v.clamp(model.specs[i].lower, model.specs[i].upper);
            }
            model.extra_starts.push(start);
        }
        model
    }

    /// Also start the fit from the full vector `start` (internal units).
    pub fn add_start(&mut self, start: Vec<f64>) {
        assert_eq!(
            start.len(),
            self.specs.len(),
            "a start names every parameter"
        );
        self.extra_starts.push(start);
    }

    /// Start effect number `effect` from exactly `values` (internal units), no other start.
    pub fn pin_starts(&mut self, effect: usize, values: &[f64]) {
        for (j, &v) in values.iter().enumerate() {
            *self.starts_mut(effect, j) = vec![v];
        }
    }

    /// Whether full-vector index `i` is held fixed in this model.
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed[i].is_some()
    }

    /// The free parameters of a full vector, in the solver's order.
    pub fn free_of(&self, full: &[f64]) -> Vec<f64> {
        self.free_indices().iter().map(|&i| full[i]).collect()
    }

    /// The starting values of parameter `j` of effect number `effect` (internal units).
    pub fn starts_mut(&mut self, effect: usize, j: usize) -> &mut Vec<f64> {
        let first = N_BASE
            + self.kinds[..effect]
                .iter()
                .map(|k| k.param_names().len())
                .sum::<usize>();
        &mut self.specs[first + j].starts
    }

    pub fn specs(&self) -> &[ParamSpec] {
        &self.specs
    }

    pub fn expand(&self, free: &[f64]) -> Vec<f64> {
        let mut it = free.iter();
        self.fixed
            .iter()
            .map(|f| f.unwrap_or_else(|| *it.next().expect("free parameter count")))
            .collect()
    }

    pub fn free_indices(&self) -> Vec<usize> {
        (0..self.fixed.len())
            .filter(|&i| self.fixed[i].is_none())
            .collect()
    }

    /// Baseline parameters and effect chain of a full parameter vector.
    pub fn decode(&self, full: &[f64]) -> (BaselineParams, EffectSet) {
        let at = |i: usize| -> [f64; 3] { [full[i], full[i + 1], full[i + 2]] };
        let base = BaselineParams {
            youngs_modulus_pa: full[0].exp(),
            exponent_shift: full[1],
            scale: at(SCALE_AT),
            force_warp: at(WARP_AT),
            map_blend: at(BLEND_AT),
            azimuth_shift_deg: 0.0,
            offset: std::array::from_fn(|c| full[OFFSET_AT + c]),
            exponent_curvature: full[9],
            force_law_blend: full[LAW_BLEND_AT],
            map_load_share: full[MAP_LOAD_AT],
            map_load_level: full[MAP_LOAD_AT + 1],
        };
        let mut effects = Vec::new();
        let mut i = N_BASE;
        for &k in &self.kinds {
            let n = k.param_names().len();
            let phys: Vec<f64> = (i..i + n)
                .map(|j| {
                    if self.specs[j].log {
                        full[j].exp()
                    } else {
                        full[j]
                    }
                })
                .collect();
            // AC coupling at the upper end of its range is DC coupling (the bound's reason,
            // `specs::MAX_COUPLING_TAU_S`): left out, so that end is the exact identity and a
            // candidate started there fits exactly as well as the model it extends.
            let dc = k == EffectKind::HighpassCoupling && full[i] >= self.specs[i].upper;
            if !dc {
                effects.push(k.with_params(&phys));
            }
            i += n;
        }
        let mut chain = EffectSet::new(effects);
        chain.thermal_reference = self.setup.thermal.map(|t| t.reference);
        (base, chain)
    }

    pub fn outputs(&self, full: &[f64], series_drive: &Drive) -> Outputs {
        EVALUATIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let (base, chain) = self.decode(full);
        evaluate(
            series_drive,
            &self.setup.readout,
            &base,
            &chain,
            self.setup.contact_angle_deg,
            None,
        )
    }

    /// Weighted residuals of a full vector on `mask` of the decimated series.
    pub fn weighted(&self, full: &[f64], mask: &[bool], out: &mut Vec<f64>) {
        let m = self.outputs(full, &self.setup.drive);
        self.weighted_of(&m, mask, out);
    }

    /// Weighted residuals of `m`, the outputs on the decimated series, on `mask`.
    pub fn weighted_of(&self, m: &Outputs, mask: &[bool], out: &mut Vec<f64>) {
        let s = self.setup;
        out.clear();
        for c in 0..4 {
            if !s.used[c] {
                continue;
            }
            let y = &s.data.fit.y[c];
            let model = m.channel(c);
            out.extend(
                (0..y.len())
                    .filter(|&k| mask[k])
                    .map(|k| (y[k] - model[k]) * s.data.weight(c, k)),
            );
        }
    }

    /// The cost (sum of squared weighted residuals on the fitting stretch) of a full vector.
    pub fn sse_at(&self, full: &[f64]) -> f64 {
        let mut r = Vec::new();
        self.weighted(
            &self.expand(&self.free_of(full)),
            &self.setup.fit_mask,
            &mut r,
        );
        r.iter().map(|v| v * v).sum()
    }

    /// Fit from the best of the starting points; `base` holds the baseline's current values.
    pub fn fit(&self, max_iterations: usize) -> Fitted {
        let free = self.free_indices();
        let opt = lm::Options {
            max_iterations,
            step: free.iter().map(|&i| self.specs[i].step).collect(),
            lower: free.iter().map(|&i| self.specs[i].lower).collect(),
            upper: free.iter().map(|&i| self.specs[i].upper).collect(),
            min_deviance_drop: MIN_BIC_STEP,
        };
        // Every start is fitted to the end: racing them (`lm::solve_best`) changed a single
        // recording's answer in the proof's categories, where the session's fits did not.
        let mut best: Option<Solution> = None;
        for start in self.starting_points() {
            let p0: Vec<f64> = free.iter().map(|&i| start[i]).collect();
            let sol = lm::solve(self, &p0, &opt);
            if best.as_ref().is_none_or(|b| sol.sse < b.sse) {
                best = Some(sol);
            }
        }
        let mut sol = best.expect("at least one starting point");
        sol.n = self.setup.counted_residuals();
        let full = self.expand(&sol.p);
        Fitted {
            full,
            free,
            solution: sol,
        }
    }

    /// Cartesian product of the effect parameters' starting values (baseline at its start).
    fn starting_points(&self) -> Vec<Vec<f64>> {
        let mut points = vec![self.specs.iter().map(|s| s.starts[0]).collect::<Vec<f64>>()];
        for (i, s) in self.specs.iter().enumerate().skip(N_BASE) {
            points = points
                .into_iter()
                .flat_map(|p| {
                    s.starts.iter().map(move |&v| {
                        let mut q = p.clone();
                        q[i] = v;
                        q
                    })
                })
                .collect();
        }
        points.extend(self.extra_starts.iter().cloned());
        for p in &mut points {
            for (i, f) in self.fixed.iter().enumerate() {
                if let Some(v) = f {
                    p[i] = *v;
                }
            }
        }
        // Starts that differ only in fixed parameters are one start.
        let mut unique: Vec<Vec<f64>> = Vec::new();
        for p in points {
            if !unique.contains(&p) {
                unique.push(p);
            }
        }
        unique
    }
}

impl Problem for Model<'_, '_> {
    fn residuals(&self, p: &[f64], out: &mut Vec<f64>) {
        let full = self.expand(p);
        self.weighted(&full, &self.setup.fit_mask, out);
    }
}

/// Index in the full vector of parameter `j` of effect `kind` among `kinds`, if it is there.
pub fn param_index(kinds: &[EffectKind], kind: EffectKind, j: usize) -> Option<usize> {
    nth_param_index(kinds, kind, 0, j)
}

/// As [`param_index`], of the `nth` time `kind` is among `kinds` (from 0: a relaxation may
/// hold a second Prony term).
pub fn nth_param_index(
    kinds: &[EffectKind],
    kind: EffectKind,
    nth: usize,
    j: usize,
) -> Option<usize> {
    let mut first = N_BASE;
    let mut seen = 0;
    for &k in kinds {
        if k == kind {
            if seen == nth {
                return Some(first + j);
            }
            seen += 1;
        }
        first += k.param_names().len();
    }
    None
}

/// A fitted model.
pub struct Fitted {
    pub full: Vec<f64>,
    /// Indices of `full` that were free, in the order of the solution's covariance.
    pub free: Vec<usize>,
    pub solution: Solution,
}

/// Baseline coding; `base` gives the starting values (from [`initial_baseline`] or a previous
/// fit). The bounds and their reasons are `hardware/fit-bounds.toml`.
fn base_specs(setup: &Setup, base: &[f64]) -> Vec<ParamSpec> {
    let (r, cal) = (setup.data.range, &setup.fit_bounds);
    let reference = setup.scale_reference();
    // The bound is the output's own scale times `scale_max`, never a number in the unit the
    // output was logged in: a channel multiplied by a constant changes only its scale.
    let scale = |name, c: usize| {
        let (v, bound) = (base[SCALE_AT + c], cal.scale_max * reference[c]);
        let step = 1e-6 * v.abs().max(1e-3 * reference[c]);
        spec(name, -bound, bound, step, &[v], false)
    };
    let offset = |name, c: usize| {
        let bound = cal.offset_range_factor * r[c].max(1e-9);
        let (start, step) = (base[OFFSET_AT + c], 1e-6 * r[c].max(1e-9));
        spec(name, -bound, bound, step, &[start], false)
    };
    let warp = |name, k: usize| {
        let bound = cal.force_warp_max;
        spec(name, -bound, bound, 1e-5, &[base[WARP_AT + k]], false)
    };
    let blend = |name, c: usize| {
        let (lo, hi) = (cal.map_blend_min, cal.map_blend_max);
        spec(name, lo, hi, 1e-5, &[base[BLEND_AT + c]], false)
    };
    // A shape parameter of the law or the maps: linear, between `lo` and `hi`, from base[i].
    let shape = |name, lo, hi, i: usize| spec(name, lo, hi, 1e-5, &[base[i]], false);
    let (ln_e, curvature) = (base[0], cal.exponent_curvature_max);
    let (shift, level) = (cal.exponent_shift_min, cal.map_load_level_max);
    vec![
        spec(
            "youngs_modulus_Pa",
            ln_e - cal.modulus_ln_range,
            ln_e + cal.modulus_ln_range,
            1e-5,
            &[ln_e],
            true,
        ),
        shape("exponent_shift", shift, cal.exponent_shift_max, 1),
        scale("scale_fz", 0),
        scale("scale_mx", 1),
        scale("scale_my", 2),
        offset("offset_load_N", 0),
        offset("offset_fz_V", 1),
        offset("offset_mx_V", 2),
        offset("offset_my_V", 3),
        shape("exponent_curvature", -curvature, curvature, 9),
        warp("force_warp_at_60pct", 0),
        warp("force_warp_at_30pct", 1),
        warp("force_warp_at_10pct", 2),
        blend("map_blend_fz", 0),
        blend("map_blend_mx", 1),
        blend("map_blend_my", 2),
        shape(
            "force_law_blend",
            0.0,
            cal.force_law_blend_max,
            LAW_BLEND_AT,
        ),
        shape("map_load_share", 0.0, cal.map_load_share_max, MAP_LOAD_AT),
        shape("map_load_level", -level, level, MAP_LOAD_AT + 1),
    ]
}

/// Starting baseline by linear least squares at the nominal shape: modulus from the load cell,
/// scales from the outputs, offsets from the first samples at rest.
pub fn initial_baseline(setup: &Setup) -> Vec<f64> {
    let d = &setup.data.fit;
    let drive = &setup.drive;
    let ls = |x: &dyn Fn(usize) -> f64, y: &[f64]| {
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (k, yk) in y.iter().enumerate() {
            if setup.fit_mask[k] {
                sxy += x(k) * yk;
                sxx += x(k) * x(k);
            }
        }
        if sxx > 0.0 {
            sxy / sxx
        } else {
            0.0
        }
    };
    let e = ls(&|k| drive.unit(k).force_n, &d.y[0]).max(1.0);
    let nominal = evaluate(
        drive,
        &setup.readout,
        &BaselineParams::nominal(e),
        &EffectSet::default(),
        setup.contact_angle_deg,
        None,
    );
    let scales: [f64; 3] = std::array::from_fn(|c| {
        let s = ls(&|k| nominal.volts[c][k], &d.y[c + 1]);
        if s != 0.0 && s.is_finite() {
            s
        } else {
            1.0
        }
    });
    let rest = rest_offsets(d);
    let mut v = vec![e.ln(), 0.0];
    v.extend(scales);
    v.extend(rest);
    v.extend([0.0; 10]);
    if let Some(law) = contact_law_start(setup, rest[0]) {
        v[0] = law[0];
        v[1] = law[1];
        v[9] = law[2];
        v[WARP_AT..WARP_AT + 3].copy_from_slice(&law[3..6]);
        v[LAW_BLEND_AT] = law[6];
    }
    v
}

/// The outputs' scale as the recording itself sets it: the largest recorded peak-to-peak range
/// of a compared output over the model's largest at the metadata's gains (the modulus from the
/// load cell), 1 where either is flat. One factor for every output, since they share one unit
/// (`sensor_unit`): an output the model leaves nearly flat (a moment across the load's plane,
/// which only a turned chip fills) would otherwise get a ratio of noise to nothing, and with it
/// bounds and steps thousands of times too wide. The calibration's scale bounds are this times
/// `scale_max` (`hardware/fit-bounds.toml`): in volts with the right gains it is about 1, and
/// outputs logged in another unit (a magnetometer's µT or mT) move it, and only it, by that
/// unit's factor.
pub fn scale_reference(setup: &Setup) -> [f64; 3] {
    let d = &setup.data.fit;
    let e = setup.initial_baseline()[0].exp();
    let nominal = evaluate(
        &setup.drive,
        &setup.readout,
        &BaselineParams::nominal(e),
        &EffectSet::default(),
        setup.contact_angle_deg,
        None,
    );
    let p2p = |v: &[f64]| {
        let fitted = v.iter().zip(&setup.fit_mask).filter(|(_, m)| **m);
        let (lo, hi) = fitted.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (x, _)| {
            (lo.min(*x), hi.max(*x))
        });
        hi - lo
    };
    let used: Vec<usize> = (0..3).filter(|&c| setup.used[c + 1]).collect();
    let widest = |of: &dyn Fn(usize) -> f64| used.iter().map(|&c| of(c)).fold(0.0, f64::max);
    let ratio = widest(&|c| p2p(&d.y[c + 1])) / widest(&|c| p2p(&nominal.volts[c]));
    let reference = if ratio.is_finite() && ratio > 0.0 {
        ratio
    } else {
        1.0
    };
    [reference; 3]
}

/// The contact law straight from the load cell: ln(load - offset) - ln(unit force) is linear
/// in ln E and the law's shape parameters ([`Drive::contact_shape_basis`]), so weighted linear
/// least squares over the loaded samples (above 5 % of the peak, each weighted by its load:
/// the load cell's noise is the same in newtons, its error in ln F falls as 1 / F) finds the
/// static law whatever its shape, within the calibration's bounds. A start only: from zeros,
/// another model's law (another exponent) left the fit in a far local minimum with a knot at its
/// bound. [ln E, shift, curvature, knots, blend], or `None` with too few loaded samples.
fn contact_law_start(setup: &Setup, offset: f64) -> Option<[f64; 7]> {
    let (load, drive, cal) = (&setup.data.fit.y[0], &setup.drive, &setup.fit_bounds);
    let peak = load.iter().map(|f| f - offset).fold(0.0, f64::max);
    let rows: Vec<([f64; 7], f64, f64)> = (0..load.len())
        .filter(|&k| setup.fit_mask[k] && load[k] - offset > 0.05 * peak)
        .filter_map(|k| {
            let u = drive.unit(k).force_n;
            let b = drive.contact_shape_basis(k).filter(|_| u > 0.0)?;
            let y = (load[k] - offset).ln() - u.ln();
            Some((
                [1.0, b[0], b[1], b[2], b[3], b[4], b[5]],
                y,
                load[k] - offset,
            ))
        })
        .collect();
    if rows.len() < 12 {
        return None;
    }
    let a = nalgebra::DMatrix::from_fn(rows.len(), 7, |r, c| rows[r].0[c] * rows[r].2);
    let y = nalgebra::DVector::from_fn(rows.len(), |r, _| rows[r].1 * rows[r].2);
    let x = a.svd(true, true).solve(&y, 1e-10).ok()?;
    let warp = cal.force_warp_max;
    let bounds = [
        (f64::NEG_INFINITY, f64::INFINITY),
        (cal.exponent_shift_min, cal.exponent_shift_max),
        (-cal.exponent_curvature_max, cal.exponent_curvature_max),
        (-warp, warp),
        (-warp, warp),
        (-warp, warp),
        (0.0, cal.force_law_blend_max),
    ];
    let law: [f64; 7] = std::array::from_fn(|i| x[i].clamp(bounds[i].0, bounds[i].1));
    law.iter().all(|v| v.is_finite()).then_some(law)
}

/// Mean of each channel over the samples before the rod first touches; none (zeros: a load
/// cell and a bridge zeroed before the test) when the recording starts in contact, where the
/// first sample is a preload, not an offset: taken as one, it sent the contact law's start
/// and then the fit to a law shifted by the whole preload.
fn rest_offsets(d: &Series) -> [f64; 4] {
    let n = d.rod_mm.iter().position(|&r| r > 0.0).unwrap_or(d.len());
    if n == 0 {
        return [0.0; 4];
    }
    std::array::from_fn(|c| d.y[c][..n].iter().sum::<f64>() / n as f64)
}

/// Physical value of internal parameter `i` of `model` in `full`.
pub fn physical(model: &Model, full: &[f64], i: usize) -> f64 {
    if model.specs()[i].log {
        full[i].exp()
    } else {
        full[i]
    }
}

/// Standard error of physical parameter `i`, from sigma² (JᵀJ)⁻¹ with sigma² the residual
/// variance inflated by (1 + rho)/(1 - rho) for lag-1 autocorrelation rho of the residual.
pub fn stderr(model: &Model, fitted: &Fitted, i: usize, rho: f64) -> Option<f64> {
    let pos = fitted.free.iter().position(|&j| j == i)?;
    let cov = fitted.solution.jtj_inv.as_ref()?;
    let dof = (fitted.solution.n as f64 - fitted.free.len() as f64).max(1.0);
    let rho = rho.clamp(0.0, 0.99);
    let var = fitted.solution.sse / dof * (1.0 + rho) / (1.0 - rho) * cov[(pos, pos)];
    let se = var.max(0.0).sqrt();
    Some(if model.specs()[i].log {
        se * fitted.full[i].exp()
    } else {
        se
    })
}
