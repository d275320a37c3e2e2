//! The chip's Wheatstone bridge as the front end sees it: four arms with this board's
//! fractional mismatch, seen from its outputs.
//!
//! R1 (to the excitation) over R2 (to ground) form the negative output, R3 over R4 the positive
//! one; each output node is the chip's divider as a Thevenin source ([`chip::bridge::divider`]),
//! so the offset-cut injection can be added exactly.

use chip::bridge::divider;
pub use chip::bridge::Thevenin;

/// A bridge with its arms' fabrication mismatch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    /// Nominal (design) resistance of arms [R1, R2, R3, R4] at zero stress.
    pub nominal_ohm: [f64; 4],
    pub excitation_v: f64,
    /// Fractional mismatch δ of arms [R1, R2, R3, R4].
    pub mismatch: [f64; 4],
}

impl Bridge {
    /// Arm resistances `R_i (1 + δ_i) (1 + ΔR_i/R_i)` for the stress-induced changes `dr_r`.
    pub fn arms_ohm(&self, dr_r: [f64; 4]) -> [f64; 4] {
        core::array::from_fn(|i| self.nominal_ohm[i] * (1.0 + self.mismatch[i]) * (1.0 + dr_r[i]))
    }

    /// The (positive, negative) output nodes for the stress-induced changes `dr_r`.
    pub fn outputs(&self, dr_r: [f64; 4]) -> (Thevenin, Thevenin) {
        let [r1, r2, r3, r4] = self.arms_ohm(dr_r);
        let pos = divider(self.excitation_v, r3, r4);
        let neg = divider(self.excitation_v, r1, r2);
        (pos, neg)
    }

    /// The output nodes for arm resistances computed elsewhere (e.g. the chip model's arms under
    /// a load, in R1..R4 order), with this bridge's mismatch applied on top.
    pub fn outputs_for_arms(&self, arms_ohm: [f64; 4]) -> (Thevenin, Thevenin) {
        let [r1, r2, r3, r4] = core::array::from_fn(|i| arms_ohm[i] * (1.0 + self.mismatch[i]));
        (
            divider(self.excitation_v, r3, r4),
            divider(self.excitation_v, r1, r2),
        )
    }

    /// Differential output `V+ - V-` for the stress-induced changes `dr_r`.
    pub fn output_v(&self, dr_r: [f64; 4]) -> f64 {
        let (pos, neg) = self.outputs(dr_r);
        pos.v - neg.v
    }

    /// Output with no stress: the raw offset the offset cut has to remove.
    pub fn raw_offset_v(&self) -> f64 {
        self.output_v([0.0; 4])
    }

    /// Largest raw offset when every arm may be off by up to `tolerance`: arms R1 and R4 high,
    /// R2 and R3 low give, for dividers of equal halves, `V_exc (1 + t)/2 - V_exc (1 - t)/2 =
    /// V_exc t`.
    pub fn worst_raw_offset_v(excitation_v: f64, tolerance: f64) -> f64 {
        excitation_v * tolerance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bridge(mismatch: [f64; 4]) -> Bridge {
        Bridge {
            nominal_ohm: [5000.0; 4],
            excitation_v: 3.3,
            mismatch,
        }
    }

    #[test]
    fn push_pull_strain_gives_excitation_times_dr_over_r() {
        // Opposite arms +-x: V+ = V(1+x)/2, V- = V(1-x)/2, so V_out = V x exactly.
        let x = 1.0e-3;
        let v = bridge([0.0; 4]).output_v([x, -x, -x, x]);
        assert!((v - 3.3 * x).abs() < 1e-15, "{v}");
    }

    #[test]
    fn worst_mismatch_pattern_gives_the_worst_offset() {
        let t = 6.0e-4;
        let b = bridge([t, -t, -t, t]);
        assert!((b.raw_offset_v() - Bridge::worst_raw_offset_v(3.3, t)).abs() < 1e-15);
    }

    #[test]
    fn chip_arms_take_the_mismatch_on_top() {
        let b = bridge([1.0e-3, 0.0, 0.0, 0.0]);
        let arms = [5000.0, 5000.0, 5000.0, 5000.0];
        assert_eq!(b.outputs_for_arms(arms), b.outputs([0.0; 4]));
    }

    #[test]
    fn balanced_nodes_sit_at_half_excitation_behind_half_r() {
        let (pos, neg) = bridge([0.0; 4]).outputs([0.0; 4]);
        assert_eq!((pos.v, pos.ohm), (1.65, 2500.0));
        assert_eq!(neg, pos);
    }
}
