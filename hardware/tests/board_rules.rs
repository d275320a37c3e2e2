//! One test per cross-key rule of board.toml.

mod common;
use common::{folder_with, rule_broken};

const FILE: &str = "board.toml";

#[test]
fn shipped_pin_map_uses_the_vcp_and_spi1() {
    let board = hardware::Params::load_default().unwrap().board;
    assert_eq!(
        (board.uart_tx.as_str(), board.uart_rx.as_str()),
        ("PA2", "PA3")
    );
    assert_eq!(board.uart_baud, 921_600);
    assert_eq!(board.spi_sck, "PA5");
}

#[test]
fn a_pin_used_twice_is_refused() {
    let dir = folder_with(FILE, "drdy = \"PC7\"", "drdy = \"PB6\"");
    let e = rule_broken(&dir, FILE, "adc.drdy");
    assert!(e.to_string().contains("already used by `spi.cs`"), "{e}");
}

#[test]
fn a_pin_that_cannot_carry_the_function_is_refused() {
    let dir = folder_with(FILE, "sck = \"PA5\"", "sck = \"PA1\"");
    let e = rule_broken(&dir, FILE, "spi.sck");
    assert!(e.to_string().contains("PA5, PB3"), "{e}");
}

#[test]
fn a_pin_the_package_lacks_is_refused() {
    let dir = folder_with(FILE, "sync_reset = \"PA9\"", "sync_reset = \"PD7\"");
    rule_broken(&dir, FILE, "adc.sync_reset");
}

#[test]
fn a_5v_digital_supply_is_refused() {
    let dir = folder_with(FILE, "digital_from = \"3V3\"", "digital_from = \"5V\"");
    let e = rule_broken(&dir, FILE, "power.digital_from");
    assert!(e.to_string().contains("3.3 V"), "{e}");
}
