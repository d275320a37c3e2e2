//! Section properties of a beam of width b and thickness h (rectangular cross-section).

use crate::params::Geometry;

/// Second moment of area about the in-plane transverse axis (bending out of the wafer plane):
/// I_Y = b h^3 / 12.
pub fn second_moment_m4(g: &Geometry) -> f64 {
    g.beam_width_m * cube(g.beam_thickness_m) / 12.0
}

/// Section modulus for the top surface: Z_Y = I_Y / (h/2) = b h^2 / 6.
pub fn section_modulus_m3(g: &Geometry) -> f64 {
    g.beam_width_m * g.beam_thickness_m * g.beam_thickness_m / 6.0
}

/// Saint-Venant torsion factor K in T = K G theta / L, for a rectangle with long side p and
/// short side q: K = p q^3 [1/3 - 0.21 (q/p) (1 - q^4 / (12 p^4))] (Roark's Formulas, 7th ed.,
/// Table 10.7 case 4; within 4 % of the exact series for every aspect ratio). For a square it
/// gives 0.1408 q^4 against the exact 0.1406 q^4.
pub fn torsion_factor_m4(g: &Geometry) -> f64 {
    rectangle_torsion_factor_m4(g.beam_width_m, g.beam_thickness_m)
}

/// The same torsion factor for any rectangle of sides `a_m` and `b_m`.
pub fn rectangle_torsion_factor_m4(a_m: f64, b_m: f64) -> f64 {
    let (p, q) = if a_m >= b_m { (a_m, b_m) } else { (b_m, a_m) };
    let ratio = q / p;
    p * cube(q) * (1.0 / 3.0 - 0.21 * ratio * (1.0 - ratio * ratio * ratio * ratio / 12.0))
}

/// Largest torsional shear stress, at the middle of the long sides, for a torque T (Roark,
/// Table 10.7 case 4, with a = p/2, b = q/2): tau = 3T/(8 a b^2) (1 + 0.6095 r + 0.8865 r^2
/// - 1.8023 r^3 + 0.9100 r^4), r = b/a. For a square it gives T / (0.208 q^3).
pub fn max_torsion_shear_pa(g: &Geometry, torque_nm: f64) -> f64 {
    let (p, q) = long_short(g);
    let (a, b) = (p / 2.0, q / 2.0);
    let r = b / a;
    let series = 1.0 + 0.6095 * r + 0.8865 * r * r - 1.8023 * r * r * r + 0.9100 * r * r * r * r;
    3.0 * torque_nm / (8.0 * a * b * b) * series
}

fn long_short(g: &Geometry) -> (f64, f64) {
    let (b, h) = (g.beam_width_m, g.beam_thickness_m);
    if b >= h {
        (b, h)
    } else {
        (h, b)
    }
}

fn cube(x: f64) -> f64 {
    x * x * x
}
