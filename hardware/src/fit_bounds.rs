//! `fit-bounds.toml`: how far the diagnosis may calibrate the baseline model to a recording
//! before it calls what remains missing physics (the reasons are in the file).

use std::path::Path;

use crate::{ParamError, Reader};

/// The bounds of the baseline fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitBounds {
    /// How far ln E may move from the load cell's first estimate.
    pub modulus_ln_range: f64,
    /// Lower bound of the force-indentation exponent's shift against the FE's.
    pub exponent_shift_min: f64,
    /// Upper bound of that shift.
    pub exponent_shift_max: f64,
    /// Largest magnitude of the curvature of ln F against ln(travel).
    pub exponent_curvature_max: f64,
    /// Largest magnitude of the force warp at each of its knots (ln F).
    pub force_warp_max: f64,
    /// Largest blend of the contact law towards a pure power law of the travel (0: the FE's).
    pub force_law_blend_max: f64,
    /// Lower bound of each output's blend between the FE's map (0) and a linear one (1).
    pub map_blend_min: f64,
    /// Upper bound of that blend.
    pub map_blend_max: f64,
    /// Largest share of the calibrated law's departure from the FE's that the outputs' maps
    /// follow (0: they follow the travel; 1: the load).
    pub map_load_share_max: f64,
    /// Largest magnitude of ln of the level of the load the outputs' maps follow.
    pub map_load_level_max: f64,
    /// Largest magnitude of an output's sensitivity scale.
    pub scale_max: f64,
    /// How far the ratio of the two moment scales may depart from 1 on identical chains.
    pub moment_gain_ratio_tolerance: f64,
    /// The jig's mounting accuracy about the load axis, deg.
    pub jig_azimuth_tolerance_deg: f64,
    /// Relative difference between per-test sensitivities within which the model's angle law
    /// stands.
    pub angle_law_tolerance: f64,
    /// An offset's bound, in multiples of its channel's recorded range.
    pub offset_range_factor: f64,
}

impl FitBounds {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let c = Self {
            modulus_ln_range: r.f64("contact.modulus_ln_range", 0.1..=20.0),
            exponent_shift_min: r.f64("contact.exponent_shift_min", -3.0..=0.0),
            exponent_shift_max: r.f64("contact.exponent_shift_max", 0.0..=3.0),
            exponent_curvature_max: r.f64("contact.exponent_curvature_max", 0.0..=2.0),
            force_warp_max: r.f64("contact.force_warp_max", 0.0..=2.0),
            force_law_blend_max: r.f64("contact.force_law_blend_max", 0.0..=1.0),
            map_blend_min: r.f64("outputs.map_blend_min", -5.0..=0.0),
            map_blend_max: r.f64("outputs.map_blend_max", 1.0..=5.0),
            map_load_share_max: r.f64("outputs.map_load_share_max", 0.0..=1.0),
            map_load_level_max: r.f64("outputs.map_load_level_max", 0.0..=3.0),
            scale_max: r.f64("outputs.scale_max", 1.0..=1e6),
            moment_gain_ratio_tolerance: r.f64("outputs.moment_gain_ratio_tolerance", 0.0..=1.0),
            jig_azimuth_tolerance_deg: r.f64("outputs.jig_azimuth_tolerance_deg", 0.0..=45.0),
            angle_law_tolerance: r.f64("outputs.angle_law_tolerance", 0.0..=1.0),
            offset_range_factor: r.f64("outputs.offset_range_factor", 0.0..=1e3),
        };
        r.finish()?;
        Ok(c)
    }
}
