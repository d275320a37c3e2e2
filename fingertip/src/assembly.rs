//! Element residuals and tangents of the mixed u–p potential (see `material`), assembled in
//! parallel over elements (rayon) and scattered into the fixed CSC pattern.

use rayon::prelude::*;

use crate::material::{deviatoric, volume_measure, Kinematics, Mat3};
use crate::model::{Model, LOCAL, NONE};
use crate::viscoelastic::{self, ElementHistory};

/// The unknowns: current node positions and nodal pressures, plus viscoelastic history.
#[derive(Debug, Clone)]
pub struct State {
    /// Current positions, m.
    pub x: Vec<[f64; 3]>,
    /// Nodal pressures, Pa.
    pub p: Vec<f64>,
    /// Per gel element (empty when elastic).
    pub history: Vec<ElementHistory>,
}

impl State {
    pub fn reference(model: &Model) -> State {
        let history = if model.material.prony.is_empty() {
            Vec::new()
        } else {
            vec![ElementHistory::default(); model.gel.len()]
        };
        State {
            x: model.mesh.nodes.clone(),
            p: vec![0.0; model.mesh.nodes.len()],
            history,
        }
    }
}

/// Global internal-force vector and tangent.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// d Pi / d(dofs) for the free dofs.
    pub residual: Vec<f64>,
    /// Internal force at every node (fixed ones too: their reactions), N.
    pub node_force: Vec<[f64; 3]>,
    /// The share of `node_force` at the inclusion's nodes from the pillar elements
    /// ([`Model::pillar`]), N; zero elsewhere.
    pub pillar_force: Vec<[f64; 3]>,
    /// Tangent values in the model's CSC pattern (upper triangle).
    pub values: Vec<f64>,
    /// Smallest element volume ratio J (<= 0 means an inverted element).
    pub min_j: f64,
}

/// Deformation gradient F_iJ = sum_a x_ai dN_a/dX_J.
pub fn deformation_gradient(x: [[f64; 3]; 4], g: &[[f64; 3]; 4]) -> Mat3 {
    let mut f = [[0.0; 3]; 3];
    for a in 0..4 {
        for i in 0..3 {
            for j in 0..3 {
                f[i][j] += x[a][i] * g[a][j];
            }
        }
    }
    f
}

/// Element force (16) and tangent (16x16), plus its J.
fn element(model: &Model, state: &State, k: usize, dt_s: f64, out: &mut [f64]) -> f64 {
    let mat = &model.material;
    let nodes = model.mesh.tets[model.gel[k]];
    let g = &model.grads[k];
    let v = model.volume[k];
    let f = deformation_gradient(nodes.map(|a| state.x[a]), g);
    let (_, mut p, mut a) = match state.history.get(k) {
        Some(_) => deviatoric(
            mat.kinematics,
            mat.mu_pa / viscoelastic::g_inf(&mat.prony),
            &f,
        ),
        None => deviatoric(mat.kinematics, mat.mu_pa, &f),
    };
    if let Some(hist) = state.history.get(k) {
        let (beta, q) = viscoelastic::step_coefficients(&mat.prony, hist, dt_s);
        let fk = if mat.kinematics == Kinematics::Linear {
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        } else {
            f
        };
        viscoelastic::apply(&fk, beta, &q, &mut p, &mut a);
    }
    let vm = volume_measure(mat.kinematics, &f);
    let pbar = nodes.iter().map(|&n| state.p[n]).sum::<f64>() / 4.0;
    if let Some(d2j) = &vm.d2j {
        for r in 0..9 {
            for c in 0..9 {
                a[r][c] += pbar * d2j[r][c];
            }
        }
    }
    let (force, kmat) = out.split_at_mut(LOCAL);
    force.fill(0.0);
    kmat.fill(0.0);
    for an in 0..4 {
        for i in 0..3 {
            let mut s = 0.0;
            for jj in 0..3 {
                s += (p[i][jj] + pbar * vm.dj[i][jj]) * g[an][jj];
            }
            force[4 * an + i] = v * s;
        }
        force[4 * an + 3] = v * (vm.j - 1.0) / 4.0;
    }
    // AG[iJ][b k] = sum_L A[iJ][kL] G[b][L]
    let mut ag = [[0.0; 12]; 9];
    for r in 0..9 {
        for b in 0..4 {
            for kk in 0..3 {
                ag[r][3 * b + kk] = (0..3).map(|l| a[r][3 * kk + l] * g[b][l]).sum();
            }
        }
    }
    // A has the major symmetry A[iJ][kL] = A[kL][iJ], so the displacement block is symmetric:
    // compute the node blocks b >= a and mirror them.
    for an in 0..4 {
        for i in 0..3 {
            let row = 4 * an + i;
            for b in an..4 {
                for kk in 0..3 {
                    let s: f64 = (0..3)
                        .map(|jj| g[an][jj] * ag[3 * i + jj][3 * b + kk])
                        .sum();
                    kmat[row * LOCAL + 4 * b + kk] = v * s;
                    kmat[(4 * b + kk) * LOCAL + row] = v * s;
                }
            }
            // d2 Pi / dx_ai dp_b = (1/4) dv_e/dx_ai, the same for every b
            let bxp = v / 4.0 * (0..3).map(|jj| vm.dj[i][jj] * g[an][jj]).sum::<f64>();
            for b in 0..4 {
                kmat[row * LOCAL + 4 * b + 3] = bxp;
                kmat[(4 * b + 3) * LOCAL + row] = bxp;
            }
        }
    }
    vm.j
}

/// The 16x16 tangent of gel element `k` (row-major, local dofs x, y, z, p per node).
pub fn element_tangent(model: &Model, state: &State, k: usize) -> Vec<f64> {
    let mut out = vec![0.0; LOCAL + LOCAL * LOCAL];
    element(model, state, k, 0.0, &mut out);
    out.split_off(LOCAL)
}

/// One thread's share of an assembly: its elements' sums, in global layout.
#[derive(Debug, Clone, Default)]
pub struct Partial {
    residual: Vec<f64>,
    node_force: Vec<[f64; 3]>,
    pillar_force: Vec<[f64; 3]>,
    values: Vec<f64>,
    min_j: f64,
}

impl Partial {
    fn reset(&mut self, model: &Model) {
        let n = model.mesh.nodes.len();
        for (v, len) in [
            (&mut self.residual, model.n_dofs),
            (&mut self.values, model.row_idx.len()),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
        for v in [&mut self.node_force, &mut self.pillar_force] {
            v.clear();
            v.resize(n, [0.0; 3]);
        }
        self.min_j = f64::INFINITY;
    }

    /// Element `k` computed and scattered at once: nothing per element is stored (a stored
    /// 16 + 16x16 block per element was 30 MB of memory traffic per assembly).
    fn add_element(&mut self, model: &Model, state: &State, k: usize, dt_s: f64, buf: &mut [f64]) {
        self.min_j = self.min_j.min(element(model, state, k, dt_s, buf));
        let (force, kmat) = buf.split_at(LOCAL);
        let nodes = model.mesh.tets[model.gel[k]];
        let dofs = model.element_dofs(k);
        let pillar = model.pillar[k];
        for (l, &d) in dofs.iter().enumerate() {
            if l % 4 < 3 {
                let node = nodes[l / 4];
                self.node_force[node][l % 4] += force[l];
                if pillar && model.mesh.in_inclusion[node] {
                    self.pillar_force[node][l % 4] += force[l];
                }
            }
            if d != NONE {
                self.residual[d as usize] += force[l];
            }
        }
        for (s, kv) in model.slots[k].iter().zip(kmat) {
            if *s != NONE {
                self.values[*s as usize] += kv;
            }
        }
    }
}

/// Assemble residual and tangent at `state`. `dt_s` is the step length for viscoelasticity.
///
/// The elements are split into one contiguous range per thread; each thread computes and
/// scatters its range into its own [`Partial`] (no locking, no colouring), and the partial
/// sums are added, in thread order so that a run is reproducible.
pub fn assemble(
    model: &Model,
    state: &State,
    dt_s: f64,
    out: &mut Assembled,
    parts: &mut Vec<Partial>,
) {
    let threads = rayon::current_num_threads().max(1);
    parts.resize_with(threads, Partial::default);
    let per = model.gel.len().div_ceil(threads);
    parts.par_iter_mut().enumerate().for_each(|(t, part)| {
        part.reset(model);
        let mut buf = [0.0; LOCAL + LOCAL * LOCAL];
        for k in (t * per)..((t + 1) * per).min(model.gel.len()) {
            part.add_element(model, state, k, dt_s, &mut buf);
        }
    });
    let (first, rest) = parts.split_first().expect("at least one thread");
    out.residual.clone_from(&first.residual);
    out.node_force.clone_from(&first.node_force);
    out.pillar_force.clone_from(&first.pillar_force);
    out.min_j = parts.iter().map(|p| p.min_j).fold(f64::INFINITY, f64::min);
    out.values.resize(model.row_idx.len(), 0.0);
    out.values
        .par_chunks_mut(1 << 14)
        .enumerate()
        .for_each(|(c, chunk)| {
            let at = c << 14;
            chunk.copy_from_slice(&first.values[at..at + chunk.len()]);
            for p in rest {
                chunk
                    .iter_mut()
                    .zip(&p.values[at..])
                    .for_each(|(v, pv)| *v += pv);
            }
        });
    for p in rest {
        out.residual
            .iter_mut()
            .zip(&p.residual)
            .for_each(|(v, pv)| *v += pv);
        for (acc, part) in [
            (&mut out.node_force, &p.node_force),
            (&mut out.pillar_force, &p.pillar_force),
        ] {
            acc.iter_mut()
                .zip(part)
                .for_each(|(v, pv)| (0..3).for_each(|d| v[d] += pv[d]));
        }
    }
    nodal_pressure_terms(model, state, out);
}

/// - V_a p_a^2 / (2 kappa): residual - V_a p_a / kappa, tangent - V_a / kappa.
fn nodal_pressure_terms(model: &Model, state: &State, out: &mut Assembled) {
    let kappa = model.material.kappa_pa;
    for (a, &d) in model.dof_p.iter().enumerate() {
        if d == NONE {
            continue;
        }
        let va = model.node_volume[a];
        out.residual[d as usize] -= va * state.p[a] / kappa;
        if let Some(s) = model.slot(d, d) {
            out.values[s] -= va / kappa;
        }
    }
}

/// Advance the viscoelastic history of every element with the converged state.
pub fn advance_history(model: &Model, state: &mut State, dt_s: f64) {
    if state.history.is_empty() {
        return;
    }
    let mat = &model.material;
    let mu0 = mat.mu_pa / viscoelastic::g_inf(&mat.prony);
    let x = &state.x;
    state
        .history
        .par_iter_mut()
        .enumerate()
        .for_each(|(k, hist)| {
            let nodes = model.mesh.tets[model.gel[k]];
            let f = deformation_gradient(nodes.map(|a| x[a]), &model.grads[k]);
            let (_, p, _) = deviatoric(mat.kinematics, mu0, &f);
            let s0 = if mat.kinematics == Kinematics::Linear {
                p
            } else {
                second_piola(&f, &p)
            };
            viscoelastic::advance(&mat.prony, hist, s0, dt_s);
        });
}

/// S = F^{-1} P.
fn second_piola(f: &Mat3, p: &Mat3) -> Mat3 {
    let cof = crate::material::cofactor(f);
    let j = crate::material::det(f);
    let mut s = [[0.0; 3]; 3];
    for i in 0..3 {
        for jj in 0..3 {
            // (F^{-1})_{ik} = cof_{ki} / J
            s[i][jj] = (0..3).map(|k| cof[k][i] / j * p[k][jj]).sum();
        }
    }
    s
}
