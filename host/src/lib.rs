#![doc = include_str!("../../README.md")]

pub mod calibration;
pub mod cli;
pub mod cmd;
pub mod decode;
pub mod device;
pub mod exit;
pub mod live;
pub mod logger;
pub mod plot;
