//! The chip's strength: the load at which the peak principal stress on the beams reaches the
//! fracture strength. The peak is searched at both ends of every beam (where bending peaks) and
//! combines the bending stress sigma with the torsional shear tau of that beam:
//! sigma_1 = |sigma|/2 + sqrt(sigma^2/4 + tau^2). Stress concentration at the beam roots (fillet
//! radius of the etch) is not modelled.

use libm::sqrt;

use crate::params::{Beam, ChipParams, Load};
use crate::stress::{surface_stress_pa, torsion_shear_pa};

/// Largest principal stress over all beams under `load`.
pub fn peak_stress_pa(p: &ChipParams, load: Load) -> f64 {
    let ends = [0.0, p.geometry.beam_length_m];
    let mut peak = 0.0_f64;
    for beam in Beam::ALL {
        let tau = torsion_shear_pa(p, load, beam);
        for x in ends {
            let sigma = surface_stress_pa(p, load, beam, x);
            let half = sigma.abs() / 2.0;
            peak = peak.max(half + sqrt(half * half + tau * tau));
        }
    }
    peak
}

/// Strength along one load direction: the magnitude of `unit` (a load of size 1 in its units)
/// that brings the peak stress to the fracture strength. The model is linear in the load.
pub fn strength_along(p: &ChipParams, unit: Load) -> f64 {
    p.silicon.fracture_strength_pa / peak_stress_pa(p, unit)
}

/// Strengths (Fz in N, Mx in N·m, My in N·m), each load applied alone.
pub fn strengths(p: &ChipParams) -> [f64; 3] {
    [
        strength_along(p, Load::new(1.0, 0.0, 0.0)),
        strength_along(p, Load::new(0.0, 1.0, 0.0)),
        strength_along(p, Load::new(0.0, 0.0, 1.0)),
    ]
}
