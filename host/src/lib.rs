#![doc = include_str!("../../README.md")]

pub mod calibration;
pub mod cli;
pub mod cmd;
