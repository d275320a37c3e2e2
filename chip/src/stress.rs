//! Combined loads by superposition: the block's displacement and rotations from (Fz, Mx, My),
//! then the surface stresses on every beam.

use crate::fz;
use crate::moment;
use crate::params::{Beam, ChipParams, Load};

/// Rotations of the block (theta_x, theta_y) for a load.
pub fn block_rotations_rad(p: &ChipParams, load: Load) -> (f64, f64) {
    let (g, si) = (&p.geometry, &p.silicon);
    (
        moment::block_rotation_rad(g, si, load.mx_nm),
        moment::block_rotation_rad(g, si, load.my_nm),
    )
}

/// Outward slope of the block edge under `beam`: w = theta_x y - theta_y x on the block, so
/// dw/d(outward) = theta_x e_y - theta_y e_x.
fn outward_slope_rad(beam: Beam, theta_x: f64, theta_y: f64) -> f64 {
    let (ex, ey) = beam.direction();
    theta_x * ey - theta_y * ex
}

/// Twist of `beam` about its own axis: the block rotation's component along the beam.
fn twist_rad(beam: Beam, theta_x: f64, theta_y: f64) -> f64 {
    let (ex, ey) = beam.direction();
    theta_x * ex + theta_y * ey
}

/// Longitudinal top-surface stress on `beam` at `x_m` from its frame end (positive = tension):
/// the Fz term plus the bending term of whichever moment bends this beam.
pub fn surface_stress_pa(p: &ChipParams, load: Load, beam: Beam, x_m: f64) -> f64 {
    let (g, si) = (&p.geometry, &p.silicon);
    let (theta_x, theta_y) = block_rotations_rad(p, load);
    let phi = outward_slope_rad(beam, theta_x, theta_y);
    fz::surface_stress_pa(g, load.fz_n, x_m) + moment::bending_stress_pa(g, si, phi, x_m)
}

/// Largest torsional shear stress on `beam` (the beams that twist under Mx or My).
pub fn torsion_shear_pa(p: &ChipParams, load: Load, beam: Beam) -> f64 {
    let (theta_x, theta_y) = block_rotations_rad(p, load);
    moment::torsion_shear_pa(&p.geometry, &p.silicon, twist_rad(beam, theta_x, theta_y))
}
