//! Cross-beam chip physics: beam stresses from the elasticity equations, piezoresistors, bridges.
#![cfg_attr(not(test), no_std)]
