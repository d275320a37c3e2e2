//! A Levenberg–Marquardt least-squares solver with box bounds and forward-difference
//! Jacobians (Marquardt 1963; scaling by diag(JᵀJ) as in Moré 1978). Problems here have at most
//! a dozen parameters and a few ten thousand residuals, so dense normal equations suffice.
//!
//! Our own because the fits need box bounds and no maintained Rust least-squares crate has them
//! (`levenberg-marquardt`, the nalgebra one, is unbounded); nalgebra does the linear algebra.

use nalgebra::{DMatrix, DVector, Dyn, LU};

/// A least-squares problem: residuals r(p) to minimise sum r².
pub trait Problem: Sync {
    /// The residuals at parameters `p`, into `out` (same length at every `p`).
    fn residuals(&self, p: &[f64], out: &mut Vec<f64>);

    /// JᵀJ and Jᵀr of the forward-difference Jacobian at `p` (residuals `r`, signed steps `h`),
    /// where the problem knows a cheaper way than the dense Jacobian (residuals in blocks that
    /// most parameters leave alone); `None` otherwise.
    fn normal_equations(&self, _p: &[f64], _r: &[f64], _h: &[f64]) -> Option<Normal> {
        None
    }
}

/// The normal equations of a linearised least-squares problem: JᵀJ and Jᵀr.
pub type Normal = (DMatrix<f64>, DVector<f64>);

/// Result of a fit.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The parameters at the optimum.
    pub p: Vec<f64>,
    /// Sum of squared residuals there.
    pub sse: f64,
    /// Number of residuals.
    pub n: usize,
    /// (JᵀJ)⁻¹ at the optimum (unscaled covariance), when JᵀJ is invertible.
    pub jtj_inv: Option<DMatrix<f64>>,
    /// Iterations taken (debugging output).
    #[allow(dead_code)]
    pub iterations: usize,
}

/// Limits, steps and bounds of a fit.
#[derive(Clone)]
pub struct Options {
    /// Most iterations (Jacobians) before giving up.
    pub max_iterations: usize,
    /// Finite-difference step per parameter (absolute).
    pub step: Vec<f64>,
    /// Lower bound per parameter.
    pub lower: Vec<f64>,
    /// Upper bound per parameter.
    pub upper: Vec<f64>,
    /// The least drop of n ln(cost) worth another iteration (n residuals): twice the
    /// log-likelihood with the noise level estimated from the residuals, the term of a BIC the
    /// fit lowers. Zero: iterate while the cost falls by 1e-9 of itself (the arithmetic's
    /// limit).
    pub min_deviance_drop: f64,
}

pub(crate) fn sse(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimise from `p0`.
pub fn solve(problem: &dyn Problem, p0: &[f64], opt: &Options) -> Solution {
    let mut p: Vec<f64> = p0
        .iter()
        .enumerate()
        .map(|(i, &v)| v.clamp(opt.lower[i], opt.upper[i]))
        .collect();
    let mut r = Vec::new();
    problem.residuals(&p, &mut r);
    let mut cost = sse(&r);
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut trial = Vec::new();
    for it in 0..opt.max_iterations {
        iterations = it + 1;
        let normal = linearised(problem, &p, &r, opt);
        let Some(step) = damped_step(problem, &p, &normal, cost, &mut lambda, opt, &mut trial)
        else {
            break;
        };
        let gain = (cost - step.cost) / cost.max(1e-300);
        let deviance_drop = -(r.len() as f64) * (1.0 - gain).max(1e-300).ln();
        p = step.p;
        std::mem::swap(&mut r, &mut trial);
        cost = step.cost;
        if gain < 1e-9 || deviance_drop < opt.min_deviance_drop {
            break;
        }
    }
    finish(problem, p, r, cost, opt, iterations)
}

/// Iterations every start of a multi-start fit gets before only the lowest cost goes on
/// ([`solve_best`]): enough to leave a start's neighbourhood (a time constant's decade, a
/// median law), so that a start in another basin shows by its cost, at an eighth of a fit's
/// budget.
pub const RACE_ITERATIONS: usize = 5;

/// Minimise from the best of `starts`: each gets [`RACE_ITERATIONS`], then only the one with
/// the lowest cost goes on to `opt.max_iterations`. The starts guard against local minima; a
/// start that is not in the best basin after a few steps is not worth a whole fit.
///
/// # Panics
/// When `starts` is empty.
pub fn solve_best(problem: &dyn Problem, starts: &[Vec<f64>], opt: &Options) -> Solution {
    if let [only] = starts {
        return solve(problem, only, opt);
    }
    let race = Options {
        max_iterations: RACE_ITERATIONS.min(opt.max_iterations),
        ..opt.clone()
    };
    let leader = starts
        .iter()
        .map(|p0| solve(problem, p0, &race))
        .min_by(|a, b| a.sse.total_cmp(&b.sse))
        .expect("at least one start");
    solve(problem, &leader.p, opt)
}

/// An accepted step: its parameters and cost (its residuals are in `trial`).
struct Step {
    p: Vec<f64>,
    cost: f64,
}

/// Try up to twelve dampings from `lambda` on; the first step that lowers the cost is taken
/// (`lambda` then shrinks), `None` if none does.
fn damped_step(
    problem: &dyn Problem,
    p: &[f64],
    normal: &Normal,
    cost: f64,
    lambda: &mut f64,
    opt: &Options,
    trial: &mut Vec<f64>,
) -> Option<Step> {
    for _ in 0..12 {
        let Some(cand) = damped(p, normal, *lambda, opt) else {
            *lambda *= 10.0;
            continue;
        };
        problem.residuals(&cand, trial);
        let c = sse(trial);
        if c.is_finite() && c < cost {
            *lambda = (*lambda / 3.0).max(1e-9);
            return Some(Step { p: cand, cost: c });
        }
        *lambda *= 8.0;
    }
    None
}

/// The parameters after one step of the normal equations `(jtj, jtr)` from `p` with damping
/// `lambda` (zero: Gauss–Newton), within the bounds; `None` where the system is singular.
pub fn damped(p: &[f64], (jtj, jtr): &Normal, lambda: f64, opt: &Options) -> Option<Vec<f64>> {
    let m = p.len();
    // A parameter with no influence here (a zero column) gets a unit diagonal, so it stays put
    // instead of making the system singular.
    let floor = 1e-12 * jtj.diagonal().iter().fold(0.0, |a: f64, &b| a.max(b));
    // A parameter at a bound that the gradient pushes further out is held there for this step
    // (the active set): left in the system, its clamped move would spoil the others' step,
    // which was solved as if it had moved, and the fit stalled against the bound.
    let held: Vec<bool> = (0..m)
        .map(|i| (p[i] <= opt.lower[i] && jtr[i] > 0.0) || (p[i] >= opt.upper[i] && jtr[i] < 0.0))
        .collect();
    let mut rhs = -jtr;
    let mut a = jtj.clone();
    for i in 0..m {
        if held[i] {
            a.row_mut(i).fill(0.0);
            a.column_mut(i).fill(0.0);
            a[(i, i)] = 1.0;
            rhs[i] = 0.0;
        } else if jtj[(i, i)] <= floor {
            a[(i, i)] = 1.0;
        } else {
            a[(i, i)] += lambda * jtj[(i, i)];
        }
    }
    let delta = solve_linear(a, rhs)?;
    Some(
        (0..m)
            .map(|i| (p[i] + delta[i]).clamp(opt.lower[i], opt.upper[i]))
            .collect(),
    )
}

fn finish(
    problem: &dyn Problem,
    p: Vec<f64>,
    r: Vec<f64>,
    sse: f64,
    opt: &Options,
    iterations: usize,
) -> Solution {
    let (jtj, _) = linearised(problem, &p, &r, opt);
    Solution {
        n: r.len(),
        jtj_inv: covariance(jtj),
        p,
        sse,
        iterations,
    }
}

/// The normal equations at `p`: the problem's own where it has them, else from the dense
/// Jacobian.
fn linearised(problem: &dyn Problem, p: &[f64], r: &[f64], opt: &Options) -> Normal {
    let h = steps(p, opt);
    problem
        .normal_equations(p, r, &h)
        .unwrap_or_else(|| normal_equations(&jacobian(problem, p, r, &h), r))
}

/// Each parameter's forward-difference step, inward at an upper bound.
pub fn steps(p: &[f64], opt: &Options) -> Vec<f64> {
    (0..p.len())
        .map(|i| {
            if p[i] + opt.step[i] > opt.upper[i] {
                -opt.step[i]
            } else {
                opt.step[i]
            }
        })
        .collect()
}

/// Forward differences with steps `h`, one column per parameter, evaluated in parallel: the
/// baseline's fit and the search's refits run one model at a time, and each column is a whole
/// model evaluation.
fn jacobian(problem: &dyn Problem, p: &[f64], r: &[f64], h: &[f64]) -> DMatrix<f64> {
    use rayon::prelude::*;
    let columns: Vec<Vec<f64>> = (0..p.len())
        .into_par_iter()
        .map(|i| {
            let mut q = p.to_vec();
            q[i] = p[i] + h[i];
            let mut out = Vec::new();
            problem.residuals(&q, &mut out);
            out.iter().zip(r).map(|(a, b)| (a - b) / h[i]).collect()
        })
        .collect();
    let mut jac = DMatrix::zeros(r.len(), p.len());
    for (i, col) in columns.iter().enumerate() {
        jac.column_mut(i).copy_from_slice(col);
    }
    jac
}

/// JᵀJ and Jᵀr.
pub fn normal_equations(jac: &DMatrix<f64>, r: &[f64]) -> Normal {
    let r = DVector::from_column_slice(r);
    (jac.tr_mul(jac), jac.tr_mul(&r))
}

/// The LU factors of `a` (partial pivoting), `None` when a pivot is below 1e-14 of the largest
/// element: singular for these fits.
fn factor(a: DMatrix<f64>) -> Option<LU<f64, Dyn, Dyn>> {
    let scale = a.amax().max(1e-300);
    let lu = a.lu();
    lu.u()
        .diagonal()
        .iter()
        .all(|pivot| pivot.abs() > 1e-14 * scale)
        .then_some(lu)
}

/// Solve `a x = b`; `None` if `a` is singular.
pub fn solve_linear(a: DMatrix<f64>, b: DVector<f64>) -> Option<DVector<f64>> {
    factor(a)?.solve(&b)
}

/// The unscaled covariance (JᵀJ)⁻¹ of a fit's parameters, inverted in correlation form (each
/// parameter scaled to unit diagonal: parameters of very different units no longer make the
/// matrix look singular). A parameter that moves nothing (a zero column) has no variance: its
/// row and column are NaN and the others' covariance is that of the fit without it. `None`
/// where the parameters that move something are themselves collinear.
pub fn covariance(a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let d: Vec<f64> = (0..n).map(|i| a[(i, i)]).collect();
    let scale = d
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n)
        .filter(|&i| d[i].is_finite() && d[i] > 1e-24 * scale)
        .collect();
    let k = keep.len();
    let s = DMatrix::from_fn(k, k, |p, q| {
        let (i, j) = (keep[p], keep[q]);
        a[(i, j)] / (d[i] * d[j]).sqrt()
    });
    let s_inv = invert(s)?;
    let mut out = DMatrix::from_element(n, n, f64::NAN);
    for (p, &i) in keep.iter().enumerate() {
        for (q, &j) in keep.iter().enumerate() {
            out[(i, j)] = s_inv[(p, q)] / (d[i] * d[j]).sqrt();
        }
    }
    Some(out)
}

/// The inverse of `a`; `None` if it is singular.
pub fn invert(a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    factor(a)?.try_inverse()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exponential decay y = a e^{-t/tau} recovered from exact data, with a bound respected.
    struct Decay {
        t: Vec<f64>,
        y: Vec<f64>,
    }
    impl Problem for Decay {
        fn residuals(&self, p: &[f64], out: &mut Vec<f64>) {
            out.clear();
            out.extend(
                self.t
                    .iter()
                    .zip(&self.y)
                    .map(|(t, y)| p[0] * (-t / p[1]).exp() - y),
            );
        }
    }

    #[test]
    fn fits_an_exponential() {
        let t: Vec<f64> = (0..200).map(|k| k as f64 * 0.05).collect();
        let y = t.iter().map(|t| 2.0 * (-t / 1.7f64).exp()).collect();
        let opt = Options {
            max_iterations: 100,
            step: vec![1e-6, 1e-6],
            lower: vec![0.0, 0.1],
            upper: vec![10.0, 10.0],
            min_deviance_drop: 0.0,
        };
        let s = solve(&Decay { t, y }, &[1.0, 5.0], &opt);
        assert!(
            (s.p[0] - 2.0).abs() < 1e-6 && (s.p[1] - 1.7).abs() < 1e-6,
            "{:?}",
            s.p
        );
        assert!(s.jtj_inv.is_some());
    }

    /// Two basins: r = (p² - 1, 0.3 (p - 1)) is zero at p = 1 and has a worse minimum near
    /// p = -1. From a start in each, the race keeps the one in the better basin.
    struct TwoBasins;

    impl Problem for TwoBasins {
        fn residuals(&self, p: &[f64], out: &mut Vec<f64>) {
            out.clear();
            out.extend([p[0] * p[0] - 1.0, 0.3 * (p[0] - 1.0)]);
        }
    }

    #[test]
    fn the_race_keeps_the_start_in_the_better_basin() {
        let opt = Options {
            max_iterations: 40,
            step: vec![1e-7],
            lower: vec![-3.0],
            upper: vec![3.0],
            min_deviance_drop: 0.0,
        };
        let alone = solve(&TwoBasins, &[-1.3], &opt);
        assert!(alone.p[0] < 0.0, "{:?}", alone.p);
        let s = solve_best(&TwoBasins, &[vec![-1.3], vec![1.4]], &opt);
        assert!((s.p[0] - 1.0).abs() < 1e-6, "{:?}", s.p);
    }

    /// With a least deviance drop, the fit stops once a step gains less, short of the budget.
    #[test]
    fn a_least_deviance_drop_stops_the_crawl() {
        let t: Vec<f64> = (0..200).map(|k| k as f64 * 0.05).collect();
        let y: Vec<f64> = t
            .iter()
            .enumerate()
            .map(|(k, t)| 2.0 * (-t / 1.7f64).exp() + 0.01 * ((k * 7919 % 13) as f64 - 6.0))
            .collect();
        let opt = |min_deviance_drop| Options {
            max_iterations: 100,
            step: vec![1e-6, 1e-6],
            lower: vec![0.0, 0.1],
            upper: vec![10.0, 10.0],
            min_deviance_drop,
        };
        let problem = Decay { t, y };
        let full = solve(&problem, &[1.0, 5.0], &opt(0.0));
        let short = solve(&problem, &[1.0, 5.0], &opt(0.01));
        assert!(
            short.iterations < full.iterations,
            "{} {}",
            short.iterations,
            full.iterations
        );
        let n = full.n as f64;
        assert!(
            n * (short.sse / full.sse).ln() < 0.01 * 10.0,
            "{} {}",
            short.sse,
            full.sse
        );
    }
}
