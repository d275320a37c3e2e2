//! Rigid flat-ended rod against the gel surface: node-to-rigid-surface penalty contact with
//! optional regularised Coulomb friction.
//!
//! Why a penalty: the rod is rigid and analytic, so the gap of every surface node is a closed
//! form; a penalty keeps the unknowns and the sparsity pattern fixed (no multipliers, no
//! active-set changes of the matrix size), which is what lets the symbolic factorisation be
//! reused for the whole curve. The penalty is a pressure per unit penetration,
//! eps = PENALTY x E / l_a (l_a = sqrt of the node's tributary area), so the penetration is
//! about p l_a / (PENALTY E): below 1 % of a typical element size at the 60 N contact
//! pressures, and it scales with E so the whole model scales exactly with E. The test
//! `penalty_does_not_drive_the_answer` doubles it and checks the force moves < 1 %.
//!
//! Geometry: rod axis through the hemisphere centre (the base centre) along
//! e = (sin th cos ph, sin th sin ph, cos th); the end face is the plane e.x = R - delta where
//! delta is the rod travel since first touch; the end disc has a rounded rim (fillet r_f) so
//! the gap is C1 and Newton does not chatter at the rim.

/// Penalty pressure per unit penetration, in units of E / l.
pub const PENALTY: f64 = 200.0;
/// Onset length of the smoothed penalty as a fraction of l. It must be short against the
/// penetrations at equilibrium (p l / (PENALTY E), 1e-3 l to 1e-2 l here): a node inside the
/// quadratic onset has a force ~ g^2, on which Newton only halves the error per iteration.
/// At 0.05 l nearly every contact node sat there and Newton needed ~4 iterations per load step
/// with a linear rate of ~0.2; at 1e-3 l the laws are linear at equilibrium and a step takes
/// 2–3 (the curve moves by < 0.1 %).
pub const RAMP_FRACTION: f64 = 0.001;
/// Rim fillet radius as a fraction of the rod radius.
const FILLET_FRACTION: f64 = 0.1;
/// Regularisation slip length of Coulomb friction as a fraction of the rod radius.
const SLIP_FRACTION: f64 = 1e-3;

use crate::rod_shape::{curved_end_probe, cylinder_axis, Drive, RodShape};

/// The rigid rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rod {
    /// Unit axis e pointing from the hemisphere centre towards the rod.
    pub axis: [f64; 3],
    /// Rod radius, m.
    pub radius_m: f64,
    /// Axial position of the end face, m (R at first touch).
    pub face_m: f64,
    /// Coulomb friction coefficient (0: frictionless).
    pub mu: f64,
    /// Shape of the end ([`RodShape`]).
    pub shape: RodShape,
    /// Axis of a cylinder lying across ([`RodShape::CylinderAcross`]), unit, perpendicular to e.
    pub across: [f64; 3],
    /// Displacement of the rod perpendicular to e since first touch, m (zero when the machine
    /// drives along e; see [`Drive`]).
    pub lateral_m: [f64; 3],
    /// Unit direction along which the machine drives the rod and its load cell measures.
    pub drive: [f64; 3],
}

/// Contact of one node: penetration, outward normal of the rod at that point.
#[derive(Debug, Clone, Copy)]
pub struct NodeContact {
    pub penetration_m: f64,
    pub normal: [f64; 3],
}

impl Rod {
    pub fn new(theta_deg: f64, phi_deg: f64, radius_m: f64, face_m: f64, mu: f64) -> Rod {
        let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
        let axis = [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()];
        Rod {
            axis,
            radius_m,
            face_m,
            mu,
            shape: RodShape::FlatEnd,
            across: cylinder_axis(theta_deg, phi_deg),
            lateral_m: [0.0; 3],
            drive: axis,
        }
    }

    /// The rod of `shape` driven along `drive` by `travel_m` since first touch, whose end first
    /// touched the hemisphere of radius `r_hemisphere_m` (its end at s_face = R then).
    pub fn driven(self, shape: RodShape, drive: Drive, r_hemisphere_m: f64, travel_m: f64) -> Rod {
        let m = drive.direction(self.axis);
        let along = m[0] * self.axis[0] + m[1] * self.axis[1] + m[2] * self.axis[2];
        // The machine moves the rod by -travel m: along e by -travel (m.e), across by the rest.
        let lateral_m = [0, 1, 2].map(|k| -travel_m * (m[k] - along * self.axis[k]));
        Rod {
            shape,
            face_m: r_hemisphere_m - travel_m * along,
            lateral_m,
            drive: m,
            ..self
        }
    }

    /// The rod's displacement since first touch relative to `face0_m`/`lateral0_m`, m.
    pub fn displacement_from(&self, face0_m: f64, lateral0_m: [f64; 3]) -> [f64; 3] {
        [0, 1, 2]
            .map(|k| (self.face_m - face0_m) * self.axis[k] + self.lateral_m[k] - lateral0_m[k])
    }

    /// Penetration of point `x` into the rod body (None when outside).
    pub fn probe(&self, x: [f64; 3]) -> Option<NodeContact> {
        // In the frame that moves across e with the rod, the rod's axis passes through 0.
        let x = [0, 1, 2].map(|k| x[k] - self.lateral_m[k]);
        let e = self.axis;
        if self.shape != RodShape::FlatEnd {
            let r = self.radius_m;
            let c = e.map(|v| v * (self.face_m + r));
            let t = (self.shape == RodShape::CylinderAcross).then_some(self.across);
            return curved_end_probe(x, c, r, t).map(|(penetration_m, normal)| NodeContact {
                penetration_m,
                normal,
            });
        }
        let s = x[0] * e[0] + x[1] * e[1] + x[2] * e[2];
        if s <= self.face_m {
            return None;
        }
        let radial = [x[0] - s * e[0], x[1] - s * e[1], x[2] - s * e[2]];
        let rho = (radial[0] * radial[0] + radial[1] * radial[1] + radial[2] * radial[2]).sqrt();
        let rf = FILLET_FRACTION * self.radius_m;
        let rc = self.radius_m - rf;
        if rho <= rc {
            return Some(NodeContact {
                penetration_m: s - self.face_m,
                normal: [-e[0], -e[1], -e[2]],
            });
        }
        let rhat = radial.map(|v| v / rho);
        let (ds, dr) = (s - (self.face_m + rf), rho - rc);
        if ds >= 0.0 {
            // Beside the cylinder wall.
            return (rho < self.radius_m).then_some(NodeContact {
                penetration_m: self.radius_m - rho,
                normal: rhat,
            });
        }
        let dist = (ds * ds + dr * dr).sqrt();
        if dist >= rf {
            return None;
        }
        let n = [0, 1, 2].map(|k| (ds * e[k] + dr * rhat[k]) / dist);
        Some(NodeContact {
            penetration_m: rf - dist,
            normal: n,
        })
    }

    pub fn slip_regularisation_m(&self) -> f64 {
        SLIP_FRACTION * self.radius_m
    }
}

/// Normal force and its derivative for penetration `g`: the penalty law k g made C1 by a
/// quadratic onset over `ramp` (k g^2 / 2 ramp below it, k (g - ramp/2) above). Without the
/// ramp a node entering contact switches its stiffness from 0 to k at once, and Newton
/// chatters between "in" and "out".
pub fn normal_law(g: f64, k: f64, ramp: f64) -> (f64, f64) {
    if g < ramp {
        (0.5 * k * g * g / ramp, k * g / ramp)
    } else {
        (k * (g - 0.5 * ramp), k)
    }
}

/// Contact force on one node and its tangent (-d force / d x), for a node of penalty
/// stiffness `k` (N/m) and onset length `ramp` (m) that has moved `slip` (m) relative to the
/// rod during the step.
pub fn node_response(
    c: &NodeContact,
    k: f64,
    ramp: f64,
    slip: [f64; 3],
    rod: &Rod,
) -> ([f64; 3], [[f64; 3]; 3]) {
    let n = c.normal;
    let (fn_, kn) = normal_law(c.penetration_m, k, ramp);
    let mut f = n.map(|v| fn_ * v);
    let mut kt = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            kt[i][j] = kn * n[i] * n[j];
        }
    }
    if rod.mu > 0.0 {
        let sn = slip[0] * n[0] + slip[1] * n[1] + slip[2] * n[2];
        let st = [0, 1, 2].map(|i| slip[i] - sn * n[i]);
        let eps = rod.slip_regularisation_m();
        let s = (st[0] * st[0] + st[1] * st[1] + st[2] * st[2] + eps * eps).sqrt();
        let c_t = rod.mu * fn_;
        for i in 0..3 {
            f[i] -= c_t * st[i] / s;
            for j in 0..3 {
                let proj = if i == j { 1.0 } else { 0.0 } - n[i] * n[j];
                // Symmetric part of the consistent tangent (the normal-force coupling is dropped).
                kt[i][j] += c_t * (proj / s - st[i] * st[j] / (s * s * s));
            }
        }
    }
    (f, kt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probe_reports_face_penetration_along_the_axis() {
        let rod = Rod::new(20.0, 60.0, 0.005, 0.019, 0.0);
        let x = rod.axis.map(|v| v * 0.0195);
        let c = rod.probe(x).expect("inside");
        assert!((c.penetration_m - 0.0005).abs() < 1e-12);
        assert!((c.normal[2] + rod.axis[2]).abs() < 1e-12);
        assert!(rod.probe(rod.axis.map(|v| v * 0.0185)).is_none());
    }

    /// Driven along z by s, the rod is its first-touch body translated by -s z: the point that
    /// was the face centre, moved with it and pushed 0.1 mm into the rod, is 0.1 mm deep.
    #[test]
    fn rod_driven_along_z_translates_the_whole_body() {
        use crate::rod_shape::{Drive, RodShape};
        let (r_m, s_m) = (0.02, 0.005);
        let rod0 = Rod::new(20.0, 60.0, 0.03, r_m, 0.0);
        let rod = rod0.driven(RodShape::FlatEnd, Drive::FingertipAxis, r_m, s_m);
        let e = rod.axis;
        let x = [0, 1, 2].map(|k| r_m * e[k] - if k == 2 { s_m } else { 0.0 } + 1e-4 * e[k]);
        let c = rod.probe(x).expect("inside");
        assert!(
            (c.penetration_m - 1e-4).abs() < 1e-12,
            "{}",
            c.penetration_m
        );
        assert_eq!(rod.drive, [0.0, 0.0, 1.0]);
        // Driven along its own axis it is the old rod, face at R - s.
        let same = rod0.driven(RodShape::FlatEnd, Drive::RodAxis, r_m, s_m);
        assert!((same.face_m - (r_m - s_m)).abs() < 1e-15 && same.lateral_m == [0.0; 3]);
    }

    #[test]
    fn rim_gap_is_continuous_with_the_face() {
        let rod = Rod::new(0.0, 0.0, 0.005, 0.0, 0.0);
        let rc = 0.005 * (1.0 - FILLET_FRACTION);
        let a = rod.probe([rc - 1e-9, 0.0, 1e-4]).unwrap();
        let b = rod.probe([rc + 1e-9, 0.0, 1e-4]).unwrap();
        assert!((a.penetration_m - b.penetration_m).abs() < 1e-8);
    }
}
