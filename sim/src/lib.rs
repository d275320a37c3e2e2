//! The emulated sensor: mechanics -> beam stress -> piezoresistors -> bridges -> amplifier -> ADC.
#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(feature = "std")]
pub mod link;

pub mod ads131m04;
pub mod frontend;
pub mod load;
pub mod pillar;
pub mod temperature;
#[cfg(feature = "std")]
pub mod chain;
#[cfg(feature = "std")]
pub mod effects;
#[cfg(feature = "std")]
pub mod compression;
