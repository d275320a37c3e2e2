//! What a recording shows but cannot attribute: a deviation that a catalogue effect and a
//! calibration parameter produce alike.
//!
//! A chip rotated on its mount (`crosstalk`) turns the moment vector by its angle. In a test in
//! one direction (one inclination, one azimuth) the baseline's moment vector keeps one
//! direction, phi, so the turn changes only the ratio of the two moment outputs: exactly what the
//! calibrated moment scales do, and what wrong gains in the metadata do. With the scales
//! s_mx, s_my the calibrated vector points along phi' = atan2(s_my sin phi, s_mx cos phi); the
//! equivalent rotation is phi' - phi. Where it exceeds what identical moment chains and the
//! jig's mounting accuracy allow (`hardware/fit-bounds.toml`), the recording shows one of the
//! two, and this says which two rather than guess.

use crate::output::{Numbers, ParamDetail, Undecided};

/// The value and standard error of the baseline parameter `name` among `details`.
fn value(details: &[ParamDetail], name: &str) -> Option<(f64, f64)> {
    let p = details.iter().find(|p| p.name == name)?;
    Some((p.value, p.stderr.unwrap_or(0.0)))
}

/// `crosstalk` against the moment gains, from the calibrated baseline parameters `details` of
/// the reported model and the baseline's moment direction `phi_rad` (atan2(My, Mx) of the chip
/// loads). None when both moment channels are not calibrated, or the turn is within tolerance.
pub fn crosstalk_or_gains(
    details: &[ParamDetail],
    phi_rad: f64,
    cal: &hardware::FitBounds,
) -> Option<Undecided> {
    let (sx, ex) = value(details, "scale_mx")?;
    let (sy, ey) = value(details, "scale_my")?;
    if sx == 0.0 || sy == 0.0 || !phi_rad.is_finite() {
        return None;
    }
    let (s, c) = phi_rad.sin_cos();
    let turned = (sy * s).atan2(sx * c);
    let angle = wrap_deg((turned - phi_rad).to_degrees());
    let ratio = sy / sx;
    // d phi' / d ln(ratio) = sin phi' cos phi': the turn a ratio error makes.
    let per_ln_ratio = (turned.sin() * turned.cos()).abs().to_degrees();
    let sigma = per_ln_ratio * ((ex / sx).powi(2) + (ey / sy).powi(2)).sqrt();
    let allowed = cal.jig_azimuth_tolerance_deg + per_ln_ratio * cal.moment_gain_ratio_tolerance;
    if angle.abs() <= allowed + 2.0 * sigma {
        return None;
    }
    let mut params = Numbers::default();
    params.push("angle_deg", angle);
    params.push("angle_stderr_deg", sigma);
    params.push("moment_gain_ratio", ratio);
    Some(Undecided {
        effects: vec!["crosstalk".into()],
        calibration: vec!["scale_mx".into(), "scale_my".into()],
        params,
        reason: format!(
            "the moment vector points {angle:+.1} deg (+- {sigma:.1}) off the model's, beyond the \
             jig's +- {:.0} deg and identical chains' {:.0} % gain match: either the chip is \
             turned on its mount (crosstalk) or the moment gains in the metadata are off by a \
             ratio of {ratio:.3}; a test in one direction cannot tell them apart (a second \
             azimuth, or a gain check with a known moment, would)",
            cal.jig_azimuth_tolerance_deg,
            100.0 * cal.moment_gain_ratio_tolerance
        ),
    })
}

/// An angle in degrees into (-180, 180].
fn wrap_deg(a: f64) -> f64 {
    let w = a.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn detail(name: &str, value: f64) -> ParamDetail {
        ParamDetail {
            name: name.into(),
            value,
            stderr: Some(1e-4),
            ci_low: None,
            ci_high: None,
            unit: "1".into(),
            lower: -1e3,
            upper: 1e3,
            at_bound: false,
            note: None,
        }
    }

    fn cal() -> hardware::FitBounds {
        hardware::Params::load_default().unwrap().fit_bounds
    }

    /// A rotation of the moment vector by 10 deg at azimuth 60 deg, seen as two scales, is
    /// recovered as 10 deg; equal scales are no turn at all.
    #[test]
    fn a_rotation_seen_as_scales_is_named_as_either() {
        let (phi, a) = (60f64.to_radians(), 10f64.to_radians());
        let (sx, sy) = ((phi + a).cos() / phi.cos(), (phi + a).sin() / phi.sin());
        let d = [detail("scale_mx", sx), detail("scale_my", sy)];
        let u = crosstalk_or_gains(&d, phi, &cal()).expect("10 deg is beyond the jig");
        assert!((u.params.get("angle_deg").unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(u.effects, ["crosstalk"]);
        let same = [detail("scale_mx", 1.3), detail("scale_my", 1.3)];
        assert!(crosstalk_or_gains(&same, phi, &cal()).is_none());
    }

    /// A turn within the jig's mounting accuracy is not reported.
    #[test]
    fn a_turn_within_the_jig_is_not_reported() {
        let (phi, a) = (60f64.to_radians(), 1f64.to_radians());
        let (sx, sy) = ((phi + a).cos() / phi.cos(), (phi + a).sin() / phi.sin());
        let d = [detail("scale_mx", sx), detail("scale_my", sy)];
        assert!(crosstalk_or_gains(&d, phi, &cal()).is_none());
    }
}
