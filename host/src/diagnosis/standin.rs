//! STAND-IN baseline physics, to be replaced as a whole when the `fingertip` (FE) and `chip`
//! crates and `hardware/frontend.toml` land on main. Until then this is the ONE place that holds
//! the provisional contact law and chip/front-end numbers, each with its reason.
//!
//! Contact law: Hertz-type power law for a rigid indenter on an elastic hemisphere,
//! F = 4/3 E/(1 - nu^2) R^(2-n) d^n with n = 3/2 (Hertz, sphere on flat; R the hemisphere
//! radius, d the rod travel). Tilt decomposition of the chip loads: a share `chip_share` of the
//! contact force reaches the chip pillar, along the load axis inclined by theta_p in the plane
//! at azimuth phi: Fz = s F cos(theta), and its tangential part s F sin(theta) acting at the
//! lever `lever_mm` above the chip gives (Mx, My) = s F sin(theta) h (-sin(phi), cos(phi))
//! (r x F with r = h e_z, F_t along (cos phi, sin phi)), so Mx > My at phi = 60 deg as observed.

use super::baseline::{FingertipResponse, FrontEnd, UnitResponse};

/// Hertz exponent of a sphere on a flat (n = 3/2).
pub const HERTZ_EXPONENT: f64 = 1.5;
/// Share of the contact force the 2x2 mm chip carries: the base pressure over a 20 mm radius
/// spread over the chip's ~4 mm^2 gives about 60 N * 4 / (pi 400) = 0.19 N at 60 N, i.e. 0.3 %.
pub const CHIP_SHARE: f64 = 3.0e-3;
/// Height of the load's line of action above the chip: the pillar plus the gel it drags, a
/// few mm (the package is 2 mm tall; stand-in value).
pub const LEVER_MM: f64 = 5.0;
/// Bridge output per volt of excitation: Fz 1 mV/V per N, moments 1 V/V per N·m. Chosen with
/// the gains below so a 60 N test gives outputs of order 1-2 V, as a 3.3 V ADC front end needs;
/// the chip crate's beam/piezoresistor model replaces these.
pub const SENSITIVITY_PER_V: [[f64; 3]; 3] = [[1.0e-3, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// Amplifier gains [Fz, Mx, My] and bridge excitation, as in the recording contract's example
/// (about 3000, lower for the moments; 3.3 V rail) until `hardware/frontend.toml` is on main.
pub const GAIN: [f64; 3] = [3000.0, 1000.0, 1000.0];
pub const EXCITATION_V: f64 = 3.3;

/// The stand-in fingertip: Hertz contact with the tilt decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    pub radius_mm: f64,
    pub poisson: f64,
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
}

impl FingertipResponse for HertzContact {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let d_m = rod_mm.max(0.0) * 1e-3;
        let r_m = self.radius_mm * 1e-3;
        let n = HERTZ_EXPONENT;
        let force_n = 4.0 / 3.0 / (1.0 - self.poisson * self.poisson) * r_m.powf(2.0 - n) * d_m.powf(n);
        let (st, ct) = self.contact_angle_deg.to_radians().sin_cos();
        let (sp, cp) = self.azimuth_deg.to_radians().sin_cos();
        let share = CHIP_SHARE * force_n;
        let tangential_moment = share * st * LEVER_MM * 1e-3;
        UnitResponse { force_n, chip: [share * ct, -tangential_moment * sp, tangential_moment * cp] }
    }
}

/// The stand-in front end with the given gains and excitation (from the recording's metadata
/// when diagnosing, from the command line when simulating).
pub fn front_end(gain: [f64; 3], excitation_v: f64) -> FrontEnd {
    FrontEnd { sensitivity_per_v: SENSITIVITY_PER_V, gain, excitation_v }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hertz: F = 4/3 E* sqrt(R) d^1.5; E = 1e5 Pa, nu = 0.5, R = 20 mm, d = 10 mm gives
    /// 4/3 * 1.3333e5 * 0.14142 * 1e-3 = 25.14 N.
    #[test]
    fn hertz_force_matches_the_closed_form() {
        let h = HertzContact { radius_mm: 20.0, poisson: 0.5, contact_angle_deg: 0.0, azimuth_deg: 0.0 };
        let f = h.unit_response(10.0).force_n * 1e5;
        assert!((f - 25.141).abs() < 1e-2, "{f}");
    }

    /// Mx > My at azimuth 60 deg, moments vanish at theta = 0, Fz falls with cos(theta).
    #[test]
    fn tilt_decomposition() {
        let h = HertzContact { radius_mm: 20.0, poisson: 0.49, contact_angle_deg: 20.0, azimuth_deg: 60.0 };
        let u = h.unit_response(10.0);
        assert!(u.chip[1].abs() > u.chip[2].abs());
        assert!((u.chip[1] / u.chip[2] + 60f64.to_radians().tan()).abs() < 1e-12);
        let flat = HertzContact { contact_angle_deg: 0.0, ..h }.unit_response(10.0);
        assert_eq!(flat.chip[1], 0.0);
        assert!((u.chip[0] / flat.chip[0] - 20f64.to_radians().cos()).abs() < 1e-12);
    }
}
