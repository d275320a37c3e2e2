//! One test per cross-key rule of frontend.toml (single keys are covered by loader.rs).

mod common;
use common::{folder_with, rule_broken};

const FILE: &str = "frontend.toml";

#[test]
fn the_shipped_front_end_loads_with_three_bridges() {
    let p = hardware::Params::load_default().unwrap();
    assert_eq!(p.frontend.bridge.arm_mismatch.len(), hardware::BRIDGES);
}

#[test]
fn mid_code_beyond_the_dac_is_refused() {
    let dir = folder_with(FILE, "mid_dac_code = 2048", "mid_dac_code = 4096");
    let e = rule_broken(&dir, FILE, "supply.mid_dac_code");
    assert!(e.to_string().contains("4096"), "{e}");
}

#[test]
fn arm_mismatch_beyond_the_tolerance_is_refused() {
    let dir = folder_with(
        FILE,
        "[3.0e-4, -3.0e-4, -3.0e-4, 3.0e-4]",
        "[3.0e-4, -3.0e-4, -7.0e-4, 3.0e-4]",
    );
    rule_broken(&dir, FILE, "bridge.arm_mismatch_my");
}

#[test]
fn amplifier_offset_beyond_its_maximum_is_refused() {
    let dir = folder_with(FILE, "offset_v = [12.0e-6,", "offset_v = [30.0e-6,");
    rule_broken(&dir, FILE, "stage1.offset_v");
}

#[test]
fn output_swing_leaving_no_range_is_refused() {
    let text = "swing_from_rail_v = 0.05\nknee_v = 0.005\n\n[antialias]";
    let dir = folder_with(
        FILE,
        text,
        "swing_from_rail_v = 1.7\nknee_v = 0.005\n\n[antialias]",
    );
    rule_broken(&dir, FILE, "stage2.swing_from_rail_v");
}

#[test]
fn large_common_mode_capacitors_are_refused() {
    let dir = folder_with(FILE, "cm_cap_f = 4.7e-9", "cm_cap_f = 10.0e-9");
    let e = rule_broken(&dir, FILE, "antialias.cm_cap_f");
    assert!(e.to_string().contains("tenth"), "{e}");
}
