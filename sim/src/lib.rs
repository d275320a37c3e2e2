//! The emulated sensor: mechanics -> beam stress -> piezoresistors -> bridges -> amplifier -> ADC.
#![cfg_attr(not(feature = "std"), no_std)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

#[cfg(feature = "std")]
pub mod clock;
#[cfg(feature = "std")]
pub mod link;

pub mod ads131m04;
#[cfg(feature = "std")]
pub mod chain;
#[cfg(feature = "std")]
pub mod compression;
#[cfg(feature = "std")]
pub mod effects;
pub mod forward;
pub mod frontend;
pub mod load;
pub mod pillar;
pub mod temperature;
