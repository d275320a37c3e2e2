//! The discrete model: which elements carry strain, the dof numbering (three displacement dofs
//! per free node, one pressure dof per gel node), shape gradients, nodal volumes and the
//! sparsity pattern of the (upper-triangular) tangent, built once.

use crate::material::Kinematics;
use crate::mesh::Mesh;
use crate::viscoelastic::PronyTerm;

/// Marker for "no dof here" (a fixed displacement component or a node without gel).
pub const NONE: u32 = u32::MAX;
/// Local dofs of one element: 4 nodes x (x, y, z, p).
pub const LOCAL: usize = 16;

/// Material data the assembly needs.
#[derive(Debug, Clone)]
pub struct MaterialData {
    pub kinematics: Kinematics,
    /// Shear modulus mu, Pa (relaxed modulus when viscoelastic).
    pub mu_pa: f64,
    /// Bulk modulus kappa, Pa.
    pub kappa_pa: f64,
    /// Prony terms (empty: elastic).
    pub prony: Vec<PronyTerm>,
}

/// Mesh + dofs + pattern.
#[derive(Debug)]
pub struct Model {
    pub mesh: Mesh,
    pub material: MaterialData,
    /// Elements that carry strain (not entirely inside the rigid inclusion).
    pub gel: Vec<usize>,
    /// Reference shape-function gradients dN_a/dX of each gel element.
    pub grads: Vec<[[f64; 3]; 4]>,
    /// Reference volume of each gel element.
    pub volume: Vec<f64>,
    /// Nodal volume V_a = sum V_e / 4.
    pub node_volume: Vec<f64>,
    /// Displacement dofs of each node (NONE where fixed).
    pub dof_x: Vec<[u32; 3]>,
    /// Pressure dof of each node (NONE without gel).
    pub dof_p: Vec<u32>,
    pub n_dofs: usize,
    /// CSC pattern of the upper triangle.
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// For each gel element, the value slot of local entry (r, c), r <= c in global order.
    pub slots: Vec<[u32; LOCAL * LOCAL]>,
    /// For each gel element, whether it loads the chip through the pillar top (see
    /// [`crate::loads`]): it touches the inclusion and lies on or above its top plane.
    pub pillar: Vec<bool>,
}

fn shape_gradients(p: [[f64; 3]; 4]) -> ([[f64; 3]; 4], f64) {
    // Columns of the Jacobian are edge vectors; grads of N1..N3 are rows of its inverse.
    let e: Vec<[f64; 3]> = (1..4)
        .map(|a| [p[a][0] - p[0][0], p[a][1] - p[0][1], p[a][2] - p[0][2]])
        .collect();
    let jm = [
        [e[0][0], e[1][0], e[2][0]],
        [e[0][1], e[1][1], e[2][1]],
        [e[0][2], e[1][2], e[2][2]],
    ];
    let det = crate::material::det(&jm);
    let cof = crate::material::cofactor(&jm);
    let mut g = [[0.0; 3]; 4];
    for a in 0..3 {
        for d in 0..3 {
            // (J^{-1})_{a d} = cof_{d a} / det
            g[a + 1][d] = cof[d][a] / det;
            g[0][d] -= g[a + 1][d];
        }
    }
    (g, det / 6.0)
}

/// Gel elements that touch the inclusion from above its top plane z = h (the highest
/// inclusion node): they hold the pillar top, every other element touching the inclusion holds
/// a package side wall. The top is a lattice plane of the mesh, so the split is exact.
fn pillar_elements(mesh: &Mesh, gel: &[usize]) -> Vec<bool> {
    let top = mesh
        .nodes
        .iter()
        .zip(&mesh.in_inclusion)
        .filter(|(_, &inc)| inc)
        .map(|(x, _)| x[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let tol = 1e-9 * mesh.radius_m;
    gel.iter()
        .map(|&e| {
            let t = mesh.tets[e];
            t.iter().any(|&a| mesh.in_inclusion[a])
                && t.iter().all(|&a| mesh.nodes[a][2] >= top - tol)
        })
        .collect()
}

impl Model {
    pub fn new(mesh: Mesh, material: MaterialData) -> Model {
        let n = mesh.nodes.len();
        let gel: Vec<usize> = (0..mesh.tets.len())
            .filter(|&e| !mesh.tet_is_rigid(e))
            .collect();
        let mut grads = Vec::with_capacity(gel.len());
        let mut volume = Vec::with_capacity(gel.len());
        let mut node_volume = vec![0.0; n];
        for &e in &gel {
            let (g, v) = shape_gradients(mesh.tets[e].map(|a| mesh.nodes[a]));
            grads.push(g);
            volume.push(v);
            for &a in &mesh.tets[e] {
                node_volume[a] += v / 4.0;
            }
        }
        let mut next = 0u32;
        let mut dof_x = vec![[NONE; 3]; n];
        let mut dof_p = vec![NONE; n];
        for a in 0..n {
            if !(mesh.on_base[a] || mesh.in_inclusion[a]) {
                for d in 0..3 {
                    dof_x[a][d] = next;
                    next += 1;
                }
            }
            if node_volume[a] > 0.0 {
                dof_p[a] = next;
                next += 1;
            }
        }
        let pillar = pillar_elements(&mesh, &gel);
        let mut model = Model {
            pillar,
            mesh,
            material,
            gel,
            grads,
            volume,
            node_volume,
            dof_x,
            dof_p,
            n_dofs: next as usize,
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
            slots: Vec::new(),
        };
        model.build_pattern();
        model
    }

    /// Global dofs of a gel element in local order (x, y, z, p per node).
    pub fn element_dofs(&self, k: usize) -> [u32; LOCAL] {
        let mut d = [NONE; LOCAL];
        for (a, &node) in self.mesh.tets[self.gel[k]].iter().enumerate() {
            d[4 * a..4 * a + 3].copy_from_slice(&self.dof_x[node]);
            d[4 * a + 3] = self.dof_p[node];
        }
        d
    }

    fn build_pattern(&mut self) {
        let n = self.n_dofs;
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for k in 0..self.gel.len() {
            let d = self.element_dofs(k);
            for &r in d.iter().filter(|&&r| r != NONE) {
                for &c in d.iter().filter(|&&c| c != NONE && r <= c) {
                    cols[c as usize].push(r as usize);
                }
            }
        }
        // Contact blocks are node-diagonal: inside the element pattern already.
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let slot = |r: u32, c: u32| -> u32 {
            if r == NONE || c == NONE {
                return NONE;
            }
            let (r, c) = if r <= c {
                (r as usize, c as usize)
            } else {
                (c as usize, r as usize)
            };
            let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            match rows.binary_search(&r) {
                Ok(i) => (col_ptr[c] + i) as u32,
                Err(_) => NONE,
            }
        };
        let mut slots = Vec::with_capacity(self.gel.len());
        for k in 0..self.gel.len() {
            let d = self.element_dofs(k);
            let mut s = [NONE; LOCAL * LOCAL];
            for i in 0..LOCAL {
                for j in 0..LOCAL {
                    // Only the upper triangle in global numbering is stored, once.
                    if d[i] != NONE && d[j] != NONE && d[i] <= d[j] {
                        s[i * LOCAL + j] = slot(d[i], d[j]);
                    }
                }
            }
            slots.push(s);
        }
        self.col_ptr = col_ptr;
        self.row_idx = row_idx;
        self.slots = slots;
    }

    /// Value slot of global upper entry (r, c) with r <= c, if stored.
    pub fn slot(&self, r: u32, c: u32) -> Option<usize> {
        let (r, c) = if r <= c {
            (r as usize, c as usize)
        } else {
            (c as usize, r as usize)
        };
        let rows = &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]];
        rows.binary_search(&r).ok().map(|i| self.col_ptr[c] + i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_gradients_reproduce_a_linear_field() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.1, 0.0],
            [0.2, 1.0, 0.1],
            [0.1, 0.3, 1.2],
        ];
        let (g, v) = shape_gradients(p);
        assert!(v > 0.0);
        // u = 2x - y + 3z: sum_a u(p_a) grad N_a = (2, -1, 3)
        let u = |x: [f64; 3]| 2.0 * x[0] - x[1] + 3.0 * x[2];
        for d in 0..3 {
            let s: f64 = (0..4).map(|a| u(p[a]) * g[a][d]).sum();
            assert!((s - [2.0, -1.0, 3.0][d]).abs() < 1e-12);
        }
    }
}
