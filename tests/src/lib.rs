//! End-to-end and hardware-in-the-loop tests live in `tests/tests/`; shared helpers here.

pub mod check;
pub mod emu;
