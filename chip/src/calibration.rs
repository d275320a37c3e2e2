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

use nalgebra::DMatrix;

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
    // X = [v | T | 1], one row per sample; Y = the loads.
    let x = DMatrix::from_fn(n, p, |k, i| match i {
        0..=2 => samples[k].volts[i],
        3 if with_temperature => samples[k].temperature,
        _ => 1.0,
    });
    let y = DMatrix::from_fn(n, 3, |k, c| samples[k].load[c]);
    let inv = invert(x.tr_mul(&x)).ok_or(FitError::Singular)?;
    let beta = &inv * x.tr_mul(&y);
    let residual = &y - &x * &beta;
    let rss: [f64; 3] = std::array::from_fn(|c| residual.column(c).norm_squared());
    let dof = (n - p) as f64;
    let se = |i: usize, c: usize| (rss[c] / dof * inv[(i, i)]).sqrt();
    let t = with_temperature.then_some(3);
    Ok(Fit {
        matrix: [0, 1, 2].map(|c| [0, 1, 2].map(|i| beta[(i, c)])),
        matrix_std_err: [0, 1, 2].map(|c| [0, 1, 2].map(|i| se(i, c))),
        temperature: t.map(|i| [0, 1, 2].map(|c| beta[(i, c)])),
        temperature_std_err: t.map(|i| [0, 1, 2].map(|c| se(i, c))),
        offset: [0, 1, 2].map(|c| beta[(p - 1, c)]),
        offset_std_err: [0, 1, 2].map(|c| se(p - 1, c)),
        residual_rms: rss.map(|r| (r / n as f64).sqrt()),
        samples: n,
    })
}

fn finite(s: &Sample) -> bool {
    s.volts.iter().chain(&s.load).all(|v| v.is_finite()) && s.temperature.is_finite()
}

/// Inverse of the small symmetric positive matrix X^T X, scaled to unit diagonal first so that
/// columns in volts and in degrees are treated alike; `None` when a pivot of the scaled matrix
/// is below 1e-12 (loads that do not excite every column independently).
fn invert(a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let d = a.diagonal().map(f64::sqrt);
    if d.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return None;
    }
    let scaled = DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] / (d[i] * d[j]));
    let lu = scaled.lu();
    if lu.u().diagonal().iter().any(|pivot| pivot.abs() < 1e-12) {
        return None;
    }
    let inv = lu.try_inverse()?;
    Some(DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| {
        inv[(i, j)] / (d[i] * d[j])
    }))
}
