//! Cross-beam chip physics: beam stresses from the elasticity equations, piezoresistors, bridges.
//!
//! One module per model, in the order of the paper's section II: [`section`] (I, Z, torsion
//! factor K), [`fz`] (fixed-guided beams under Fz), [`moment`] (bending plus torsion under Mx,
//! My), [`stress`] (superposition), [`piezo`] (Delta R / R), [`bridge`] (Wheatstone outputs),
//! [`sensitivity`] (S and C = S^-1), [`strength`] (load at fracture). The core is no_std and
//! allocation-free; the `std` feature adds the parameters from `hardware/chip.toml`, the
//! least-squares calibration fit and the frame finite-element check.
//!
//! Units are SI throughout (m, Pa, N, N·m, V); the load convention is in [`Load`].
#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod bridge;
pub mod fz;
pub mod moment;
pub mod params;
pub mod piezo;
pub mod section;
pub mod sensitivity;
pub mod strength;
pub mod stress;
pub mod tolerance;

#[cfg(any(test, feature = "std"))]
pub mod calibration;
#[cfg(any(test, feature = "std"))]
pub mod frame_fe;
#[cfg(any(test, feature = "std"))]
pub mod from_hardware;
#[cfg(feature = "std")]
pub mod report;

#[cfg(test)]
mod tests;

pub use bridge::bridge_outputs_v;
pub use params::{Arm, Beam, Bridge, ChipParams, Geometry, Load, Orientation, Resistor, Silicon};
pub use sensitivity::{calibration_matrix, sensitivity_matrix, Matrix3};
