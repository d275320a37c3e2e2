//! One model of the sensor and the gel for every recording of a session: each recording keeps its
//! own [`Model`] (its drive, front end and effects), and a layout says which of its free
//! parameters are the session's (one value for all) and which are its own.
//!
//! A recording's effects are laid out shared first, in the session's order, then its own, so a
//! shared parameter has the same index in every recording's vector. What is shared: every
//! baseline parameter but the four offsets (the modulus and contact law, the outputs' scales and
//! maps), unless a scale is made per recording ([`Layout::own_scales`]), and every parameter of
//! the shared effects.

use std::collections::BTreeMap;

use sim::effects::EffectKind;

use crate::fit::{nth_param_index, Model, Setup, N_BASE, OFFSET_AT, SCALE_AT};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::lm::{self, Problem};
use crate::specs::{second_prony_seeds, starts};

/// Which effects and scales are shared, and which each recording has alone.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Effects with one parameter set for the session.
    pub shared: Vec<EffectKind>,
    /// Each recording's own effects (one list per recording).
    pub own: Vec<Vec<EffectKind>>,
    /// Output scales (0 = Fz, 1 = Mx, 2 = My) fitted per recording instead of shared.
    pub own_scales: Vec<usize>,
}

impl Layout {
    /// Recording `r`'s effects: the shared ones, then its own.
    pub fn kinds(&self, r: usize) -> Vec<EffectKind> {
        [self.shared.as_slice(), &self.own[r]].concat()
    }

    /// The layout with the shared effect `kind` (each of its terms) fitted per recording
    /// instead.
    pub fn per_recording(&self, kind: EffectKind) -> Layout {
        let mut layout = self.clone();
        let terms = layout.shared.iter().filter(|&&s| s == kind).count();
        layout.shared.retain(|&s| s != kind);
        for own in &mut layout.own {
            own.extend(std::iter::repeat_n(kind, terms));
        }
        layout
    }

    /// The layout of recordings `idx` alone (their own effects, the same shared ones).
    pub fn only(&self, idx: &[usize]) -> Layout {
        Layout {
            shared: self.shared.clone(),
            own: idx.iter().map(|&i| self.own[i].clone()).collect(),
            own_scales: self.own_scales.clone(),
        }
    }

    fn shared_len(&self) -> usize {
        N_BASE
            + self
                .shared
                .iter()
                .map(|k| k.param_names().len())
                .sum::<usize>()
    }

    /// Whether index `i` of a recording's vector is the session's.
    pub fn is_shared(&self, i: usize) -> bool {
        let offset = (OFFSET_AT..OFFSET_AT + 4).contains(&i);
        let own_scale = self.own_scales.iter().any(|&c| i == SCALE_AT + c);
        i < self.shared_len() && !offset && !own_scale
    }
}

/// Where a free parameter of the session's vector lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Slot {
    Shared(usize),
    Own(usize, usize),
}

/// The session's least-squares problem over its recordings.
pub struct Joint<'s, 'a> {
    pub layout: Layout,
    pub models: Vec<Model<'s, 'a>>,
    /// Per recording: the session-vector index of each of its free parameters.
    map: Vec<Vec<usize>>,
    pub(super) slots: Vec<Slot>,
    /// Shared values held fixed (leave-one-out: the shared physics of the other recordings).
    frozen: BTreeMap<usize, f64>,
    /// Each recording's number of residuals on its fitting stretch.
    block_len: Vec<usize>,
}

/// A fitted session: each recording's full vector and the fit's statistics.
#[derive(Debug, Clone)]
pub struct JointFit {
    pub full: Vec<Vec<f64>>,
    /// Sum of squares on the fitting stretches (noise units), and the number of residuals.
    pub sse: f64,
    pub n: usize,
    /// Free parameters of the session's vector.
    pub k: usize,
    /// Each recording's sum of squares on its held-out stretch (noise units).
    pub heldout_chi2: Vec<f64>,
    /// The held-out residuals of all recordings, one after the other (noise units).
    pub heldout_r: Vec<f64>,
    /// (JᵀJ)⁻¹ of the session's vector, and which recording index each of its entries is.
    pub jtj_inv: Option<nalgebra::DMatrix<f64>>,
    slots: Vec<Slot>,
    /// The session's vector at the optimum.
    p: Vec<f64>,
}

impl<'s, 'a> Joint<'s, 'a> {
    /// The session's problem: `base[r]` is recording `r`'s starting baseline (internal units).
    /// Shared values in `frozen` (by index of a recording's vector) are held, not fitted.
    pub fn new(
        setups: &[&'s Setup<'a>],
        layout: Layout,
        base: &[Vec<f64>],
        frozen: BTreeMap<usize, f64>,
    ) -> Self {
        let models: Vec<Model> = setups
            .iter()
            .enumerate()
            .map(|(r, s)| Model::new(s, &layout.kinds(r), &base[r][..N_BASE]))
            .collect();
        let mut slots: Vec<Slot> = Vec::new();
        let mut map = Vec::new();
        for (r, m) in models.iter().enumerate() {
            let mut own_map = Vec::new();
            for i in m.free_indices() {
                if layout.is_shared(i) && frozen.contains_key(&i) {
                    own_map.push(usize::MAX);
                    continue;
                }
                let slot = if layout.is_shared(i) {
                    Slot::Shared(i)
                } else {
                    Slot::Own(r, i)
                };
                let at = slots.iter().position(|&s| s == slot).unwrap_or_else(|| {
                    slots.push(slot);
                    slots.len() - 1
                });
                own_map.push(at);
            }
            map.push(own_map);
        }
        let block_len = models
            .iter()
            .map(|m| {
                let n = m.setup.fit_mask.iter().filter(|&&f| f).count();
                n * m.setup.used.iter().filter(|&&u| u).count()
            })
            .collect();
        Self {
            layout,
            models,
            map,
            slots,
            frozen,
            block_len,
        }
    }

    /// Recording `r`'s full vector from the session's vector `p`.
    pub(super) fn full_of(&self, r: usize, p: &[f64]) -> Vec<f64> {
        let m = &self.models[r];
        let free: Vec<f64> = m
            .free_indices()
            .iter()
            .zip(&self.map[r])
            .map(|(i, &at)| {
                if at == usize::MAX {
                    self.frozen[i]
                } else {
                    p[at]
                }
            })
            .collect();
        m.expand(&free)
    }

    /// The session's vector read from recordings' full vectors: a shared value is the median
    /// of the values of the recordings that fit it. (A recording that does not, a moment scale
    /// at 0° where no moment shows, carries whatever its vector held: taken into a median of
    /// two, a scale of 6e5 had started a leave-one-out fit far off.)
    pub(super) fn vector_of(&self, full: &[Vec<f64>]) -> Vec<f64> {
        self.slots
            .iter()
            .map(|&s| match s {
                Slot::Own(r, i) => full[r][i],
                Slot::Shared(i) => {
                    let fitting: Vec<f64> = (0..full.len())
                        .filter(|&r| self.models[r].free_indices().contains(&i))
                        .map(|r| full[r][i])
                        .collect();
                    if fitting.is_empty() {
                        median(full.iter().map(|f| f[i]).collect())
                    } else {
                        median(fitting)
                    }
                }
            })
            .collect()
    }

    /// Bounds and step of each entry of the session's vector (from the first recording that
    /// has it).
    pub(super) fn options(&self, max_iterations: usize) -> lm::Options {
        let spec = |s: &Slot| {
            let (r, i) = match *s {
                Slot::Own(r, i) => (r, i),
                Slot::Shared(i) => (
                    (0..self.models.len())
                        .find(|&r| self.models[r].free_indices().contains(&i))
                        .unwrap_or(0),
                    i,
                ),
            };
            &self.models[r].specs()[i]
        };
        lm::Options {
            max_iterations,
            step: self.slots.iter().map(|s| spec(s).step).collect(),
            lower: self.slots.iter().map(|s| spec(s).lower).collect(),
            upper: self.slots.iter().map(|s| spec(s).upper).collect(),
            min_deviance_drop: crate::fit::MIN_BIC_STEP,
        }
    }

    /// The `keep` of `starts` whose session misfit is lowest as they stand (the first, the
    /// recordings' medians, always among them).
    pub fn screened(&self, starts: Vec<Vec<Vec<f64>>>, keep: usize) -> Vec<Vec<Vec<f64>>> {
        if starts.len() <= keep {
            return starts;
        }
        let mut r = Vec::new();
        let mut cost: Vec<(usize, f64)> = starts
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, full)| {
                self.residuals(&self.vector_of(full), &mut r);
                (i, lm::sse(&r))
            })
            .collect();
        cost.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut kept = vec![0];
        kept.extend(cost.iter().take(keep - 1).map(|&(i, _)| i));
        kept.sort_unstable();
        kept.into_iter().map(|i| starts[i].clone()).collect()
    }

    /// Fit from the best of `starts` (recordings' full vectors, internal units; `lm::solve_best`).
    pub fn fit(&self, starts: &[Vec<Vec<f64>>], max_iterations: usize) -> JointFit {
        let vectors: Vec<Vec<f64>> = starts.iter().map(|f| self.vector_of(f)).collect();
        let best = lm::solve_best(self, &vectors, &self.options(max_iterations));
        let full: Vec<Vec<f64>> = (0..self.models.len())
            .map(|r| self.full_of(r, &best.p))
            .collect();
        let mut heldout_r = Vec::new();
        let heldout_chi2 = self
            .models
            .iter()
            .zip(&full)
            .map(|(m, f)| {
                let mut r = Vec::new();
                m.weighted(f, &m.setup.heldout_mask, &mut r);
                heldout_r.extend_from_slice(&r);
                r.iter().map(|v| v * v).sum()
            })
            .collect();
        JointFit {
            full,
            sse: best.sse,
            // The residuals the criterion counts, as a single fit does (no noiseless channel's).
            n: self
                .models
                .iter()
                .map(|m| m.setup.counted_residuals())
                .sum(),
            k: self.slots.len(),
            heldout_chi2,
            heldout_r,
            jtj_inv: best.jtj_inv,
            slots: self.slots.clone(),
            p: best.p,
        }
    }

    /// Starting vectors for the recordings: `previous` (a fitted session with fewer effects,
    /// or the recordings' own baselines) with each new effect at each of its catalogue starts.
    pub fn starts_from(&self, previous: &[Vec<f64>], before: &Layout) -> Vec<Vec<Vec<f64>>> {
        let count = |l: &[EffectKind], k: EffectKind| l.iter().filter(|&&x| x == k).count();
        let n_starts = self
            .layout
            .shared
            .iter()
            .filter(|&&k| count(&self.layout.shared, k) > count(&before.shared, k))
            .map(|&k| match count(&before.shared, k) {
                0 => starts(k, &self.specs_of(0, k), &[]).len(),
                _ => second_prony_seeds(0.0).len(),
            })
            .max()
            .unwrap_or(1);
        (0..n_starts)
            .map(|s| {
                (0..self.models.len())
                    .map(|r| self.carry(r, &previous[r], before, s))
                    .collect()
            })
            .collect()
    }

    /// Besides `full` itself (shared values at the recordings' median), one start per
    /// recording with every shared value at that recording's: recordings calibrated alone can
    /// trade the contact law's parameters among themselves, so their medians need not be a
    /// consistent law.
    pub fn starts_each(&self, full: &[Vec<f64>]) -> Vec<Vec<Vec<f64>>> {
        let mut out = vec![full.to_vec()];
        for j in 0..full.len() {
            let mut start = full.to_vec();
            for f in &mut start {
                for (i, v) in f.iter_mut().enumerate() {
                    if self.layout.is_shared(i) && i < full[j].len() {
                        *v = full[j][i];
                    }
                }
            }
            out.push(start);
        }
        out
    }

    fn specs_of(&self, r: usize, kind: EffectKind) -> Vec<crate::specs::ParamSpec> {
        let m = &self.models[r];
        let at = crate::fit::param_index(&m.kinds, kind, 0).unwrap_or(N_BASE);
        m.specs()[at..at + kind.param_names().len()].to_vec()
    }

    /// Recording `r`'s vector: the baseline and each effect `before` had at their values in
    /// `prev` (the n-th term of a kind at the n-th term's), a new effect at its `s`-th
    /// catalogue start (its neutral one first), a second Prony term at its `s`-th seed beside
    /// the first.
    fn carry(&self, r: usize, prev: &[f64], before: &Layout, s: usize) -> Vec<f64> {
        let mut v = prev[..N_BASE].to_vec();
        let before_kinds = before.kinds(r);
        let kinds = self.layout.kinds(r);
        for (i, &k) in kinds.iter().enumerate() {
            let n = k.param_names().len();
            let nth = kinds[..i].iter().filter(|&&x| x == k).count();
            match nth_param_index(&before_kinds, k, nth, 0) {
                Some(at) if at + n <= prev.len() => v.extend_from_slice(&prev[at..at + n]),
                _ => {
                    let seeds = match nth_param_index(&kinds, k, 0, 0) {
                        Some(first) if nth > 0 => second_prony_seeds(v[first]),
                        _ => Vec::new(),
                    };
                    let all = starts(k, &self.specs_of(r, k), &seeds);
                    v.extend_from_slice(&all[s.min(all.len() - 1)]);
                }
            }
        }
        v
    }
}

impl Problem for Joint<'_, '_> {
    fn residuals(&self, p: &[f64], out: &mut Vec<f64>) {
        let blocks: Vec<Vec<f64>> = (0..self.models.len())
            .into_par_iter()
            .map(|i| self.block(i, p))
            .collect();
        out.clear();
        for b in blocks {
            out.extend_from_slice(&b);
        }
    }

    /// Recording by recording: a recording's residuals move with the session's parameters and
    /// its own alone, so its part of the Jacobian has those columns only, and JᵀJ is summed
    /// from the parts. Held whole, the Jacobian grew as the square of the session (every
    /// recording's own parameters a column over every residual) and JᵀJ as its cube.
    fn normal_equations(&self, p: &[f64], r: &[f64], h: &[f64]) -> Option<lm::Normal> {
        let k = p.len();
        let starts: Vec<usize> = self
            .block_len
            .iter()
            .scan(0, |at, &n| {
                *at += n;
                Some(*at - n)
            })
            .collect();
        let zero = || (DMatrix::zeros(k, k), DVector::zeros(k));
        let sum = |mut a: lm::Normal, b: lm::Normal| {
            a.0 += b.0;
            a.1 += b.1;
            a
        };
        let normal = (0..self.models.len())
            .into_par_iter()
            .map(|rec| {
                let base = &r[starts[rec]..starts[rec] + self.block_len[rec]];
                self.part(rec, p, base, h)
            })
            .fold(zero, |mut acc, part| {
                part.add_to(&mut acc);
                acc
            })
            .reduce(zero, sum);
        Some(normal)
    }
}

impl Joint<'_, '_> {
    /// Recording `rec`'s weighted residuals on its fitting stretch at the session's `p`.
    pub(super) fn block(&self, rec: usize, p: &[f64]) -> Vec<f64> {
        let m = &self.models[rec];
        let mut r = Vec::new();
        m.weighted(&self.full_of(rec, p), &m.setup.fit_mask, &mut r);
        r
    }

    /// Recording `rec`'s part of the normal equations at `p` (its residuals `base`, steps `h`).
    pub(super) fn part(&self, rec: usize, p: &[f64], base: &[f64], h: &[f64]) -> Part {
        let cols: Vec<usize> = self.map[rec]
            .iter()
            .copied()
            .filter(|&at| at != usize::MAX)
            .collect();
        let mut jac = DMatrix::zeros(base.len(), cols.len());
        for (a, &i) in cols.iter().enumerate() {
            let mut q = p.to_vec();
            q[i] += h[i];
            let moved = self.block(rec, &q);
            for (row, (x, y)) in moved.iter().zip(base).enumerate() {
                jac[(row, a)] = (x - y) / h[i];
            }
        }
        let (jtj, jtr) = lm::normal_equations(&jac, base);
        Part {
            cols,
            jtj,
            jtr,
            sse: lm::sse(base),
            n: base.len(),
        }
    }
}

/// One recording's part of the session's normal equations: the session-vector indices of the
/// parameters that move its residuals (the shared ones and its own), its JᵀJ and Jᵀr over
/// them, and its sum of squares and number of residuals.
pub(super) struct Part {
    pub cols: Vec<usize>,
    pub jtj: DMatrix<f64>,
    pub jtr: DVector<f64>,
    pub sse: f64,
    pub n: usize,
}

impl Part {
    /// This part added into the session's normal equations.
    pub fn add_to(&self, normal: &mut lm::Normal) {
        for (a, &i) in self.cols.iter().enumerate() {
            normal.1[i] += self.jtr[a];
            for (b, &j) in self.cols.iter().enumerate() {
                normal.0[(i, j)] += self.jtj[(a, b)];
            }
        }
    }
}

impl JointFit {
    /// Recordings calibrated alone (`full`), as the start of a search: no fit statistics.
    pub fn start(full: Vec<Vec<f64>>) -> Self {
        Self {
            full,
            sse: f64::INFINITY,
            n: 0,
            k: 0,
            heldout_chi2: Vec::new(),
            heldout_r: Vec::new(),
            jtj_inv: None,
            slots: Vec::new(),
            p: Vec::new(),
        }
    }

    /// BIC of the session's fit (the single fits' form, over all residuals).
    pub fn bic(&self) -> f64 {
        let n = self.n as f64;
        n * (self.sse / n).max(1e-300).ln() + self.k as f64 * n.ln()
    }

    /// Standard error of recording `r`'s own index `i` (internal units).
    pub fn own_stderr(&self, r: usize, i: usize) -> Option<f64> {
        let pos = self.slots.iter().position(|&s| s == Slot::Own(r, i))?;
        let cov = self.jtj_inv.as_ref()?;
        let dof = (self.n as f64 - self.k as f64).max(1.0);
        Some((self.sse / dof * cov[(pos, pos)]).max(0.0).sqrt())
    }

    /// The fitted shared values, by index of a recording's vector (internal units).
    pub fn shared_values(&self) -> BTreeMap<usize, f64> {
        self.slots
            .iter()
            .zip(&self.p)
            .filter_map(|(s, &v)| match *s {
                Slot::Shared(i) => Some((i, v)),
                Slot::Own(..) => None,
            })
            .collect()
    }

    /// Held-out chi-square summed over the recordings.
    pub fn heldout(&self) -> f64 {
        self.heldout_chi2.iter().sum()
    }

    /// Standard error of index `i` of a shared vector (internal units), residual variance
    /// from the fit.
    pub fn shared_stderr(&self, i: usize) -> Option<f64> {
        let pos = self.slots.iter().position(|&s| s == Slot::Shared(i))?;
        let cov = self.jtj_inv.as_ref()?;
        let dof = (self.n as f64 - self.k as f64).max(1.0);
        Some((self.sse / dof * cov[(pos, pos)]).max(0.0).sqrt())
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
