//! Statistics the diagnosis tests and estimates with, written out where no kept crate has
//! them in this form (each a few lines): tests of whiteness (Ljung–Box with the chi-square
//! tail, an autoregression's evidence by BIC through Levinson–Durbin), erfc, lag-1 and Pearson
//! correlations, a periodogram.

use std::f64::consts::TAU;

/// Ljung–Box statistic over lags 1..=m and its p-value (chi-square with m degrees of freedom,
/// Wilson–Hilferty approximation).
pub fn ljung_box(r: &[f64], m: usize) -> (f64, f64) {
    let n = r.len();
    if n <= m + 1 {
        return (0.0, 1.0);
    }
    let mean = r.iter().sum::<f64>() / n as f64;
    let c0: f64 = r.iter().map(|v| (v - mean).powi(2)).sum();
    if c0 <= 0.0 {
        return (0.0, 1.0);
    }
    let q: f64 = (1..=m)
        .map(|k| {
            let ck: f64 = (k..n).map(|i| (r[i] - mean) * (r[i - k] - mean)).sum();
            (ck / c0).powi(2) / (n - k) as f64
        })
        .sum::<f64>()
        * n as f64
        * (n + 2) as f64;
    (q, chi2_survival(q, m as f64))
}

/// How strongly `r` shows structure, on the information criterion that names effects: the BIC of
/// white noise less that of the best autoregression of order 1 to `max_order` (Yule–Walker, order
/// by BIC), and that order; (0, 0) when white noise is best. An AR model of the residual is a
/// generic stand-in for whatever is missing, so structure is claimed on the same evidence as an
/// effect (a BIC gain above [`crate::candidate::MIN_BIC_GAIN`]). Unlike a portmanteau test at a
/// fixed level, a few small autocorrelations spread over many lags (a model's approximations at
/// a ten-thousandth of the range) must pay for every lag they use.
pub fn ar_evidence(r: &[f64], max_order: usize) -> (f64, usize) {
    let n = r.len();
    if n <= 2 * max_order + 2 {
        return (0.0, 0);
    }
    let mean = r.iter().sum::<f64>() / n as f64;
    let c: Vec<f64> = (0..=max_order)
        .map(|h| {
            (h..n)
                .map(|i| (r[i] - mean) * (r[i - h] - mean))
                .sum::<f64>()
                / n as f64
        })
        .collect();
    let (_, errors) = levinson_durbin(&c);
    let nf = n as f64;
    let bic = |p: usize, e: f64| nf * e.max(f64::MIN_POSITIVE).ln() + p as f64 * nf.ln();
    let white = bic(0, errors[0]);
    errors
        .iter()
        .enumerate()
        .skip(1)
        .map(|(p, &e)| (white - bic(p, e), p))
        .fold((0.0, 0), |best, x| if x.0 > best.0 { x } else { best })
}

/// Lag-1 autocorrelation.
pub fn lag1(r: &[f64]) -> f64 {
    let n = r.len();
    if n < 3 {
        return 0.0;
    }
    let mean = r.iter().sum::<f64>() / n as f64;
    let c0: f64 = r.iter().map(|v| (v - mean).powi(2)).sum();
    let c1: f64 = (1..n).map(|i| (r[i] - mean) * (r[i - 1] - mean)).sum();
    if c0 > 0.0 {
        c1 / c0
    } else {
        0.0
    }
}

/// P(chi2_k > x), Wilson–Hilferty.
pub fn chi2_survival(x: f64, k: f64) -> f64 {
    let z = ((x / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Complementary error function (Numerical Recipes' erfcc, |error| < 1.2e-7).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Pearson correlation of `a` and `b` (over their common length).
pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 3 {
        return 0.0;
    }
    let (ma, mb) = (
        a[..n].iter().sum::<f64>() / n as f64,
        b[..n].iter().sum::<f64>() / n as f64,
    );
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x, y) = (a[i] - ma, b[i] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        0.0
    }
}

/// Coefficients a_1..a_p of the best linear predictor x_k ~ sum_j a_j x_(k-j) for a stationary
/// series with autocovariances `c` (c_0..c_p), and the prediction error's variance at each order
/// 0..=p (fewer where the recursion stops on a singular series). Written out: a dozen lines, no
/// crate for it.
pub fn levinson_durbin(c: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let p = c.len().saturating_sub(1);
    let mut a: Vec<f64> = Vec::with_capacity(p);
    let mut err = c.first().copied().unwrap_or(0.0);
    let mut errors = vec![err];
    for k in 1..=p {
        if err <= 0.0 {
            break;
        }
        let acc: f64 = a.iter().enumerate().map(|(j, aj)| aj * c[k - 1 - j]).sum();
        let kappa = (c[k] - acc) / err;
        let prev = a.clone();
        for (j, aj) in a.iter_mut().enumerate() {
            *aj -= kappa * prev[k - 2 - j];
        }
        a.push(kappa);
        err *= 1.0 - kappa * kappa;
        errors.push(err);
    }
    (a, errors)
}

/// |X_k|^2 of `x` zero-padded to `size` (a power of two). An in-place radix-2 FFT of our own:
/// none of the crates the workspace keeps has one, and a periodogram needs nothing more.
pub fn periodogram(x: &[f64], size: usize) -> Vec<f64> {
    let mut re: Vec<f64> = x
        .iter()
        .copied()
        .chain(std::iter::repeat(0.0))
        .take(size)
        .collect();
    let mut im = vec![0.0; size];
    let bits = size.trailing_zeros();
    for i in 0..size {
        let j = i.reverse_bits() >> (usize::BITS - bits);
        if j > i {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= size {
        let (ws, wc) = (-TAU / len as f64).sin_cos();
        for start in (0..size).step_by(len) {
            let (mut ur, mut ui) = (1.0, 0.0);
            for k in 0..len / 2 {
                let (a, b) = (start + k, start + k + len / 2);
                let (tr, ti) = (re[b] * ur - im[b] * ui, re[b] * ui + im[b] * ur);
                (re[b], im[b]) = (re[a] - tr, im[a] - ti);
                (re[a], im[a]) = (re[a] + tr, im[a] + ti);
                (ur, ui) = (ur * wc - ui * ws, ur * ws + ui * wc);
            }
        }
        len *= 2;
    }
    re.iter().zip(&im).map(|(r, i)| r * r + i * i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The periodogram of a sampled sinusoid peaks at its frequency's bin.
    #[test]
    fn the_periodogram_peaks_at_the_line() {
        let x: Vec<f64> = (0..1000).map(|k| (TAU * 0.125 * k as f64).sin()).collect();
        let p = periodogram(&x, 2048);
        let k = (1..1024).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
        assert_eq!(k, 256);
    }

    #[test]
    fn ljung_box_accepts_noise_and_rejects_a_ramp() {
        let mut g = baseline::synth::Gaussian::new(11);
        let noise: Vec<f64> = (0..5000).map(|_| g.normal()).collect();
        assert!(ljung_box(&noise, 20).1 > 0.01);
        let smooth: Vec<f64> = (0..5000)
            .map(|k| (k as f64 * 0.01).sin() + 0.1 * g.normal())
            .collect();
        assert!(ljung_box(&smooth, 20).1 < 1e-6);
    }

    /// White noise never earns an autoregression on the effects' evidence scale (the largest of
    /// 300 series of 700 is far below it); a sway of 0.8 deviations does, and so does AR(1)
    /// noise with a correlation of 0.3.
    #[test]
    fn ar_evidence_separates_white_from_structure() {
        let mut g = baseline::synth::Gaussian::new(5);
        let worst = (0..300)
            .map(|_| {
                let white: Vec<f64> = (0..700).map(|_| g.normal()).collect();
                ar_evidence(&white, 20).0
            })
            .fold(0.0, f64::max);
        assert!(worst < 0.8 * crate::candidate::MIN_BIC_GAIN, "{worst}");
        let sway: Vec<f64> = (0..700)
            .map(|k| 0.8 * (k as f64 * std::f64::consts::TAU / 60.0).sin() + g.normal())
            .collect();
        assert!(ar_evidence(&sway, 20).0 > crate::candidate::MIN_BIC_GAIN);
        let mut e = 0.0;
        let ar1: Vec<f64> = (0..700)
            .map(|_| {
                e = 0.3 * e + g.normal();
                e
            })
            .collect();
        let (gain, order) = ar_evidence(&ar1, 20);
        assert!(
            gain > 3.0 * crate::candidate::MIN_BIC_GAIN && order == 1,
            "{gain} {order}"
        );
    }

    #[test]
    fn chi2_survival_at_known_points() {
        // chi2_{20}: 31.41 is the 95th percentile.
        assert!((chi2_survival(31.41, 20.0) - 0.05).abs() < 2e-3);
    }
}

/// P(T > t) for Student's t with `df` degrees of freedom (any positive real `df`), through the
/// regularised incomplete beta function. Written here because no kept crate has it (nalgebra
/// and rand carry no distributions).
pub fn student_t_survival(t: f64, df: f64) -> f64 {
    if !t.is_finite() || !df.is_finite() || df <= 0.0 {
        return if t == f64::INFINITY { 0.0 } else { f64::NAN };
    }
    let tail = 0.5 * incomplete_beta(df / (df + t * t), 0.5 * df, 0.5);
    if t >= 0.0 {
        tail
    } else {
        1.0 - tail
    }
}

/// The regularised incomplete beta function I_x(a, b) (continued fraction, Numerical Recipes
/// 6.4, modified Lentz).
fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_fraction(x, a, b) / a
    } else {
        1.0 - ln_front.exp() * beta_fraction(1.0 - x, b, a) / b
    }
}

fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    d = 1.0 / if d.abs() < TINY { TINY } else { d };
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        for aa in [
            m * (b - m) * x / ((qam + m2) * (a + m2)),
            -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)),
        ] {
            d = 1.0 + aa * d;
            d = 1.0 / if d.abs() < TINY { TINY } else { d };
            c = 1.0 + aa / c;
            c = if c.abs() < TINY { TINY } else { c };
            h *= d * c;
        }
        if (d * c - 1.0).abs() < 1e-14 {
            break;
        }
    }
    h
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, |relative error| < 1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

#[cfg(test)]
mod t_tests {
    use super::student_t_survival;

    /// Against tabulated quantiles: t_{0.975} at 1, 5 and 30 degrees of freedom, the normal's
    /// 1.96 at many, and symmetry.
    #[test]
    fn student_t_matches_its_tables() {
        for (t, df) in [(12.706, 1.0), (2.571, 5.0), (2.042, 30.0), (1.960, 1e6)] {
            let p = student_t_survival(t, df);
            assert!((p - 0.025).abs() < 2e-4, "df {df}: {p}");
        }
        assert!((student_t_survival(0.0, 3.0) - 0.5).abs() < 1e-12);
        let (a, b) = (student_t_survival(-1.3, 4.5), student_t_survival(1.3, 4.5));
        assert!((a + b - 1.0).abs() < 1e-12);
    }
}
