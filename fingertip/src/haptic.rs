//! Haptic mode: a condensed contact compliance for 1 kHz updates.
//!
//! Around a converged state with the rod at travel d0, the gel's tangent K (without the
//! contact penalty) relates small load increments to displacements. Condensing it onto the
//! normal dofs of the candidate contact nodes (the Schur complement of everything else) gives
//! the dense Delassus compliance W = N^T K^{-1} N (n_c x n_c, N the rod-normal directions), and
//! the chip loads respond to contact forces through G = T K_Ic K^{-1} N (3 x n_c), read off
//! the same n_c solves (K_Ic: the couplings of the pillar elements into the inclusion's nodes, see [`crate::loads`]). Each update then solves the small complementarity problem
//!
//!   g = g0 - (d - d0) 1 + W (f - f0) + f / k,   f >= 0,  g >= 0,  f g = 0
//!
//! (penalty compliance 1/k as in the full model) by active-set steps on its affine solutions
//! (see [`Haptic::update`]), and returns the rod force and chip loads. It is exact to first
//! order in (d - d0) for the frictionless rod, and treats contact nodes lifting off or
//! touching down.

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

use crate::contact::Rod;
use crate::model::NONE;
use crate::solver::Solver;
use crate::{Error, Fingertip};

/// Gauss–Seidel sweeps per update at most (fallback only).
const MAX_SWEEPS: usize = 200;
/// Active-set changes per update before falling back to Gauss–Seidel.
const MAX_ACTIVE_SET_CHANGES: usize = 8;

/// Precomputed condensed model.
#[derive(Debug, Clone)]
pub struct Haptic {
    /// Compliance along the rod normal, row-major n_c x n_c, m/N.
    w: Vec<f64>,
    /// Chip-load sensitivity to contact forces (Fz, Mx, My) per unit normal force.
    g: [Vec<f64>; 3],
    /// Penalty compliance of each node, m/N.
    inv_k: Vec<f64>,
    /// Gap of each candidate at the base state, m (negative: penetration).
    gap0: Vec<f64>,
    /// Normal force of each node at the base state, N.
    f0: Vec<f64>,
    /// Offset of the linearised penalty law, m: f0 / k - pen0 for nodes in contact, else 0.
    shift: Vec<f64>,
    /// Current normal forces, N (warm start).
    f: Vec<f64>,
    travel0_m: f64,
    loads0: [f64; 3],
    force0_n: f64,
    /// The solution for the current active set, affine in the travel.
    affine: Option<Affine>,
}

/// For a fixed active set A the contact problem is linear in dd = d - d0:
/// f_A = alpha + dd beta (from (W_AA + diag 1/k) f_A = b0 + dd 1), the complementarity
/// function of the inactive nodes is gamma + dd delta, and the outputs are a + dd b. An update
/// is then O(n_c) (a feasibility check); only a change of the active set costs a small dense
/// Cholesky (faer).
#[derive(Debug, Clone)]
struct Affine {
    active: Vec<bool>,
    alpha: Vec<f64>,
    beta: Vec<f64>,
    gamma: Vec<f64>,
    delta: Vec<f64>,
    /// (force, Fz, Mx, My) at dd = 0 and their slopes.
    out_a: [f64; 4],
    out_b: [f64; 4],
}

/// Outputs of one update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HapticSample {
    pub force_n: f64,
    pub fz_n: f64,
    pub mx_nm: f64,
    pub my_nm: f64,
}

impl Haptic {
    /// Condense around the current converged state of `ft`, with candidate nodes within
    /// `margin_mm` of the rod face.
    pub fn new(ft: &mut Fingertip, margin_mm: f64) -> Result<Haptic, Error> {
        let rod = ft.rod_at(ft.travel_mm() * 1e-3);
        let cand = candidate_nodes(&ft.solver, &rod, margin_mm);
        let (w, unit_solutions) = condense(&mut ft.solver, &rod, &cand)?;
        let g = chip_sensitivity(ft, &cand, &unit_solutions)?;
        let s = &mut ft.solver;
        let base = BaseState::new(s, &rod, &cand);
        // Restore the assembled contact state of the full model.
        s.evaluate(&rod, 0.0);
        let inv_k = cand.iter().map(|&a| 1.0 / s.contact_k[a]).collect();
        let p = ft.point();
        let mut h = Haptic {
            w,
            g,
            inv_k,
            gap0: base.gap,
            shift: base.shift,
            f: base.force.clone(),
            f0: base.force,
            travel0_m: ft.travel_mm() * 1e-3,
            loads0: [p.fz_n, p.mx_nm, p.my_nm],
            force0_n: p.force_n,
            affine: None,
        };
        let active: Vec<bool> = h.f0.iter().map(|&f| f > 0.0).collect();
        h.affine = h.affine_solution(active);
        Ok(h)
    }

    /// Number of condensed contact dofs.
    pub fn len(&self) -> usize {
        self.f.len()
    }

    pub fn is_empty(&self) -> bool {
        self.f.is_empty()
    }

    /// Rod force and chip loads with the rod at `travel_mm`.
    ///
    /// With the penetration pen_i = -gap0_i + (d - d0) - sum_j W_ij (f_j - f0_j), the penalty
    /// law (linearised through the base state, shift s_i) is the complementarity
    /// h_i = f_i / k_i - pen_i - s_i >= 0, f_i >= 0, f_i h_i = 0. It is solved by active-set
    /// steps on the affine solutions; projected Gauss–Seidel is the fallback if they cycle.
    pub fn update(&mut self, travel_mm: f64) -> HapticSample {
        let dd = travel_mm * 1e-3 - self.travel0_m;
        for _ in 0..MAX_ACTIVE_SET_CHANGES {
            let Some(aff) = &self.affine else { break };
            let mut next = aff.active.clone();
            let mut feasible = true;
            for i in 0..next.len() {
                if aff.active[i] && aff.alpha[i] + dd * aff.beta[i] < 0.0 {
                    next[i] = false;
                    feasible = false;
                } else if !aff.active[i] && aff.gamma[i] + dd * aff.delta[i] < 0.0 {
                    next[i] = true;
                    feasible = false;
                }
            }
            if feasible {
                let o: Vec<f64> = (0..4).map(|k| aff.out_a[k] + dd * aff.out_b[k]).collect();
                return HapticSample {
                    force_n: o[0],
                    fz_n: o[1],
                    mx_nm: o[2],
                    my_nm: o[3],
                };
            }
            self.affine = self.affine_solution(next);
        }
        self.projected_gauss_seidel(dd)
    }

    /// The affine solution for active set `active` (None if the set is empty-degenerate).
    fn affine_solution(&self, active: Vec<bool>) -> Option<Affine> {
        let nc = self.f0.len();
        let idx: Vec<usize> = (0..nc).filter(|&i| active[i]).collect();
        let na = idx.len();
        let mut alpha = vec![0.0; nc];
        let mut beta = vec![0.0; nc];
        if na > 0 {
            let m = Mat::from_fn(na, na, |r, c| {
                self.w[idx[r] * nc + idx[c]] + if r == c { self.inv_k[idx[r]] } else { 0.0 }
            });
            let llt = m.llt(Side::Lower).ok()?;
            let rhs = Mat::from_fn(na, 2, |r, c| {
                let i = idx[r];
                if c == 1 {
                    1.0
                } else {
                    let wf0: f64 = (0..nc).map(|j| self.w[i * nc + j] * self.f0[j]).sum();
                    -self.gap0[i] + self.shift[i] + wf0
                }
            });
            let x = llt.solve(&rhs);
            for (r, &i) in idx.iter().enumerate() {
                alpha[i] = x[(r, 0)];
                beta[i] = x[(r, 1)];
            }
        }
        let mut gamma = vec![0.0; nc];
        let mut delta = vec![0.0; nc];
        for i in (0..nc).filter(|&i| !active[i]) {
            let row = &self.w[i * nc..(i + 1) * nc];
            let wa: f64 = idx.iter().map(|&j| row[j] * alpha[j]).sum();
            let wb: f64 = idx.iter().map(|&j| row[j] * beta[j]).sum();
            let wf0: f64 = row.iter().zip(&self.f0).map(|(w, f)| w * f).sum();
            gamma[i] = self.gap0[i] + wa - wf0 - self.shift[i];
            delta[i] = -1.0 + wb;
        }
        let sum0: f64 = self.f0.iter().sum();
        let mut out_a = [
            self.force0_n + alpha.iter().sum::<f64>() - sum0,
            0.0,
            0.0,
            0.0,
        ];
        let mut out_b = [beta.iter().sum::<f64>(), 0.0, 0.0, 0.0];
        for k in 0..3 {
            let g = &self.g[k];
            out_a[k + 1] =
                self.loads0[k] + (0..nc).map(|j| g[j] * (alpha[j] - self.f0[j])).sum::<f64>();
            out_b[k + 1] = (0..nc).map(|j| g[j] * beta[j]).sum();
        }
        Some(Affine {
            active,
            alpha,
            beta,
            gamma,
            delta,
            out_a,
            out_b,
        })
    }

    /// Coordinate-wise solution of the complementarity problem (robust fallback).
    fn projected_gauss_seidel(&mut self, dd: f64) -> HapticSample {
        let nc = self.f.len();
        let tol = 1e-9 * (1.0 + self.force0_n);
        for _ in 0..MAX_SWEEPS {
            let mut change: f64 = 0.0;
            for i in 0..nc {
                let row = &self.w[i * nc..(i + 1) * nc];
                let coupling: f64 = row
                    .iter()
                    .zip(self.f.iter().zip(&self.f0))
                    .map(|(w, (f, f0))| w * (f - f0))
                    .sum();
                let h = self.f[i] * self.inv_k[i] + self.gap0[i] - dd + coupling - self.shift[i];
                let new = (self.f[i] - h / (row[i] + self.inv_k[i])).max(0.0);
                change = change.max((new - self.f[i]).abs());
                self.f[i] = new;
            }
            if change < tol {
                break;
            }
        }
        let df: f64 = self.f.iter().zip(&self.f0).map(|(f, f0)| f - f0).sum();
        let mut loads = self.loads0;
        for (k, l) in loads.iter_mut().enumerate() {
            *l += self.g[k]
                .iter()
                .zip(self.f.iter().zip(&self.f0))
                .map(|(g, (f, f0))| g * (f - f0))
                .sum::<f64>();
        }
        HapticSample {
            force_n: self.force0_n + df,
            fz_n: loads[0],
            mx_nm: loads[1],
            my_nm: loads[2],
        }
    }
}

/// G = T K_Ic K^{-1} N: chip loads per unit normal contact force at each candidate, from the
/// displacement fields already solved (one per candidate).
fn chip_sensitivity(
    ft: &Fingertip,
    cand: &[usize],
    fields: &[f64],
) -> Result<[Vec<f64>; 3], Error> {
    let s = &ft.solver;
    let model = &s.model;
    let n = model.n_dofs;
    let touching: Vec<(usize, Vec<f64>)> = (0..model.gel.len())
        .filter(|&k| model.pillar[k])
        .map(|k| (k, crate::assembly::element_tangent(model, &s.state, k)))
        .collect();
    let mut g = [
        vec![0.0; cand.len()],
        vec![0.0; cand.len()],
        vec![0.0; cand.len()],
    ];
    for j in 0..cand.len() {
        let du = &fields[j * n..(j + 1) * n];
        let mut load = [0.0; 3];
        for (k, kmat) in &touching {
            element_reaction(model, *k, kmat, du, &mut load);
        }
        for c in 0..3 {
            g[c][j] = load[c];
        }
    }
    Ok(g)
}

/// Add the (Fz, Mx, My) on the inclusion produced by displacement increment `du` through
/// element `k`'s tangent.
fn element_reaction(
    model: &crate::model::Model,
    k: usize,
    kmat: &[f64],
    du: &[f64],
    load: &mut [f64; 3],
) {
    let nodes = model.mesh.tets[model.gel[k]];
    let dofs = model.element_dofs(k);
    for (a, &node) in nodes.iter().enumerate() {
        if !model.mesh.in_inclusion[node] {
            continue;
        }
        let x = model.mesh.nodes[node];
        let mut r = [0.0; 3];
        for (i, ri) in r.iter_mut().enumerate() {
            let row = 4 * a + i;
            for (l, &d) in dofs.iter().enumerate() {
                if d != NONE {
                    *ri += kmat[row * 16 + l] * du[d as usize];
                }
            }
        }
        // Gel load on the chip is minus the reaction increment.
        let f = r.map(|v| -v);
        load[0] += f[2];
        load[1] += x[1] * f[2] - x[2] * f[1];
        load[2] += x[2] * f[0] - x[0] * f[2];
    }
}

/// Surface nodes under the rod face, within `margin_mm` of it: the ones that may touch.
fn candidate_nodes(s: &Solver, rod: &Rod, margin_mm: f64) -> Vec<usize> {
    let e = rod.axis;
    let radius = rod.radius_m;
    let mut cand = Vec::new();
    for &a in &s.surface_nodes {
        let x = s.state.x[a];
        let along = x[0] * e[0] + x[1] * e[1] + x[2] * e[2];
        let rho2 = (0..3).map(|d| (x[d] - along * e[d]).powi(2)).sum::<f64>();
        if along > rod.face_m - margin_mm * 1e-3 && rho2 < radius * radius {
            cand.push(a);
        }
    }
    cand
}

/// The Delassus compliance W (n_c x n_c, row-major) of the gel tangent without contact, and the
/// n_c unit-force solutions K^{-1} N it was read from (column j: unit normal force at `cand[j]`).
fn condense(s: &mut Solver, rod: &Rod, cand: &[usize]) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let e = rod.axis;
    let rod_away = Rod {
        face_m: f64::INFINITY,
        ..*rod
    };
    s.evaluate(&rod_away, 0.0);
    s.ldlt.factorize(&s.asm.values)?;
    let model = &s.model;
    let n = model.n_dofs;
    let nc = cand.len();
    let mut rhs = vec![0.0; n * nc];
    for (j, &a) in cand.iter().enumerate() {
        for d in 0..3 {
            // Force -e (the rod pushes the gel) per unit normal force.
            rhs[j * n + model.dof_x[a][d] as usize] = -e[d];
        }
    }
    s.ldlt.solve_in_place(&mut rhs, nc);
    let mut w = vec![0.0; nc * nc];
    for i in 0..nc {
        for (j, &a) in cand.iter().enumerate() {
            // Displacement of node a along -e (closing the gap) due to unit force at i.
            w[j * nc + i] = -(0..3)
                .map(|d| rhs[i * n + model.dof_x[a][d] as usize] * e[d])
                .sum::<f64>();
        }
    }
    Ok((w, rhs))
}

/// Each candidate's gap, penalty force and penalty-line shift at the converged state.
struct BaseState {
    gap: Vec<f64>,
    force: Vec<f64>,
    shift: Vec<f64>,
}

impl BaseState {
    fn new(s: &Solver, rod: &Rod, cand: &[usize]) -> Self {
        let e = rod.axis;
        let nc = cand.len();
        let (mut gap, mut force, mut shift) = (
            Vec::with_capacity(nc),
            Vec::with_capacity(nc),
            Vec::with_capacity(nc),
        );
        for &a in cand {
            let x = s.state.x[a];
            let along = x[0] * e[0] + x[1] * e[1] + x[2] * e[2];
            let pen = along - rod.face_m;
            let f = if pen > 0.0 {
                crate::contact::normal_law(pen, s.contact_k[a], s.contact_ramp[a]).0
            } else {
                0.0
            };
            gap.push(-pen);
            force.push(f);
            // Nodes in contact follow the penalty line through their base state.
            shift.push(if f > 0.0 {
                f / s.contact_k[a] - pen
            } else {
                0.0
            });
        }
        Self { gap, force, shift }
    }
}
