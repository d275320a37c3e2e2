//! What a fingertip model gives the baseline: the probe force and the chip loads at one rod
//! travel, per pascal of gel modulus. The FE tables ([`crate::response_table`]), their blend
//! over angles ([`crate::fe_response`]) and the tests' linear fixture all answer it.

/// Probe force and chip loads per pascal of gel modulus at one rod travel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UnitResponse {
    /// Force along the rod axis, N/Pa.
    pub force_n: f64,
    /// Chip loads [Fz (N), Mx (N·m), My (N·m)] per Pa.
    pub chip: [f64; 3],
}

/// A fingertip model: the quasi-static response to rod travel at unit modulus.
pub trait FingertipResponse: Sync {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse;
}

/// A fingertip whose force and chip loads grow linearly with the travel: the tests' fixture.
#[cfg(test)]
pub(crate) struct Linear;

#[cfg(test)]
impl FingertipResponse for Linear {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let d = rod_mm.max(0.0);
        UnitResponse {
            force_n: d,
            chip: [d, -d, 0.5 * d],
        }
    }
}
