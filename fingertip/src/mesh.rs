//! Tetrahedral mesh of the hemisphere, generated at run time.
//!
//! Layout: the classical "inner cube + shells" block-structured ball, cut in half. An inner
//! half-cube `[-c R, c R]^2 x [0, c R]` is meshed as a graded Cartesian lattice; five shell
//! blocks (+z, ±x, ±y) connect each outer face of that cube to the sphere by blending
//! `x = R [(1 - t) c q + t q / |q|]` with `q` on the unit-cube face and `t` in `[0, 1]`. Unlike
//! a single cube-to-ball map this keeps hexahedra near-orthogonal at the sphere (no 180° face
//! angles). Every hexahedron is split into six tetrahedra along its main diagonal (Kuhn); the
//! blocks index their shared faces along the same global axes, so the face diagonals agree and
//! the mesh is conforming.
//!
//! Grading: the lateral and vertical lattices are finest at the chip (base centre) and the
//! inclusion edges are lattice lines; the +z shell inherits the lateral lattice, so the cap
//! around the pole, where the rod lands, is fine too; the radial lattice of the shells is finer
//! towards the surface. All sizes scale with the one density parameter `size_mm`.

use std::collections::HashMap;

/// Inner-cube half size as a fraction of R (0.45 keeps the thinnest shell corner at 0.22 R).
const INNER_CUBE_FRACTION: f64 = 0.45;
/// Element size at the chip relative to the nominal size.
const CHIP_REFINEMENT: f64 = 0.3;
/// Largest radial element size at the sphere relative to the nominal size.
const SURFACE_REFINEMENT: f64 = 0.5;

/// What the mesh generator needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshParams {
    /// Hemisphere radius R.
    pub radius_mm: f64,
    /// Nominal element edge length away from the refinements.
    pub size_mm: f64,
    /// Half width of the square chip-package inclusion at the base centre.
    pub inclusion_half_width_mm: f64,
    /// Height of the inclusion (package + pillar) above the base.
    pub inclusion_height_mm: f64,
}

/// A linear tetrahedral mesh in metres.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Reference node positions, m.
    pub nodes: Vec<[f64; 3]>,
    /// Tetrahedra, positively oriented.
    pub tets: Vec<[usize; 4]>,
    /// Node lies on the bonded base (z = 0).
    pub on_base: Vec<bool>,
    /// Node belongs to the rigid chip inclusion (closed box at the base centre).
    pub in_inclusion: Vec<bool>,
    /// Triangles of the spherical surface (outward), for contact areas and export.
    pub surface_tris: Vec<[usize; 3]>,
    /// Hemisphere radius, m.
    pub radius_m: f64,
}

/// A graded 1-D lattice on `[0, len]`: spacing varies linearly from `h0` to `h1`.
fn graded(len: f64, h0: f64, h1: f64) -> Vec<f64> {
    let n = ((2.0 * len / (h0 + h1)).round() as usize).max(1);
    let raw: Vec<f64> = (0..n)
        .map(|k| h0 + (h1 - h0) * (k as f64 + 0.5) / n as f64)
        .collect();
    let scale = len / raw.iter().sum::<f64>();
    let mut out = Vec::with_capacity(n + 1);
    let mut s = 0.0;
    out.push(0.0);
    for (k, h) in raw.iter().enumerate() {
        s += h * scale;
        out.push(if k + 1 == n { len } else { s });
    }
    out
}

/// Lattice on `[0, end]` with `fine_len` meshed uniformly at `h_fine`, then graded to `h`.
fn half_lattice(fine_len: f64, end: f64, h_fine: f64, h: f64) -> Vec<f64> {
    let n_fine = ((fine_len / h_fine).ceil() as usize).max(2);
    let mut out: Vec<f64> = (0..=n_fine)
        .map(|k| fine_len * k as f64 / n_fine as f64)
        .collect();
    for s in graded(end - fine_len, fine_len / n_fine as f64, h)
        .into_iter()
        .skip(1)
    {
        out.push(fine_len + s);
    }
    if let Some(last) = out.last_mut() {
        *last = end;
    }
    out
}

/// Node deduplication on the parametric point of the unit half-ball.
struct NodeTable {
    index: HashMap<[i64; 3], usize>,
    nodes: Vec<[f64; 3]>,
    param: Vec<[f64; 3]>,
}

impl NodeTable {
    fn id(&mut self, param: [f64; 3], pos: [f64; 3]) -> usize {
        let key = param.map(|v| (v * 1e9).round() as i64);
        *self.index.entry(key).or_insert_with(|| {
            self.nodes.push(pos);
            self.param.push(param);
            self.nodes.len() - 1
        })
    }
}

/// A block: `pos(t_idx, a_idx, b_idx)`; the three index axes are Kuhn-split in that order.
struct Block<'a> {
    dims: [usize; 3],
    point: &'a dyn Fn(usize, usize, usize) -> ([f64; 3], [f64; 3]),
    /// Whether cell `c` along local axis `axis` lies on the negative side of a symmetry plane;
    /// there the split diagonal is mirrored, so the mesh keeps the x -> -x, y -> -y and x <-> y
    /// symmetries of the hemisphere exactly (theta_p = 0 then gives Mx = My = 0 to solver
    /// precision, and phi + 90° rotates the answer exactly).
    negative: &'a dyn Fn(usize, usize) -> bool,
    /// The `t = last` face lies on the sphere.
    outer: bool,
}

const KUHN: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

fn signed_volume(p: [[f64; 3]; 4]) -> f64 {
    let d = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let (a, b, c) = (d(p[1], p[0]), d(p[2], p[0]), d(p[3], p[0]));
    (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]))
        / 6.0
}

fn mesh_block(
    block: &Block,
    table: &mut NodeTable,
    tets: &mut Vec<[usize; 4]>,
    tris: &mut Vec<[usize; 3]>,
) {
    let [n0, n1, n2] = block.dims;
    let mut id = |i: usize, j: usize, k: usize| {
        let (param, pos) = (block.point)(i, j, k);
        table.id(param, pos)
    };
    for i in 0..n0 {
        for j in 0..n1 {
            for k in 0..n2 {
                let start = [
                    (block.negative)(0, i),
                    (block.negative)(1, j),
                    (block.negative)(2, k),
                ]
                .map(usize::from);
                for perm in KUHN {
                    let mut c = start;
                    let mut v = [id(i + c[0], j + c[1], k + c[2]), 0, 0, 0];
                    for (s, axis) in perm.iter().enumerate() {
                        c[*axis] = 1 - start[*axis];
                        v[s + 1] = id(i + c[0], j + c[1], k + c[2]);
                    }
                    tets.push(v);
                }
                if block.outer && i + 1 == n0 {
                    let (s1, s2) = (start[1], start[2]);
                    let mut q = |a, b| id(n0, j + a, k + b);
                    let (p00, p10, p11, p01) =
                        (q(s1, s2), q(1 - s1, s2), q(1 - s1, 1 - s2), q(s1, 1 - s2));
                    tris.push([p00, p10, p11]);
                    tris.push([p00, p11, p01]);
                }
            }
        }
    }
}

/// The block lattices in units of R: lateral (x and y, symmetric), vertical, and radial
/// through the shells.
struct Lattices {
    lat: Vec<f64>,
    ver: Vec<f64>,
    rad: Vec<f64>,
}

impl Lattices {
    fn new(params: &MeshParams) -> Self {
        let r = params.radius_mm;
        let c = INNER_CUBE_FRACTION;
        let h = params.size_mm;
        let w = params.inclusion_half_width_mm.min(0.8 * c * r);
        let hi = params.inclusion_height_mm.min(0.8 * c * r);
        let h_fine = (CHIP_REFINEMENT * h).min(w / 2.0).min(hi / 2.0);
        let half = half_lattice(w, c * r, h_fine, h);
        let lat = half
            .iter()
            .rev()
            .map(|v| -v / r)
            .chain(half.iter().skip(1).map(|v| v / r))
            .collect();
        let ver = half_lattice(hi, c * r, h_fine, h)
            .iter()
            .map(|v| v / r)
            .collect();
        let shell = (1.0 - c) * r;
        // Radially, grade towards the surface down to the cap's lateral spacing (h_fine / c at
        // the pole), so the elements under the contact are about isotropic.
        let h_surface = (SURFACE_REFINEMENT * h).min(h_fine / c);
        let rad = graded(shell, h, h_surface)
            .iter()
            .map(|v| v / shell)
            .collect();
        Self { lat, ver, rad }
    }

    /// The lateral cell lies on the negative half of its axis (mirrored there).
    fn negative(&self, cell: usize) -> bool {
        self.lat[cell + 1] <= 0.0
    }
}

/// A block's lattice point `(i, j, k)` -> (parameter, position).
type PointFn<'a> = &'a dyn Fn(usize, usize, usize) -> ([f64; 3], [f64; 3]);
/// Whether cell `c` along a block's local axis lies on a mirrored half.
type NegativeFn<'a> = &'a dyn Fn(usize, usize) -> bool;

/// Nodes, tetrahedra and surface triangles as the blocks add them.
struct Builder {
    table: NodeTable,
    tets: Vec<[usize; 4]>,
    tris: Vec<[usize; 3]>,
}

impl Builder {
    fn add(&mut self, block: &Block) {
        mesh_block(block, &mut self.table, &mut self.tets, &mut self.tris);
    }
}

/// Generate the hemisphere mesh.
pub fn generate(params: &MeshParams) -> Mesh {
    let r_m = params.radius_mm * 1e-3;
    let lattices = Lattices::new(params);
    let mut builder = Builder {
        table: NodeTable {
            index: HashMap::new(),
            nodes: Vec::new(),
            param: Vec::new(),
        },
        tets: Vec::new(),
        tris: Vec::new(),
    };
    mesh_inner_cube(&lattices, r_m, &mut builder);
    mesh_shells(&lattices, r_m, &mut builder);
    finish(builder.table, builder.tets, builder.tris, params, r_m)
}

/// The inner half-cube as a graded Cartesian lattice.
fn mesh_inner_cube(l: &Lattices, r_m: f64, builder: &mut Builder) {
    let (lat, ver) = (&l.lat, &l.ver);
    let inner = |i: usize, j: usize, k: usize| {
        let p = [lat[i], lat[j], ver[k]];
        (p, p.map(|v| v * r_m))
    };
    let inner_neg = |axis: usize, cell: usize| axis < 2 && l.negative(cell);
    builder.add(&Block {
        dims: [lat.len() - 1, lat.len() - 1, ver.len() - 1],
        point: &inner,
        negative: &inner_neg,
        outer: false,
    });
}

/// The five shell blocks (+z, ±x, ±y) from the cube's faces to the sphere.
fn mesh_shells(l: &Lattices, r_m: f64, builder: &mut Builder) {
    let c = INNER_CUBE_FRACTION;
    let (lat, ver, rad) = (&l.lat, &l.ver, &l.rad);
    let shell_point = |t: f64, q: [f64; 3]| {
        let norm = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        let m = c + t * (1.0 - c);
        let param = q.map(|v| v * m);
        let pos = q.map(|v| r_m * ((1.0 - t) * c * v + t * v / norm));
        (param, pos)
    };
    let a = |i: usize| lat[i] / c;
    let b = |k: usize| ver[k] / c;
    let nt = rad.len() - 1;
    let (na, nb) = (lat.len() - 1, ver.len() - 1);
    let top = |m: usize, i: usize, j: usize| shell_point(rad[m], [a(i), a(j), 1.0]);
    let xp = |m: usize, j: usize, k: usize| shell_point(rad[m], [1.0, a(j), b(k)]);
    let xm = |m: usize, j: usize, k: usize| shell_point(rad[m], [-1.0, a(j), b(k)]);
    let yp = |m: usize, i: usize, k: usize| shell_point(rad[m], [a(i), 1.0, b(k)]);
    let ym = |m: usize, i: usize, k: usize| shell_point(rad[m], [a(i), -1.0, b(k)]);
    // Axis 0 is radial; the lateral axes are mirrored on their negative half, z never is.
    let top_neg = |axis: usize, cell: usize| axis > 0 && l.negative(cell);
    let side_neg = |axis: usize, cell: usize| axis == 1 && l.negative(cell);
    let blocks: [(PointFn, [usize; 3], NegativeFn); 5] = [
        (&top, [nt, na, na], &top_neg),
        (&xp, [nt, na, nb], &side_neg),
        (&xm, [nt, na, nb], &side_neg),
        (&yp, [nt, na, nb], &side_neg),
        (&ym, [nt, na, nb], &side_neg),
    ];
    for (point, dims, negative) in blocks {
        builder.add(&Block {
            dims,
            point,
            negative,
            outer: true,
        });
    }
}

/// Orient elements and surface triangles, flag base and inclusion nodes.
fn finish(
    table: NodeTable,
    mut tets: Vec<[usize; 4]>,
    mut tris: Vec<[usize; 3]>,
    params: &MeshParams,
    r_m: f64,
) -> Mesh {
    let nodes = table.nodes;
    for t in &mut tets {
        if signed_volume(t.map(|v| nodes[v])) < 0.0 {
            t.swap(2, 3);
        }
    }
    for t in &mut tris {
        let p = t.map(|v| nodes[v]);
        let (u, v) = (
            [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]],
            [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]],
        );
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let centroid: Vec<f64> = (0..3).map(|d| p[0][d] + p[1][d] + p[2][d]).collect();
        if n[0] * centroid[0] + n[1] * centroid[1] + n[2] * centroid[2] < 0.0 {
            t.swap(1, 2);
        }
    }
    let tol = 1e-9 * r_m;
    let w = params.inclusion_half_width_mm * 1e-3 + tol;
    let hi = params.inclusion_height_mm * 1e-3 + tol;
    let on_base = table.param.iter().map(|p| p[2].abs() < 1e-12).collect();
    let in_inclusion = nodes
        .iter()
        .map(|x| x[0].abs() <= w && x[1].abs() <= w && x[2] <= hi)
        .collect();
    Mesh {
        nodes,
        tets,
        on_base,
        in_inclusion,
        surface_tris: tris,
        radius_m: r_m,
    }
}

impl Mesh {
    /// Reference volume of element `e`, m^3.
    pub fn tet_volume(&self, e: usize) -> f64 {
        signed_volume(self.tets[e].map(|v| self.nodes[v]))
    }

    /// Element lies entirely in the rigid inclusion (it carries no strain).
    pub fn tet_is_rigid(&self, e: usize) -> bool {
        self.tets[e].iter().all(|&v| self.in_inclusion[v])
    }

    /// Tributary area of every node on the spherical surface (a third of each triangle), m^2.
    pub fn surface_node_areas(&self) -> Vec<f64> {
        let mut area = vec![0.0; self.nodes.len()];
        for t in &self.surface_tris {
            let p = t.map(|v| self.nodes[v]);
            let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
            let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let a = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            for &i in t {
                area[i] += a / 3.0;
            }
        }
        area
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_lattice_spans_the_interval_monotonically() {
        let g = graded(9.0, 0.5, 2.0);
        assert_eq!(g[0], 0.0);
        assert_eq!(*g.last().unwrap(), 9.0);
        assert!(g.windows(2).all(|w| w[1] > w[0]));
        assert!(g[1] < g[g.len() - 1] - g[g.len() - 2]);
    }
}
