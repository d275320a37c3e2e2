//! Quasi-static equilibrium at a given rod position: Newton's method on the mixed u–p
//! potential plus contact, with a backtracking line search on a scaled residual norm and an
//! inversion guard. The caller (`stepping`) cuts the load step back when Newton fails.

use std::time::Instant;

use crate::assembly::{assemble, Assembled, State};
use crate::contact::{node_response, Rod, PENALTY, RAMP_FRACTION};
use crate::linsolve::{Ldlt, Precision};
use crate::model::{Model, NONE};
use crate::Error;

/// Iterations before a step is declared failed (and cut back).
const MAX_NEWTON: usize = 40;
/// Smallest line-search step (six halvings).
const MIN_ALPHA: f64 = 1.0 / 64.0;
/// Relative residual of the GMRES solves (inexact Newton). After a step with forcing eta the
/// scaled residual is about eta |r| + C |r|^2 (C |r| ~ 1e-2 here). The forcing is
/// GMRES_FORCING |r| (tight enough to keep the quadratic rate), at most GMRES_RTOL_MAX, but
/// never tighter than needed to land at half the convergence tolerance: solving the last
/// systems to 1e-8 when 1e-2 suffices was most of the GMRES work.
const GMRES_FORCING: f64 = 0.1;
const GMRES_RTOL_MIN: f64 = 1e-8;
const GMRES_RTOL_MAX: f64 = 1e-3;
/// The largest forcing allowed when the convergence tolerance takes over.
const GMRES_RTOL_LOOSE: f64 = 0.1;

/// GMRES tolerance for a Newton system with scaled residual norm `merit`.
fn forcing(merit: f64) -> f64 {
    let rate = (GMRES_FORCING * merit).clamp(GMRES_RTOL_MIN, GMRES_RTOL_MAX);
    let enough = 0.5 * FORCE_TOL.min(VOLUME_TOL) / merit;
    rate.max(enough.min(GMRES_RTOL_LOOSE))
}
/// GMRES iterations before giving up on the kept factor for this system.
const GMRES_MAX: usize = 20;
/// A kept factor that needed more GMRES iterations than this is refreshed for the next
/// system. Measured on the 10^4-tetrahedron curve (perf): a single-precision factorisation
/// (compute-bound dense kernels, parallel) costs about 7 GMRES iterations (memory-bound
/// triangular solves), a fresh factor needs 1 iteration, and a stale one needs more with
/// every Newton iteration it ages: refreshing after 3/5/10 iterations cost 27/20/12
/// factorisations + 294/397/573 GMRES iterations, i.e. 490/540/660 iteration-equivalents.
const GMRES_REFRESH: usize = 4;
/// The same threshold when the refresh runs on a background thread: it costs the Newton loop
/// nothing but arrives an iteration or two late, so it is started earlier. On the 60 N curve
/// (2 cores) thresholds 1–4 gave 493–544 GMRES iterations and 30–43 factorisations, and the
/// wall time 5.1–5.9 s against 5.8 s for the synchronous refresh in the same minutes: the
/// factorisations (1.6–1.7 s) leave the critical path, GMRES gains ~1 s of it back.
const BACKGROUND_REFRESH: usize = 2;
/// Force tolerance, in units of E R^2 (60 N at 0.15 MPa is 1 E R^2).
const FORCE_TOL: f64 = 1e-6;
/// Relative volume tolerance of the nodal constraint.
const VOLUME_TOL: f64 = 1e-6;

/// When the tangent is refactored for the next Newton direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refresh {
    /// Keep the held factor.
    Keep,
    /// Factor the current tangent on another thread; keep using the held factor meanwhile.
    Background,
    /// Factor the current tangent before solving.
    Now,
}

/// Counters and wall times.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    pub newton_iterations: usize,
    pub factorizations: usize,
    /// Of those, factorisations done on a background thread (not in `factor_s`).
    pub background_factorizations: usize,
    /// GMRES iterations (each one triangular solve with a kept factor).
    pub krylov_iterations: usize,
    pub cutbacks: usize,
    pub assembly_s: f64,
    pub factor_s: f64,
    pub solve_s: f64,
}

/// The nonlinear solver with its reusable symbolic factorisation.
#[derive(Debug)]
pub struct Solver {
    pub model: Model,
    pub state: State,
    /// Penalty stiffness of each surface node, N/m (0 elsewhere).
    pub contact_k: Vec<f64>,
    /// Onset length of the smoothed penalty of each surface node, m.
    pub contact_ramp: Vec<f64>,
    pub surface_nodes: Vec<usize>,
    /// Weight of each dof's residual in the scaled norm: 1 / (E R^2) on forces, 1 / V_a on
    /// the volume constraints.
    residual_weight: Vec<f64>,
    pub ldlt: Ldlt,
    pub asm: Assembled,
    /// Per-thread accumulators of the assembly.
    parts: Vec<crate::assembly::Partial>,
    /// Positions at the start of the step (the friction slip is measured from there).
    step_start: Vec<[f64; 3]>,
    /// Rod face position at the start of the step, m.
    step_face_m: f64,
    /// Rod displacement across its axis at the start of the step, m.
    step_lateral_m: [f64; 3],
    pub stats: Stats,
    /// Factor every Newton system (no Krylov reuse), for comparisons (`FINGERTIP_DIRECT=1`).
    pub direct_only: bool,
    /// Refresh the preconditioner on a background thread (off: `FINGERTIP_SYNC_REFRESH=1`).
    pub background_refresh: bool,
}

/// Totals of the contact forces at one state.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactTotals {
    /// Force the rod applies to the gel, N.
    pub force: [f64; 3],
    /// Number of nodes in contact.
    pub nodes: usize,
}

impl Solver {
    pub fn new(model: Model, youngs_modulus_pa: f64) -> Result<Solver, Error> {
        let area = model.mesh.surface_node_areas();
        let contact_k: Vec<f64> = area
            .iter()
            .map(|&a| {
                if a > 0.0 {
                    PENALTY * youngs_modulus_pa * a.sqrt()
                } else {
                    0.0
                }
            })
            .collect();
        let contact_ramp: Vec<f64> = area.iter().map(|&a| RAMP_FRACTION * a.sqrt()).collect();
        let surface_nodes = (0..area.len())
            .filter(|&a| area[a] > 0.0 && model.dof_x[a][0] != NONE)
            .collect();
        let mut owner = vec![0usize; model.n_dofs];
        for a in 0..model.mesh.nodes.len() {
            for d in model.dof_x[a]
                .into_iter()
                .chain([model.dof_p[a]])
                .filter(|&d| d != NONE)
            {
                owner[d as usize] = a;
            }
        }
        // AMD on the node graph, each node's dofs kept together: 9 % less fill than AMD on
        // the dofs (5.0 M against 5.5 M entries on the 13,536-tet curve; a geometric nested
        // dissection gave the same 5.0 M).
        let perm = crate::linsolve::blocked_amd(
            &model.col_ptr,
            &model.row_idx,
            &owner,
            model.mesh.nodes.len(),
        )?;
        let ldlt = Ldlt::new(model.n_dofs, &model.col_ptr, &model.row_idx, Some(&perm))?;
        let f_scale = youngs_modulus_pa * model.mesh.radius_m * model.mesh.radius_m;
        let mut residual_weight = vec![0.0; model.n_dofs];
        for a in 0..model.mesh.nodes.len() {
            for d in model.dof_x[a].into_iter().filter(|&d| d != NONE) {
                residual_weight[d as usize] = 1.0 / f_scale;
            }
            if model.dof_p[a] != NONE {
                residual_weight[model.dof_p[a] as usize] = 1.0 / model.node_volume[a];
            }
        }
        let state = State::reference(&model);
        let step_start = state.x.clone();
        let asm = Assembled {
            residual: Vec::new(),
            node_force: Vec::new(),
            pillar_force: Vec::new(),
            values: Vec::new(),
            min_j: 1.0,
        };
        Ok(Solver {
            model,
            state,
            contact_k,
            contact_ramp,
            surface_nodes,
            residual_weight,
            ldlt,
            asm,
            parts: Vec::new(),
            step_start,
            step_face_m: 0.0,
            step_lateral_m: [0.0; 3],
            stats: Stats::default(),
            direct_only: std::env::var_os("FINGERTIP_DIRECT").is_some(),
            background_refresh: std::env::var_os("FINGERTIP_SYNC_REFRESH").is_none(),
        })
    }

    /// Mark the current state as the start of a load step with the rod face at `face_m`.
    pub fn begin_step(&mut self, face_m: f64) {
        self.begin_step_at(face_m, [0.0; 3]);
    }

    /// As [`Solver::begin_step`], for a rod also displaced across its axis by `lateral_m`.
    pub fn begin_step_at(&mut self, face_m: f64, lateral_m: [f64; 3]) {
        self.step_start.clone_from(&self.state.x);
        self.step_face_m = face_m;
        self.step_lateral_m = lateral_m;
    }

    /// Residual and tangent at the current state with the rod at `rod`.
    pub fn evaluate(&mut self, rod: &Rod, dt_s: f64) -> ContactTotals {
        let t0 = Instant::now();
        assemble(
            &self.model,
            &self.state,
            dt_s,
            &mut self.asm,
            &mut self.parts,
        );
        let totals = self.add_contact(rod);
        self.stats.assembly_s += t0.elapsed().as_secs_f64();
        totals
    }

    fn add_contact(&mut self, rod: &Rod) -> ContactTotals {
        let mut totals = ContactTotals::default();
        for &a in &self.surface_nodes {
            let Some(c) = rod.probe(self.state.x[a]) else {
                continue;
            };
            // Slip relative to the rod since the step began.
            let rod_move = rod.displacement_from(self.step_face_m, self.step_lateral_m);
            let slip = [0, 1, 2].map(|d| self.state.x[a][d] - self.step_start[a][d] - rod_move[d]);
            let (f, kt) = node_response(&c, self.contact_k[a], self.contact_ramp[a], slip, rod);
            let dofs = self.model.dof_x[a];
            for i in 0..3 {
                totals.force[i] += f[i];
                self.asm.residual[dofs[i] as usize] -= f[i];
                for j in i..3 {
                    if let Some(s) = self.model.slot(dofs[i], dofs[j]) {
                        self.asm.values[s] += kt[i][j];
                    }
                }
            }
            totals.nodes += 1;
        }
        totals
    }

    /// Scaled residual norm (`residual_weight`), and whether every scaled force is below
    /// FORCE_TOL and every scaled volume residual below VOLUME_TOL.
    fn merit(&self) -> (f64, bool) {
        let m = &self.model;
        let w = &self.residual_weight;
        let r = &self.asm.residual;
        let (mut sum, mut fmax, mut vmax) = (0.0, 0.0f64, 0.0f64);
        for a in 0..m.mesh.nodes.len() {
            for d in m.dof_x[a].into_iter().filter(|&d| d != NONE) {
                let v = r[d as usize] * w[d as usize];
                sum += v * v;
                fmax = fmax.max(v.abs());
            }
            let d = m.dof_p[a];
            if d != NONE {
                let v = r[d as usize] * w[d as usize];
                sum += v * v;
                vmax = vmax.max(v.abs());
            }
        }
        (sum.sqrt(), fmax < FORCE_TOL && vmax < VOLUME_TOL)
    }

    fn apply(&mut self, delta: &[f64], alpha: f64) {
        let m = &self.model;
        for a in 0..m.mesh.nodes.len() {
            for d in 0..3 {
                let k = m.dof_x[a][d];
                if k != NONE {
                    self.state.x[a][d] += alpha * delta[k as usize];
                }
            }
            let k = m.dof_p[a];
            if k != NONE {
                self.state.p[a] += alpha * delta[k as usize];
            }
        }
    }

    /// Newton to equilibrium with the rod at `rod`. On failure the state is left wherever it
    /// got to; the caller restores its copy.
    ///
    /// A factorisation costs about 7 preconditioned GMRES iterations, so the Newton systems
    /// are solved by GMRES preconditioned with the last single-precision factor, kept across
    /// iterations and load steps ([`crate::krylov`]), to the inexact-Newton tolerance
    /// `forcing`; the tangent is refactored when the kept factor needed more than
    /// BACKGROUND_REFRESH iterations (on a background thread, adopted when done; or
    /// GMRES_REFRESH and at once with `background_refresh` off), and at once when GMRES stalls
    /// or when its direction fails the line search.
    pub fn equilibrate(&mut self, rod: &Rod, dt_s: f64) -> Result<ContactTotals, Error> {
        let mut totals = self.evaluate(rod, dt_s);
        let mut delta = vec![0.0; self.model.n_dofs];
        let mut rhs = vec![0.0; self.model.n_dofs];
        let mut refresh = if self.ldlt.is_factored() {
            Refresh::Keep
        } else {
            Refresh::Now
        };
        let trace = std::env::var_os("FINGERTIP_TRACE").is_some();
        for it in 0..MAX_NEWTON {
            let (merit, converged) = self.merit();
            if trace {
                eprintln!(
                    "newton it {it} face {:.6e} merit {merit:.3e} minJ {:.4} contact {}",
                    rod.face_m, self.asm.min_j, totals.nodes
                );
            }
            if converged && it > 0 {
                return Ok(totals);
            }
            for (d, r) in rhs.iter_mut().zip(&self.asm.residual) {
                *d = -r;
            }
            let rtol = forcing(merit);
            let (fresh, krylov) = self.newton_direction(&rhs, &mut delta, refresh, rtol)?;
            if trace {
                eprintln!("  direction: fresh factor {fresh}, GMRES iterations {krylov}");
            }
            self.stats.newton_iterations += 1;
            match self.line_search(&delta, merit, rod, dt_s) {
                Some((t, _)) => {
                    totals = t;
                    refresh = match self.background_refresh {
                        true if krylov > BACKGROUND_REFRESH => Refresh::Background,
                        false if krylov > GMRES_REFRESH => Refresh::Now,
                        _ => Refresh::Keep,
                    };
                }
                None if !fresh => refresh = Refresh::Now,
                None => {
                    // Fresh Newton direction failed: accept the smallest step if elements stay
                    // valid, Newton may need to climb out of a non-monotone merit region.
                    self.apply(&delta, MIN_ALPHA);
                    totals = self.evaluate(rod, dt_s);
                    if self.asm.min_j <= 0.0 {
                        return Err(Error::NotConverged {
                            iterations: it + 1,
                            travel_mm: 0.0,
                            force_n: 0.0,
                        });
                    }
                    refresh = Refresh::Now;
                }
            }
        }
        Err(Error::NotConverged {
            iterations: MAX_NEWTON,
            travel_mm: 0.0,
            force_n: 0.0,
        })
    }

    /// Solve K delta = rhs by GMRES preconditioned with the kept single-precision factor,
    /// refactoring first when asked or when GMRES stalls on a stale factor; a double factor
    /// (exact solve) is the last resort, and the only path with `direct_only`. Returns whether
    /// the direction was computed with a factor of this very tangent, and the GMRES iterations.
    fn newton_direction(
        &mut self,
        rhs: &[f64],
        delta: &mut [f64],
        refresh: Refresh,
        rtol: f64,
    ) -> Result<(bool, usize), Error> {
        if !self.direct_only {
            let mut fresh = false;
            if refresh == Refresh::Now || self.ldlt.precision() != Some(Precision::Single) {
                self.factor_single()?;
                fresh = true;
            } else {
                if self.ldlt.adopt_background() {
                    self.stats.factorizations += 1;
                    self.stats.background_factorizations += 1;
                }
                if refresh == Refresh::Background {
                    self.ldlt.factorize_single_in_background(&self.asm.values)?;
                }
            }
            if let Some(k) = self.gmres(rhs, delta, rtol) {
                return Ok((fresh, k));
            }
            if !fresh {
                self.factor_single()?;
                if let Some(k) = self.gmres(rhs, delta, rtol) {
                    return Ok((true, k));
                }
            }
        }
        let t0 = Instant::now();
        self.ldlt.factorize(&self.asm.values)?;
        self.stats.factor_s += t0.elapsed().as_secs_f64();
        self.stats.factorizations += 1;
        let t2 = Instant::now();
        delta.copy_from_slice(rhs);
        self.ldlt.solve_in_place(delta, 1);
        self.stats.solve_s += t2.elapsed().as_secs_f64();
        Ok((true, 0))
    }

    fn factor_single(&mut self) -> Result<(), Error> {
        let t0 = Instant::now();
        self.ldlt.factorize_single(&self.asm.values)?;
        self.stats.factor_s += t0.elapsed().as_secs_f64();
        self.stats.factorizations += 1;
        Ok(())
    }

    fn gmres(&mut self, rhs: &[f64], delta: &mut [f64], rtol: f64) -> Option<usize> {
        let t1 = Instant::now();
        let m = &self.model;
        let its = crate::krylov::gmres(
            &m.col_ptr,
            &m.row_idx,
            &self.asm.values,
            &mut self.ldlt,
            &self.residual_weight,
            rhs,
            delta,
            rtol,
            GMRES_MAX,
        );
        self.stats.solve_s += t1.elapsed().as_secs_f64();
        self.stats.krylov_iterations += its.unwrap_or(GMRES_MAX);
        its
    }

    /// Backtracking (halving) on the scaled residual norm with an inversion guard. Returns the
    /// contact totals and the new merit, or None with the state unchanged.
    fn line_search(
        &mut self,
        delta: &[f64],
        merit: f64,
        rod: &Rod,
        dt_s: f64,
    ) -> Option<(ContactTotals, f64)> {
        let mut alpha = 1.0;
        while alpha >= MIN_ALPHA {
            self.apply(delta, alpha);
            let totals = self.evaluate(rod, dt_s);
            let (trial, _) = self.merit();
            if self.asm.min_j > 0.0 && trial < (1.0 - 1e-4 * alpha) * merit {
                return Some((totals, trial));
            }
            self.apply(delta, -alpha);
            alpha *= 0.5;
        }
        self.evaluate(rod, dt_s);
        None
    }
}
