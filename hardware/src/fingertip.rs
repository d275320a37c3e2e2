//! `fingertip.toml`: the gel hemisphere, the chip package inside it, the rod and the standard
//! compression test of the original experiments.

use std::path::Path;

use crate::{ParamError, Reader};

/// The soft fingertip and how it is loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct Fingertip {
    /// Hemisphere radius.
    pub radius_mm: f64,
    /// Small-strain Young's modulus of the gel.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio of the gel (nearly incompressible).
    pub poisson: f64,
    /// Radius of the stiff package/pillar inclusion at the base centre.
    pub inclusion_radius_mm: f64,
    /// Height of that inclusion above the base.
    pub inclusion_height_mm: f64,
    /// Radius of the flat-ended rod.
    pub rod_radius_mm: f64,
    /// Coulomb friction coefficient between rod and gel.
    pub friction_mu: f64,
    /// The standard compression test.
    pub test: CompressionTest,
}

/// The micro-tester's motion in the original experiments.
#[derive(Debug, Clone, PartialEq)]
pub struct CompressionTest {
    pub rod_speed_mm_per_min: f64,
    pub peak_load_n: f64,
    pub hold_s: f64,
    pub return_speed_mm_per_min: f64,
    pub recovery_s: f64,
    pub sample_rate_hz: f64,
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
}

impl Fingertip {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let fingertip = Self::read(&mut r);
        if fingertip.inclusion_radius_mm >= fingertip.radius_mm / 2.0 {
            r.reject(
                "package.inclusion_radius_mm",
                "must be below half the hemisphere radius",
            );
        }
        r.finish()?;
        Ok(fingertip)
    }

    fn read(r: &mut Reader) -> Self {
        Self {
            radius_mm: r.f64("geometry.radius_mm", 5.0..=100.0),
            youngs_modulus_pa: r.f64("gel.youngs_modulus_pa", 1.0e3..=1.0e8),
            poisson: r.f64("gel.poisson", 0.0..=0.4999),
            inclusion_radius_mm: r.f64("package.inclusion_radius_mm", 0.1..=20.0),
            inclusion_height_mm: r.f64("package.inclusion_height_mm", 0.1..=20.0),
            rod_radius_mm: r.f64("rod.radius_mm", 0.1..=50.0),
            friction_mu: r.f64("rod.friction_mu", 0.0..=2.0),
            test: CompressionTest {
                rod_speed_mm_per_min: r.f64("test.rod_speed_mm_per_min", 0.01..=1000.0),
                peak_load_n: r.f64("test.peak_load_n", 0.01..=500.0),
                hold_s: r.f64("test.hold_s", 0.0..=3600.0),
                return_speed_mm_per_min: r.f64("test.return_speed_mm_per_min", 0.01..=10000.0),
                recovery_s: r.f64("test.recovery_s", 0.0..=3600.0),
                sample_rate_hz: r.f64("test.sample_rate_hz", 1.0..=32000.0),
                contact_angle_deg: r.f64("test.contact_angle_deg", 0.0..=60.0),
                azimuth_deg: r.f64("test.azimuth_deg", -360.0..=360.0),
            },
        }
    }
}
