//! The emulated sensor: mechanics -> beam stress -> piezoresistors -> bridges -> amplifier -> ADC.
#![cfg_attr(not(feature = "std"), no_std)]

pub mod ads131m04;
#[cfg(feature = "std")]
pub mod link;

pub mod frontend;

#[cfg(feature = "std")]
pub mod effects;
#[cfg(feature = "std")]
pub mod compression;
