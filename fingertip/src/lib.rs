//! Soft-fingertip finite-element model: hyperelastic hemisphere, rod contact, loads on the chip.
