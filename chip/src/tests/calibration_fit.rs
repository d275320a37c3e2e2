//! The least-squares calibration recovers a known matrix from emulated noisy data, within the
//! uncertainty it reports.

#![allow(clippy::needless_range_loop)]

use crate::bridge::bridge_outputs_v;
use crate::calibration::{fit, FitError, Sample};
use crate::params::{ChipParams, Load};
use crate::sensitivity::{inverse, sensitivity_matrix};

/// splitmix64: a small deterministic generator for the emulated recordings.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * core::f64::consts::PI * u2).cos()
    }
}

const GAINS: [f64; 3] = [3000.0, 1000.0, 1000.0];
/// Load-cell noise of the reference (N, N·m, N·m).
const NOISE: [f64; 3] = [1e-4, 2e-8, 2e-8];

/// A recording: random loads that keep the amplified outputs within +-2.5 V (+-4 mN, +-0.8 N·um
/// at the gains below), the model's amplified volts
/// plus a temperature drift of the offsets, and a noisy reference load.
fn recording(p: &ChipParams, seed: u64, n: usize) -> (Vec<Sample>, [f64; 3]) {
    let mut rng = Rng(seed);
    let drift_v_per_k = [1e-3, -2e-3, 5e-4];
    let offset_v = [0.05, -0.02, 0.01];
    let samples = (0..n)
        .map(|_| {
            let load = Load::new(
                0.004 * (2.0 * rng.uniform() - 1.0),
                0.8e-6 * (2.0 * rng.uniform() - 1.0),
                0.8e-6 * (2.0 * rng.uniform() - 1.0),
            );
            let t = 25.0 + 10.0 * (2.0 * rng.uniform() - 1.0);
            let raw = bridge_outputs_v(p, load);
            let volts = [0, 1, 2].map(|i| GAINS[i] * raw[i] + offset_v[i] + drift_v_per_k[i] * t);
            let noisy = [0, 1, 2].map(|i| load.to_array()[i] + NOISE[i] * rng.normal());
            Sample {
                volts,
                temperature: t,
                load: noisy,
            }
        })
        .collect();
    (samples, drift_v_per_k)
}

fn true_matrix(p: &ChipParams) -> [[f64; 3]; 3] {
    let c = inverse(&sensitivity_matrix(p)).expect("invertible");
    c.map(|row| [row[0] / GAINS[0], row[1] / GAINS[1], row[2] / GAINS[2]])
}

#[test]
fn fit_recovers_the_model_matrix_within_its_reported_uncertainty() {
    let p = ChipParams::load_default().unwrap();
    let truth = true_matrix(&p);
    let (mut sum_z2, mut count, mut beyond_3) = (0.0, 0, 0);
    for seed in 1..=20u64 {
        let (samples, drift) = recording(&p, seed, 200);
        let f = fit(&samples, true).expect("fit");
        for i in 0..3 {
            for j in 0..3 {
                let z = (f.matrix[i][j] - truth[i][j]) / f.matrix_std_err[i][j];
                sum_z2 += z * z;
                count += 1;
                beyond_3 += usize::from(z.abs() > 3.0);
            }
            // Temperature coefficient truth: -sum_j C_ij drift_j.
            let t_true: f64 = -(0..3).map(|j| truth[i][j] * drift[j]).sum::<f64>();
            let (t, se) = (f.temperature.unwrap()[i], f.temperature_std_err.unwrap()[i]);
            let z = (t - t_true) / se;
            sum_z2 += z * z;
            count += 1;
            beyond_3 += usize::from(z.abs() > 3.0);
        }
    }
    let mean_z2 = sum_z2 / count as f64;
    println!("{count} z-scores over 20 seeds: mean z^2 = {mean_z2:.3}, {beyond_3} beyond 3 sigma");
    // 240 z-scores: mean z^2 is 1 +- 0.09 (1 sigma) when the reported errors are right.
    assert!((0.7..1.35).contains(&mean_z2), "mean z^2 = {mean_z2}");
    assert!(beyond_3 <= 3, "{beyond_3} of {count} beyond 3 sigma");
}

#[test]
fn fit_is_precise_enough_to_matter() {
    let p = ChipParams::load_default().unwrap();
    let truth = true_matrix(&p);
    let (samples, _) = recording(&p, 99, 500);
    let f = fit(&samples, true).unwrap();
    for i in 0..3 {
        let rel = (f.matrix[i][i] - truth[i][i]).abs() / truth[i][i].abs();
        assert!(rel < 0.01, "diagonal {i} off by {rel}");
    }
}

#[test]
fn fit_refuses_degenerate_data() {
    let s = Sample {
        volts: [1.0, 2.0, 3.0],
        temperature: 20.0,
        load: [0.0; 3],
    };
    assert_eq!(
        fit(&[s; 4], false),
        Err(FitError::TooFewSamples {
            samples: 4,
            parameters: 4
        })
    );
    assert_eq!(fit(&[s; 10], false), Err(FitError::Singular));
    let mut bad = vec![s; 10];
    bad[3].volts[1] = f64::NAN;
    assert_eq!(fit(&bad, false), Err(FitError::NonFinite { index: 3 }));
}
