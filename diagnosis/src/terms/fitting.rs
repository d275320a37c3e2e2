//! What every term is fitted on: the chosen model's residual on the decimated series, in noise
//! units, and the recorded quantities a term may be a function of; and the weighted linear
//! least squares that fits a term's amplitudes once its shape is chosen.

use nalgebra::{DMatrix, DVector};

use crate::data::Data;

/// The recording, the chosen model and the quantities the terms are functions of.
pub(crate) struct Context<'d> {
    pub data: &'d Data,
    pub fit_mask: &'d [bool],
    pub heldout_mask: &'d [bool],
    /// Channels compared.
    pub used: [bool; 4],
    /// The chosen model's channels on the decimated series.
    pub model: [Vec<f64>; 4],
    /// Its calibrated offsets [load, Fz, Mx, My]: `model - offset` is the signal.
    pub offset: [f64; 4],
    /// Recorded minus model, per channel.
    pub residual: [Vec<f64>; 4],
    /// The rod's speed, mm/s (central differences of the block means).
    pub rod_speed: Vec<f64>,
    /// Each decimated sample's span of time at the full rate (first and last instant, plus half
    /// a sample either side): a line's block mean is taken over it.
    pub block_span: Vec<(f64, f64)>,
    /// The chosen model's residual at the full rate (a line's frequency is found there).
    pub full_residual: [Vec<f64>; 4],
    /// The chosen model holds a catalogue effect that opens a loop between loading and
    /// unloading (`hysteresis`, `viscoelastic_relaxation`): a loop left in its residual is that
    /// effect's misfit, so terms that only open a loop (a lag, an odd power of the speed) are
    /// not looked for.
    pub loop_in_model: bool,
    /// The terms are searched beside the whole catalogue model: only those that no catalogue
    /// effect's own misfit can mimic are offered ([`super::TermKind::beside_catalogue`]).
    pub beside_catalogue: bool,
    /// Whether the discovery step runs ([`crate::fit::Setup::discover`]).
    pub discover: bool,
    /// The outputs hold volts, the unit of the metadata's gains
    /// ([`crate::fit::Setup::outputs_in_volts`]): only then is the model at those gains a
    /// swing an output should show.
    pub outputs_in_volts: bool,
    /// Beside the whole catalogue model, per channel: the directions in which the catalogue's
    /// fitted parameters move the model (its Jacobian, orthonormal on the fitting stretch with
    /// the channel's offset and scale). A term is fitted with them refitted beside it, to
    /// first order, as the catalogue would refit its parameters with the term in the model;
    /// else a term must fit what the calibration, fitted without it, bent towards both.
    /// Empty: only the offset and scale are refitted.
    pub catalogue: [Vec<Vec<f64>>; 4],
    /// Catalogue entries the recording's protocol cannot show (`Features::protocol_allows`):
    /// the library's terms that meet them at another stage are not offered either (a lag on
    /// a single ramp is a shift of the contact point wherever it acts).
    pub forbidden: Vec<sim::effects::EffectKind>,
    /// Per channel, the chosen model's calibration directions as [`Self::catalogue`] has them,
    /// for the discovery step (`super::discover`), which fits its terms with the calibration
    /// refitted beside them to first order wherever it runs. Empty: not worked out.
    pub directions: [Vec<Vec<f64>>; 4],
}

impl<'d> Context<'d> {
    /// The context of the chosen model `model` (its channels on the decimated series and
    /// `full_model` at the full rate) with its calibrated `offset`.
    pub fn new(
        data: &'d Data,
        masks: (&'d [bool], &'d [bool]),
        used: [bool; 4],
        model: [Vec<f64>; 4],
        full_model: [&[f64]; 4],
        offset: [f64; 4],
    ) -> Self {
        let d = &data.fit;
        let residual =
            std::array::from_fn(|c| d.y[c].iter().zip(&model[c]).map(|(y, m)| y - m).collect());
        let full_residual = std::array::from_fn(|c| {
            data.full.y[c]
                .iter()
                .zip(full_model[c])
                .map(|(y, m)| y - m)
                .collect()
        });
        let half = 0.5 / data.rate_hz.max(1e-9);
        let block_span = data
            .bounds
            .iter()
            .map(|&(a, b)| (data.full.t_s[a] - half, data.full.t_s[b - 1] + half))
            .collect();
        Self {
            data,
            fit_mask: masks.0,
            heldout_mask: masks.1,
            used,
            model,
            offset,
            residual,
            rod_speed: derivative(&d.t_s, &d.rod_mm),
            block_span,
            full_residual,
            loop_in_model: false,
            beside_catalogue: false,
            discover: true,
            outputs_in_volts: true,
            catalogue: Default::default(),
            forbidden: Vec::new(),
            directions: Default::default(),
        }
    }

    /// Set [`Self::catalogue`] from the model's derivatives `jacobian` per channel (one column
    /// per fitted parameter): with the channel's offset and scale, an orthonormal basis of what
    /// they span on the fitting stretch (weighted by the noise), directions the stretch cannot
    /// resolve (below a millionth of the largest) left out, so that collinear parameters do
    /// not extrapolate wildly onto the held-out stretch.
    pub fn set_catalogue(&mut self, jacobian: [Vec<Vec<f64>>; 4]) {
        for (c, cols) in jacobian.into_iter().enumerate() {
            let mut all = vec![vec![1.0; self.len()], self.signal(c)];
            all.extend(cols);
            self.catalogue[c] = self.orthonormal(c, &all);
        }
    }

    /// Set [`Self::directions`] from the model's derivatives, as [`Self::set_catalogue`] sets
    /// its own.
    pub fn set_directions(&mut self, jacobian: [Vec<Vec<f64>>; 4]) {
        for (c, cols) in jacobian.into_iter().enumerate() {
            let mut all = vec![vec![1.0; self.len()], self.signal(c)];
            all.extend(cols);
            self.directions[c] = self.orthonormal(c, &all);
        }
    }

    /// [`Self::orthonormal`] of `cols` on channel `c`.
    pub fn orthonormal_of(&self, c: usize, cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
        self.orthonormal(c, cols)
    }

    /// An orthonormal basis (weighted inner product over the fitting stretch) of `cols`, by the
    /// singular value decomposition of the weighted columns.
    fn orthonormal(&self, c: usize, cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let rows: Vec<usize> = (0..self.len()).filter(|&k| self.fit_mask[k]).collect();
        if rows.is_empty() || cols.is_empty() {
            return Vec::new();
        }
        let w = |k: usize| self.data.weight(c, k);
        let a = DMatrix::from_fn(rows.len(), cols.len(), |i, j| cols[j][rows[i]] * w(rows[i]));
        let svd = a.svd(false, true);
        let Some(v_t) = svd.v_t else {
            return Vec::new();
        };
        let largest = svd.singular_values.max();
        (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > 1e-6 * largest)
            .map(|i| {
                let s = svd.singular_values[i];
                (0..self.len())
                    .map(|k| {
                        (0..cols.len())
                            .map(|j| cols[j][k] * v_t[(i, j)])
                            .sum::<f64>()
                            / s
                    })
                    .collect()
            })
            .collect()
    }

    pub fn t_s(&self) -> &[f64] {
        &self.data.fit.t_s
    }

    pub fn len(&self) -> usize {
        self.data.fit.len()
    }

    /// Channel `c`'s signal without its offset, as the model has it.
    pub fn signal(&self, c: usize) -> Vec<f64> {
        self.model[c].iter().map(|m| m - self.offset[c]).collect()
    }

    /// The first time the rod starts back after its first loading (the first reversal), if any.
    pub fn first_reversal_s(&self) -> Option<f64> {
        let v = &self.rod_speed;
        let moving_up = v.iter().position(|&s| s > 0.0)?;
        (moving_up..v.len())
            .find(|&k| v[k] < 0.0)
            .map(|k| self.t_s()[k])
    }

    /// Chi-square (noise units) of `r - part` on `mask` for channel `c`.
    pub fn chi2(&self, c: usize, part: Option<&[f64]>, mask: &[bool]) -> f64 {
        let r = &self.residual[c];
        (0..r.len())
            .filter(|&k| mask[k])
            .map(|k| ((r[k] - part.map_or(0.0, |p| p[k])) * self.data.weight(c, k)).powi(2))
            .sum()
    }
}

/// dx/dt by central differences (one-sided at the ends).
pub fn derivative(t_s: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n.saturating_sub(1)));
            let dt = t_s[b] - t_s[a];
            if dt > 0.0 {
                (x[b] - x[a]) / dt
            } else {
                0.0
            }
        })
        .collect()
}

/// A term's columns on the decimated series and its fixed part (added whatever the amplitudes:
/// a frozen channel replaces the model).
#[derive(Debug, Clone, Default)]
pub(crate) struct Columns {
    pub x: Vec<Vec<f64>>,
    pub fixed: Option<Vec<f64>>,
}

impl Columns {
    /// The columns and fixed part, each sample times `by`'s (a stuck channel's live share).
    pub fn scaled(&self, by: &[f64]) -> Columns {
        let times = |v: &Vec<f64>| v.iter().zip(by).map(|(a, b)| a * b).collect();
        Columns {
            x: self.x.iter().map(times).collect(),
            fixed: self.fixed.as_ref().map(times),
        }
    }

    pub fn contribution(&self, beta: &[f64]) -> Vec<f64> {
        let n = self
            .x
            .first()
            .or(self.fixed.as_ref())
            .map_or(0, |v| v.len());
        (0..n)
            .map(|k| {
                self.fixed.as_ref().map_or(0.0, |f| f[k])
                    + self.x.iter().zip(beta).map(|(x, b)| x[k] * b).sum::<f64>()
            })
            .collect()
    }

    /// These columns followed by `other`'s.
    pub fn joined(&self, other: &Columns) -> Columns {
        let fixed = match (&self.fixed, &other.fixed) {
            (Some(a), Some(b)) => Some(a.iter().zip(b).map(|(a, b)| a + b).collect()),
            (a, b) => a.clone().or_else(|| b.clone()),
        };
        Columns {
            x: self.x.iter().chain(&other.x).cloned().collect(),
            fixed,
        }
    }
}

/// Weighted least squares of channel `c`'s residual on `cols` over the fitting stretch: the
/// amplitudes and the chi-square left. None where the columns do not reach the fitting stretch
/// (a singular system).
pub fn solve(ctx: &Context, c: usize, cols: &Columns) -> Option<(Vec<f64>, f64)> {
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
    let k = cols.x.len();
    let target = |i: usize| ctx.residual[c][i] - cols.fixed.as_ref().map_or(0.0, |f| f[i]);
    let mut a = DMatrix::<f64>::zeros(k, k);
    let mut b = DVector::<f64>::zeros(k);
    for &i in &rows {
        let w2 = ctx.data.weight(c, i).powi(2);
        for p in 0..k {
            b[p] += w2 * cols.x[p][i] * target(i);
            for q in 0..=p {
                a[(p, q)] += w2 * cols.x[p][i] * cols.x[q][i];
            }
        }
    }
    for p in 0..k {
        for q in 0..p {
            a[(q, p)] = a[(p, q)];
        }
    }
    let beta: Vec<f64> = if k == 0 {
        Vec::new()
    } else {
        let scale: f64 = (0..k).map(|p| a[(p, p)]).fold(0.0, f64::max);
        if scale.is_nan() || scale <= 0.0 {
            return None;
        }
        // A tiny ridge keeps a column that barely reaches the stretch from blowing up.
        let ridged = &a + DMatrix::identity(k, k) * (1e-12 * scale);
        ridged.cholesky()?.solve(&b).iter().copied().collect()
    };
    let part = cols.contribution(&beta);
    Some((beta, ctx.chi2(c, Some(&part), ctx.fit_mask)))
}

/// The best of `shapes` (each a shape and its columns) for channel `c` with the columns already
/// on the channel (`others`, refitted with it): its shape, columns, own amplitudes and the
/// chi-square left on the fitting stretch.
pub fn best_shape(
    ctx: &Context,
    c: usize,
    others: &Columns,
    shapes: impl Iterator<Item = (Vec<f64>, Columns)>,
) -> Option<(Vec<f64>, Columns, Vec<f64>, f64)> {
    best_shape_where(ctx, c, others, shapes, |_| true)
}

/// [`best_shape`] among the shapes whose own amplitudes `accept` takes.
pub fn best_shape_where(
    ctx: &Context,
    c: usize,
    others: &Columns,
    shapes: impl Iterator<Item = (Vec<f64>, Columns)>,
    accept: impl Fn(&[f64]) -> bool,
) -> Option<(Vec<f64>, Columns, Vec<f64>, f64)> {
    let mut best: Option<(Vec<f64>, Columns, Vec<f64>, f64)> = None;
    for (shape, cols) in shapes {
        let Some((beta, sse)) = solve(ctx, c, &cols.joined(others)) else {
            continue;
        };
        if sse.is_finite() && accept(&beta) && best.as_ref().is_none_or(|b| sse < b.3) {
            let own = beta[..cols.x.len()].to_vec();
            best = Some((shape, cols, own, sse));
        }
    }
    best
}

/// The best of `shapes` on channel `c` as a term of `kind` (one grid dimension, one
/// amplitude) among those whose amplitude its physics admits ([`super::TermKind::admits`]):
/// the other sign is other physics (said at each call).
pub fn admitted_term(
    ctx: &Context,
    c: usize,
    others: &Columns,
    kind: super::TermKind,
    shapes: impl Iterator<Item = (Vec<f64>, Columns)>,
) -> Option<super::Term> {
    let (shape, columns, beta, _) =
        best_shape_where(ctx, c, others, shapes, |b| kind.admits(b[0]))?;
    Some(super::Term {
        kind,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 2,
        info: None,
    })
}

/// The best step in time on channel `c`, over the fitting stretch's inner samples: the column
/// H(t - t0) and, with `freeze`, the fixed part -H(t - t0) m(t) (the channel reads a constant
/// from t0 on). The other columns on the channel are fitted first and held; the step's size
/// then has a closed form at every t0 from running sums, so the scan costs one pass rather
/// than a least-squares solve per t0. Returns t0 and the columns.
pub fn best_step(
    ctx: &Context,
    c: usize,
    others: &Columns,
    freeze: bool,
) -> Option<(f64, Columns)> {
    let mut base = if others.x.is_empty() && others.fixed.is_none() {
        vec![0.0; ctx.len()]
    } else {
        let (beta, _) = solve(ctx, c, others)?;
        others.contribution(&beta)
    };
    // A freeze: the other columns fitted beside it reach only the live samples, and the scan
    // is repeated with them held there until its time stays (the columns fitted to the frozen
    // samples too had pulled the freeze off its time, and a set that holds the peak had
    // fitted better than the freeze at the wrong time).
    let mut found: Option<(f64, Columns)> = None;
    for _ in 0..if freeze { 3 } else { 1 } {
        let k = scan_step(ctx, c, &base, freeze)?;
        let (t0, columns) = refine_step(ctx, c, others, k, freeze)?;
        let settled = found.as_ref().is_some_and(|f| f.0 == t0);
        if settled {
            break;
        }
        if freeze && !others.x.is_empty() {
            let live: Vec<f64> = columns.x[0].iter().map(|h| 1.0 - h).collect();
            let (beta, _) = solve(ctx, c, &columns.joined(&others.scaled(&live)))?;
            base = others.contribution(&beta[1..]);
        }
        found = Some((t0, columns));
    }
    found
}

/// The block where a step (or, with `freeze`, a freeze) on channel `c` removes the most
/// chi-square, the other columns held at `base`.
fn scan_step(ctx: &Context, c: usize, base: &[f64], freeze: bool) -> Option<usize> {
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
    // Leave a few samples either side: a step at the stretch's edge is an offset.
    if rows.len() < 8 {
        return None;
    }
    // From the end: sums over k >= k0 of w^2, w^2 z and w^2 z^2, where z is what the step's
    // amplitude must match (the residual; for a frozen channel the recording itself, which
    // the other columns no longer reach), and of w^2 r^2 (what the frozen stretch loses).
    let (mut sw, mut swz, mut swzz, mut swrr) = (0.0, 0.0, 0.0, 0.0);
    let mut best: Option<(f64, usize)> = None;
    for (i, &k) in rows.iter().enumerate().rev() {
        let w2 = ctx.data.weight(c, k).powi(2);
        let r = ctx.residual[c][k] - base[k];
        let z = if freeze {
            ctx.residual[c][k] + ctx.model[c][k]
        } else {
            r
        };
        sw += w2;
        swz += w2 * z;
        swzz += w2 * z * z;
        swrr += w2 * r * r;
        if i < 3 || i + 3 >= rows.len() {
            continue;
        }
        // The chi-square the step removes over k >= k0.
        let left = swzz - swz * swz / sw;
        let gain = swrr - left;
        if best.is_none_or(|b| gain > b.0) {
            best = Some((gain, k));
        }
    }
    best.map(|b| b.1)
}

/// The step's time refined between the blocks either side of block `k`, with its columns:
/// each block holds the share of its span after t0 (a step inside a block moves its mean
/// part of the way).
fn refine_step(
    ctx: &Context,
    c: usize,
    others: &Columns,
    k: usize,
    freeze: bool,
) -> Option<(f64, Columns)> {
    let (from, to) = (ctx.block_span[k.saturating_sub(1)].0, ctx.block_span[k].1);
    let step_at = |t0: f64| {
        let h: Vec<f64> = ctx
            .block_span
            .iter()
            .map(|&(a, b)| ((b - t0) / (b - a).max(1e-12)).clamp(0.0, 1.0))
            .collect();
        let fixed = freeze.then(|| h.iter().zip(&ctx.model[c]).map(|(h, m)| -h * m).collect());
        Columns { x: vec![h], fixed }
    };
    let shapes = (0..=20).map(|i| {
        let t0 = from + (to - from) * f64::from(i) / 20.0;
        (vec![t0], step_at(t0))
    });
    let (shape, columns, _, _) = best_shape(ctx, c, others, shapes)?;
    Some((shape[0], columns))
}
