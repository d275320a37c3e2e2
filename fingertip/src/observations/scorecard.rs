//! The seven rows: each observation's quantities from the FE runs, against the criteria.

use super::criteria::*;
use super::measures::{crossing_fraction, power_law, recovery_time_s, s_shape_lobe};
use super::runs::{inclination_sweep, standard_test};
use super::{cross_moment_nm, tilt_moment_nm, Check, Row, Scorecard, Setup, TestSeries};
use crate::{CurvePoint, Drive, Error};

fn check(quantity: &str, value: f64, criterion: &str, agree: bool) -> Check {
    Check {
        quantity: quantity.into(),
        value,
        criterion: criterion.into(),
        agree: agree && value.is_finite(),
    }
}

fn row(number: u8, statement: &str, checks: Vec<Check>, physics: String) -> Row {
    Row {
        number,
        statement: statement.into(),
        agree: checks.iter().all(|c| c.agree),
        checks,
        physics,
    }
}

/// Run the FE and score the seven observations.
pub fn score(setup: &Setup) -> Result<Scorecard, Error> {
    let theta_test = setup.config.contact_angle_deg;
    let others: Vec<f64> = setup
        .sweep_deg
        .iter()
        .copied()
        .filter(|&t| t != theta_test)
        .collect();
    let mut series = standard_test(&setup.config, &setup.test)?;
    let mut sweep = inclination_sweep(&setup.config, &others, setup.test.peak_load_n)?;
    let test_peak = series.points[series.loading_len - 1];
    sweep.push((theta_test, test_peak));
    sweep.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some(filter) = setup.output_filter {
        apply_filter(&mut series, filter);
    }
    let phi = setup.config.azimuth_deg;
    let rows = vec![
        power_law_row(&series),
        ratio_row(&sweep, theta_test, setup.config.drive),
        recovery_row(&series),
        moments_row(&test_peak, phi),
        crossing_row(&series, phi),
        inclination_row(&sweep, phi),
        s_shape_row(&series),
    ];
    Ok(Scorecard {
        label: setup.label.clone(),
        rows,
        sweep,
        series,
        azimuth_deg: phi,
    })
}

fn apply_filter(series: &mut TestSeries, filter: &super::OutputFilter) {
    let t: Vec<f64> = series.points.iter().map(|p| p.t_s).collect();
    let channels: [fn(&mut CurvePoint) -> &mut f64; 3] =
        [|p| &mut p.fz_n, |p| &mut p.mx_nm, |p| &mut p.my_nm];
    for get in channels {
        let mut y: Vec<f64> = series.points.iter_mut().map(|p| *get(p)).collect();
        filter(&t, &mut y);
        for (p, v) in series.points.iter_mut().zip(y) {
            *get(p) = v;
        }
    }
}

fn at_theta(sweep: &[(f64, CurvePoint)], theta: f64) -> CurvePoint {
    sweep
        .iter()
        .min_by(|a, b| (a.0 - theta).abs().total_cmp(&(b.0 - theta).abs()))
        .map(|s| s.1)
        .unwrap_or_default()
}

fn power_law_row(series: &TestSeries) -> Row {
    let loading = &series.points[..series.loading_len];
    let samples: Vec<(f64, f64)> = loading.iter().map(|p| (p.rod_mm, p.fz_n)).collect();
    let (n, rms) = power_law(&samples, POWER_LAW_FROM);
    row(
        1,
        "The outputs grow nonlinearly (a power law) while the rod moves at constant speed.",
        vec![
            check(
                "exponent n of |Fz| against rod travel (30-100 % of travel)",
                n,
                &format!("n >= {NONLINEAR_EXPONENT}"),
                n >= NONLINEAR_EXPONENT,
            ),
            check(
                "rms log residual of the power-law fit",
                rms,
                &format!("<= {POWER_LAW_RMS}"),
                rms <= POWER_LAW_RMS,
            ),
        ],
        "contact area growing with the travel (Hertz: n = 1.5) and the bonded base stiffening \
         the thinning gel layer (n towards 2): geometric nonlinearity of the contact"
            .into(),
    )
}

fn ratio_row(sweep: &[(f64, CurvePoint)], theta_test: f64, drive: Drive) -> Row {
    let f0 = at_theta(sweep, 0.0).fz_n;
    let ratio = at_theta(sweep, theta_test).fz_n / f0;
    let cos = theta_test.to_radians().cos();
    let physics = if drive == Drive::FingertipAxis {
        format!(
            "the load cell measures along the chip axis, so the chip keeps the whole load (no \
             cos theta_p); finite strain changes the share the gel passes to the pillar by a \
             factor {ratio:.3} at {theta_test:.0}°"
        )
    } else {
        format!(
        "the chip's Fz is the rod load's component along the chip axis (cos {theta_test:.0}° = \
         {cos:.3}) times the share the gel passes to the pillar; finite strain changes that share \
         by a factor {:.3} at {theta_test:.0}°",
            ratio / cos
        )
    };
    row(
        2,
        "Fz at theta_p = 20° is larger than at 0° (explained by a local minimum of elastic \
         potential energy of a hemispherical fingertip).",
        vec![check(
            &format!("Fz({theta_test:.0}°) / Fz(0°) at the peak load"),
            ratio,
            &format!("> {LARGER_RATIO}"),
            ratio > LARGER_RATIO,
        )],
        physics,
    )
}

/// Time series of one output of the test.
fn channel(series: &TestSeries, f: impl Fn(&CurvePoint) -> f64) -> (Vec<f64>, Vec<f64>) {
    series.points.iter().map(|p| (p.t_s, f(p))).unzip()
}

fn recovery_row(series: &TestSeries) -> Row {
    let (t, fz) = channel(series, |p| p.fz_n);
    let (y0, peak) = (fz[0], fz[series.loading_len - 1]);
    let back = series
        .points
        .iter()
        .position(|p| p.t_s >= series.t_back_s - 1e-9)
        .map_or(y0, |k| fz[k]);
    let dropped = 1.0 - (back - y0) / (peak - y0);
    let t_rec = recovery_time_s(&t, &fz, y0, peak - y0, series.t_back_s, VISIBLE_FRACTION);
    let (lo, hi) = SLOW_RECOVERY_S;
    let residual = value_after(&t, &fz, series.t_back_s + 1.0, y0) / (peak - y0);
    let physics = if t_rec < lo {
        "an elastic (rate-independent) gel and DC-coupled outputs: the outputs follow the rod \
         back at once and nothing is left to recover"
            .to_string()
    } else if residual > 0.0 {
        format!(
            "the gel's shape lags the rod: Fz still {:.1} % of its peak 1 s after the \
                 return, decaying",
            100.0 * residual
        )
    } else {
        format!(
            "a slow tail of the wrong sign: Fz {:.1} % of its peak 1 s after the return, below \
             its initial value (relaxed stress left in the gel, or AC coupling), not above it",
            100.0 * residual
        )
    };
    row(
        3,
        "When the rod returns quickly the outputs drop at once, then return slowly to the initial \
         value over seconds (about 35-36 s on the paper's time axis).",
        vec![
            check(
                "fraction of the Fz peak gone when the rod is back",
                dropped,
                &format!(">= {DROP_AT_ONCE}"),
                dropped >= DROP_AT_ONCE,
            ),
            check(
                &format!(
                    "time after the return until Fz stays within {:.0} % of its peak, s",
                    100.0 * VISIBLE_FRACTION
                ),
                t_rec,
                &format!("in [{lo}, {hi}] s"),
                (lo..=hi).contains(&t_rec),
            ),
            check(
                "Fz 1 s after the return, fraction of its peak (the paper's Fz decreases to its \
                 initial value: from above)",
                residual,
                &format!(">= {VISIBLE_FRACTION}"),
                residual >= VISIBLE_FRACTION,
            ),
        ],
        physics,
    )
}

/// Deviation from `y0` at the first sample at or after `t`.
fn value_after(t_s: &[f64], y: &[f64], t: f64, y0: f64) -> f64 {
    t_s.iter().position(|&s| s >= t).map_or(0.0, |k| y[k] - y0)
}

fn moments_row(peak: &CurvePoint, phi: f64) -> Row {
    let ratio = peak.mx_nm.abs() / peak.my_nm.abs();
    let tan = phi.to_radians().tan().abs();
    row(
        4,
        "Mx > My at azimuth 60°, as the geometry predicts.",
        vec![check(
            "|Mx| / |My| at the peak load",
            ratio,
            &format!("> {LARGER_RATIO}"),
            ratio > LARGER_RATIO,
        )],
        format!(
            "the tilt plane at phi = {phi:.0}° puts the moment vector perpendicular to it \
             (|Mx|/|My| = tan phi = {tan:.2} for a round package; the square package turns it)"
        ),
    )
}

fn crossing_row(series: &TestSeries, phi: f64) -> Row {
    let (t, m) = channel(series, |p| tilt_moment_nm(p, phi));
    let (y0, peak) = (m[0], m[series.loading_len - 1]);
    let crossing = crossing_fraction(&t, &m, y0, peak, series.t_back_s);
    let end = (m[m.len() - 1] - y0) / (peak - y0);
    let physics = if crossing <= -VISIBLE_FRACTION {
        "a high-pass in the path (AC coupling of the offset cut, or the gel's relaxed stress \
         left in the package): the output falls below its initial value and creeps back"
            .into()
    } else {
        "nothing in the model stores a signal of the opposite sign: elastic gel, DC-coupled \
         outputs; the moments come back to their initial value from above"
            .into()
    };
    row(
        5,
        "After the return the moment outputs pass across the initial value before settling back.",
        vec![
            check(
                "largest excursion of the tilt moment past its initial value after the \
                   return, fraction of its peak (negative: crossed)",
                crossing,
                &format!("<= -{VISIBLE_FRACTION}"),
                crossing <= -VISIBLE_FRACTION,
            ),
            check(
                "tilt moment at the end of the recording, fraction of its peak",
                end,
                &format!("within +-{VISIBLE_FRACTION}"),
                end.abs() <= VISIBLE_FRACTION,
            ),
        ],
        physics,
    )
}

fn inclination_row(sweep: &[(f64, CurvePoint)], phi: f64) -> Row {
    let (th_lo, th_hi) = (
        sweep.iter().map(|s| s.0).find(|&t| t > 0.0).unwrap_or(0.0),
        sweep.last().map_or(0.0, |s| s.0),
    );
    let (p0, p_lo, p_hi) = (
        at_theta(sweep, 0.0),
        at_theta(sweep, th_lo),
        at_theta(sweep, th_hi),
    );
    let fz_ratio = p_hi.fz_n / p0.fz_n;
    let growth = tilt_moment_nm(&p_hi, phi) / tilt_moment_nm(&p_lo, phi);
    let cross = (cross_moment_nm(&p_hi, phi) / tilt_moment_nm(&p_hi, phi)).abs();
    let cos = th_hi.to_radians().cos();
    row(
        6,
        "While the load points at the hemisphere's centre Fz hardly changes with theta_p; the \
         moment in the tilt plane grows with theta_p; crosstalk between Mx and My is small.",
        vec![
            check(
                &format!("Fz({th_hi:.0}°) / Fz(0°) at the peak load"),
                fz_ratio,
                &format!("within 1 +- {HARDLY_CHANGES}"),
                (fz_ratio - 1.0).abs() <= HARDLY_CHANGES,
            ),
            check(
                &format!("tilt moment({th_hi:.0}°) / tilt moment({th_lo:.0}°)"),
                growth,
                &format!("> {LARGER_RATIO}"),
                growth > LARGER_RATIO,
            ),
            check(
                &format!("|moment about the tilt direction| / |tilt moment| at {th_hi:.0}°"),
                cross,
                &format!("<= {SMALL_CROSSTALK}"),
                cross <= SMALL_CROSSTALK,
            ),
        ],
        format!(
            "Fz follows the load's component along the chip axis (cos {th_hi:.0}° = {cos:.3}) \
             with a finite-strain factor {:.3}; the tilt moment is the pillar's share of the \
             load's lateral component; the crosstalk is the square package's",
            fz_ratio / cos
        ),
    )
}

fn s_shape_row(series: &TestSeries) -> Row {
    let loading = &series.points[..series.loading_len];
    let traj: Vec<(f64, f64)> = loading.iter().map(|p| (p.fz_n, p.mx_nm)).collect();
    let lobe = s_shape_lobe(&traj);
    let agree = (VISIBLE_FRACTION..=SLIGHT_S_MAX).contains(&lobe);
    let physics = if agree {
        "the ratio Mx/Fz first rises then falls as the contact spreads and the gel stiffens: \
         geometric and material nonlinearity"
            .into()
    } else {
        "Mx/Fz changes monotonically over the loading: the trajectory bends one way only (no \
         inflexion above the plot's resolution)"
            .into()
    };
    row(
        7,
        "A slight S-shaped curve in the Mx trajectory (blamed on geometric and material \
         nonlinearity of the soft material).",
        vec![check(
            "weaker lobe of the S of Mx against Fz over the loading (each over its final value)",
            lobe,
            &format!("in [{VISIBLE_FRACTION}, {SLIGHT_S_MAX}]"),
            agree,
        )],
        physics,
    )
}
