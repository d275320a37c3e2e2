//! The rod's end shape and the direction the test machine drives it: the geometry of the
//! compression test that the paper leaves open.
//!
//! The paper's Fig. 10 speaks of the rod's "contact line" kept at 60° from the chip's x axis,
//! and its text of "a pushing rod that inclines by 20 deg". Neither fixes the end's shape nor
//! whether the fingertip is tilted on a jig under a rod pushing along its own axis, or stands
//! upright under a rod with an inclined end that the machine drives along the fingertip's
//! axis. Each reading is a shape here plus a [`Drive`]:
//!
//! - [`RodShape::FlatEnd`]: a flat end disc of radius r with a rounded rim (the default; with
//!   r = R it is the platen of the benches);
//! - [`RodShape::SphereEnd`]: a spherical end of radius r, first touching at the pole of the
//!   rod's axis e, centre c = (s_face + r) e: gap g = |x - c| - r;
//! - [`RodShape::CylinderAcross`]: a cylinder of radius r lying across the fingertip (line
//!   contact), its axis t perpendicular to e and in the tilt plane, so that at theta_p = 0 its
//!   contact line runs at the azimuth phi from the chip's x axis: gap g = |(x - c) - ((x - c)
//!   . t) t| - r.
//!
//! Symbols: e the rod axis (unit, from the hemisphere centre towards the rod), s_face the end's
//! position along e, r the rod radius, phi the azimuth, theta_p the inclination.

/// Shape of the rod's end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[non_exhaustive]
pub enum RodShape {
    /// Flat end disc with a rounded rim.
    #[default]
    FlatEnd,
    /// Spherical end of the rod's radius.
    SphereEnd,
    /// Cylinder of the rod's radius lying across the fingertip, axis in the tilt plane.
    CylinderAcross,
}

/// The direction the test machine moves the rod, and along which its load cell measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[non_exhaustive]
pub enum Drive {
    /// Along the rod axis e: the fingertip is tilted by theta_p on a jig under a vertical rod
    /// (the default).
    #[default]
    RodAxis,
    /// Along the fingertip axis z: the fingertip stands upright and the rod's end is inclined
    /// by theta_p; the load cell reads the force along z.
    FingertipAxis,
}

impl Drive {
    /// Unit drive direction for the rod axis `axis` (the machine pushes along minus this).
    pub fn direction(self, axis: [f64; 3]) -> [f64; 3] {
        match self {
            Drive::RodAxis => axis,
            Drive::FingertipAxis => [0.0, 0.0, 1.0],
        }
    }
}

/// Penetration and outward normal (away from the rod) of point `x` relative to a curved end
/// whose centre of curvature is `c_m` and radius `r_m`; `along_t` is the unit axis of a
/// cylinder (None for a sphere).
pub fn curved_end_probe(
    x: [f64; 3],
    c_m: [f64; 3],
    r_m: f64,
    along_t: Option<[f64; 3]>,
) -> Option<(f64, [f64; 3])> {
    let mut d = [x[0] - c_m[0], x[1] - c_m[1], x[2] - c_m[2]];
    if let Some(t) = along_t {
        let s = d[0] * t[0] + d[1] * t[1] + d[2] * t[2];
        d = [0, 1, 2].map(|k| d[k] - s * t[k]);
    }
    let dist_m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if dist_m >= r_m || dist_m <= 1e-12 * r_m {
        return None;
    }
    Some((r_m - dist_m, d.map(|v| v / dist_m)))
}

/// Axis of a cylinder lying across the fingertip: in the tilt plane, perpendicular to the rod
/// axis, t = (cos theta cos phi, cos theta sin phi, -sin theta).
pub fn cylinder_axis(theta_deg: f64, phi_deg: f64) -> [f64; 3] {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    [t.cos() * p.cos(), t.cos() * p.sin(), -t.sin()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius 10 mm centred 25 mm up z: the point (0, 0, 16 mm) lies 1 mm inside,
    /// with the normal pointing down (away from the centre); (0, 0, 14 mm) is outside.
    #[test]
    fn sphere_gap_is_the_distance_to_the_centre_minus_the_radius() {
        let c = [0.0, 0.0, 0.025];
        let (pen, n) = curved_end_probe([0.0, 0.0, 0.016], c, 0.010, None).expect("inside");
        assert!((pen - 0.001).abs() < 1e-12);
        assert!((n[2] + 1.0).abs() < 1e-12);
        assert!(curved_end_probe([0.0, 0.0, 0.014], c, 0.010, None).is_none());
        // Off axis by 6 mm at height 17 mm: distance sqrt(36 + 64) = 10 mm, on the surface.
        assert!(curved_end_probe([0.006, 0.0, 0.017 - 1e-9], c, 0.010, None).is_none());
    }

    /// A cylinder's gap does not depend on the position along its axis; it is the sphere's
    /// gap in the plane normal to the axis.
    #[test]
    fn cylinder_gap_is_invariant_along_its_axis() {
        let t = cylinder_axis(20.0, 60.0);
        let e = crate::contact::Rod::new(20.0, 60.0, 0.01, 0.02, 0.0).axis;
        assert!(
            (t[0] * e[0] + t[1] * e[1] + t[2] * e[2]).abs() < 1e-12,
            "t ⊥ e"
        );
        let c = e.map(|v| v * 0.03);
        let x0 = e.map(|v| v * 0.0205);
        let x1 = [0, 1, 2].map(|k| x0[k] + 0.015 * t[k]);
        let (p0, n0) = curved_end_probe(x0, c, 0.01, Some(t)).expect("inside");
        let (p1, n1) = curved_end_probe(x1, c, 0.01, Some(t)).expect("inside");
        assert!((p0 - 0.0005).abs() < 1e-12 && (p1 - p0).abs() < 1e-12);
        for k in 0..3 {
            assert!((n0[k] + e[k]).abs() < 1e-12 && (n1[k] - n0[k]).abs() < 1e-12);
        }
    }
}
