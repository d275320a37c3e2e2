//! STAND-IN baseline physics, to be replaced as a whole when the `fingertip` (FE) and `chip`
//! crates and `hardware/frontend.toml` land on main. Until then this is the ONE place that holds
//! the provisional contact law and chip/front-end numbers, each with its reason.
//!
//! Contact law: Hertz-type power law for a rigid indenter on an elastic hemisphere,
//! F = 4/3 E/(1 - nu^2) R^(2-n) d^n with n = 3/2 (Hertz, sphere on flat; R the hemisphere
//! radius, d the rod travel). Tilt decomposition of the chip loads: a share `chip_share` of the
//! contact force reaches the chip pillar, along the load axis inclined by theta_p in the plane
//! at azimuth phi: Fz = s F cos(theta), and its tangential part s F sin(theta) acting at the
//! lever `lever_mm` above the chip (the pillar's height, `hardware/chip.toml`) gives (Mx, My) = s F sin(theta) h (-sin(phi), cos(phi))
//! (r x F with r = h e_z, F_t along (cos phi, sin phi)), so Mx > My at phi = 60 deg as observed.

use super::baseline::{FingertipResponse, UnitResponse};

/// Hertz exponent of a sphere on a flat (n = 3/2).
pub const HERTZ_EXPONENT: f64 = 1.5;
/// Share of the contact force that the chip pillar carries. The pressure under a 20 mm
/// hemisphere spread over the 2x2 mm chip would give ~0.3 %, but with the chip's Table I
/// sensitivity (0.2 mV/mN) and the rig's gain of ~3000 that would drive the ADC (+-1.2 V) far
/// into clipping (`hardware/frontend.md`, "Open question: the gains against the chip's
/// sensitivity"). 2e-5 keeps the standard 60 N test near 0.7 V (Fz) and 1 V (moments) at
/// 20 deg, so the diagnosis is exercised in range. The FE model replaces this number.
pub const CHIP_SHARE: f64 = 2.0e-5;

/// The stand-in fingertip: Hertz contact with the tilt decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    pub radius_mm: f64,
    pub poisson: f64,
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    /// Height of the tangential load's line of action above the chip.
    pub lever_mm: f64,
}

impl FingertipResponse for HertzContact {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let d_m = rod_mm.max(0.0) * 1e-3;
        let r_m = self.radius_mm * 1e-3;
        let n = HERTZ_EXPONENT;
        let force_n =
            4.0 / 3.0 / (1.0 - self.poisson * self.poisson) * r_m.powf(2.0 - n) * d_m.powf(n);
        let (st, ct) = self.contact_angle_deg.to_radians().sin_cos();
        let (sp, cp) = self.azimuth_deg.to_radians().sin_cos();
        let share = CHIP_SHARE * force_n;
        let tangential_moment = share * st * self.lever_mm * 1e-3;
        UnitResponse {
            force_n,
            chip: [share * ct, -tangential_moment * sp, tangential_moment * cp],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hertz: F = 4/3 E* sqrt(R) d^1.5; E = 1e5 Pa, nu = 0.5, R = 20 mm, d = 10 mm gives
    /// 4/3 * 1.3333e5 * 0.14142 * 1e-3 = 25.14 N.
    #[test]
    fn hertz_force_matches_the_closed_form() {
        let h = HertzContact {
            radius_mm: 20.0,
            poisson: 0.5,
            contact_angle_deg: 0.0,
            azimuth_deg: 0.0,
            lever_mm: 1.0,
        };
        let f = h.unit_response(10.0).force_n * 1e5;
        assert!((f - 25.141).abs() < 1e-2, "{f}");
    }

    /// Mx > My at azimuth 60 deg, moments vanish at theta = 0, Fz falls with cos(theta).
    #[test]
    fn tilt_decomposition() {
        let h = HertzContact {
            radius_mm: 20.0,
            poisson: 0.49,
            contact_angle_deg: 20.0,
            azimuth_deg: 60.0,
            lever_mm: 1.0,
        };
        let u = h.unit_response(10.0);
        assert!(u.chip[1].abs() > u.chip[2].abs());
        assert!((u.chip[1] / u.chip[2] + 60f64.to_radians().tan()).abs() < 1e-12);
        let flat = HertzContact {
            contact_angle_deg: 0.0,
            ..h
        }
        .unit_response(10.0);
        assert_eq!(flat.chip[1], 0.0);
        assert!((u.chip[0] / flat.chip[0] - 20f64.to_radians().cos()).abs() < 1e-12);
    }
}
