//! The offset cut: a trim-DAC output (MCP4728, VDD reference) summed through a resistor into the
//! bridge's positive output node.
//!
//! The node becomes `V' = (V_th R_inj + V_dac R_th) / (R_inj + R_th)`: the DAC moves the bridge
//! output by `(V_dac - V_th) R_th / (R_inj + R_th)`, ratiometric with the excitation because the
//! DAC's reference is the same rail.

use super::bridge::Thevenin;

/// The DAC channel and its summing resistor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trim {
    /// DAC reference (VDD): full scale of the output.
    pub reference_v: f64,
    pub dac_bits: u32,
    pub injection_ohm: f64,
}

impl Trim {
    /// Number of codes, `2^bits`.
    pub fn codes(&self) -> u32 {
        1 << self.dac_bits
    }

    /// DAC output for `code`: `V_ref code / 2^bits` (MCP4728 datasheet, VREF = VDD, gain 1).
    pub fn dac_v(&self, code: u32) -> f64 {
        self.reference_v * f64::from(code.min(self.codes() - 1)) / f64::from(self.codes())
    }

    /// The node after injection from DAC `code`.
    pub fn inject(&self, node: Thevenin, code: u32) -> Thevenin {
        let (r_inj, r_th) = (self.injection_ohm, node.ohm);
        let v = (node.v * r_inj + self.dac_v(code) * r_th) / (r_inj + r_th);
        Thevenin {
            v,
            ohm: r_inj * r_th / (r_inj + r_th),
        }
    }

    /// Shift of the bridge output per DAC volt: `R_th / (R_inj + R_th)`.
    pub fn coupling(&self, node: Thevenin) -> f64 {
        node.ohm / (self.injection_ohm + node.ohm)
    }

    /// The (lowest, highest) shift of the bridge output the DAC can make, codes 0 and 2^bits - 1.
    pub fn range_v(&self, node: Thevenin) -> (f64, f64) {
        let lo = self.inject(node, 0).v - node.v;
        let hi = self.inject(node, self.codes() - 1).v - node.v;
        (lo, hi)
    }

    /// Shift of the bridge output per code: the offset cut's resolution.
    pub fn step_v(&self, node: Thevenin) -> f64 {
        self.reference_v / f64::from(self.codes()) * self.coupling(node)
    }

    /// The code whose shift is nearest to `-error_v` (cancels an input error), if in range.
    pub fn null_code(&self, node: Thevenin, error_v: f64) -> Option<u32> {
        let dac_v = node.v - error_v / self.coupling(node);
        let code = libm::round(dac_v / self.reference_v * f64::from(self.codes()));
        (0.0..f64::from(self.codes()))
            .contains(&code)
            .then_some(code as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIM: Trim = Trim {
        reference_v: 3.3,
        dac_bits: 12,
        injection_ohm: 1.5e6,
    };
    const NODE: Thevenin = Thevenin {
        v: 1.65,
        ohm: 2500.0,
    };

    #[test]
    fn mid_code_leaves_a_balanced_node_alone() {
        assert!((TRIM.inject(NODE, 2048).v - 1.65).abs() < 1e-15);
    }

    #[test]
    fn range_and_step_follow_the_divider() {
        // k = 2500 / 1502500; range +-1.65 V k, step 3.3 V / 4096 k (hand-computed).
        let k = 2500.0 / 1_502_500.0;
        let (lo, hi) = TRIM.range_v(NODE);
        assert!(
            (lo + 1.65 * k).abs() < 1e-12
                && (hi - (3.3 * 4095.0 / 4096.0 - 1.65) * k).abs() < 1e-12
        );
        assert!((TRIM.step_v(NODE) - 3.3 / 4096.0 * k).abs() < 1e-15);
    }

    #[test]
    fn null_code_cancels_within_half_a_step() {
        let error = 0.66e-3;
        let code = TRIM.null_code(NODE, error).unwrap();
        let residual = TRIM.inject(NODE, code).v - NODE.v + error;
        assert!(
            residual.abs() <= TRIM.step_v(NODE) / 2.0 + 1e-15,
            "{residual}"
        );
        assert_eq!(TRIM.null_code(NODE, 10.0e-3), None);
    }
}
