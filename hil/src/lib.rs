//! End-to-end and hardware-in-the-loop tests live in `hil/tests/`; the support they share is here:
//! the pty device emulator ([`emu`]), the firmware library running on the host against the
//! emulated sensor behind a pseudo-terminal ([`native`]), the firmware's QEMU binary with its UART
//! on a pty ([`qemu`]), the f64 references the decoded values are checked against
//! ([`mod@reference`]), and recording checks ([`check`]).
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod check;
pub mod emu;
pub mod hand_clock;
pub mod native;
pub mod procfs;
pub mod pty;
pub mod qemu;
pub mod reference;
