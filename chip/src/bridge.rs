//! Wheatstone bridges: each arm is its fixed resistance plus its piezoresistors in series;
//! V_out = V_ex [R_LL / (R_UL + R_LL) - R_LR / (R_UR + R_LR)] (left node minus right node).

use crate::params::{Arm, Bridge, ChipParams, Load};
use crate::piezo::resistor_change;

/// Arm resistances [upper_left, lower_left, upper_right, lower_right] under `load`.
pub fn arm_resistances_ohm(p: &ChipParams, bridge: &Bridge, load: Load) -> [f64; 4] {
    let mut arms = bridge.fixed_ohm;
    for r in &bridge.resistors {
        arms[r.arm.index()] += p.resistance_ohm * (1.0 + resistor_change(p, load, r));
    }
    arms
}

/// Exact bridge output for arm resistances `arms` at excitation `v_ex`.
pub fn output_from_arms_v(v_ex: f64, arms: [f64; 4]) -> f64 {
    let [ul, ll, ur, lr] = arms;
    v_ex * (ll / (ul + ll) - lr / (ur + lr))
}

/// Output of one bridge under `load` (exact divider, nonlinear in Delta R / R at large loads).
pub fn output_v(p: &ChipParams, bridge: &Bridge, load: Load) -> f64 {
    output_from_arms_v(p.excitation_v, arm_resistances_ohm(p, bridge, load))
}

/// The three bridge outputs (Fz, Mx, My) at the bridge terminals, before any amplifier. This is
/// the function the emulated sensor and the diagnosis call; it allocates nothing.
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
