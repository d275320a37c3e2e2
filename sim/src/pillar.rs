//! The pillar between the gel and the chip's central block.
//!
//! The chip does not carry the whole package's reaction: the gel presses, through the package's
//! thin rubber film, on the top of a pillar of area `A_p = π d² / 4` bonded to the central block.
//! The chip therefore sees the gel's mean traction `t` over that area: `Fz = t_z A_p` (pressing
//! positive, the chip crate's convention), and the lateral traction's force `(t_x, t_y) A_p` acts
//! at the pillar tip, a height H above the chip surface, so it adds the moments
//! `Mx = -H t_y A_p`, `My = H t_x A_p` (`chip::tolerance::load_at_chip`).
//!
//! When a model gives the resultant `(F_x, F_y, F_z)` on the whole package top (the fingertip FE's
//! rigid inclusion of radius r), the mean traction is that resultant over `π r²`.

use chip::{ChipParams, Load};

/// Mean traction of the gel on the package top, chip frame, Pa. `tz_pa` is positive when the gel
/// presses on the chip (along -z); `tx_pa`, `ty_pa` are the lateral components along +x, +y.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Traction {
    pub tx_pa: f64,
    pub ty_pa: f64,
    pub tz_pa: f64,
}

impl Traction {
    /// Mean traction from the resultant force of the gel on a package top of radius
    /// `package_radius_m`: `t = F / (π r²)`. `fz_n` follows the fingertip FE's convention (along
    /// +z, out of the base, negative when pressed), so `t_z = -F_z / (π r²)`.
    pub fn from_package_resultant(fx_n: f64, fy_n: f64, fz_n: f64, package_radius_m: f64) -> Self {
        let area = core::f64::consts::PI * package_radius_m * package_radius_m;
        Self {
            tx_pa: fx_n / area,
            ty_pa: fy_n / area,
            tz_pa: -fz_n / area,
        }
    }
}

/// The pillar on the central block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pillar {
    /// Diameter d of its top face.
    pub diameter_m: f64,
}

impl Pillar {
    /// Top area `A_p = π d² / 4`.
    pub fn area_m2(&self) -> f64 {
        core::f64::consts::PI * self.diameter_m * self.diameter_m / 4.0
    }

    /// The load on the chip from the gel's traction `t` (pillar height from `chip`).
    pub fn chip_load(&self, chip: &ChipParams, t: Traction) -> Load {
        let a = self.area_m2();
        chip::tolerance::load_at_chip(
            chip,
            Load::new(t.tz_pa * a, 0.0, 0.0),
            t.tx_pa * a,
            t.ty_pa * a,
        )
    }
}

#[cfg(feature = "std")]
impl Pillar {
    /// From `hardware/sim.toml`.
    pub fn from_params(p: &hardware::Params) -> Self {
        Self {
            diameter_m: p.sim.pillar_diameter_um * 1.0e-6,
        }
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    #[test]
    fn traction_times_pillar_area_and_height() {
        // By hand: A = pi (75 um)^2 = 1.767146e-8 m^2; 100 kPa -> 1.767146 mN; 10 kPa along x at
        // the tip of the 1 mm pillar -> My = 1e-3 m * 1.767146e-4 N = 1.767146e-7 N m; 20 kPa
        // along y -> Mx = -3.534292e-7 N m.
        let chip = ChipParams::load_default().unwrap();
        assert_eq!(chip.geometry.pillar_height_m, 1.0e-3);
        let pillar = Pillar {
            diameter_m: 150.0e-6,
        };
        let load = pillar.chip_load(
            &chip,
            Traction {
                tx_pa: 1.0e4,
                ty_pa: 2.0e4,
                tz_pa: 1.0e5,
            },
        );
        assert!((load.fz_n - 1.767_146e-3).abs() < 1e-9, "{load:?}");
        assert!((load.my_nm - 1.767_146e-7).abs() < 1e-13, "{load:?}");
        assert!((load.mx_nm + 3.534_292e-7).abs() < 1e-13, "{load:?}");
    }

    #[test]
    fn package_resultant_spreads_over_the_package_top() {
        // 3 mm radius: area 2.827433e-5 m^2; 1 N pressing (FE fz = -1 N) -> 35.3678 kPa.
        let t = Traction::from_package_resultant(0.5, 0.0, -1.0, 3.0e-3);
        assert!((t.tz_pa - 35_367.765).abs() < 1e-2, "{t:?}");
        assert!((t.tx_pa - 17_683.883).abs() < 1e-2, "{t:?}");
    }
}
