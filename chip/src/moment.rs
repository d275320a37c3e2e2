//! Mx, My (the paper's section II-B), written for My; Mx is the same turned by 90 degrees.
//!
//! The block rotates by theta. Beams A and B bend: the block end of beam A moves by
//! delta_z = c theta and turns by theta, with the frame end clamped. Inverting the cantilever
//! end relations (delta_z = F_RZ L^3/(3EI) + M_RY L^2/(2EI), slope = F_RZ L^2/(2EI) + M_RY L/(EI))
//! with delta_z = c theta and a slope of theta against the frame gives
//!   F_RZ = 6 E I theta (L + 2c) / L^3,   M_RY = 2 E I theta (2L + 3c) / L^2.
//! Beams C and D twist by theta: T_RY = K G theta / L. The moment balance of the block,
//!   My = 2 (F_RZ c + M_RY) + 2 T_RY,
//! gives theta = My / [ (8 E I / L)(1 + 3c/L + 3c^2/L^2) + 2 K G / L ].
//! The bending moment along beam A is M(x) = M_RY - F_RZ (L - x) (magnitudes as above), and the
//! top-surface stress sigma_L(x) = M(x)/Z_Y by superposition of the M_RY and F_RZ terms. The
//! axial force F_RX of the paper is of second order in theta and left out of this linear model.
//! Signs: with the outward slope phi of the block edge under a beam, the beam's top surface is
//! in compression at the block end when phi < 0 (edge going down). Beam B (and D for Mx) sees
//! the opposite phi, hence the opposite stress.

use crate::params::{Geometry, Silicon};
use crate::section::{
    max_torsion_shear_pa, second_moment_m4, section_modulus_m3, torsion_factor_m4,
};

/// Reactions at the block end of a bending beam for a block rotation `theta_rad`:
/// (F_RZ in N, M_RY in N·m), both as magnitudes per radian times `theta_rad`.
pub fn end_reactions(g: &Geometry, si: &Silicon, theta_rad: f64) -> (f64, f64) {
    let ei = si.youngs_modulus_pa * second_moment_m4(g);
    let (l, c) = (g.beam_length_m, g.block_half_width_m);
    let f_rz = 6.0 * ei * theta_rad * (l + 2.0 * c) / (l * l * l);
    let m_ry = 2.0 * ei * theta_rad * (2.0 * l + 3.0 * c) / (l * l);
    (f_rz, m_ry)
}

/// Torque in a twisting beam: T_RY = K G theta / L.
pub fn torque_nm(g: &Geometry, si: &Silicon, theta_rad: f64) -> f64 {
    torsion_factor_m4(g) * si.shear_modulus_pa * theta_rad / g.beam_length_m
}

/// Rotational stiffness of the block, My / theta, from the block's moment balance.
pub fn rotational_stiffness_nm_per_rad(g: &Geometry, si: &Silicon) -> f64 {
    let (f_rz, m_ry) = end_reactions(g, si, 1.0);
    2.0 * (f_rz * g.block_half_width_m + m_ry) + 2.0 * torque_nm(g, si, 1.0)
}

/// Block rotation theta for a moment about one in-plane axis.
pub fn block_rotation_rad(g: &Geometry, si: &Silicon, moment_nm: f64) -> f64 {
    moment_nm / rotational_stiffness_nm_per_rad(g, si)
}

/// Top-surface longitudinal stress at `x_m` from the frame end of a bending beam whose block
/// edge has the outward slope `phi_rad` (positive = going up away from the block centre).
pub fn bending_stress_pa(g: &Geometry, si: &Silicon, phi_rad: f64, x_m: f64) -> f64 {
    let (f_rz, m_ry) = end_reactions(g, si, phi_rad);
    let m_x = m_ry - f_rz * (g.beam_length_m - x_m);
    m_x / section_modulus_m3(g)
}

/// Largest torsional shear stress in a beam twisted by `twist_rad` at the block.
pub fn torsion_shear_pa(g: &Geometry, si: &Silicon, twist_rad: f64) -> f64 {
    max_torsion_shear_pa(g, torque_nm(g, si, twist_rad))
}
