//! The public model: build the mesh and solver from a [`Config`], drive the rod, record the
//! curve. Load stepping is by rod travel; a failed step is restored and cut in half.

use std::time::Instant;

use crate::assembly::{advance_history, State};
use crate::contact::Rod;
use crate::loads::{chip_loads, mount_reaction, ChipLoads};
use crate::material::{moduli, Kinematics};
use crate::mesh::{generate, MeshParams};
use crate::model::{MaterialData, Model};
use crate::quality::{report, QualityReport};
use crate::solver::{Solver, Stats};
use crate::{Config, Error, Material};

/// Halvings of one load step before giving up.
const MAX_CUTBACK_DEPTH: usize = 8;
/// The rod may travel at most this fraction of R.
const MAX_TRAVEL_FRACTION: f64 = 0.95;
/// The peak is hit within this relative tolerance.
const PEAK_TOL: f64 = 5e-3;

/// One recorded state of the compression.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct CurvePoint {
    /// Time since the start (rod travel / speed for a compression), s.
    pub t_s: f64,
    /// Rod travel since first touch, mm.
    pub rod_mm: f64,
    /// Contact force along the machine's drive (what its load cell reads; the rod axis unless
    /// [`crate::Drive::FingertipAxis`]), N; positive pushing.
    pub force_n: f64,
    /// Chip loads (see [`ChipLoads`]): force along chip z, N (negative when pressed).
    pub fz_n: f64,
    /// Moment about chip x, N·m.
    pub mx_nm: f64,
    /// Moment about chip y, N·m.
    pub my_nm: f64,
    /// Surface nodes in contact.
    pub contact_nodes: usize,
}

/// A force–travel curve and how it was computed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Curve {
    pub points: Vec<CurvePoint>,
    pub quality: QualityReport,
    pub stats: Stats,
    /// Wall time of mesh generation + setup, s.
    pub setup_s: f64,
    /// Wall time of the load stepping, s.
    pub solve_s: f64,
    /// Unknowns of the linear systems.
    pub dofs: usize,
    /// Stored entries of the LDL^T factor.
    pub factor_nnz: usize,
}

/// A fingertip model and the state of its rod.
#[derive(Debug)]
pub struct Fingertip {
    pub config: Config,
    pub solver: Solver,
    /// Current rod travel, m.
    travel_m: f64,
    t_s: f64,
    pub setup_s: f64,
    /// Positions, pressures and rod travel of the previous converged step (the predictor).
    previous: Option<(Vec<[f64; 3]>, Vec<f64>, f64)>,
}

/// Build the model and compress it to `peak_load_n` along the rod.
pub fn compress(config: &Config, peak_load_n: f64) -> Result<Curve, Error> {
    let mut ft = Fingertip::new(config.clone())?;
    ft.compress_to_peak(peak_load_n)
}

impl Fingertip {
    pub fn new(config: Config) -> Result<Fingertip, Error> {
        config.validate()?;
        let t0 = Instant::now();
        let mesh = generate(&MeshParams {
            radius_mm: config.radius_mm,
            size_mm: config.mesh_size_mm,
            inclusion_half_width_mm: config.inclusion_half_width_mm,
            inclusion_height_mm: config.inclusion_height_mm,
        });
        let (mu, kappa) = moduli(config.youngs_modulus_pa, config.poisson);
        let (kinematics, prony) = match &config.material {
            Material::Linear => (Kinematics::Linear, Vec::new()),
            Material::NeoHookean => (Kinematics::NeoHookean, Vec::new()),
            Material::ViscoNeoHookean(terms) => (Kinematics::NeoHookean, terms.clone()),
        };
        let model = Model::new(
            mesh,
            MaterialData {
                kinematics,
                mu_pa: mu,
                kappa_pa: kappa,
                prony,
            },
        );
        let solver = Solver::new(model, config.youngs_modulus_pa)?;
        let mut ft = Fingertip {
            config,
            solver,
            travel_m: 0.0,
            t_s: 0.0,
            setup_s: 0.0,
            previous: None,
        };
        let rod = ft.rod_at(0.0);
        ft.solver.evaluate(&rod, 0.0);
        ft.setup_s = t0.elapsed().as_secs_f64();
        Ok(ft)
    }

    pub fn quality(&self) -> QualityReport {
        report(&self.solver.model.mesh)
    }

    /// Current rod travel, mm.
    pub fn travel_mm(&self) -> f64 {
        self.travel_m * 1e3
    }

    pub fn rod_at(&self, travel_m: f64) -> Rod {
        let c = &self.config;
        let r_m = c.radius_mm * 1e-3;
        Rod::new(
            c.contact_angle_deg,
            c.azimuth_deg,
            c.rod_radius_mm * 1e-3,
            r_m - travel_m,
            c.friction_mu,
        )
        .driven(c.rod_shape, c.drive, r_m, travel_m)
    }

    /// Advance the rod to `travel_mm` over `dt_s` seconds, cutting the step back if needed.
    pub fn step_to(&mut self, travel_mm: f64, dt_s: f64) -> Result<CurvePoint, Error> {
        self.advance(travel_mm * 1e-3, dt_s, 0)?;
        Ok(self.point())
    }

    fn advance(&mut self, target_m: f64, dt_s: f64, depth: usize) -> Result<(), Error> {
        let saved: State = self.solver.state.clone();
        let rod = self.rod_at(target_m);
        let from = self.rod_at(self.travel_m);
        self.solver.begin_step_at(from.face_m, from.lateral_m);
        self.predict(target_m);
        match self.solver.equilibrate(&rod, dt_s) {
            Ok(_) => {
                advance_history(&self.solver.model, &mut self.solver.state, dt_s);
                self.previous = Some((saved.x, saved.p, self.travel_m));
                self.travel_m = target_m;
                self.t_s += dt_s;
                Ok(())
            }
            Err(_) if depth < MAX_CUTBACK_DEPTH => {
                self.solver.state = saved;
                self.previous = None;
                self.solver.stats.cutbacks += 1;
                let mid = 0.5 * (self.travel_m + target_m);
                self.advance(mid, 0.5 * dt_s, depth + 1)?;
                self.advance(target_m, 0.5 * dt_s, depth + 1)
            }
            Err(err) => {
                self.solver.state = saved;
                self.solver.evaluate(&self.rod_at(self.travel_m), 0.0);
                Err(match err {
                    Error::NotConverged { iterations, .. } => Error::NotConverged {
                        iterations,
                        travel_mm: target_m * 1e3,
                        force_n: self.point().force_n,
                    },
                    other => other,
                })
            }
        }
    }

    /// Linear extrapolation of the last converged increment to the new rod position: most of
    /// the step's displacement is then known before Newton starts.
    fn predict(&mut self, target_m: f64) {
        let Some((x_prev, p_prev, travel_prev)) = &self.previous else {
            return;
        };
        let span = self.travel_m - travel_prev;
        if span.abs() < 1e-15 {
            return;
        }
        let ratio = (target_m - self.travel_m) / span;
        if !(0.0..=4.0).contains(&ratio) {
            return;
        }
        let st = &mut self.solver.state;
        for (x, xp) in st.x.iter_mut().zip(x_prev) {
            for d in 0..3 {
                x[d] += ratio * (x[d] - xp[d]);
            }
        }
        for (p, pp) in st.p.iter_mut().zip(p_prev) {
            *p += ratio * (*p - pp);
        }
    }

    /// The outputs at the current (converged) state.
    pub fn point(&self) -> CurvePoint {
        let rod = self.rod_at(self.travel_m);
        let s = &self.solver;
        // At equilibrium the contact force (normal + friction) on a free node equals its
        // internal force, so the rod's push on the gel is the sum over the nodes in contact.
        let mut f = [0.0; 3];
        let mut nodes = 0;
        for &a in &s.surface_nodes {
            if rod.probe(s.state.x[a]).is_some() {
                nodes += 1;
                for d in 0..3 {
                    f[d] += s.asm.node_force[a][d];
                }
            }
        }
        let force = -(0..3).map(|d| f[d] * rod.drive[d]).sum::<f64>();
        let loads: ChipLoads = chip_loads(&s.model, &s.asm.pillar_force);
        CurvePoint {
            t_s: self.t_s,
            rod_mm: self.travel_m * 1e3,
            force_n: force,
            fz_n: loads.fz_n,
            mx_nm: loads.mx_nm,
            my_nm: loads.my_nm,
            contact_nodes: nodes,
        }
    }

    /// Full chip loads at the current state (including the in-plane force).
    pub fn chip_loads(&self) -> ChipLoads {
        chip_loads(&self.solver.model, &self.solver.asm.pillar_force)
    }

    /// Total force the gel applies to the mount (base and whole package) at the current
    /// state, N; at equilibrium it equals the rod's push on the gel.
    pub fn mount_reaction(&self) -> [f64; 3] {
        mount_reaction(&self.solver.model, &self.solver.asm.node_force)
    }

    /// Compress from the current state until the force along the rod reaches `peak_load_n`,
    /// in at least `config.load_steps` steps sized from the local power law of the curve.
    pub fn compress_to_peak(&mut self, peak_load_n: f64) -> Result<Curve, Error> {
        if !(peak_load_n.is_finite() && peak_load_n > 0.0) {
            return Err(Error::InvalidConfig {
                field: "peak_load_n",
                reason: format!("{peak_load_n} must be positive"),
            });
        }
        let t0 = Instant::now();
        let c = self.config.clone();
        let r_m = c.radius_mm * 1e-3;
        let speed = c.rod_speed_mm_per_s * 1e-3;
        let max_travel = MAX_TRAVEL_FRACTION * r_m;
        let mut points = vec![self.point()];
        // First guess of the final travel: Hertz for a sphere on a flat.
        let e_star = c.youngs_modulus_pa / (1.0 - c.poisson * c.poisson);
        let hertz = (3.0 * peak_load_n / (4.0 * e_star * r_m.sqrt())).powf(2.0 / 3.0);
        let mut d_final = hertz.min(0.8 * r_m);
        let n = c.load_steps.max(1);
        let mut step = 0usize;
        loop {
            let last = *points.last().unwrap_or(&CurvePoint::default());
            let done = step as f64;
            let remaining = ((n as f64 - done).max(1.0)).max(1.0);
            let mut target =
                self.travel_m + ((d_final - self.travel_m) / remaining).max(1e-3 * d_final);
            target = target.min(max_travel);
            let dt = (target - self.travel_m) / speed;
            let saved = (self.solver.state.clone(), self.travel_m, self.t_s);
            self.advance(target, dt, 0)?;
            let p = self.point();
            step += 1;
            if p.force_n > peak_load_n * (1.0 + PEAK_TOL) && last.force_n > 0.0 {
                // Overshoot: go back and land on the peak by log-log interpolation.
                let (x0, f0) = (last.rod_mm * 1e-3, last.force_n);
                let (x1, f1) = (target, p.force_n);
                let expo = (f1 / f0).ln() / (x1 / x0).ln();
                let x_peak = x0 * (peak_load_n / f0).powf(1.0 / expo);
                (self.solver.state, self.travel_m, self.t_s) = saved;
                self.previous = None;
                self.advance(x_peak.clamp(x0, x1), (x_peak - x0).max(0.0) / speed, 0)?;
                let q = self.point();
                points.push(q);
                if (q.force_n - peak_load_n).abs() <= peak_load_n * PEAK_TOL * 4.0 || step > 4 * n {
                    break;
                }
                continue;
            }
            points.push(p);
            if p.force_n >= peak_load_n * (1.0 - PEAK_TOL) {
                break;
            }
            if target >= max_travel {
                return Err(Error::PeakNotReached {
                    peak_n: peak_load_n,
                    reached_n: p.force_n,
                    travel_mm: target * 1e3,
                });
            }
            // Re-estimate the final travel from the local power law F ~ d^n.
            if last.force_n > 0.0 && p.force_n > last.force_n {
                let expo = ((p.force_n / last.force_n).ln() / (target / (last.rod_mm * 1e-3)).ln())
                    .clamp(0.8, 4.0);
                d_final = (target * (peak_load_n / p.force_n).powf(1.0 / expo)).min(max_travel);
            } else if p.force_n > 0.0 {
                d_final = (target * (peak_load_n / p.force_n).powf(1.0 / 1.5)).min(max_travel);
            }
        }
        Ok(Curve {
            points,
            quality: self.quality(),
            stats: self.solver.stats,
            setup_s: self.setup_s,
            solve_s: t0.elapsed().as_secs_f64(),
            dofs: self.solver.model.n_dofs,
            factor_nnz: self.solver.ldlt.factor_nnz(),
        })
    }

    /// Follow a prescribed rod-travel history `(t_s, travel_mm)` (e.g. press, hold, fast
    /// return) and record a point after each sample. Meant for the viscoelastic material.
    pub fn follow(&mut self, history: &[(f64, f64)]) -> Result<Vec<CurvePoint>, Error> {
        let mut out = Vec::with_capacity(history.len());
        for &(t, d_mm) in history {
            let dt = t - self.t_s;
            if !(dt.is_finite() && dt >= 0.0 && d_mm.is_finite()) {
                return Err(Error::InvalidConfig {
                    field: "history",
                    reason: format!("time {t} s / travel {d_mm} mm not increasing or not finite"),
                });
            }
            self.advance(d_mm * 1e-3, dt, 0)?;
            out.push(self.point());
        }
        Ok(out)
    }

    /// Write the deformed mesh as legacy VTK.
    pub fn write_vtk(&self, path: &std::path::Path) -> Result<(), Error> {
        let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
        crate::vtk::write(&self.solver.model.mesh, &self.solver.state, &mut f)?;
        Ok(())
    }
}
