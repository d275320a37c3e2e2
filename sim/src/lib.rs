//! The emulated sensor: mechanics -> beam stress -> piezoresistors -> bridges -> amplifier -> ADC.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "std")]
pub mod link;

pub mod frontend;
