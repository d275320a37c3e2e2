//! Fine-mesh verification studies, `#[ignore]`d from the default run (minutes each):
//!
//! ```text
//! cargo test -p fingertip --release --test studies -- --ignored --nocapture
//! ```

use fingertip::{Config, Fingertip, Material};

fn base(material: Material, mesh_size_mm: f64) -> Config {
    Config {
        radius_mm: 20.0,
        youngs_modulus_pa: 0.15e6,
        poisson: 0.49,
        material,
        mesh_size_mm,
        rod_radius_mm: 40.0,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        friction_mu: 0.0,
        inclusion_half_width_mm: 1.5,
        inclusion_height_mm: 1.5,
        load_steps: 40,
        rod_speed_mm_per_s: 20.0 / 60.0,
        rod_shape: fingertip::RodShape::FlatEnd,
        drive: fingertip::Drive::RodAxis,
    }
}

/// Hertz limit: a rigid flat (rod radius 2R, larger than any contact radius) on the linear
/// elastic hemisphere, F_H = 4/3 E/(1 - nu^2) sqrt(R) d^{3/2}.
///
/// Bonded-base effect: Hertz treats the sphere as a half-space, whose points at depth R under
/// the contact still move by the Boussinesq far field u_z(R) = P (1 + nu)(3 - 2 nu)/(2 pi E R).
/// The hemisphere's base is bonded there, so that share of the approach is missing: the local
/// (Hertz) approach is d_H = d + u_z(R), i.e. d_H = d (1 + c sqrt(d/R)) to first order with
/// c = (4/3)(1 + nu)(3 - 2 nu) / (2 pi (1 - nu^2)) (0.84 at nu = 0.49), and
/// F = F_H(d) (1 + c sqrt(d/R))^{3/2}. It vanishes only like sqrt(d/R): +6 % at d/R = 0.0025,
/// +13 % at 0.01, so the raw Hertz error does not fall below 5 % in this range; the test
/// asserts the corrected law within 5 % and prints both. The mesh is refined at the pole by
/// shrinking the chip inclusion (the cap inherits the chip's lateral spacing).
///
/// Resolution: what the small-indentation points need is a fine bulk, not a finer contact.
/// On the h = 2 mm mesh (88,800 tets) the points at d/R = 0.0025 and 0.005 (a = 3 and 4 pole
/// spacings) were +7.5 and +6.5 % above the corrected law; contact integrated over the
/// surface triangles instead of node by node gave the same numbers to 0.1 %, so ring
/// quantisation was not the cause. At h = 1.4 mm (210,912 tets, same 0.33 mm pole spacing)
/// they are +1.3 and +1.9 %, and every point from 0.0025 to 0.02 is within 5 %:
/// +1.3, +1.9, -2.5, -1.5, -1.8, -4.1, -4.9, -4.5 % (raw Hertz +8..+13 %).
///
/// What is left: from d/R ~ 0.015 the FE falls 4–5 % below the corrected law, and further as
/// the bulk is refined (-1.0 % at h = 2 mm, -4.5 % at 1.4 mm at d/R = 0.02). The correction
/// takes the base's stiffening from the half-space's field at depth R, but a hemisphere lacks
/// the half-space's material beside the axis, so it is stiffened less: the correction is an
/// upper estimate whose error grows with d/R. The base compliance the FE implies,
/// lambda = (d_H(F) - d) E R / F, falls from 0.54 at d/R = 0.0025 to 0.30 at 0.02 against the
/// half-space's 0.48: a constant would mean Hertz plus a rigid-body shift; its fall is the
/// finite hemisphere, and Hertz's own a/R corrections (a/R = 0.14 at d/R = 0.02). Minutes in
/// release (3–5 on the 2-core machine).
#[test]
#[ignore]
fn hertz_limit_at_small_indentation() {
    let mut c = base(Material::Linear, 1.4);
    c.inclusion_half_width_mm = 0.3;
    c.inclusion_height_mm = 0.3;
    let nu = c.poisson;
    let youngs_pa = c.youngs_modulus_pa;
    let e_star = youngs_pa / (1.0 - nu * nu);
    let bonded =
        4.0 / 3.0 * (1.0 + nu) * (3.0 - 2.0 * nu) / (2.0 * std::f64::consts::PI * (1.0 - nu * nu));
    let r = c.radius_mm * 1e-3;
    let mut ft = Fingertip::new(c).unwrap();
    let spacing = pole_spacing_m(&ft.solver.model.mesh);
    println!(
        "{:?}; pole node spacing {:.3} mm",
        ft.quality(),
        spacing * 1e3
    );
    let mut worst: f64 = 0.0;
    for d_over_r in [0.0025, 0.005, 0.0075, 0.01, 0.0125, 0.015, 0.0175, 0.02] {
        let p = ft.step_to(d_over_r * 20.0, 1.0).unwrap();
        let d = d_over_r * r;
        let hertz = 4.0 / 3.0 * e_star * r.sqrt() * d.powf(1.5);
        let corrected = hertz * (1.0 + bonded * d_over_r.sqrt()).powf(1.5);
        let (raw, err) = (p.force_n / hertz - 1.0, p.force_n / corrected - 1.0);
        // The base compliance the FE implies: the Hertz approach of its force minus the
        // travel, in units of F / (E R) (the half-space estimate is (1 + nu)(3 - 2 nu) / 2 pi).
        let approach = (3.0 * p.force_n / (4.0 * e_star * r.sqrt())).powf(2.0 / 3.0);
        let lambda = (approach - d) * youngs_pa * r / p.force_n;
        println!(
            "d/R {d_over_r:.4}: F {:.5} N, Hertz {hertz:.5} N ({:+.2} %), bonded-base Hertz {corrected:.5} N ({:+.2} %), implied base compliance {lambda:.3} (half-space {:.3}), {} contact nodes, a = {:.1} pole spacings",
            p.force_n,
            100.0 * raw,
            100.0 * err,
            (1.0 + nu) * (3.0 - 2.0 * nu) / (2.0 * std::f64::consts::PI),
            p.contact_nodes,
            (r * d).sqrt() / spacing
        );
        worst = worst.max(err.abs());
    }
    assert!(worst < 0.05, "bonded-base Hertz error {worst}");
}

/// Distance from the pole (the highest node) to its nearest neighbour on the surface, m.
fn pole_spacing_m(mesh: &fingertip::mesh::Mesh) -> f64 {
    let pole = (0..mesh.nodes.len())
        .max_by(|&a, &b| mesh.nodes[a][2].total_cmp(&mesh.nodes[b][2]))
        .expect("nodes");
    let q = mesh.nodes[pole];
    mesh.surface_tris
        .iter()
        .filter(|t| t.contains(&pole))
        .flat_map(|t| t.iter().copied())
        .filter(|&v| v != pole)
        .map(|v| {
            (0..3)
                .map(|d| (mesh.nodes[v][d] - q[d]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Mesh convergence of the travel at 60 N (neo-Hookean, platen): three densities in ratio
/// sqrt 2, observed order p = ln((d1 - d2)/(d2 - d3)) / ln(sqrt 2). The inclusion is 4 mm so
/// that every mesh size (including the chip's, 0.3 h) scales with h: a uniform refinement.
#[test]
#[ignore]
fn mesh_convergence_of_the_60n_indentation() {
    let sizes = [6.0, 6.0 / 2f64.sqrt(), 3.0];
    let mut travel = Vec::new();
    for &h in &sizes {
        let mut c = base(Material::NeoHookean, h);
        c.rod_radius_mm = 20.0;
        c.inclusion_half_width_mm = 4.0;
        c.inclusion_height_mm = 4.0;
        let curve = fingertip::compress(&c, 60.0).unwrap();
        let last = *curve.points.last().unwrap();
        // Travel at exactly 60 N by log-log interpolation of the last two points.
        let prev = curve.points[curve.points.len() - 2];
        let n = (last.force_n / prev.force_n).ln() / (last.rod_mm / prev.rod_mm).ln();
        let d60 = last.rod_mm * (60.0 / last.force_n).powf(1.0 / n);
        println!(
            "h {h:.3} mm: {} tets, {} dofs, travel at 60 N {d60:.4} mm, Fz {:.4} N, solve {:.1} s",
            curve.quality.tets, curve.dofs, last.fz_n, curve.solve_s
        );
        travel.push(d60);
    }
    let order = ((travel[0] - travel[1]) / (travel[1] - travel[2])).ln() / 2f64.sqrt().ln();
    let extrapolated = travel[2] + (travel[2] - travel[1]) / (2f64.sqrt().powf(order) - 1.0);
    println!("observed order {order:.2}, Richardson-extrapolated travel {extrapolated:.4} mm");
    assert!(
        order.is_finite() && order > 0.5,
        "no convergence: {travel:?}"
    );
}
