//! Loads carried by the chip: the resultant of the reactions on the rigid inclusion.
//!
//! At a node whose displacement is prescribed, equilibrium reads f_int = f_ext + r, and no
//! external (contact) load acts there, so the support reaction on the gel is r_a = f_int,a and
//! the gel loads the inclusion with -f_int,a. Summing over the inclusion's nodes gives the
//! force on the chip, and the moments about the chip centre (the base centre, the origin of
//! the chip frame, whose x, y, z axes are the fingertip's).

use crate::model::Model;

/// Force and moments on the chip, chip frame, SI.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ChipLoads {
    /// Force on the chip along its z axis (out of the base, into the gel), N. Negative when
    /// the fingertip is pressed.
    pub fz_n: f64,
    /// Moment about the chip's x axis, N·m.
    pub mx_nm: f64,
    /// Moment about the chip's y axis, N·m.
    pub my_nm: f64,
    /// In-plane force components (not measured by the three-axis chip), N.
    pub fx_n: f64,
    pub fy_n: f64,
}

/// Resultant on the inclusion from the nodal internal forces.
pub fn chip_loads(model: &Model, node_force: &[[f64; 3]]) -> ChipLoads {
    let mut f = [0.0; 3];
    let mut m = [0.0; 3];
    for (a, x) in model.mesh.nodes.iter().enumerate() {
        if !model.mesh.in_inclusion[a] {
            continue;
        }
        let load = node_force[a].map(|v| -v);
        for d in 0..3 {
            f[d] += load[d];
        }
        m[0] += x[1] * load[2] - x[2] * load[1];
        m[1] += x[2] * load[0] - x[0] * load[2];
        m[2] += x[0] * load[1] - x[1] * load[0];
    }
    ChipLoads { fz_n: f[2], mx_nm: m[0], my_nm: m[1], fx_n: f[0], fy_n: f[1] }
}
