//! Wheatstone bridges: each arm is its fixed resistance plus its piezoresistors in series;
//! V_out = V_ex [R_LL / (R_UL + R_LL) - R_LR / (R_UR + R_LR)] (left node minus right node).
//! Each side is a divider, seen from its output node as a Thevenin source ([`divider`]): the
//! front end (`sim::frontend::bridge`) adds its arms' mismatch and its offset-cut injection to
//! these same nodes.

use crate::params::{Arm, Bridge, ChipParams, Load};
use crate::piezo::resistor_change;

/// One bridge output node as a Thevenin source.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thevenin {
    /// Open-circuit voltage.
    pub v: f64,
    /// Source resistance.
    pub ohm: f64,
}

/// A divider of `top_ohm` (to `supply_v`) over `bottom_ohm` (to ground) seen from its middle:
/// `V = V_s R_bottom / (R_top + R_bottom)` behind `R_top || R_bottom`.
pub fn divider(supply_v: f64, top_ohm: f64, bottom_ohm: f64) -> Thevenin {
    let sum = top_ohm + bottom_ohm;
    Thevenin {
        v: supply_v * bottom_ohm / sum,
        ohm: top_ohm * bottom_ohm / sum,
    }
}

/// Arm resistances [upper_left, lower_left, upper_right, lower_right] under `load`.
pub fn arm_resistances_ohm(p: &ChipParams, bridge: &Bridge, load: Load) -> [f64; 4] {
    let mut arms = bridge.fixed_ohm;
    for r in &bridge.resistors {
        arms[r.arm.index()] += p.resistance_ohm * (1.0 + resistor_change(p, load, r));
    }
    arms
}

/// Exact bridge output for arm resistances `arms` [upper_left, lower_left, upper_right,
/// lower_right] at excitation `v_ex`: left node minus right node.
pub fn output_from_arms_v(v_ex: f64, arms: [f64; 4]) -> f64 {
    let [ul, ll, ur, lr] = arms;
    divider(v_ex, ul, ll).v - divider(v_ex, ur, lr).v
}

/// Output of one bridge under `load` (exact divider, nonlinear in Delta R / R at large loads).
pub fn output_v(p: &ChipParams, bridge: &Bridge, load: Load) -> f64 {
    output_from_arms_v(p.excitation_v, arm_resistances_ohm(p, bridge, load))
}

/// The three bridge outputs (Fz, Mx, My) at the bridge terminals, before any amplifier, exact
/// (the emulated sensor and the diagnosis use the linearised [`crate::sensitivity_matrix`]).
pub fn bridge_outputs_v(p: &ChipParams, load: Load) -> [f64; 3] {
    [0, 1, 2].map(|i| output_v(p, &p.bridges[i], load))
}

/// dV_out / d(Delta R / R) of each resistor at zero stress: the bridge's first-order weights.
pub fn linear_weights_v(p: &ChipParams, bridge: &Bridge) -> [f64; 4] {
    let arms = arm_resistances_ohm(p, bridge, Load::default());
    let [ul, ll, ur, lr] = arms;
    let left = ul + ll;
    let right = ur + lr;
    bridge.resistors.map(|r| {
        let d_v_d_r = match r.arm {
            Arm::UpperLeft => -ll / (left * left),
            Arm::LowerLeft => ul / (left * left),
            Arm::UpperRight => lr / (right * right),
            Arm::LowerRight => -ur / (right * right),
        };
        p.excitation_v * d_v_d_r * p.resistance_ohm
    })
}
