//! The 3x3 sensitivity matrix S (bridge volts per N and per N·m, at the bridge terminals) and its
//! inverse, the calibration matrix C = S^-1 (volts to N, N·m).

use crate::bridge::linear_weights_v;
use crate::params::{ChipParams, Load};
use crate::piezo::resistor_change;

/// A 3x3 matrix, row-major.
pub type Matrix3 = [[f64; 3]; 3];

/// Unit loads: 1 N of Fz, 1 N·m of Mx, 1 N·m of My.
const UNIT_LOADS: [Load; 3] = [
    Load::new(1.0, 0.0, 0.0),
    Load::new(0.0, 1.0, 0.0),
    Load::new(0.0, 0.0, 1.0),
];

/// `S[i][j]` = d(output of bridge i) / d(load component j), rows Fz, Mx, My bridges, columns
/// Fz (V/N), Mx (V/(N·m)), My (V/(N·m)). Exact for the linearised bridges: the stresses are
/// linear in the load, so Delta R / R at a unit load is the derivative.
pub fn sensitivity_matrix(p: &ChipParams) -> Matrix3 {
    let mut s = [[0.0; 3]; 3];
    for (i, bridge) in p.bridges.iter().enumerate() {
        let weights = linear_weights_v(p, bridge);
        for (j, unit) in UNIT_LOADS.iter().enumerate() {
            s[i][j] = bridge
                .resistors
                .iter()
                .zip(weights)
                .map(|(r, w)| w * resistor_change(p, *unit, r))
                .sum();
        }
    }
    s
}

/// Determinant of a 3x3 matrix.
pub fn determinant(m: &Matrix3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Inverse by the adjugate; `None` when the matrix is singular. The test is scale-free (rows in
/// V/N and V/(N·m) differ by 10^4): |det| over the product of the row norms (Hadamard's ratio,
/// 1 for orthogonal rows) must exceed 1e-12.
pub fn inverse(m: &Matrix3) -> Option<Matrix3> {
    let det = determinant(m);
    let row_norms: f64 = m
        .iter()
        .map(|r| libm::sqrt(r.iter().map(|v| v * v).sum::<f64>()))
        .product();
    if !det.is_finite() || row_norms == 0.0 || det.abs() <= 1e-12 * row_norms {
        return None;
    }
    let cof =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let adj = [
        [cof(1, 2, 1, 2), -cof(0, 2, 1, 2), cof(0, 1, 1, 2)],
        [-cof(1, 2, 0, 2), cof(0, 2, 0, 2), -cof(0, 1, 0, 2)],
        [cof(1, 2, 0, 1), -cof(0, 2, 0, 1), cof(0, 1, 0, 1)],
    ];
    Some(adj.map(|row| row.map(|v| v / det)))
}

/// Product of two 3x3 matrices.
pub fn multiply(a: &Matrix3, b: &Matrix3) -> Matrix3 {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// The calibration matrix C = S^-1 at the bridge terminals (volts to N, N·m, N·m).
pub fn calibration_matrix(p: &ChipParams) -> Option<Matrix3> {
    inverse(&sensitivity_matrix(p))
}

/// Calibration matrix for volts after amplifiers of gains `gains` (per bridge):
/// C_adc = S^-1 diag(1/G).
pub fn calibration_matrix_after_gains(p: &ChipParams, gains: [f64; 3]) -> Option<Matrix3> {
    let c = calibration_matrix(p)?;
    if gains.iter().any(|g| !g.is_finite() || *g == 0.0) {
        return None;
    }
    Some(c.map(|row| [row[0] / gains[0], row[1] / gains[1], row[2] / gains[2]]))
}

/// Crosstalk of load j into bridge i relative to bridge j's own response: `S[i][j] / S[j][j]`
/// (zero on the diagonal).
pub fn crosstalk(s: &Matrix3) -> Matrix3 {
    let mut x = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            if i != j && s[j][j] != 0.0 {
                x[i][j] = s[i][j] / s[j][j];
            }
        }
    }
    x
}
