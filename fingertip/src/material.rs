//! Constitutive kernels: the deviatoric (isochoric) energy of each material and the volume
//! measure that the nodal pressure field constrains.
//!
//! Volumetric locking. Linear tetrahedra lock when each element must keep its own volume. We
//! use the average-nodal-pressure tetrahedron (Bonet & Burton 1998) written as a mixed u–p
//! field: a pressure unknown p_a at each node, the total potential
//!
//!   Pi(x, p) = sum_e V_e W_dev(F_e) + sum_a [ p_a (v_a - V_a) - V_a p_a^2 / (2 kappa) ],
//!   v_a = sum_{e∋a} v_e / 4,  V_a = sum_{e∋a} V_e / 4,
//!
//! whose stationarity in p_a gives p_a = kappa (J_a - 1) with the nodal Jacobian
//! J_a = v_a / V_a, i.e. the volumetric energy sum_a V_a kappa/2 (J_a - 1)^2. The constraint is
//! imposed once per node instead of once per element (about 1 constraint per 3 dofs instead of
//! ~5 per 3 dofs), which is what removes locking. Because sum_a p_a v_a = sum_e p̄_e v_e with
//! p̄_e the element mean of its nodal pressures, every term stays element-local, the tangent
//! keeps the 1-ring sparsity, and the symmetric system [K_xx B; B^T -M/kappa] is
//! quasi-definite for kappa < inf, so a sparse LDL^T without pivoting factors it.
//!
//! Indices: a second-order tensor `T[i][J]`, a fourth-order one as `[[f64; 9]; 9]` with
//! row `3 i + J`, column `3 k + L`, i.e. dP_iJ / dF_kL.

/// 3x3 matrix, `m[i][J]`.
pub type Mat3 = [[f64; 3]; 3];
/// Fourth-order tensor dP_iJ/dF_kL as a 9x9 matrix.
pub type Tensor4 = [[f64; 9]; 9];

/// Which constitutive law the gel follows.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub enum Kinematics {
    /// Small-strain linear elasticity (the limit for checks against Hertz and the peer).
    Linear,
    /// Finite-strain neo-Hookean.
    NeoHookean,
}

/// Lamé shear modulus and bulk modulus from E and nu.
pub fn moduli(youngs_modulus_pa: f64, poisson: f64) -> (f64, f64) {
    let mu = youngs_modulus_pa / (2.0 * (1.0 + poisson));
    let kappa = youngs_modulus_pa / (3.0 * (1.0 - 2.0 * poisson));
    (mu, kappa)
}

pub fn det(f: &Mat3) -> f64 {
    f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1])
        - f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0])
        + f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0])
}

/// Cofactor matrix, dJ/dF.
pub fn cofactor(f: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            c[i][j] = f[i1][j1] * f[i2][j2] - f[i1][j2] * f[i2][j1];
        }
    }
    c
}

fn levi(i: usize, j: usize, k: usize) -> f64 {
    ((i as i64 - j as i64) * (j as i64 - k as i64) * (k as i64 - i as i64)) as f64 / 2.0
}

/// d(cof F)_iJ / dF_kL = eps_ikm eps_JLN F_mN.
pub fn cofactor_derivative(f: &Mat3) -> Tensor4 {
    let mut d = [[0.0; 9]; 9];
    for i in 0..3 {
        for k in 0..3 {
            if i == k {
                continue;
            }
            let m = 3 - i - k;
            let e1 = levi(i, k, m);
            for jj in 0..3 {
                for l in 0..3 {
                    if jj == l {
                        continue;
                    }
                    let n = 3 - jj - l;
                    d[3 * i + jj][3 * k + l] = e1 * levi(jj, l, n) * f[m][n];
                }
            }
        }
    }
    d
}

/// Volume measure J(F) with its first and second derivatives, per unit reference volume.
pub struct VolumeMeasure {
    pub j: f64,
    pub dj: Mat3,
    pub d2j: Option<Tensor4>,
}

/// `J = det F` (finite strain) or its linearisation `1 + tr(F - I)` (small strain).
pub fn volume_measure(kin: Kinematics, f: &Mat3) -> VolumeMeasure {
    match kin {
        Kinematics::Linear => VolumeMeasure {
            j: f[0][0] + f[1][1] + f[2][2] - 2.0,
            dj: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            d2j: None,
        },
        Kinematics::NeoHookean => VolumeMeasure {
            j: det(f),
            dj: cofactor(f),
            d2j: Some(cofactor_derivative(f)),
        },
    }
}

/// Deviatoric energy density, its stress P = dW/dF and tangent A = d2W/dF2 (all per unit
/// reference volume), for shear modulus `mu`.
pub fn deviatoric(kin: Kinematics, mu: f64, f: &Mat3) -> (f64, Mat3, Tensor4) {
    match kin {
        Kinematics::Linear => small_strain_deviatoric(mu, f),
        Kinematics::NeoHookean => neo_hookean_deviatoric(mu, f),
    }
}

/// W = mu eps_dev : eps_dev, eps = sym(F - I).
fn small_strain_deviatoric(mu: f64, f: &Mat3) -> (f64, Mat3, Tensor4) {
    let mut eps = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            eps[i][j] = 0.5 * (f[i][j] + f[j][i]) - if i == j { 1.0 } else { 0.0 };
        }
    }
    let tr = (eps[0][0] + eps[1][1] + eps[2][2]) / 3.0;
    let mut w = 0.0;
    let mut p = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let dev = eps[i][j] - if i == j { tr } else { 0.0 };
            w += mu * dev * dev;
            p[i][j] = 2.0 * mu * dev;
        }
    }
    let mut a = [[0.0; 9]; 9];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    let d = |x: usize, y: usize| if x == y { 1.0 } else { 0.0 };
                    a[3 * i + j][3 * k + l] = mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k))
                        - 2.0 * mu / 3.0 * d(i, j) * d(k, l);
                }
            }
        }
    }
    (w, p, a)
}

/// W = mu/2 (J^{-2/3} I1 - 3), I1 = F:F. With g(J) = J^{-2/3} and H = cof F:
/// P = mu/2 (g' I1 H + 2 g F),
/// A = mu/2 [g'' I1 H⊗H + 2 g' (F⊗H + H⊗F) + g' I1 dH/dF + 2 g 1⊗1].
fn neo_hookean_deviatoric(mu: f64, f: &Mat3) -> (f64, Mat3, Tensor4) {
    let j = det(f);
    let h = cofactor(f);
    let dh = cofactor_derivative(f);
    let i1: f64 = f.iter().flatten().map(|v| v * v).sum();
    let g = j.powf(-2.0 / 3.0);
    let g1 = -2.0 / 3.0 * g / j;
    let g2 = 10.0 / 9.0 * g / (j * j);
    let w = 0.5 * mu * (g * i1 - 3.0);
    let mut p = [[0.0; 3]; 3];
    for i in 0..3 {
        for jj in 0..3 {
            p[i][jj] = 0.5 * mu * (g1 * i1 * h[i][jj] + 2.0 * g * f[i][jj]);
        }
    }
    let fl: [f64; 9] = std::array::from_fn(|r| f[r / 3][r % 3]);
    let hl: [f64; 9] = std::array::from_fn(|r| h[r / 3][r % 3]);
    let mut a = [[0.0; 9]; 9];
    for r in 0..9 {
        for c in 0..9 {
            let ident = if r == c { 2.0 * g } else { 0.0 };
            a[r][c] = 0.5
                * mu
                * (g2 * i1 * hl[r] * hl[c]
                    + 2.0 * g1 * (fl[r] * hl[c] + hl[r] * fl[c])
                    + g1 * i1 * dh[r][c]
                    + ident);
        }
    }
    (w, p, a)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_f() -> Mat3 {
        [[1.1, 0.05, -0.02], [0.03, 0.93, 0.04], [-0.01, 0.02, 1.02]]
    }

    /// Central differences of W give P, of P give A (the tangent drives Newton's quadratic rate).
    #[test]
    fn neo_hookean_stress_and_tangent_match_finite_differences() {
        let f = sample_f();
        let (_, p, a) = neo_hookean_deviatoric(2.0, &f);
        let h = 1e-6;
        for r in 0..9 {
            let (i, jj) = (r / 3, r % 3);
            let mut fp = f;
            let mut fm = f;
            fp[i][jj] += h;
            fm[i][jj] -= h;
            let (wp, pp, _) = neo_hookean_deviatoric(2.0, &fp);
            let (wm, pm, _) = neo_hookean_deviatoric(2.0, &fm);
            assert!(((wp - wm) / (2.0 * h) - p[i][jj]).abs() < 1e-7);
            for c in 0..9 {
                let fd = (pp[c / 3][c % 3] - pm[c / 3][c % 3]) / (2.0 * h);
                assert!((fd - a[c][r]).abs() < 1e-6, "A[{c}][{r}]");
            }
        }
    }

    #[test]
    fn cofactor_derivative_matches_finite_differences() {
        let f = sample_f();
        let d = cofactor_derivative(&f);
        let h = 1e-6;
        for c in 0..9 {
            let mut fp = f;
            let mut fm = f;
            fp[c / 3][c % 3] += h;
            fm[c / 3][c % 3] -= h;
            let (hp, hm) = (cofactor(&fp), cofactor(&fm));
            for r in 0..9 {
                let fd = (hp[r / 3][r % 3] - hm[r / 3][r % 3]) / (2.0 * h);
                assert!((fd - d[r][c]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn neo_hookean_reduces_to_small_strain_near_identity() {
        let mut f = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        f[0][1] = 1e-5;
        f[2][2] += 2e-5;
        let (_, pn, _) = neo_hookean_deviatoric(3.0, &f);
        let (_, pl, _) = small_strain_deviatoric(3.0, &f);
        for i in 0..3 {
            for j in 0..3 {
                assert!((pn[i][j] - pl[i][j]).abs() < 1e-8);
            }
        }
    }
}
