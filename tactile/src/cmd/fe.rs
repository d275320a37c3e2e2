//! `tactile fe`: run the soft-fingertip finite-element model of a rod compression and print
//! the force–travel curve with the chip loads (CSV on stdout, or `--json`), timings on stderr.
//!
//! Every physical default (gel modulus and Poisson's ratio, radius, chip package, rod radius,
//! friction coefficient, contact angle, azimuth, peak load, rod speed) comes from
//! `hardware/fingertip.toml`; a flag overrides it. The package is modelled as a square rigid
//! inclusion of the same footprint area as the toml's round one (half width r sqrt(pi) / 2).

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;
use sysexit::ResultExt as _;

use anyhow::Context;
use fingertip::{Config, Drive, Fingertip, Material, RodShape};

use sysexit::{self as exit, ExitStatus};

/// Gel law on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MaterialArg {
    /// Small-strain linear elasticity.
    Linear,
    /// Finite-strain neo-Hookean (locking-free nodal-pressure tetrahedra).
    NeoHookean,
}

/// Rod end on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RodShapeArg {
    /// Flat end disc with a rounded rim.
    Flat,
    /// Spherical end of the rod's radius.
    Sphere,
    /// Cylinder of the rod's radius lying across the fingertip, axis in the tilt plane.
    Cylinder,
}

/// Drive direction on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DriveArg {
    /// Along the rod's axis.
    Rod,
    /// Along the fingertip's axis z.
    Fingertip,
}

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Inclination theta_p of the rod from the fingertip axis, degrees [0, 60] (default: toml).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub contact_angle: Option<f64>,
    /// Azimuth phi of the tilt plane from the chip's x axis, degrees [-360, 360] (default: toml).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub azimuth: Option<f64>,
    /// Stop when the force along the rod reaches this, N (default: toml).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub peak_load: Option<f64>,
    /// Young's modulus of the gel, Pa (default: toml).
    #[arg(long, value_name = "PA", allow_negative_numbers = true)]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio of the gel, [0, 0.4999] (default: toml).
    #[arg(long, allow_negative_numbers = true)]
    pub poisson: Option<f64>,
    /// Hemisphere radius, mm (default: toml).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Constitutive law.
    #[arg(long, value_enum, default_value_t = MaterialArg::NeoHookean)]
    pub material: MaterialArg,
    /// Nominal element size, mm (finer at the chip and under the rod).
    #[arg(
        long,
        value_name = "MM",
        default_value_t = 5.0,
        allow_negative_numbers = true
    )]
    pub mesh_size: f64,
    /// Rod radius, mm (default: toml).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub rod_radius: Option<f64>,
    /// Coulomb friction between rod and gel; `--friction` alone takes the toml's value.
    #[arg(long, value_name = "MU", num_args = 0..=1, allow_negative_numbers = true)]
    pub friction: Option<Option<f64>>,
    /// Shape of the rod's end.
    #[arg(long, value_enum, default_value_t = RodShapeArg::Flat)]
    pub rod_shape: RodShapeArg,
    /// What the machine drives the rod along: its own axis (fingertip tilted on a jig) or the
    /// fingertip's axis (fingertip upright, rod end inclined); the load is measured along it.
    #[arg(long, value_enum, default_value_t = DriveArg::Rod)]
    pub drive: DriveArg,
    /// Minimum number of load steps to the peak.
    #[arg(long, default_value_t = 40)]
    pub load_steps: usize,
    /// Print one JSON object (config, mesh quality, timings, points) instead of CSV.
    #[arg(long)]
    pub json: bool,
    /// Write the deformed mesh at the peak as legacy VTK.
    #[arg(long, value_name = "PATH")]
    pub vtk: Option<PathBuf>,
}

/// A flag value outside its range.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FeError {
    /// The named flag's value is not in the allowed closed interval.
    #[error("{flag} = {value} is out of range [{lo}, {hi}]")]
    OutOfRange {
        flag: &'static str,
        value: f64,
        lo: f64,
        hi: f64,
    },
}

impl ExitStatus for FeError {
    fn exit_code(&self) -> u8 {
        exit::USAGE
    }
}

fn in_range(flag: &'static str, value: f64, lo: f64, hi: f64) -> Result<f64, FeError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(FeError::OutOfRange {
            flag,
            value,
            lo,
            hi,
        })
    }
}

/// The model configuration from the flags and `hardware/fingertip.toml`, and the peak load.
pub fn config(args: &Args, hw: &hardware::Fingertip) -> Result<(Config, f64), FeError> {
    let radius_mm = in_range("--radius", args.radius.unwrap_or(hw.radius_mm), 1.0, 1000.0)?;
    let friction = match args.friction {
        None => 0.0,
        Some(None) => hw.friction_mu,
        Some(Some(mu)) => mu,
    };
    let config = Config {
        radius_mm,
        youngs_modulus_pa: in_range(
            "--youngs-modulus",
            args.youngs_modulus.unwrap_or(hw.youngs_modulus_pa),
            1e2,
            1e10,
        )?,
        poisson: in_range("--poisson", args.poisson.unwrap_or(hw.poisson), 0.0, 0.4999)?,
        material: match args.material {
            MaterialArg::Linear => Material::Linear,
            MaterialArg::NeoHookean => Material::NeoHookean,
        },
        mesh_size_mm: in_range(
            "--mesh-size",
            args.mesh_size,
            radius_mm / 60.0,
            radius_mm / 2.0,
        )?,
        rod_radius_mm: in_range(
            "--rod-radius",
            args.rod_radius.unwrap_or(hw.rod_radius_mm),
            radius_mm / 50.0,
            10.0 * radius_mm,
        )?,
        contact_angle_deg: in_range(
            "--contact-angle",
            args.contact_angle.unwrap_or(hw.test.contact_angle_deg),
            0.0,
            60.0,
        )?,
        azimuth_deg: in_range(
            "--azimuth",
            args.azimuth.unwrap_or(hw.test.azimuth_deg),
            -360.0,
            360.0,
        )?,
        friction_mu: in_range("--friction", friction, 0.0, 2.0)?,
        load_steps: in_range("--load-steps", args.load_steps as f64, 1.0, 10_000.0)? as usize,
        rod_shape: match args.rod_shape {
            RodShapeArg::Flat => RodShape::FlatEnd,
            RodShapeArg::Sphere => RodShape::SphereEnd,
            RodShapeArg::Cylinder => RodShape::CylinderAcross,
        },
        drive: match args.drive {
            DriveArg::Rod => Drive::RodAxis,
            DriveArg::Fingertip => Drive::FingertipAxis,
        },
        ..Config::from_hardware(hw, args.mesh_size)
    };
    let peak = in_range(
        "--peak-load",
        args.peak_load.unwrap_or(hw.test.peak_load_n),
        1e-6,
        1e4,
    )?;
    Ok((config, peak))
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let hw = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let (config, peak) = config(&args, &hw.fingertip)?;
    let t0 = Instant::now();
    let mut ft = Fingertip::new(config.clone())
        .coded()
        .context("building the fingertip model")?;
    let curve = ft.compress_to_peak(peak).with_context(|| {
        if config.rod_radius_mm < 0.5 * config.radius_mm {
            format!(
                "compressing the fingertip (a {} mm rod narrower than the contact patch lets the gel wrap round its rim; a platen, e.g. --rod-radius {}, reaches the peak)",
                config.rod_radius_mm, config.radius_mm
            )
        } else {
            "compressing the fingertip".to_string()
        }
    })?;
    let total_s = t0.elapsed().as_secs_f64();
    if let Some(path) = &args.vtk {
        ft.write_vtk(path)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        let doc = serde_json::json!({
            "config": config, "peak_load_n": peak, "quality": curve.quality, "stats": curve.stats,
            "dofs": curve.dofs, "setup_s": curve.setup_s, "solve_s": curve.solve_s, "total_s": total_s,
            "points": curve.points,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&doc)?)?;
    } else {
        writeln!(out, "rod_mm,force_n,fz_n,mx_nm,my_nm,t_s,contact_nodes")?;
        for p in &curve.points {
            writeln!(
                out,
                "{:.5},{:.6},{:.6},{:.6e},{:.6e},{:.4},{}",
                p.rod_mm, p.force_n, p.fz_n, p.mx_nm, p.my_nm, p.t_s, p.contact_nodes
            )?;
        }
        let q = &curve.quality;
        let s = &curve.stats;
        eprintln!(
            "# mesh: {} nodes, {} tets, {} dofs; dihedral {:.1}..{:.1} deg, aspect <= {:.2}, volume {:.4} of 2/3 pi R^3",
            q.nodes, q.tets, curve.dofs, q.min_dihedral_deg, q.max_dihedral_deg, q.max_aspect_ratio, q.volume_ratio
        );
        eprintln!(
            "# time: setup {:.3} s, solve {:.3} s ({} steps, {} Newton iterations, {} factorisations of which {} in the background, {} cutbacks; assembly {:.3} s, factor {:.3} s on the Newton path)",
            curve.setup_s,
            curve.solve_s,
            curve.points.len() - 1,
            s.newton_iterations,
            s.factorizations,
            s.background_factorizations,
            s.cutbacks,
            s.assembly_s,
            s.factor_s
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Debug, Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    fn hw() -> hardware::Fingertip {
        hardware::Params::load_default()
            .expect("hardware/")
            .fingertip
    }

    #[test]
    fn defaults_come_from_the_toml_and_flags_override_them() {
        let hw = hw();
        let (c, peak) = config(&Cli::parse_from(["fe"]).args, &hw).unwrap();
        assert_eq!(
            (c.youngs_modulus_pa, c.poisson, c.radius_mm),
            (hw.youngs_modulus_pa, hw.poisson, hw.radius_mm)
        );
        assert_eq!(peak, hw.test.peak_load_n);
        assert_eq!(c.friction_mu, 0.0);
        let (c, _) = config(
            &Cli::parse_from(["fe", "--poisson", "0.45", "--friction"]).args,
            &hw,
        )
        .unwrap();
        assert_eq!((c.poisson, c.friction_mu), (0.45, hw.friction_mu));
    }

    #[test]
    fn out_of_range_values_name_the_flag() {
        let hw = hw();
        for (flag, value) in [
            ("--poisson", "0.5"),
            ("--contact-angle", "75"),
            ("--mesh-size", "0.01"),
            ("--peak-load", "-1"),
            ("--azimuth", "-400"),
        ] {
            let err = config(&Cli::parse_from(["fe", flag, value]).args, &hw).unwrap_err();
            assert!(err.to_string().starts_with(flag), "{err}");
            assert_eq!(err.exit_code(), exit::USAGE);
        }
    }
}
