//! Fz (the paper's section II-A): by symmetry each beam is fixed at the frame (x = 0) and guided
//! at the block (x = L, no end rotation), carrying P = Fz/4.
//!
//! Bending moment M(x) = P (L/2 - x), hogging near the frame; longitudinal stress on the top
//! surface sigma_L(x) = M(x) / Z_Y: tension at the frame end, equal compression at the block end,
//! zero at mid-span. Block deflection delta = Fz L^3 / (48 E_X I_Y).

use crate::params::{Geometry, Silicon};
use crate::section::{second_moment_m4, section_modulus_m3};

/// Top-surface longitudinal stress at `x_m` from the frame end of any beam, for a pressing force
/// `fz_n` (positive = tension).
pub fn surface_stress_pa(g: &Geometry, fz_n: f64, x_m: f64) -> f64 {
    let p_n = fz_n / 4.0;
    let m_nm = p_n * (g.beam_length_m / 2.0 - x_m);
    m_nm / section_modulus_m3(g)
}

/// Block deflection into the chip: delta = Fz L^3 / (48 E_X I_Y).
pub fn block_deflection_m(g: &Geometry, si: &Silicon, fz_n: f64) -> f64 {
    let l = g.beam_length_m;
    fz_n * l * l * l / (48.0 * si.youngs_modulus_pa * second_moment_m4(g))
}
