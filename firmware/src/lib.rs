//! tactile firmware library: the parts of the firmware that do not touch a particular board.
//!
//! Drivers (ADS131M04 bridge ADC, MCP4728 trim DAC), the offset cut (auto-null, tare, drift
//! tracking), the IIR filters, and the streaming pipeline (sample queue, frame batching with drop
//! counting, command handling). Everything is `no_std`, allocation-free, and builds and tests on
//! the host; `#[entry]`, interrupts, the panic handler and board wiring live in `src/bin/`.
#![cfg_attr(not(test), no_std)]

pub mod ads131m04;
pub mod device;
pub mod dsp;
pub mod iwdg;
pub mod mcp4728;
pub mod offset;
pub mod stream;
