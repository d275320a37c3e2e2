//! The sensor's driver on the host: find and open its port ([`device`]), decode its frames fast
//! ([`decode`]), record them to the recording CSV and MCAP ([`logger`]) and re-decode a capture;
//! the calibration matrix a device stores ([`calibration`]). A library with no command line:
//! the `tactile` crate is the thin binary over it, and the HIL tests and fuzz targets link it
//! alone.
//!
//! Each error type says which exit code a command ending on it deserves
//! ([`sysexit::ExitStatus`]).
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod calibration;
pub mod clock;
pub mod decode;
pub mod device;
pub mod hand;
pub mod logger;
