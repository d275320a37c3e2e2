//! Piezoresistance: Delta R / R = pi_l sigma_l + pi_t sigma_t, with sigma_l along the current and
//! sigma_t across it. On a beam in bending the surface stress is uniaxial along the beam (free
//! side walls, beam theory), so a longitudinal resistor sees (sigma_l, sigma_t) = (sigma, 0) and a
//! transverse one (0, sigma). The torsional shear tau_xy does not act: for <110> resistors on a
//! (001) wafer the in-plane shear coefficient pi'_16 vanishes by symmetry.

use crate::params::{ChipParams, Load, Orientation, Resistor, Silicon};
use crate::stress::surface_stress_pa;

/// Delta R / R for a resistor of `orientation` under a beam stress `sigma_pa` along the beam.
pub fn relative_change(si: &Silicon, orientation: Orientation, sigma_pa: f64) -> f64 {
    let (sigma_l, sigma_t) = match orientation {
        Orientation::Longitudinal => (sigma_pa, 0.0),
        Orientation::Transverse => (0.0, sigma_pa),
    };
    si.pi_l_per_pa * sigma_l + si.pi_t_per_pa * sigma_t
}

/// Stress along the beam at the centre of `r` (the mean over its length: the stress is linear).
pub fn resistor_stress_pa(p: &ChipParams, load: Load, r: &Resistor) -> f64 {
    surface_stress_pa(p, load, r.beam, r.x_m)
}

/// Delta R / R of resistor `r` under `load`.
pub fn resistor_change(p: &ChipParams, load: Load, r: &Resistor) -> f64 {
    relative_change(&p.silicon, r.orientation, resistor_stress_pa(p, load, r))
}
