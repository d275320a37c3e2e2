//! Support for the hardware-in-the-loop tests (issue 7): the firmware library running on the host
//! against the emulated sensor behind a pseudo-terminal ([`native`]), the firmware's QEMU binary
//! with its UART on a pty ([`qemu`]), and the f64 references the decoded values are checked
//! against ([`reference`]).

pub mod native;
pub mod pty;
pub mod qemu;
pub mod reference;
