//! The baseline's fingertip, backed by the `fingertip` FE model.
//!
//! One quasi-static FE compression per (contact angle theta_p, azimuth phi) at the nominal gel
//! modulus E0 gives rod travel -> rod force and the FE's resultant on the chip package. With nu
//! and the geometry fixed every stress of the neo-Hookean model is proportional to E, so the
//! whole curve scales exactly with E (`fingertip/tests/verification.rs`,
//! `response_scales_linearly_with_youngs_modulus`): the table is stored per pascal and the
//! calibration varies E by a factor, never by re-running the FE. Angles off the tabulated grid
//! blend the two neighbouring tables linearly in theta_p ([`AngleBlend`]).
//!
//! The package resultant becomes the chip's load through `sim::pillar` (mean traction on the
//! package top times the pillar area, lateral traction at the pillar tip), the same path the
//! emulated sensor takes: [`chip_load`] is the only place that knows what the FE's loads mean.
//! FE curves are cached on disk beside the FE (`fingertip::cache`).

use fingertip::{Config, Fingertip};

use crate::response::{FingertipResponse, UnitResponse};
use crate::response_table::ResponseTable;
use fingertip::cache::{self, RawCurve};

/// Mesh size as a fraction of R: 5 mm on the 20 mm fingertip, the mesh of the FE crate's own
/// figures (`fingertip/figures/summary.txt`). An 8 mm mesh costs nearly as much (the Newton
/// iterations dominate) but its package Fz at 60 N, 20 deg is twice the 5 mm one's (-12.4 N
/// against -6.56 N) while the rod force agrees within 1 %: the chip loads need the finer mesh.
const MESH_FRACTION_OF_RADIUS: f64 = 0.25;
/// Rod travel per FE step as a fraction of R (0.8 mm: ~11 steps to 60 N, enough for the
/// monotone cubic between points to stay within 0.3 % of a d^1.5 law past the second step).
const STEP_FRACTION_OF_RADIUS: f64 = 0.04;
/// The table reaches this multiple of the standard test's peak load at E0, so that a recording
/// with a softer gel (down to E0 / 1.25) or a higher peak stays inside it; beyond, the table
/// continues along its end slope.
const REACH_OF_PEAK: f64 = 1.25;
/// If Newton gives up before the reach, a table that got this far of it is still used.
const MIN_SHARE_OF_REACH: f64 = 0.6;
/// The rod travels at most this fraction of R. On the 5 mm mesh Newton stops converging a little
/// beyond 0.5 R at 20 deg (10.4 mm; 73.8 N reached at 9.6 mm), and a failing step costs minutes
/// of cutbacks (a cold `diagnose` took 159 s instead of ~20 s), so the table stops short of it
/// and continues along its end slope.
const MAX_TRAVEL_FRACTION: f64 = 0.5;
/// Tables are computed on this grid of contact angles; others are blended from the two nearest.
pub const ANGLE_GRID_DEG: f64 = 5.0;

/// What can go wrong building the fingertip's response.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FeResponseError {
    /// The FE model refused the configuration or failed to converge early in the compression.
    #[error("fingertip FE at contact angle {theta_deg} deg, azimuth {phi_deg} deg: {source}")]
    Fe {
        theta_deg: f64,
        phi_deg: f64,
        source: fingertip::Error,
    },
    /// The FE stopped converging before the table covered enough of the load range.
    #[error("fingertip FE at contact angle {theta_deg} deg reached only {reached_n:.1} N of {reach_n:.1} N")]
    ShortCurve {
        theta_deg: f64,
        reached_n: f64,
        reach_n: f64,
    },
    /// An earlier attempt at the same table failed in this process (its message).
    #[error("fingertip FE (failed earlier in this run): {0}")]
    Cached(String),
}

/// The project's fingertip and chip, everything the FE tables depend on besides the angles.
#[derive(Debug, Clone)]
pub struct FeSource {
    pub fingertip: hardware::Fingertip,
    pub chip: chip::ChipParams,
    pub pillar: sim::pillar::Pillar,
}

impl FeSource {
    pub fn from_hardware(
        hw: &hardware::Params,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        Ok(Self {
            fingertip: hw.fingertip.clone(),
            chip: chip::ChipParams::try_from(&hw.chip)?,
            pillar: sim::pillar::Pillar::from_params(hw),
        })
    }

    /// The FE configuration for one table: the hardware's gel at its nominal modulus, the
    /// recording's radius, a platen rod of radius R as in the FE crate's figures, frictionless
    /// (friction is a catalogue effect), the package as a square inclusion of the same area as
    /// the toml's round one.
    pub fn config(&self, radius_mm: f64, theta_deg: f64, phi_deg: f64) -> Config {
        Config {
            radius_mm,
            mesh_size_mm: MESH_FRACTION_OF_RADIUS * radius_mm,
            rod_radius_mm: radius_mm,
            contact_angle_deg: theta_deg,
            azimuth_deg: phi_deg,
            load_steps: 1,
            ..Config::from_hardware(&self.fingertip, 0.0)
        }
    }

    /// The load the table must reach at the nominal modulus.
    pub fn reach_n(&self) -> f64 {
        REACH_OF_PEAK * self.fingertip.test.peak_load_n
    }

    /// The per-pascal table at exactly (`theta_deg`, `phi_deg`), from the cache or the FE.
    pub fn table(
        &self,
        radius_mm: f64,
        theta_deg: f64,
        phi_deg: f64,
    ) -> Result<ResponseTable, FeResponseError> {
        let config = self.config(radius_mm, theta_deg, phi_deg);
        let reach_n = self.reach_n();
        let raw = cache::get_or_compute(&config, reach_n, STEP_FRACTION_OF_RADIUS, || {
            run_fe(&config, reach_n)
        })
        .map_err(|failed| match failed {
            cache::Failed::Now(e) => e,
            cache::Failed::Earlier(text) => FeResponseError::Cached(text),
        })?;
        let package_radius_m = self.fingertip.inclusion_radius_mm * 1e-3;
        let points = raw.points().map(|(rod_mm, force_n, loads)| {
            (
                rod_mm,
                force_n,
                chip_load(loads, package_radius_m, &self.pillar, &self.chip),
            )
        });
        Ok(ResponseTable::from_curve(points, config.youngs_modulus_pa))
    }

    /// The response at any contact angle: the grid tables either side, blended.
    pub fn response(
        &self,
        radius_mm: f64,
        theta_deg: f64,
        phi_deg: f64,
    ) -> Result<AngleBlend, FeResponseError> {
        // A negative inclination is the positive one in the opposite tilt plane.
        let (theta_deg, phi_deg) = if theta_deg < 0.0 {
            (-theta_deg, phi_deg + 180.0)
        } else {
            (theta_deg, phi_deg)
        };
        let phi_deg = phi_deg.rem_euclid(360.0);
        let lo = (theta_deg / ANGLE_GRID_DEG).floor() * ANGLE_GRID_DEG;
        let weight = (theta_deg - lo) / ANGLE_GRID_DEG;
        let lower = self.table(radius_mm, lo, phi_deg)?;
        let upper = if weight > 1e-9 {
            Some((self.table(radius_mm, lo + ANGLE_GRID_DEG, phi_deg)?, weight))
        } else {
            None
        };
        Ok(AngleBlend { lower, upper })
    }
}

/// The chip's (Fz, Mx, My) from the FE's resultant on the package `[fx, fy, fz, mx, my]`
/// (N, N·m, FE convention: fz negative when pressed): the mean traction on the package top
/// through the pillar (`sim::pillar`). When the FE counts the pillar alone, this is the one
/// function to change.
pub fn chip_load(
    fe: [f64; 5],
    package_radius_m: f64,
    pillar: &sim::pillar::Pillar,
    chip: &chip::ChipParams,
) -> [f64; 3] {
    let [fx, fy, fz, _, _] = fe;
    let t = sim::pillar::Traction::from_package_resultant(fx, fy, fz, package_radius_m);
    let l = pillar.chip_load(chip, t);
    [l.fz_n, l.mx_nm, l.my_nm]
}

/// Compress the FE model in even travel steps until the rod force reaches `reach_n`; keep what
/// converged if Newton gives up late.
fn run_fe(config: &Config, reach_n: f64) -> Result<RawCurve, FeResponseError> {
    let fe_err = |source| FeResponseError::Fe {
        theta_deg: config.contact_angle_deg,
        phi_deg: config.azimuth_deg,
        source,
    };
    let mut ft = Fingertip::new(config.clone()).map_err(fe_err)?;
    let step_mm = STEP_FRACTION_OF_RADIUS * config.radius_mm;
    let mut raw = RawCurve::default();
    raw.push(0.0, 0.0, [0.0; 5]);
    let mut reached_n = 0.0;
    while reached_n < reach_n {
        let target_mm = ft.travel_mm() + step_mm;
        if target_mm > MAX_TRAVEL_FRACTION * config.radius_mm {
            break;
        }
        match ft.step_to(target_mm, step_mm / config.rod_speed_mm_per_s) {
            Ok(p) => {
                let l = ft.chip_loads();
                raw.push(
                    p.rod_mm,
                    p.force_n,
                    [l.fx_n, l.fy_n, l.fz_n, l.mx_nm, l.my_nm],
                );
                reached_n = p.force_n;
            }
            Err(_) if reached_n >= MIN_SHARE_OF_REACH * reach_n => break,
            Err(e) => return Err(fe_err(e)),
        }
    }
    if reached_n < MIN_SHARE_OF_REACH * reach_n {
        return Err(FeResponseError::ShortCurve {
            theta_deg: config.contact_angle_deg,
            reached_n,
            reach_n,
        });
    }
    Ok(raw)
}

/// The fingertip response at a contact angle between two grid tables: (1 - w) lower + w upper.
#[derive(Debug, Clone)]
pub struct AngleBlend {
    lower: ResponseTable,
    upper: Option<(ResponseTable, f64)>,
}

impl AngleBlend {
    /// The largest travel both tables cover.
    pub fn max_rod_mm(&self) -> f64 {
        let lo = self.lower.max_rod_mm();
        self.upper
            .as_ref()
            .map_or(lo, |(t, _)| lo.min(t.max_rod_mm()))
    }
}

impl FingertipResponse for AngleBlend {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        let a = self.lower.unit_response(rod_mm);
        let Some((table, w)) = &self.upper else {
            return a;
        };
        let b = table.unit_response(rod_mm);
        UnitResponse {
            force_n: a.force_n + w * (b.force_n - a.force_n),
            chip: std::array::from_fn(|k| a.chip[k] + w * (b.chip[k] - a.chip[k])),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source() -> FeSource {
        FeSource::from_hardware(&hardware::Params::load_default().unwrap()).unwrap()
    }

    /// By hand: 1 N pressing (FE fz = -1 N) on a 3 mm package is 35.37 kPa; on the 150 um
    /// pillar (1.767e-8 m^2) that is 0.625 mN; 0.5 N along x at the 1 mm pillar tip gives
    /// My = 1e-3 * 0.5 * 1.767e-8 / 2.827e-5 = 3.125e-7 N m. The FE's package moments do not
    /// reach the chip through the pillar's mean traction.
    #[test]
    fn package_resultant_to_chip_load() {
        let s = source();
        let area_ratio = s.pillar.area_m2() / (std::f64::consts::PI * 9e-6);
        let h = s.chip.geometry.pillar_height_m;
        let l = chip_load([0.5, 0.0, -1.0, 7.0, 7.0], 3e-3, &s.pillar, &s.chip);
        assert!((l[0] - area_ratio).abs() < 1e-15, "{l:?}");
        assert!(l[1].abs() < 1e-18, "{l:?}");
        assert!((l[2] - h * 0.5 * area_ratio).abs() < 1e-15, "{l:?}");
    }

    /// The blend is linear in the angle and exact on the grid.
    #[test]
    fn angle_blend_weights() {
        let t = |k: f64| {
            ResponseTable::new(
                vec![0.0, 1.0],
                vec![
                    UnitResponse::default(),
                    UnitResponse {
                        force_n: k,
                        chip: [k, 2.0 * k, 0.0],
                    },
                ],
            )
        };
        let b = AngleBlend {
            lower: t(1.0),
            upper: Some((t(3.0), 0.25)),
        };
        let u = b.unit_response(1.0);
        assert!((u.force_n - 1.5).abs() < 1e-12 && (u.chip[1] - 3.0).abs() < 1e-12);
    }
}
