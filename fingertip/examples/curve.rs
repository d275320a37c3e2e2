//! Print the mesh quality and one force–travel curve.
//! `cargo run --release -p fingertip --example curve -- [mesh_mm] [theta_deg] [phi_deg] [linear|neo] [peak_n] [nu] [rod_radius_mm]`

use fingertip::{compress, Config, Material};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize, d: f64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let material = if args.get(3).map(String::as_str) == Some("linear") {
        Material::Linear
    } else {
        Material::NeoHookean
    };
    let config = Config {
        radius_mm: 20.0,
        youngs_modulus_pa: 0.15e6,
        poisson: num(5, 0.49),
        material,
        mesh_size_mm: num(0, 4.0),
        rod_radius_mm: num(6, 20.0),
        contact_angle_deg: num(1, 0.0),
        azimuth_deg: num(2, 60.0),
        friction_mu: 0.0,
        inclusion_half_width_mm: 1.5,
        inclusion_height_mm: 1.5,
        load_steps: 40,
        rod_speed_mm_per_s: 20.0 / 60.0,
        rod_shape: fingertip::RodShape::FlatEnd,
        drive: fingertip::Drive::RodAxis,
    };
    let curve = compress(&config, num(4, 60.0))?;
    println!("{:?}", curve.quality);
    println!(
        "factor nnz {} dofs {} setup {:.3} s solve {:.3} s {:?}",
        curve.factor_nnz, curve.dofs, curve.setup_s, curve.solve_s, curve.stats
    );
    println!("rod_mm,force_n,fz_n,mx_nm,my_nm,contact_nodes");
    for p in &curve.points {
        println!(
            "{:.4},{:.5},{:.5},{:.6e},{:.6e},{}",
            p.rod_mm, p.force_n, p.fz_n, p.mx_nm, p.my_nm, p.contact_nodes
        );
    }
    Ok(())
}
