//! Least-squares fit of the calibration matrix from recordings with known loads.
//!
//! Model, per sample k: load_k = C v_k + t_coef T_k + offset + e_k, with v_k the three bridge
//! volts (at whatever point of the chain they were recorded, usually the ADC input), T_k an
//! optional temperature reading and e_k the error of the reference load. Stacking the samples,
//! X = [v | T | 1] (n x p) and Y = loads (n x 3): B = (X^T X)^-1 X^T Y, one column per load
//! component. Each column j has residual variance s_j^2 = RSS_j / (n - p) and covariance
//! s_j^2 (X^T X)^-1; the standard errors are the square roots of its diagonal.
//!
//! Ordinary least squares assumes the regressors (volts) are exact and the noise is in the
//! reference load. Noise on the volts biases C towards zero by about var(noise)/var(v) per
//! channel (errors in variables), negligible when the calibration loads span the range well.
//!
//! It lives in the `chip` crate (std feature) rather than in the host so that the emulated
//! sensor, the diagnosis and the host share one fit, next to the model that its tests check it
//! against; the host only turns the result into the device's set-calibration command.

use std::fmt;

use crate::sensitivity::Matrix3;

/// One calibration sample: the bridge volts, an optional temperature, the known load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Bridge volts (Fz, Mx, My channels).
    pub volts: [f64; 3],
    /// Temperature reading (any consistent unit), used when the fit has a temperature column.
    pub temperature: f64,
    /// Known load (Fz in N, Mx and My in N·m).
    pub load: [f64; 3],
}

/// The fitted calibration with its uncertainties.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// C: volts to load, row = load component, column = bridge channel.
    pub matrix: Matrix3,
    /// Standard errors of `matrix`.
    pub matrix_std_err: Matrix3,
    /// Temperature coefficients (load per temperature unit), if fitted.
    pub temperature: Option<[f64; 3]>,
    /// Standard errors of `temperature`.
    pub temperature_std_err: Option<[f64; 3]>,
    /// Load at zero volts (and zero temperature).
    pub offset: [f64; 3],
    /// Standard errors of `offset`.
    pub offset_std_err: [f64; 3],
    /// Root-mean-square residual per load component.
    pub residual_rms: [f64; 3],
    /// Number of samples used.
    pub samples: usize,
}

/// Why a calibration could not be fitted.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum FitError {
    /// Not more samples than fitted parameters per component.
    TooFewSamples {
        /// Samples given.
        samples: usize,
        /// Parameters per load component.
        parameters: usize,
    },
    /// A sample holds a NaN or an infinity.
    NonFinite {
        /// Index of the first bad sample.
        index: usize,
    },
    /// The loads do not excite every channel independently (X^T X is singular).
    Singular,
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewSamples { samples, parameters } => write!(
                f,
                "{samples} samples cannot determine {parameters} parameters per component with an uncertainty"
            ),
            Self::NonFinite { index } => write!(f, "sample {index} holds a NaN or infinite value"),
            Self::Singular => write!(f, "the calibration loads do not excite the channels independently"),
        }
    }
}

impl std::error::Error for FitError {}

/// Fit C (and offsets, and a temperature column if `with_temperature`) to `samples`.
pub fn fit(samples: &[Sample], with_temperature: bool) -> Result<Fit, FitError> {
    let p = if with_temperature { 5 } else { 4 };
    let n = samples.len();
    if n <= p {
        return Err(FitError::TooFewSamples {
            samples: n,
            parameters: p,
        });
    }
    if let Some(index) = samples.iter().position(|s| !finite(s)) {
        return Err(FitError::NonFinite { index });
    }
    let row = |s: &Sample| -> Vec<f64> {
        let mut r = s.volts.to_vec();
        if with_temperature {
            r.push(s.temperature);
        }
        r.push(1.0);
        r
    };
    let mut xtx = vec![vec![0.0; p]; p];
    let mut xty = vec![[0.0; 3]; p];
    for s in samples {
        let x = row(s);
        for i in 0..p {
            for j in 0..p {
                xtx[i][j] += x[i] * x[j];
            }
            for (c, y) in s.load.iter().enumerate() {
                xty[i][c] += x[i] * y;
            }
        }
    }
    let inv = invert(xtx).ok_or(FitError::Singular)?;
    let beta: Vec<[f64; 3]> = (0..p)
        .map(|i| [0, 1, 2].map(|c| (0..p).map(|k| inv[i][k] * xty[k][c]).sum()))
        .collect();
    let mut rss = [0.0; 3];
    for s in samples {
        let x = row(s);
        for c in 0..3 {
            let predicted: f64 = (0..p).map(|i| x[i] * beta[i][c]).sum();
            rss[c] += (s.load[c] - predicted).powi(2);
        }
    }
    let dof = (n - p) as f64;
    let se = |i: usize, c: usize| (rss[c] / dof * inv[i][i]).sqrt();
    let t = with_temperature.then_some(3);
    Ok(Fit {
        matrix: [0, 1, 2].map(|c| [0, 1, 2].map(|i| beta[i][c])),
        matrix_std_err: [0, 1, 2].map(|c| [0, 1, 2].map(|i| se(i, c))),
        temperature: t.map(|i| [0, 1, 2].map(|c| beta[i][c])),
        temperature_std_err: t.map(|i| [0, 1, 2].map(|c| se(i, c))),
        offset: [0, 1, 2].map(|c| beta[p - 1][c]),
        offset_std_err: [0, 1, 2].map(|c| se(p - 1, c)),
        residual_rms: rss.map(|r| (r / n as f64).sqrt()),
        samples: n,
    })
}

fn finite(s: &Sample) -> bool {
    s.volts.iter().chain(&s.load).all(|v| v.is_finite()) && s.temperature.is_finite()
}

/// Gauss-Jordan inverse with partial pivoting of a small symmetric positive matrix, after
/// scaling it to unit diagonal so that columns in volts and in degrees are treated alike.
fn invert(mut a: Vec<Vec<f64>>) -> Option<Vec<Vec<f64>>> {
    let p = a.len();
    let d: Vec<f64> = (0..p).map(|i| a[i][i].sqrt()).collect();
    if d.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return None;
    }
    for i in 0..p {
        for j in 0..p {
            a[i][j] /= d[i] * d[j];
        }
    }
    let mut inv: Vec<Vec<f64>> = (0..p)
        .map(|i| (0..p).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for col in 0..p {
        let pivot = (col..p).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let div = a[col][col];
        for j in 0..p {
            a[col][j] /= div;
            inv[col][j] /= div;
        }
        for r in 0..p {
            if r != col {
                let factor = a[r][col];
                for j in 0..p {
                    a[r][j] -= factor * a[col][j];
                    inv[r][j] -= factor * inv[col][j];
                }
            }
        }
    }
    for i in 0..p {
        for j in 0..p {
            inv[i][j] /= d[i] * d[j];
        }
    }
    Some(inv)
}
