//! Restart-free GMRES with right preconditioning by a kept LDL^T factor of an earlier tangent.
//!
//! The tangent drifts slowly along a load path, so the factor of a tangent a few Newton
//! iterations (or load steps) old is an excellent preconditioner: K M^{-1} is close to the
//! identity and GMRES converges in a handful of iterations, each one triangular solve and one
//! sparse product, about 20x cheaper than a new factorisation. When it does not converge in
//! `max_iter` iterations the caller refactors.

use crate::linsolve::Ldlt;

/// y = K x for K symmetric, stored as the upper triangle in CSC.
pub fn sym_matvec(col_ptr: &[usize], row_idx: &[usize], values: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    for c in 0..x.len() {
        let xc = x[c];
        let mut acc = 0.0;
        for k in col_ptr[c]..col_ptr[c + 1] {
            let r = row_idx[k];
            y[r] += values[k] * xc;
            if r != c {
                acc += values[k] * x[r];
            }
        }
        y[c] += acc;
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solve K x = b to relative residual `rtol` within `max_iter` iterations, preconditioned by
/// `m` (a factor of a nearby matrix). The residual is measured in the norm |W r| with the
/// diagonal weights `w` (the caller's scaled merit norm, so that force and volume rows count
/// alike): GMRES runs on (W K M^{-1} W^{-1}) y = W b, x = M^{-1} W^{-1} y, whose operator is
/// similar to K M^{-1} (≈ I), so the scaling changes the norm but not the convergence.
/// Returns the iterations used, or None without convergence.
#[allow(clippy::too_many_arguments)]
pub fn gmres(
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &[f64],
    m: &mut Ldlt,
    w: &[f64],
    b: &[f64],
    x: &mut [f64],
    rtol: f64,
    max_iter: usize,
) -> Option<usize> {
    let n = b.len();
    let wb: Vec<f64> = b.iter().zip(w).map(|(bi, wi)| bi * wi).collect();
    let beta = dot(&wb, &wb).sqrt();
    x.fill(0.0);
    if beta == 0.0 {
        return Some(0);
    }
    let mut v: Vec<Vec<f64>> = vec![wb.iter().map(|bi| bi / beta).collect()];
    let mut h = vec![vec![0.0; max_iter]; max_iter + 1];
    let (mut cs, mut sn) = (vec![0.0; max_iter], vec![0.0; max_iter]);
    let mut g = vec![0.0; max_iter + 1];
    g[0] = beta;
    let mut z = vec![0.0; n];
    let mut kz = vec![0.0; n];
    let mut k = 0;
    while k < max_iter {
        z.iter_mut()
            .zip(&v[k])
            .zip(w)
            .for_each(|((zj, vj), wj)| *zj = vj / wj);
        m.solve_in_place(&mut z, 1);
        sym_matvec(col_ptr, row_idx, values, &z, &mut kz);
        kz.iter_mut().zip(w).for_each(|(k, wi)| *k *= wi);
        for (i, vi) in v.iter().enumerate() {
            let hik = dot(&kz, vi);
            h[i][k] = hik;
            kz.iter_mut().zip(vi).for_each(|(kj, vj)| *kj -= hik * vj);
        }
        let norm = dot(&kz, &kz).sqrt();
        h[k + 1][k] = norm;
        for i in 0..k {
            let t = cs[i] * h[i][k] + sn[i] * h[i + 1][k];
            h[i + 1][k] = -sn[i] * h[i][k] + cs[i] * h[i + 1][k];
            h[i][k] = t;
        }
        let r = h[k][k].hypot(h[k + 1][k]);
        cs[k] = h[k][k] / r;
        sn[k] = h[k + 1][k] / r;
        h[k][k] = r;
        h[k + 1][k] = 0.0;
        g[k + 1] = -sn[k] * g[k];
        g[k] *= cs[k];
        k += 1;
        if g[k].abs() <= rtol * beta || norm == 0.0 {
            break;
        }
        v.push(kz.iter().map(|ki| ki / norm).collect());
    }
    if g[k].abs() > rtol * beta {
        return None;
    }
    // y = H^{-1} g (upper triangular), x = M^{-1} V y.
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let s: f64 = (i + 1..k).map(|j| h[i][j] * y[j]).sum();
        y[i] = (g[i] - s) / h[i][i];
    }
    for (i, vi) in v.iter().take(k).enumerate() {
        x.iter_mut().zip(vi).for_each(|(xj, vj)| *xj += y[i] * vj);
    }
    x.iter_mut().zip(w).for_each(|(xj, wj)| *xj /= wj);
    m.solve_in_place(x, 1);
    Some(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Preconditioned by the factor of a perturbed matrix, GMRES solves the original exactly.
    #[test]
    fn solves_with_a_stale_factor() {
        // Tridiagonal SPD-like 5x5 upper CSC with a negative last pivot (quasi-definite).
        let n = 5;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut a = Vec::new();
        for c in 0..n {
            if c > 0 {
                row_idx.push(c - 1);
                a.push(-1.0);
            }
            row_idx.push(c);
            a.push(if c == n - 1 { -0.5 } else { 4.0 });
            col_ptr.push(row_idx.len());
        }
        let mut m = Ldlt::new(n, &col_ptr, &row_idx, None).unwrap();
        let stale: Vec<f64> = a.iter().map(|v| v * 1.1).collect();
        m.factorize(&stale).unwrap();
        let xs = [1.0, -1.0, 2.0, 0.5, 3.0];
        let mut b = vec![0.0; n];
        sym_matvec(&col_ptr, &row_idx, &a, &xs, &mut b);
        let mut x = vec![0.0; n];
        let weights = [1.0, 2.0, 0.5, 1.0, 3.0];
        let its = gmres(
            &col_ptr, &row_idx, &a, &mut m, &weights, &b, &mut x, 1e-12, 10,
        )
        .expect("converges");
        assert!(its <= n);
        for i in 0..n {
            assert!((x[i] - xs[i]).abs() < 1e-9, "{x:?}");
        }
    }
}
