//! Soft-fingertip finite-element model: hyperelastic hemisphere, rod contact, loads on the chip.
//!
//! A solid gel hemisphere (radius R) with its flat base bonded to a rigid mount and the chip
//! package + pillar as a rigid inclusion at the base centre is pressed by a rigid flat-ended
//! rod whose axis passes through the hemisphere centre at inclination theta_p from the
//! fingertip axis z, in the plane at azimuth phi from the chip's x axis. The rod advances
//! quasi-statically; each load step is solved by Newton's method (see [`solver`]).
//!
//! ```no_run
//! use fingertip::{Config, Material};
//! let config = Config {
//!     radius_mm: 20.0, youngs_modulus_pa: 0.15e6, poisson: 0.49, material: Material::NeoHookean,
//!     mesh_size_mm: 4.0, rod_radius_mm: 10.0, contact_angle_deg: 20.0, azimuth_deg: 60.0,
//!     friction_mu: 0.0, inclusion_half_width_mm: 1.5, inclusion_height_mm: 1.5,
//!     load_steps: 40, rod_speed_mm_per_s: 20.0 / 60.0,
//!     rod_shape: fingertip::RodShape::FlatEnd, drive: fingertip::Drive::RodAxis,
//! };
//! let curve = fingertip::compress(&config, 60.0)?;
//! for p in &curve.points { println!("{} {} {}", p.rod_mm, p.force_n, p.fz_n); }
//! # Ok::<(), fingertip::Error>(())
//! ```
//!
//! Modelling choices, each justified where it is implemented:
//! - mesh ([`mesh`]): block-structured inner cube + 5 shells, Kuhn-split, mirrored on the
//!   negative half-axes so the mesh has the square's symmetry exactly;
//! - locking ([`material`]): average-nodal-pressure tetrahedra as a mixed u–p field
//!   (nodal pressure unknowns), quasi-definite, solved by sparse LDL^T ([`linsolve`], faer);
//! - contact ([`contact`]): node-to-rigid-rod penalty with a C1 onset and regularised Coulomb
//!   friction;
//! - chip ([`loads`]): the package + pillar is rigid (silicon/epoxy vs a 0.1 MPa gel, ratio
//!   ~1e4) and clamped to the mount; the chip's loads are the reactions on its top face only
//!   (the pillar's), the side walls load the mount through the package;
//! - linear algebra ([`linsolve`], [`krylov`], [`solver`]): one symbolic analysis (AMD on the
//!   node graph), Newton systems by GMRES preconditioned with a kept single-precision factor
//!   that is refreshed on a background thread, inexact Newton;
//! - haptic ([`haptic`]): Schur complement of the tangent onto the contact normals.
//! - rod geometry ([`rod_shape`]): flat end (default), sphere or cylinder lying across, driven
//!   along its own axis (default) or the fingertip's;
//! - observations ([`observations`]): the paper's seven observations as a scorecard, the
//!   causes tried for its disagreements and the elastic energy along the inclination
//!   (`fingertip/OBSERVATIONS.md`).
//!
//! Data note: with the nominal gel (E = 0.1 MPa) a 5 mm-radius flat rod cannot carry 60 N
//! without the gel wrapping round its rim (a flat punch needs d ≈ F (1 - nu^2) / (2 a E) ≈ 45 mm
//! on a half-space). The benches and figures therefore use a platen (rod radius = R).
//!
//! Scaling: with nu and the geometry fixed, every stress in the model (deviatoric, nodal
//! pressure, contact penalty) is proportional to E, so the force–travel curve scales exactly
//! linearly with E (`tests/verification.rs`, `response_scales_linearly_with_youngs_modulus`). A curve at one modulus therefore calibrates E by a
//! single factor.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]
// Index loops follow the tensor and node-dof notation of the equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod assembly;
pub mod cache;
pub mod contact;
mod fingertip;
pub mod haptic;
pub mod krylov;
pub mod linsolve;
pub mod loads;
pub mod material;
pub mod mesh;
pub mod model;
pub mod observations;
pub mod quality;
pub mod rod_shape;
pub mod solver;
pub mod viscoelastic;
pub mod vtk;

pub use fingertip::{compress, Curve, CurvePoint, Fingertip};
pub use haptic::Haptic;
pub use loads::ChipLoads;
pub use quality::QualityReport;
pub use rod_shape::{Drive, RodShape};
pub use viscoelastic::PronyTerm;

/// Constitutive model of the gel.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub enum Material {
    /// Small-strain linear elasticity (a check limit).
    Linear,
    /// Finite-strain neo-Hookean, compressible or nearly incompressible.
    NeoHookean,
    /// Neo-Hookean with a Prony-series viscoelastic deviatoric part; E is the relaxed modulus.
    ViscoNeoHookean(Vec<PronyTerm>),
}

/// Everything that defines one simulated compression.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Config {
    /// Hemisphere radius R.
    pub radius_mm: f64,
    /// Young's modulus of the gel (relaxed modulus if viscoelastic).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio of the gel.
    pub poisson: f64,
    pub material: Material,
    /// Nominal element size (finer at the chip and under the contact).
    pub mesh_size_mm: f64,
    /// Radius of the flat-ended rod.
    pub rod_radius_mm: f64,
    /// Inclination theta_p of the rod from the fingertip axis.
    pub contact_angle_deg: f64,
    /// Azimuth phi of the tilt plane from the chip's x axis, counter-clockwise.
    pub azimuth_deg: f64,
    /// Coulomb friction coefficient between rod and gel (0: frictionless).
    pub friction_mu: f64,
    /// Half width of the square chip package (rigid inclusion) at the base centre.
    pub inclusion_half_width_mm: f64,
    /// Height of package + pillar above the base.
    pub inclusion_height_mm: f64,
    /// Load steps to the peak load (at least this many are taken).
    pub load_steps: usize,
    /// Rod speed, for the viscoelastic time step (mm/s).
    pub rod_speed_mm_per_s: f64,
    /// Shape of the rod's end.
    pub rod_shape: RodShape,
    /// Direction the machine drives the rod (and measures its load) along.
    pub drive: Drive,
}

/// What can go wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A configuration value is out of its physical or numerical range.
    #[error("invalid {field}: {reason}")]
    InvalidConfig { field: &'static str, reason: String },
    /// The sparse factorisation failed (singular or non-quasi-definite tangent).
    #[error("linear solver: {0}")]
    LinearSolver(String),
    /// Newton did not converge even after the step cutbacks (`travel_mm` is the rod travel
    /// it was heading for, 0 when unknown; `force_n` the last converged rod force).
    #[error("Newton did not converge after {iterations} iterations and all step cutbacks, going to rod travel {travel_mm:.3} mm (last converged force {force_n:.3} N)")]
    NotConverged {
        iterations: usize,
        travel_mm: f64,
        force_n: f64,
    },
    /// The rod travelled close to the base without reaching the requested load.
    #[error("peak load {peak_n} N not reached: {reached_n:.3} N at rod travel {travel_mm:.2} mm")]
    PeakNotReached {
        peak_n: f64,
        reached_n: f64,
        travel_mm: f64,
    },
    /// Writing an output file failed.
    #[error("writing output: {0}")]
    Io(#[from] std::io::Error),
}

fn check(field: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), Error> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::InvalidConfig {
            field,
            reason: format!("{value} is outside [{lo}, {hi}]"),
        })
    }
}

impl Config {
    /// The fingertip of `hardware/fingertip.toml` under its standard compression test: gel,
    /// radius, rod, angles and speed from the file; neo-Hookean, frictionless, 40 load steps.
    /// The FE's package is square: a half width of r·√π/2 gives it the area of the file's
    /// round package, which the chip's mean traction is taken over.
    pub fn from_hardware(hw: &hardware::Fingertip, mesh_size_mm: f64) -> Config {
        Config {
            radius_mm: hw.radius_mm,
            youngs_modulus_pa: hw.youngs_modulus_pa,
            poisson: hw.poisson,
            material: Material::NeoHookean,
            mesh_size_mm,
            rod_radius_mm: hw.rod_radius_mm,
            contact_angle_deg: hw.test.contact_angle_deg,
            azimuth_deg: hw.test.azimuth_deg,
            friction_mu: 0.0,
            inclusion_half_width_mm: hw.inclusion_radius_mm * std::f64::consts::PI.sqrt() / 2.0,
            inclusion_height_mm: hw.inclusion_height_mm,
            load_steps: 40,
            rod_speed_mm_per_s: hw.test.rod_speed_mm_per_min / 60.0,
            rod_shape: RodShape::FlatEnd,
            drive: Drive::RodAxis,
        }
    }

    /// Reject values outside the ranges the model is built for.
    pub fn validate(&self) -> Result<(), Error> {
        check("radius_mm", self.radius_mm, 1.0, 1000.0)?;
        check("youngs_modulus_pa", self.youngs_modulus_pa, 1e2, 1e10)?;
        check("poisson", self.poisson, 0.0, 0.4999)?;
        check(
            "mesh_size_mm",
            self.mesh_size_mm,
            self.radius_mm / 60.0,
            self.radius_mm / 2.0,
        )?;
        check(
            "rod_radius_mm",
            self.rod_radius_mm,
            self.radius_mm / 50.0,
            10.0 * self.radius_mm,
        )?;
        check("contact_angle_deg", self.contact_angle_deg, 0.0, 60.0)?;
        check("azimuth_deg", self.azimuth_deg, -360.0, 360.0)?;
        check("friction_mu", self.friction_mu, 0.0, 2.0)?;
        check(
            "inclusion_half_width_mm",
            self.inclusion_half_width_mm,
            0.01 * self.radius_mm,
            0.3 * self.radius_mm,
        )?;
        check(
            "inclusion_height_mm",
            self.inclusion_height_mm,
            0.01 * self.radius_mm,
            0.3 * self.radius_mm,
        )?;
        check("load_steps", self.load_steps as f64, 1.0, 10_000.0)?;
        check("rod_speed_mm_per_s", self.rod_speed_mm_per_s, 1e-6, 1e6)?;
        if let Material::ViscoNeoHookean(terms) = &self.material {
            for t in terms {
                check("prony g", t.g, 1e-9, 1.0)?;
                check("prony tau_s", t.tau_s, 1e-9, 1e9)?;
            }
            check("prony g_inf", viscoelastic::g_inf(terms), 1e-3, 1.0)?;
        }
        Ok(())
    }
}

/// A configuration out of range or a load the model cannot reach is bad input; a solver that
/// fails is the program's own failure.
impl sysexit::ExitStatus for Error {
    fn exit_code(&self) -> u8 {
        match self {
            Error::InvalidConfig { .. } | Error::PeakNotReached { .. } => sysexit::DATA,
            Error::Io(_) => sysexit::IO,
            _ => sysexit::SOFTWARE,
        }
    }
}
