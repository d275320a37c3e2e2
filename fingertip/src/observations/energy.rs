//! The fingertip's elastic potential energy and its course along the inclination: the
//! mechanism the paper names for observation 2, a local minimum of elastic potential energy
//! (LMEE) of a hemispherical soft fingertip.
//!
//! The energy is the potential the FE minimises, without the contact penalty:
//!
//!   U = sum_e V_e W_dev(F_e) + sum_a V_a kappa / 2 (J_a - 1)^2,  J_a = v_a / V_a,
//!
//! (V_e, V_a reference element and nodal volumes, v_a the current nodal volume, `material`).
//! For a viscoelastic gel it is the relaxed part only.

use crate::assembly::deformation_gradient;
use crate::material::{det, deviatoric};
use crate::{Config, Error, Fingertip};

/// Elastic potential energy of the current state of `ft`, J.
pub fn elastic_energy_j(ft: &Fingertip) -> f64 {
    let model = &ft.solver.model;
    let state = &ft.solver.state;
    let mat = &model.material;
    let mut current_node_volume = vec![0.0; model.mesh.nodes.len()];
    let mut u_dev = 0.0;
    for (k, &e) in model.gel.iter().enumerate() {
        let nodes = model.mesh.tets[e];
        let f = deformation_gradient(nodes.map(|a| state.x[a]), &model.grads[k]);
        let (w, _, _) = deviatoric(mat.kinematics, mat.mu_pa, &f);
        u_dev += model.volume[k] * w;
        let v = det(&f) * model.volume[k];
        for &a in &nodes {
            current_node_volume[a] += v / 4.0;
        }
    }
    let u_vol: f64 = model
        .node_volume
        .iter()
        .zip(&current_node_volume)
        .filter(|(&va, _)| va > 0.0)
        .map(|(&va, &v)| 0.5 * mat.kappa_pa * va * (v / va - 1.0).powi(2))
        .sum();
    u_dev + u_vol
}

/// One point of the energy landscape along the inclination.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct EnergyPoint {
    /// Inclination theta_p, degrees.
    pub theta_deg: f64,
    /// Elastic potential energy at the rod travel of the sweep, J.
    pub energy_j: f64,
    /// Load along the machine's drive at that travel, N.
    pub force_n: f64,
    /// Chip Fz at that travel, N (negative pressed).
    pub fz_n: f64,
}

/// Energy along the inclination at a fixed rod travel `travel_mm` (reached in `steps`
/// equal steps), one FE run per angle of `thetas_deg`.
pub fn energy_along_inclination(
    base: &Config,
    thetas_deg: &[f64],
    travel_mm: f64,
    steps: usize,
) -> Result<Vec<EnergyPoint>, Error> {
    let mut out = Vec::with_capacity(thetas_deg.len());
    for &theta_deg in thetas_deg {
        let mut ft = Fingertip::new(Config {
            contact_angle_deg: theta_deg,
            ..base.clone()
        })?;
        let dt = travel_mm / steps as f64 / base.rod_speed_mm_per_s;
        let mut p = ft.point();
        for k in 1..=steps {
            p = ft.step_to(travel_mm * k as f64 / steps as f64, dt)?;
        }
        out.push(EnergyPoint {
            theta_deg,
            energy_j: elastic_energy_j(&ft),
            force_n: p.force_n,
            fz_n: p.fz_n,
        });
    }
    Ok(out)
}

/// Angles of the interior local minima of the energy along the sweep (a point lower than both
/// neighbours by more than `rel_tol` of its value).
pub fn interior_minima(points: &[EnergyPoint], rel_tol: f64) -> Vec<f64> {
    points
        .windows(3)
        .filter(|w| {
            let tol = rel_tol * w[1].energy_j.abs();
            w[1].energy_j < w[0].energy_j - tol && w[1].energy_j < w[2].energy_j - tol
        })
        .map(|w| w[1].theta_deg)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under a uniform stretch the energy is the closed form of the compressible neo-Hookean
    /// model times the volume: W_dev = mu/2 (J^(-2/3) tr C - 3) plus kappa/2 (J - 1)^2.
    #[test]
    fn uniform_stretch_energy_matches_the_closed_form() {
        let hw = hardware::Params::load_default()
            .expect("hardware")
            .fingertip;
        let mut ft = Fingertip::new(Config::from_hardware(&hw, 6.0)).expect("model");
        let stretch = [1.05, 0.98, 0.99];
        for (x, x0) in ft
            .solver
            .state
            .x
            .iter_mut()
            .zip(&ft.solver.model.mesh.nodes)
        {
            *x = [0, 1, 2].map(|d| stretch[d] * x0[d]);
        }
        let model = &ft.solver.model;
        let volume: f64 = model.volume.iter().sum();
        let j: f64 = stretch.iter().product();
        let tr_c: f64 = stretch.iter().map(|l| l * l).sum();
        let (mu, kappa) = (model.material.mu_pa, model.material.kappa_pa);
        let w = 0.5 * mu * (j.powf(-2.0 / 3.0) * tr_c - 3.0) + 0.5 * kappa * (j - 1.0).powi(2);
        let u = elastic_energy_j(&ft);
        assert!(
            (u / (w * volume) - 1.0).abs() < 1e-9,
            "U {u} closed form {}",
            w * volume
        );
    }
}
