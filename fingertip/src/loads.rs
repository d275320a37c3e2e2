//! Loads carried by the chip: the resultant the gel applies to the pillar top.
//!
//! At a node whose displacement is prescribed, equilibrium reads f_int = f_ext + r, and no
//! external (contact) load acts there, so the support reaction on the gel is r_a = f_int,a and
//! the gel loads the support with -f_int,a. Summed over the base and the whole inclusion this
//! is what the mount carries, equal and opposite to the rod's push on the gel
//! ([`mount_reaction`]).
//!
//! Only part of it reaches the chip. The package (base, cover; sensor facts, "The soft
//! fingertip") is bonded to the mount, and "a pillar bonded to the central block carries the
//! load in from the soft material" (sensor facts, "The sensing chip"): the cross-beams see
//! the gel only through the pillar's top, while whatever the gel applies to the package's side
//! walls flows through the package into the mount without bending the beams. So the chip's
//! loads are the resultant over the inclusion's top face alone, i.e. the contributions of the
//! gel elements that touch the inclusion from above its top plane ([`Model::pillar`]), and
//! the moments are taken about the chip centre (the base centre, origin of the chip frame,
//! whose x, y, z axes are the fingertip's). On the nominal fingertip at 60 N (5 mm mesh) the
//! side walls carry a small opposite Fz (the whole package carries 6 % less Fz than its top)
//! but half again the top's lateral force, so counting them overstated the chip's moments by
//! ~20 % at theta_p = 20° (`fingertip/figures/summary.txt`).

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

/// Resultant on the chip from the pillar elements' nodal forces on the inclusion
/// (`Assembled::pillar_force`).
pub fn chip_loads(model: &Model, pillar_force: &[[f64; 3]]) -> ChipLoads {
    let mut f = [0.0; 3];
    let mut m = [0.0; 3];
    for (a, x) in model.mesh.nodes.iter().enumerate() {
        if !model.mesh.in_inclusion[a] {
            continue;
        }
        let load = pillar_force[a].map(|v| -v);
        for d in 0..3 {
            f[d] += load[d];
        }
        m[0] += x[1] * load[2] - x[2] * load[1];
        m[1] += x[2] * load[0] - x[0] * load[2];
        m[2] += x[0] * load[1] - x[1] * load[0];
    }
    ChipLoads {
        fz_n: f[2],
        mx_nm: m[0],
        my_nm: m[1],
        fx_n: f[0],
        fy_n: f[1],
    }
}

/// Total force the gel applies to the mount (bonded base and the whole inclusion), N, from the
/// nodal internal forces (`Assembled::node_force`).
pub fn mount_reaction(model: &Model, node_force: &[[f64; 3]]) -> [f64; 3] {
    let mut f = [0.0; 3];
    for (a, nf) in node_force.iter().enumerate() {
        if model.mesh.on_base[a] || model.mesh.in_inclusion[a] {
            for d in 0..3 {
                f[d] -= nf[d];
            }
        }
    }
    f
}
