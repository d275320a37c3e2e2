//! A fingertip from another plausible model of the same test: the proof's independent baseline
//! family.

use baseline::{FingertipResponse, UnitResponse};

/// The fingertip of another plausible model of the same test: a power-law contact
/// F = F_ref (d / d_ref)^n instead of the FE's, agreeing with the FE at `d_ref` (the nominal
/// peak), and chip loads either linear in the load (`linear_outputs`) or following the FE's own
/// load-to-load map at the same force. The exponent is drawn from Hertz's 1.5 to 2.3 (a bonded
/// thin layer stiffens towards 2 and beyond): inside what the calibration's exponent shift and
/// curvature may absorb.
pub struct OtherFingertip<'a> {
    pub fe: &'a dyn FingertipResponse,
    pub exponent: f64,
    pub d_ref_mm: f64,
    pub linear_outputs: bool,
}

impl FingertipResponse for OtherFingertip<'_> {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        if rod_mm <= 0.0 {
            return UnitResponse {
                force_n: 0.0,
                chip: [0.0; 3],
            };
        }
        let reference = self.fe.unit_response(self.d_ref_mm);
        let force_n = reference.force_n * (rod_mm / self.d_ref_mm).powf(self.exponent);
        let per_force = if self.linear_outputs {
            reference
        } else {
            // The FE's travel at the same force, by bisection (the FE force is monotone).
            let at = sim::compression::rod_at_load(
                |d| self.fe.unit_response(d).force_n,
                force_n,
                4.0 * self.d_ref_mm,
            );
            self.fe.unit_response(at)
        };
        let k = force_n / per_force.force_n.max(f64::MIN_POSITIVE);
        UnitResponse {
            force_n,
            chip: per_force.chip.map(|c| c * k),
        }
    }
}
