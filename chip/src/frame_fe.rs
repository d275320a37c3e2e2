//! An independent numerical check of the analytical model: a 3D frame finite-element model of
//! the cross-beam. Each beam is meshed into many two-node frame elements (axial, torsion, and
//! bending in both planes, Timoshenko with shear deformation or Euler-Bernoulli), the block is
//! four very stiff stubs from its centre to the beam roots, and the frame ends are clamped. The
//! load is applied at the block centre. A small dense Cholesky solve (a few hundred dofs).
//!
//! The element is exact for end-loaded prismatic beams, so with Euler-Bernoulli elements and a
//! rigid block it must reproduce the analytical model to round-off; Timoshenko elements add the
//! shear deformation that the paper's model leaves out.

use std::fmt;

use nalgebra::{DMatrix, DVector};

use crate::params::{Beam, ChipParams, Load};
use crate::section::{rectangle_torsion_factor_m4, section_modulus_m3};

/// Shear correction factor of a rectangular section.
const SHEAR_CORRECTION: f64 = 5.0 / 6.0;
/// Degrees of freedom per node: u, v, w, theta_x, theta_y, theta_z.
const DOF: usize = 6;

/// How to build the frame model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameOptions {
    /// Elements along each beam.
    pub elements_per_beam: usize,
    /// Include shear deformation (Timoshenko) in the beams.
    pub shear_deformation: bool,
    /// Stiffness of the block stubs relative to the beams (large = rigid block).
    pub block_stiffness_factor: f64,
    /// Give the block stubs the block's own section instead (ignores the factor).
    pub real_block: bool,
}

impl FrameOptions {
    /// Options with the block stubs given the block's real section (width 2c, the wafer's
    /// thickness) instead of a rigid block. A stub of beam theory is more flexible than the
    /// solid block it stands for, so this bounds the block's flexibility from above.
    pub fn with_real_block() -> Self {
        Self {
            real_block: true,
            ..Self::default()
        }
    }
}

impl Default for FrameOptions {
    fn default() -> Self {
        Self {
            elements_per_beam: 20,
            shear_deformation: true,
            block_stiffness_factor: 1e4,
            real_block: false,
        }
    }
}

/// Why the frame model could not be solved.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum FrameError {
    /// Fewer than one element per beam was asked for.
    NoElements,
    /// The stiffness matrix is not positive definite (bad parameters).
    NotPositiveDefinite,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoElements => write!(f, "the frame model needs at least one element per beam"),
            Self::NotPositiveDefinite => {
                write!(f, "the frame stiffness matrix is not positive definite")
            }
        }
    }
}

impl std::error::Error for FrameError {}

/// One frame element: its nodes, length, local axes and local stiffness.
struct Element {
    nodes: [usize; 2],
    length_m: f64,
    axes: [[f64; 3]; 3],
    k_local: [[f64; 12]; 12],
}

/// A solved frame model.
pub struct FrameSolution {
    n_per_beam: usize,
    length_m: f64,
    section_modulus_m3: f64,
    displacement: Vec<f64>,
    beam_elements: Vec<Element>,
}

/// Section stiffnesses of one element.
struct SectionStiffness {
    ea: f64,
    gj: f64,
    ei_y: f64,
    ei_z: f64,
    kga: f64,
}

fn node_of(beam: usize, i: usize, n: usize) -> usize {
    1 + beam * (n + 1) + i
}

/// Solve the frame model of chip `p` under `load`.
pub fn solve(p: &ChipParams, load: Load, opt: FrameOptions) -> Result<FrameSolution, FrameError> {
    let n = opt.elements_per_beam;
    if n == 0 {
        return Err(FrameError::NoElements);
    }
    let g = &p.geometry;
    let (beam_section, block_section) = sections(p, &opt);
    let (l, c) = (g.beam_length_m, g.block_half_width_m);
    let n_nodes = 1 + 4 * (n + 1);
    let mut coords = vec![[0.0; 3]; n_nodes];
    let mut beam_elements = Vec::new();
    let mut block_elements = Vec::new();
    for (k, beam) in Beam::ALL.iter().enumerate() {
        let (ex, ey) = beam.direction();
        for i in 0..=n {
            let s = l * i as f64 / n as f64; // from the frame
            let rho = c + l - s;
            coords[node_of(k, i, n)] = [rho * ex, rho * ey, 0.0];
        }
        for i in 0..n {
            let nodes = [node_of(k, i, n), node_of(k, i + 1, n)];
            beam_elements.push(element(nodes, &coords, &beam_section));
        }
        block_elements.push(element([0, node_of(k, n, n)], &coords, &block_section));
    }
    let n_dof = n_nodes * DOF;
    let mut stiffness = vec![0.0; n_dof * n_dof];
    for el in beam_elements.iter().chain(&block_elements) {
        assemble(&mut stiffness, n_dof, el);
    }
    let mut force = vec![0.0; n_dof];
    force[2] = -load.fz_n; // pressing along -z
    force[3] = load.mx_nm;
    force[4] = load.my_nm;
    let clamped: Vec<bool> = (0..n_dof)
        .map(|d| (0..4).any(|k| d / DOF == node_of(k, 0, n)))
        .collect();
    let displacement = solve_clamped(&stiffness, &force, &clamped)?;
    Ok(FrameSolution {
        n_per_beam: n,
        length_m: l,
        section_modulus_m3: section_modulus_m3(g),
        displacement,
        beam_elements,
    })
}

/// The stiffnesses of a beam's section and of the block's stubs.
fn sections(p: &ChipParams, opt: &FrameOptions) -> (SectionStiffness, SectionStiffness) {
    let g = &p.geometry;
    let (e, gs) = (p.silicon.youngs_modulus_pa, p.silicon.shear_modulus_pa);
    let shear = opt.shear_deformation;
    let beam = rectangle(g.beam_width_m, g.beam_thickness_m, e, gs, shear);
    let block = if opt.real_block {
        rectangle(
            2.0 * g.block_half_width_m,
            g.block_thickness_m,
            e,
            gs,
            shear,
        )
    } else {
        let f = opt.block_stiffness_factor;
        SectionStiffness {
            ea: beam.ea * f,
            gj: beam.gj * f,
            ei_y: beam.ei_y * f,
            ei_z: beam.ei_z * f,
            kga: beam.kga * f,
        }
    };
    (beam, block)
}

/// Stiffnesses of a rectangular section `width` (in plane) by `thickness` (along z).
fn rectangle(width: f64, thickness: f64, e: f64, g: f64, shear: bool) -> SectionStiffness {
    let area = width * thickness;
    SectionStiffness {
        ea: e * area,
        gj: g * rectangle_torsion_factor_m4(width, thickness),
        ei_y: e * width * thickness.powi(3) / 12.0,
        ei_z: e * thickness * width.powi(3) / 12.0,
        kga: if shear {
            SHEAR_CORRECTION * g * area
        } else {
            f64::INFINITY
        },
    }
}

fn element(nodes: [usize; 2], coords: &[[f64; 3]], s: &SectionStiffness) -> Element {
    let (a, b) = (coords[nodes[0]], coords[nodes[1]]);
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let length_m = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let x = [d[0] / length_m, d[1] / length_m, d[2] / length_m];
    let z = [0.0, 0.0, 1.0];
    let y = [
        z[1] * x[2] - z[2] * x[1],
        z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0],
    ];
    Element {
        nodes,
        length_m,
        axes: [x, y, z],
        k_local: local_stiffness(length_m, s),
    }
}

/// The 12x12 local stiffness of a two-node frame element (Przemieniecki), dofs
/// [u1 v1 w1 tx1 ty1 tz1 u2 v2 w2 tx2 ty2 tz2], with shear parameters Phi = 12 EI / (kGA l^2).
fn local_stiffness(l: f64, s: &SectionStiffness) -> [[f64; 12]; 12] {
    let mut k = [[0.0; 12]; 12];
    let mut put = |i: usize, j: usize, v: f64| {
        k[i][j] += v;
        if i != j {
            k[j][i] += v;
        }
    };
    put(0, 0, s.ea / l);
    put(0, 6, -s.ea / l);
    put(6, 6, s.ea / l);
    put(3, 3, s.gj / l);
    put(3, 9, -s.gj / l);
    put(9, 9, s.gj / l);
    // Bending in the x-z plane (w, theta_y = -w').
    let phi = 12.0 * s.ei_y / (s.kga * l * l);
    let a = s.ei_y / ((1.0 + phi) * l * l * l);
    put(2, 2, 12.0 * a);
    put(2, 4, -6.0 * l * a);
    put(2, 8, -12.0 * a);
    put(2, 10, -6.0 * l * a);
    put(4, 4, (4.0 + phi) * l * l * a);
    put(4, 8, 6.0 * l * a);
    put(4, 10, (2.0 - phi) * l * l * a);
    put(8, 8, 12.0 * a);
    put(8, 10, 6.0 * l * a);
    put(10, 10, (4.0 + phi) * l * l * a);
    // Bending in the x-y plane (v, theta_z = v').
    let phi = 12.0 * s.ei_z / (s.kga * l * l);
    let a = s.ei_z / ((1.0 + phi) * l * l * l);
    put(1, 1, 12.0 * a);
    put(1, 5, 6.0 * l * a);
    put(1, 7, -12.0 * a);
    put(1, 11, 6.0 * l * a);
    put(5, 5, (4.0 + phi) * l * l * a);
    put(5, 7, -6.0 * l * a);
    put(5, 11, (2.0 - phi) * l * l * a);
    put(7, 7, 12.0 * a);
    put(7, 11, -6.0 * l * a);
    put(11, 11, (4.0 + phi) * l * l * a);
    k
}

/// Local dof vector of `el` from the global displacement: u_local = R u_global per 3-block.
fn to_local(el: &Element, global: &[f64]) -> [f64; 12] {
    let mut out = [0.0; 12];
    for block in 0..4 {
        let node = el.nodes[block / 2];
        let base = node * DOF + (block % 2) * 3;
        for (r, axis) in el.axes.iter().enumerate() {
            out[block * 3 + r] = (0..3).map(|c| axis[c] * global[base + c]).sum();
        }
    }
    out
}

#[allow(clippy::needless_range_loop)] // index algebra of T^T k T reads clearer
fn assemble(k: &mut [f64], n_dof: usize, el: &Element) {
    // T (12x12, block diagonal with R) : K_global = T^T k T.
    let t = |i: usize, j: usize| -> f64 {
        if i / 3 == j / 3 {
            el.axes[i % 3][j % 3]
        } else {
            0.0
        }
    };
    let mut kt = [[0.0; 12]; 12];
    for i in 0..12 {
        for j in 0..12 {
            kt[i][j] = (0..12).map(|m| el.k_local[i][m] * t(m, j)).sum();
        }
    }
    let global = |i: usize| el.nodes[i / 6] * DOF + i % 6;
    for i in 0..12 {
        for j in 0..12 {
            let v: f64 = (0..12).map(|m| t(m, i) * kt[m][j]).sum();
            k[global(i) * n_dof + global(j)] += v;
        }
    }
}

/// Solve K u = f with the `clamped` dofs held at zero (nalgebra's dense Cholesky on the free
/// dofs).
fn solve_clamped(k: &[f64], f: &[f64], clamped: &[bool]) -> Result<Vec<f64>, FrameError> {
    let n_dof = f.len();
    let free: Vec<usize> = (0..n_dof).filter(|&d| !clamped[d]).collect();
    let m = free.len();
    let a = DMatrix::from_fn(m, m, |i, j| k[free[i] * n_dof + free[j]]);
    let cholesky = a.cholesky().ok_or(FrameError::NotPositiveDefinite)?;
    let y = cholesky.solve(&DVector::from_fn(m, |q, _| f[free[q]]));
    if y.iter().any(|v| !v.is_finite()) {
        return Err(FrameError::NotPositiveDefinite);
    }
    let mut u = vec![0.0; n_dof];
    for (q, &d) in free.iter().enumerate() {
        u[d] = y[q];
    }
    Ok(u)
}

impl FrameSolution {
    /// Top-surface longitudinal stress on `beam` at `x_m` from its frame end, from the element
    /// end forces: M_y(x') = M_y2 - (l - x') V_z2 inside the element, sigma = M_y / Z_Y.
    pub fn surface_stress_pa(&self, beam: Beam, x_m: f64) -> f64 {
        let k = Beam::ALL.iter().position(|b| *b == beam).unwrap_or(0);
        let n = self.n_per_beam;
        let h = self.length_m / n as f64;
        let i = ((x_m / h).floor().max(0.0) as usize).min(n - 1);
        let el = &self.beam_elements[k * n + i];
        let u = to_local(el, &self.displacement);
        let end = |row: usize| -> f64 { (0..12).map(|j| el.k_local[row][j] * u[j]).sum() };
        let local_x = x_m - i as f64 * h;
        let moment = end(10) - (el.length_m - local_x) * end(8);
        moment / self.section_modulus_m3
    }

    /// Deflection of the block centre into the chip (along -z).
    pub fn block_deflection_m(&self) -> f64 {
        -self.displacement[2]
    }

    /// Rotations of the block (theta_x, theta_y).
    pub fn block_rotations_rad(&self) -> (f64, f64) {
        (self.displacement[3], self.displacement[4])
    }
}
