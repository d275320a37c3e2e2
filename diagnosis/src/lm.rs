//! A small Levenberg–Marquardt least-squares solver with box bounds and forward-difference
//! Jacobians (Marquardt 1963; scaling by diag(JᵀJ) as in Moré 1978). Problems here have at most
//! a dozen parameters and a few ten thousand residuals, so dense normal equations suffice.

/// A least-squares problem: residuals r(p) to minimise sum r².
pub trait Problem: Sync {
    fn residuals(&self, p: &[f64], out: &mut Vec<f64>);
}

/// Result of a fit.
#[derive(Debug, Clone)]
pub struct Solution {
    pub p: Vec<f64>,
    pub sse: f64,
    /// Number of residuals.
    pub n: usize,
    /// (JᵀJ)⁻¹ at the optimum (unscaled covariance), when JᵀJ is invertible.
    pub jtj_inv: Option<Vec<Vec<f64>>>,
    pub iterations: usize,
}

pub struct Options {
    pub max_iterations: usize,
    /// Finite-difference step per parameter (absolute).
    pub step: Vec<f64>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

fn sse(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimise from `p0`.
pub fn solve(problem: &dyn Problem, p0: &[f64], opt: &Options) -> Solution {
    let m = p0.len();
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
    let mut jac = vec![Vec::new(); m];
    let mut trial = Vec::new();
    for it in 0..opt.max_iterations {
        iterations = it + 1;
        jacobian(problem, &p, &r, opt, &mut jac);
        let (jtj, jtr) = normal_equations(&jac, &r);
        // A parameter with no influence here (a zero column) gets a unit diagonal, so it stays
        // put instead of making the system singular.
        let floor = 1e-12 * (0..m).map(|i| jtj[i][i]).fold(0.0, f64::max);
        let mut improved = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for i in 0..m {
                if jtj[i][i] <= floor {
                    a[i][i] = 1.0;
                } else {
                    a[i][i] += lambda * jtj[i][i];
                }
            }
            let Some(delta) = solve_linear(a, jtr.iter().map(|v| -v).collect()) else {
                lambda *= 10.0;
                continue;
            };
            let cand: Vec<f64> = (0..m)
                .map(|i| (p[i] + delta[i]).clamp(opt.lower[i], opt.upper[i]))
                .collect();
            problem.residuals(&cand, &mut trial);
            let c = sse(&trial);
            if c.is_finite() && c < cost {
                let gain = (cost - c) / cost.max(1e-300);
                p = cand;
                std::mem::swap(&mut r, &mut trial);
                cost = c;
                lambda = (lambda / 3.0).max(1e-9);
                improved = true;
                if gain < 1e-9 {
                    return finish(problem, p, r, cost, opt, iterations);
                }
                break;
            }
            lambda *= 8.0;
        }
        if !improved {
            break;
        }
    }
    finish(problem, p, r, cost, opt, iterations)
}

fn finish(
    problem: &dyn Problem,
    p: Vec<f64>,
    r: Vec<f64>,
    sse: f64,
    opt: &Options,
    iterations: usize,
) -> Solution {
    let mut jac = vec![Vec::new(); p.len()];
    jacobian(problem, &p, &r, opt, &mut jac);
    let (jtj, _) = normal_equations(&jac, &r);
    Solution {
        n: r.len(),
        jtj_inv: invert(jtj),
        p,
        sse,
        iterations,
    }
}

/// Forward differences, stepping inward at an upper bound.
fn jacobian(problem: &dyn Problem, p: &[f64], r: &[f64], opt: &Options, jac: &mut [Vec<f64>]) {
    let mut q = p.to_vec();
    let mut out = Vec::new();
    for i in 0..p.len() {
        let h = if p[i] + opt.step[i] > opt.upper[i] {
            -opt.step[i]
        } else {
            opt.step[i]
        };
        q[i] = p[i] + h;
        problem.residuals(&q, &mut out);
        q[i] = p[i];
        jac[i].clear();
        jac[i].extend(out.iter().zip(r).map(|(a, b)| (a - b) / h));
    }
}

fn normal_equations(jac: &[Vec<f64>], r: &[f64]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let m = jac.len();
    let mut jtj = vec![vec![0.0; m]; m];
    let mut jtr = vec![0.0; m];
    for i in 0..m {
        jtr[i] = jac[i].iter().zip(r).map(|(a, b)| a * b).sum();
        for j in 0..=i {
            let v: f64 = jac[i].iter().zip(&jac[j]).map(|(a, b)| a * b).sum();
            jtj[i][j] = v;
            jtj[j][i] = v;
        }
    }
    (jtj, jtr)
}

/// Gaussian elimination with partial pivoting; `None` if singular.
pub fn solve_linear(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() <= 1e-14 * scale {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..n {
            let f = a[row][col] / a[col][col];
            if f != 0.0 {
                let (upper, lower) = a.split_at_mut(row);
                for (x, p) in lower[0][col..].iter_mut().zip(&upper[col][col..]) {
                    *x -= f * p;
                }
                b[row] -= f * b[col];
            }
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    Some(x)
}

/// Inverse by solving for each unit vector.
pub fn invert(a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let cols: Option<Vec<Vec<f64>>> = (0..n)
        .map(|j| {
            solve_linear(
                a.clone(),
                (0..n).map(|i| if i == j { 1.0 } else { 0.0 }).collect(),
            )
        })
        .collect();
    let cols = cols?;
    Some(
        (0..n)
            .map(|i| (0..n).map(|j| cols[j][i]).collect())
            .collect(),
    )
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
        };
        let s = solve(&Decay { t, y }, &[1.0, 5.0], &opt);
        assert!(
            (s.p[0] - 2.0).abs() < 1e-6 && (s.p[1] - 1.7).abs() < 1e-6,
            "{:?}",
            s.p
        );
        assert!(s.jtj_inv.is_some());
    }
}
