//! Load histories: what the gel does to the package top over time, as the chain's first stage.
//!
//! Two sources:
//! - [`ContactForce`] given directly (no fingertip model): a force on the fingertip whose line of
//!   action passes through the hemisphere's centre (the chip), as in the original experiments
//!   ("while the load points at the hemisphere's centre"). The traction it causes at the package
//!   top is Boussinesq's: for a point force P on an incompressible (ν = 1/2) elastic half-space the
//!   stress is purely radial, `σ_ρρ = -3 P cos β / (2 π ρ²)` (Johnson, Contact Mechanics, §3.2;
//!   exact for ν = 1/2, and the gel's 0.49 is within 2 %). On the load line (β = 0), a depth ρ
//!   below the contact, the gel is compressed along the load direction `u` by `s = 3P / (2πρ²)`,
//!   and the package top (normal +z) receives the traction `t = -s (u·z) u`. The half-space
//!   ignores the hemisphere's curvature, its bonded base and large strain: an estimate of the
//!   traction's size and direction, replaced by the FE's resultant when the fingertip model runs.
//! - [`Table`]: a time series of resultants on the package (the fingertip FE's output) or of
//!   tractions, linearly interpolated.
//!
//! Rod travel for the direct path comes from Hertz's sphere-on-flat law `P = 4/3 E* √R d^(3/2)`,
//! `E* = E / (1 - ν²)`: only the small-load start of the real curve (beyond d ≈ R/10 the gel's
//! large strain and the rigid base stiffen the contact).

use crate::pillar::Traction;

/// The state of the load at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Contact {
    /// Rod travel from first contact, mm (the recording's `rod_mm`).
    pub rod_mm: f64,
    /// Force along the rod axis, N (the load cell, the recording's `load_N`).
    pub load_n: f64,
    /// Mean traction of the gel on the package top.
    pub traction: Traction,
}

/// A load history: the contact at time `t_s` since power-up.
pub trait LoadHistory {
    fn contact(&self, t_s: f64) -> Contact;
}

/// A force on the fingertip, chip frame, whose line of action passes through the hemisphere's
/// centre, and the geometry that carries it to the package top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// Unit vector of the force (from the contact point towards the centre).
    pub direction: [f64; 3],
    /// Distance ρ from the contact point to the package top along the load line: the hemisphere
    /// radius minus the package height.
    pub depth_m: f64,
}

impl ContactForce {
    /// The original experiment's load: along the fingertip axis tilted by the contact angle θ_p
    /// in the plane at azimuth φ from the chip's x axis, pressing towards the centre.
    pub fn tilted(contact_angle_deg: f64, azimuth_deg: f64, depth_m: f64) -> Self {
        let (th, ph) = (contact_angle_deg.to_radians(), azimuth_deg.to_radians());
        let outward = [
            libm::sin(th) * libm::cos(ph),
            libm::sin(th) * libm::sin(ph),
            libm::cos(th),
        ];
        Self {
            direction: outward.map(|c| -c),
            depth_m,
        }
    }

    /// Boussinesq traction on the package top for a force of `load_n` along the direction.
    pub fn traction(&self, load_n: f64) -> Traction {
        let s = 3.0 * load_n / (2.0 * core::f64::consts::PI * self.depth_m * self.depth_m);
        let u = self.direction;
        // t = -s (u·z) u; pressing traction is -t_z.
        let t = u.map(|c| -s * u[2] * c);
        Traction {
            tx_pa: t[0],
            ty_pa: t[1],
            tz_pa: -t[2],
        }
    }
}

/// Hertz contact of the gel hemisphere with a flat rod: travel from force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    pub radius_m: f64,
    pub youngs_modulus_pa: f64,
    pub poisson: f64,
}

impl Hertz {
    /// Effective modulus `E* = E / (1 - ν²)` (rigid rod).
    pub fn effective_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (1.0 - self.poisson * self.poisson)
    }

    /// Force at travel `d`: `4/3 E* √R d^(3/2)`.
    pub fn force_n(&self, travel_m: f64) -> f64 {
        let d = travel_m.max(0.0);
        4.0 / 3.0 * self.effective_modulus_pa() * libm::sqrt(self.radius_m) * d * libm::sqrt(d)
    }

    /// Travel at force `P`: `(3P / (4 E* √R))^(2/3)`.
    pub fn travel_m(&self, load_n: f64) -> f64 {
        let x =
            3.0 * load_n.max(0.0) / (4.0 * self.effective_modulus_pa() * libm::sqrt(self.radius_m));
        libm::cbrt(x * x)
    }
}

/// The standard test driven by force directly: rest, a ramp of the rod force to the peak, a hold,
/// the return, then rest again. The force rises as the Hertz law gives it for a rod moving at
/// constant speed (`P ∝ t^(3/2)`), and falls along it on the return.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceSchedule {
    pub force: ContactForce,
    pub hertz: Hertz,
    /// Time before the rod touches.
    pub start_s: f64,
    pub peak_load_n: f64,
    pub rod_speed_m_per_s: f64,
    pub hold_s: f64,
    pub return_speed_m_per_s: f64,
}

impl ForceSchedule {
    /// Travel at the peak.
    pub fn peak_travel_m(&self) -> f64 {
        self.hertz.travel_m(self.peak_load_n)
    }

    /// Time at which the rod is back at first contact.
    pub fn end_s(&self) -> f64 {
        let d = self.peak_travel_m();
        self.start_s + d / self.rod_speed_m_per_s + self.hold_s + d / self.return_speed_m_per_s
    }

    /// Rod travel at `t_s`.
    pub fn travel_m(&self, t_s: f64) -> f64 {
        let d = self.peak_travel_m();
        let t_up = d / self.rod_speed_m_per_s;
        let t = t_s - self.start_s;
        if t <= 0.0 {
            0.0
        } else if t < t_up {
            self.rod_speed_m_per_s * t
        } else if t < t_up + self.hold_s {
            d
        } else {
            (d - self.return_speed_m_per_s * (t - t_up - self.hold_s)).max(0.0)
        }
    }
}

impl LoadHistory for ForceSchedule {
    fn contact(&self, t_s: f64) -> Contact {
        let d = self.travel_m(t_s);
        let load_n = self.hertz.force_n(d).min(self.peak_load_n);
        Contact {
            rod_mm: d * 1.0e3,
            load_n,
            traction: self.force.traction(load_n),
        }
    }
}

#[cfg(feature = "std")]
pub use table::Table;

#[cfg(feature = "std")]
mod table {
    use super::{Contact, LoadHistory};
    use crate::pillar::Traction;

    /// A sampled history (e.g. the fingertip FE's resultants over a run), interpolated linearly
    /// in time and held at both ends.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct Table {
        rows: Vec<(f64, Contact)>,
    }

    impl Table {
        /// Rows `(t_s, contact)` with non-decreasing times (a programmer's invariant).
        pub fn new(rows: Vec<(f64, Contact)>) -> Self {
            assert!(
                rows.windows(2).all(|w| w[0].0 <= w[1].0),
                "table times must not decrease"
            );
            Self { rows }
        }

        /// From resultants on the package top: `(t_s, rod_mm, load_n, [fx, fy, fz])` with the
        /// FE's sign convention (fz along +z, negative when pressed).
        pub fn from_resultants(rows: &[(f64, f64, f64, [f64; 3])], package_radius_m: f64) -> Self {
            Self::new(
                rows.iter()
                    .map(|&(t, rod_mm, load_n, [fx, fy, fz])| {
                        let traction =
                            Traction::from_package_resultant(fx, fy, fz, package_radius_m);
                        (
                            t,
                            Contact {
                                rod_mm,
                                load_n,
                                traction,
                            },
                        )
                    })
                    .collect(),
            )
        }
    }

    fn lerp(a: f64, b: f64, w: f64) -> f64 {
        a + (b - a) * w
    }

    impl LoadHistory for Table {
        fn contact(&self, t_s: f64) -> Contact {
            let Some(first) = self.rows.first() else {
                return Contact::default();
            };
            let after = self.rows.partition_point(|r| r.0 <= t_s);
            if after == 0 {
                return first.1;
            }
            let (t0, a) = self.rows[after - 1];
            let Some(&(t1, b)) = self.rows.get(after) else {
                return a;
            };
            let w = if t1 > t0 { (t_s - t0) / (t1 - t0) } else { 0.0 };
            Contact {
                rod_mm: lerp(a.rod_mm, b.rod_mm, w),
                load_n: lerp(a.load_n, b.load_n, w),
                traction: Traction {
                    tx_pa: lerp(a.traction.tx_pa, b.traction.tx_pa, w),
                    ty_pa: lerp(a.traction.ty_pa, b.traction.ty_pa, w),
                    tz_pa: lerp(a.traction.tz_pa, b.traction.tz_pa, w),
                },
            }
        }
    }
}

#[cfg(feature = "std")]
impl ForceSchedule {
    /// The standard test of `hardware/fingertip.toml` (contact angle, azimuth, peak load, hold,
    /// rod speeds; Hertz from the gel and radius; Boussinesq depth = radius - package height),
    /// starting `start_s` after power-up, every speed multiplied by `speed_factor` (a HIL run
    /// cannot wait the real test's minute).
    pub fn from_params(p: &hardware::Params, start_s: f64, speed_factor: f64) -> Self {
        let f = &p.fingertip;
        let mm_per_min = 1.0e-3 / 60.0;
        Self {
            force: ContactForce::tilted(
                f.test.contact_angle_deg,
                f.test.azimuth_deg,
                (f.radius_mm - f.inclusion_height_mm) * 1.0e-3,
            ),
            hertz: Hertz {
                radius_m: f.radius_mm * 1.0e-3,
                youngs_modulus_pa: f.youngs_modulus_pa,
                poisson: f.poisson,
            },
            start_s,
            peak_load_n: f.test.peak_load_n,
            rod_speed_m_per_s: f.test.rod_speed_mm_per_min * mm_per_min * speed_factor,
            hold_s: f.test.hold_s / speed_factor,
            return_speed_m_per_s: f.test.return_speed_mm_per_min * mm_per_min * speed_factor,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axial_load_gives_boussinesq_pressure() {
        // By hand: 60 N, 18 mm deep: s = 180 / (2 pi 3.24e-4) = 88 419.4 Pa, all normal.
        let t = ContactForce::tilted(0.0, 60.0, 0.018).traction(60.0);
        assert!((t.tz_pa - 88_419.4).abs() < 0.1, "{t:?}");
        assert!(t.tx_pa.abs() < 1e-9 && t.ty_pa.abs() < 1e-9);
    }

    #[test]
    fn tilted_load_pushes_the_package_away_from_the_contact_side() {
        // 20 deg at azimuth 60: normal s cos^2, lateral s cos sin towards -(cos 60, sin 60).
        let s = 88_419.4;
        let (c, n) = (20f64.to_radians().cos(), 20f64.to_radians().sin());
        let t = ContactForce::tilted(20.0, 60.0, 0.018).traction(60.0);
        assert!((t.tz_pa - s * c * c).abs() < 0.1, "{t:?}");
        assert!((t.tx_pa + s * c * n * 0.5).abs() < 0.1, "{t:?}");
        assert!(
            (t.ty_pa + s * c * n * 3f64.sqrt() / 2.0).abs() < 0.1,
            "{t:?}"
        );
    }

    #[test]
    fn hertz_inverts_and_follows_the_three_halves_power() {
        let h = Hertz {
            radius_m: 0.02,
            youngs_modulus_pa: 1.0e5,
            poisson: 0.49,
        };
        // By hand at d = 1 mm: 4/3 * 1e5/(1 - 0.2401) * sqrt(0.02) * 1e-3^1.5 = 0.78478 N.
        assert!(
            (h.force_n(1.0e-3) - 0.784_68).abs() < 1e-5,
            "{}",
            h.force_n(1.0e-3)
        );
        assert!((h.travel_m(h.force_n(2.0e-3)) - 2.0e-3).abs() < 1e-12);
        assert!((h.force_n(4.0e-3) / h.force_n(1.0e-3) - 8.0).abs() < 1e-12);
    }

    #[cfg(feature = "std")]
    #[test]
    fn table_interpolates_and_holds() {
        let rows = [
            (0.0, 0.0, 0.0, [0.0, 0.0, 0.0]),
            (1.0, 2.0, 10.0, [0.0, 0.0, -1.0]),
        ];
        let table = Table::from_resultants(&rows, 3.0e-3);
        let mid = table.contact(0.5);
        assert_eq!((mid.rod_mm, mid.load_n), (1.0, 5.0));
        assert!((mid.traction.tz_pa - 0.5 / (core::f64::consts::PI * 9.0e-6)).abs() < 1e-6);
        assert_eq!(table.contact(7.0).load_n, 10.0);
        assert_eq!(table.contact(-1.0).load_n, 0.0);
    }
}
