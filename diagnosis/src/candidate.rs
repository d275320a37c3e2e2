//! One fitted candidate model (the calibrated baseline plus a list of catalogue effects), its
//! scores, and the two tests by which a larger model must beat a model it contains.

use sim::effects::EffectKind;

use crate::fit::{Fitted, Model, Setup, N_BASE};
use crate::lm::Solution;
use crate::specs::starts;
use baseline::{Drive, Outputs};

/// Minimum BIC decrease for an effect to count. A BIC difference approximates twice the log
/// Bayes factor (Schwarz 1978); above 10 the evidence is "very strong" on the Kass & Raftery
/// (1995) scale, which fixes this constant independently of our generator.
pub const MIN_BIC_GAIN: f64 = 10.0;
/// The held-out improvement must exceed this many standard deviations of its own sampling noise
/// (see [`heldout_needed`]): two is the usual one-sided 2.3 % level.
const HELDOUT_Z: f64 = 2.0;
/// The smallest held-out improvement worth a name, as a share of the held-out misfit left by
/// the smaller model: below half a percent an effect changes the held-out RMSE by less than a
/// quarter of a percent, which changes no conclusion about the fit even when it is significant
/// (on real rigs with a large structured misfit, tiny significant gains are the rule).
pub(crate) const MIN_HELDOUT_SHARE: f64 = 0.005;

/// One fitted candidate.
pub struct Candidate<'s, 'a> {
    /// The catalogue effects it adds to the baseline (a kind may appear twice: two Prony terms).
    pub kinds: Vec<EffectKind>,
    /// The model that was fitted.
    pub model: Model<'s, 'a>,
    /// Its fit.
    pub fitted: Fitted,
    /// Bayesian information criterion on the fitting stretch.
    pub bic: f64,
    /// Small-sample Akaike information criterion on the fitting stretch.
    pub aicc: f64,
    /// Chi-square on the held-out stretch (noise units).
    pub heldout_chi2: f64,
    /// The held-out residuals (noise units), for the paired held-out test.
    heldout_r: Vec<f64>,
    /// Its outputs on the decimated series at the fit, evaluated once when it is scored.
    pub outputs: Outputs,
    /// Its weighted residuals on the fitting stretch (noise units), from [`Self::outputs`]: the
    /// report's parameter uncertainties read their correlation, not a new evaluation.
    pub fit_residual: Vec<f64>,
    /// The fit ended above the model it nests and was replaced by that model's solution with
    /// the new effect at its neutral values (a solver failure, reported, never hidden).
    pub at_neutral: bool,
}

/// The outcome of comparing a model with one it contains.
#[derive(Debug, Clone, Copy)]
pub struct Comparison {
    /// BIC of the smaller model minus the larger one's (positive: the larger is better).
    pub bic_gain: f64,
    /// Held-out chi-square of the smaller over the larger one's.
    pub heldout_ratio: f64,
    /// Held-out chi-square decrease and the least it had to be.
    pub heldout_gain: f64,
    pub heldout_needed: f64,
    /// The held-out gain the larger model would make were it the truth: the squared norm of
    /// the two models' difference on the held-out stretch (noise units).
    pub heldout_reach: f64,
}

impl Comparison {
    /// Both tests passed.
    pub fn passes(&self) -> bool {
        self.bic_gain > MIN_BIC_GAIN && self.heldout_gain > self.heldout_needed
    }

    /// The criterion keeps the larger model, and the held-out stretch cannot test it: were it
    /// the truth, its gain there would still not count (a hysteresis that acts only while the
    /// rod moves, with the held-out stretch at rest).
    pub fn untestable(&self) -> bool {
        self.bic_gain > MIN_BIC_GAIN
            && self.heldout_gain <= self.heldout_needed
            && self.heldout_reach <= self.heldout_needed
    }

    /// The criterion passed: enough to enter the search's model. The held-out test is left to
    /// the search's end ([`Self::passes`]): while another effect is missing (a drift, a
    /// relaxation), an AC coupling's undershoot can predict the held-out recovery worse than
    /// leaving it out.
    pub fn admits(&self) -> bool {
        self.bic_gain > MIN_BIC_GAIN
    }

    /// The comparison in words, against `what` ("the baseline", "without hysteresis").
    pub fn words(&self, what: &str) -> String {
        let bic = format!("BIC {:+.0} vs {what}", -self.bic_gain);
        let held = if self.heldout_ratio >= 1.0 {
            format!("held-out misfit {:.2}x smaller", self.heldout_ratio)
        } else {
            format!(
                "held-out misfit {:.2}x worse",
                1.0 / self.heldout_ratio.max(1e-300)
            )
        };
        let verdict = match (
            self.bic_gain > MIN_BIC_GAIN,
            self.heldout_gain > self.heldout_needed,
        ) {
            (true, true) => "",
            (false, _) => " (BIC gain under 10)",
            (true, false) => " (held-out gain below its noise or 0.5 %)",
        };
        format!("{bic}, {held}{verdict}")
    }
}

impl<'s, 'a> Candidate<'s, 'a> {
    /// Fit `model` from its starting points and score it.
    pub fn fit(model: Model<'s, 'a>, max_iterations: usize) -> Self {
        let fitted = model.fit(max_iterations);
        Self::scored(model, fitted, false)
    }

    fn scored(model: Model<'s, 'a>, fitted: Fitted, at_neutral: bool) -> Self {
        let n = fitted.solution.n as f64;
        let k = fitted.free.len() as f64;
        let fit_term = n * (fitted.solution.sse / n).max(1e-300).ln();
        let bic = fit_term + k * n.ln();
        let aicc = fit_term + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0).max(1.0);
        let outputs = model.outputs(&fitted.full, &model.setup.drive);
        let mut heldout_r = Vec::new();
        model.weighted_of(&outputs, &model.setup.heldout_mask, &mut heldout_r);
        let heldout_chi2 = heldout_r.iter().map(|v| v * v).sum();
        let mut fit_residual = Vec::new();
        model.weighted_of(&outputs, &model.setup.fit_mask, &mut fit_residual);
        Self {
            kinds: model.kinds.clone(),
            model,
            fitted,
            bic,
            aicc,
            heldout_chi2,
            heldout_r,
            outputs,
            fit_residual,
            at_neutral,
        }
    }

    /// `nested` plus `kind`: the baseline and the nested effects start at their fitted values,
    /// the new effect at its neutral values (where it is the identity) and at its other starts
    /// ([`starts`], from `seeds`). LM only takes steps that lower the cost, so from the neutral
    /// start it cannot end above the nested fit; should it (a solver failure), the nested
    /// solution with the effect at neutral is kept, scored as the nested model and marked.
    pub fn extend(
        setup: &'s Setup<'a>,
        nested: &Candidate<'s, 'a>,
        kind: EffectKind,
        seeds: &[Vec<f64>],
        max_iterations: usize,
    ) -> Self {
        let mut kinds = nested.kinds.clone();
        kinds.push(kind);
        let mut model = Model::new(setup, &kinds, &nested.fitted.full[..N_BASE]);
        let mut at = N_BASE;
        for (e, k) in nested.kinds.iter().enumerate() {
            let n = k.param_names().len();
            model.pin_starts(e, &nested.fitted.full[at..at + n]);
            at += n;
        }
        let own = starts(kind, &model.specs()[at..], seeds);
        model.pin_starts(kinds.len() - 1, &own[0]);
        let neutral_full = [nested.fitted.full.as_slice(), &own[0]].concat();
        for other in &own[1..] {
            model.add_start([nested.fitted.full.as_slice(), other].concat());
        }
        let fitted = model.fit(max_iterations);
        if fitted.solution.sse <= nested.sse() {
            return Self::scored(model, fitted, false);
        }
        // The nested solution with the effect at neutral, scored as the nested model (where the
        // neutral vector is not its exact identity, e.g. crosstalk carrying the azimuth through
        // a per-channel friction, the nested model's own scores are what it stands for). Such a
        // candidate is never reported (`Selection::addition_test`).
        let free = model.free_of(&neutral_full);
        let fallback = Fitted {
            full: model.expand(&free),
            free: model.free_indices(),
            solution: Solution {
                p: free,
                sse: nested.sse(),
                n: nested.fitted.solution.n,
                jtj_inv: None,
                iterations: 0,
            },
        };
        let mut c = Self::scored(model, fallback, true);
        c.heldout_r = nested.heldout_r.clone();
        c.heldout_chi2 = nested.heldout_chi2;
        c
    }

    /// The model's derivatives on the decimated series, per channel, with respect to each
    /// parameter it fitted (forward differences at the solver's own steps, internal units).
    /// A parameter at a bound is left out: the fit could not move it that way, and a refit to
    /// first order must not either.
    pub fn directions(&self) -> [Vec<Vec<f64>>; 4] {
        let specs = self.model.specs();
        let drive = &self.model.setup.drive;
        let mut out: [Vec<Vec<f64>>; 4] = Default::default();
        for &i in &self.fitted.free {
            let (s, p) = (&specs[i], self.fitted.full[i]);
            if p - s.lower <= s.step || s.upper - p <= s.step {
                continue;
            }
            let mut moved = self.fitted.full.clone();
            moved[i] = p + s.step;
            let m = self.model.outputs(&moved, drive);
            for (c, cols) in out.iter_mut().enumerate() {
                let d = m.channel(c).iter().zip(self.outputs.channel(c));
                cols.push(d.map(|(a, b)| (a - b) / s.step).collect());
            }
        }
        out
    }

    /// Compare with `smaller`, a model this one contains: the BIC difference and a paired test
    /// on the held-out stretch.
    ///
    /// The held-out gain G = sum(r_s^2 - r_l^2) over held-out samples. With the residuals in
    /// noise units, its sampling noise (the measurement noise e entering both models alike) is
    /// sum 2 (m_l - m_s) e: for white noise of standard deviation 2 |m_l - m_s|, twice the norm
    /// of the two models' difference on the held-out stretch; under slow noise, which moves
    /// neighbouring blocks together, more for a smooth difference (`sum_deviation`). G must
    /// exceed `HELDOUT_Z` such deviations and `MIN_HELDOUT_SHARE` of the smaller model's
    /// held-out misfit.
    pub fn compare(&self, smaller: &Candidate) -> Comparison {
        let d: Vec<f64> = self
            .heldout_r
            .iter()
            .zip(&smaller.heldout_r)
            .map(|(a, b)| a - b)
            .collect();
        let setup = self.model.setup;
        let diff = sum_deviation(setup, &setup.heldout_mask, &d);
        Comparison {
            bic_gain: smaller.bic - self.bic,
            heldout_ratio: smaller.heldout_chi2 / self.heldout_chi2.max(1e-300),
            heldout_gain: smaller.heldout_chi2 - self.heldout_chi2,
            heldout_needed: heldout_needed(diff, smaller.heldout_chi2),
            heldout_reach: d.iter().map(|x| x * x).sum(),
        }
    }

    /// The cost (sum of squares on the fitting stretch).
    pub fn sse(&self) -> f64 {
        self.fitted.solution.sse
    }

    /// Its outputs on `drive`.
    pub fn outputs(&self, drive: &Drive) -> Outputs {
        self.model.outputs(&self.fitted.full, drive)
    }

    /// The kinds as a sorted list: two candidates with the same key are the same model.
    pub fn key(&self) -> Vec<EffectKind> {
        key_of(&self.kinds)
    }

    /// Effect names joined with " + ", "baseline" for none.
    pub fn label(&self) -> String {
        label_of(&self.kinds)
    }
}

/// Standard deviation of sum_k d_k e_k, `d` a difference of weighted residuals on `mask` (the
/// used channels one after the other, as [`Model::weighted`] lays them out) and e the noise in
/// the same units, under each channel's noise model: |d| for white noise.
pub(crate) fn sum_deviation(setup: &Setup, mask: &[bool], d: &[f64]) -> f64 {
    let data = setup.data;
    let rows: Vec<usize> = (0..mask.len()).filter(|&k| mask[k]).collect();
    let blocks: Vec<(usize, usize)> = rows.iter().map(|&k| data.bounds[k]).collect();
    (0..4)
        .filter(|&c| setup.used[c])
        .zip(d.chunks(rows.len().max(1)))
        .map(|(c, d)| {
            let coefficients: Vec<f64> = rows
                .iter()
                .zip(d)
                .map(|(&k, dk)| dk * data.weight(c, k))
                .collect();
            data.noise[c].block_means_variance(&blocks, &coefficients)
        })
        .sum::<f64>()
        .max(0.0)
        .sqrt()
}

/// The least held-out chi-square decrease that counts, for two models whose predictions on the
/// held-out stretch differ by `diff` (norm, noise units) when the smaller leaves `smaller_chi2`.
pub fn heldout_needed(diff: f64, smaller_chi2: f64) -> f64 {
    (HELDOUT_Z * 2.0 * diff).max(MIN_HELDOUT_SHARE * smaller_chi2)
}

/// Sorted kinds: the model's identity (effects apply in an order fixed by physics).
pub fn key_of(kinds: &[EffectKind]) -> Vec<EffectKind> {
    let mut k = kinds.to_vec();
    k.sort();
    k
}

/// Effect names joined with " + ", "baseline" for none.
pub fn label_of(kinds: &[EffectKind]) -> String {
    if kinds.is_empty() {
        return "baseline".into();
    }
    kinds
        .iter()
        .map(|k| k.name())
        .collect::<Vec<_>>()
        .join(" + ")
}
