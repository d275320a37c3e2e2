//! tactile firmware library: everything but each binary's own logic.
//!
//! Drivers (ADS131M04 bridge ADC, MCP4728 trim DAC), the offset cut (auto-null, tare, drift
//! tracking), the IIR filters, and the streaming pipeline (sample clock read, sample queue, frame
//! batching with drop counting, command handling): `no_std`, allocation-free, built and tested on
//! the host too. The boards' parameters from `hardware/*.toml` ([`params`]) and the board support
//! the binaries share ([`board`]: start-up, exit, panic reporting, and the macros that give each
//! binary its panic handler, logger and interrupt table); `#[entry]`, interrupt handlers and each
//! binary's own logic live in `src/bin/`.
#![cfg_attr(not(test), no_std)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod ads131m04;
pub mod board;
pub mod device;
pub mod dsp;
pub mod iwdg;
pub mod mcp4728;
pub mod offset;
pub mod params;
pub mod stream;
