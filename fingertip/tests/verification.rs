//! Verification of the fingertip model against analytical cases and exact symmetries.
//! Fast cases run by default (`cargo test -p fingertip --release`); the fine-mesh studies
//! are `#[ignore]`d, see `tests/studies.rs`.

use fingertip::contact::Rod;
use fingertip::{Config, Fingertip, Material};

/// A coarse but complete model: nominal gel of the project (E = 0.15 MPa, nu = 0.49), a
/// platen-like rod (radius = R), a 3 mm-wide inclusion.
fn coarse(material: Material) -> Config {
    Config {
        radius_mm: 20.0,
        youngs_modulus_pa: 0.15e6,
        poisson: 0.49,
        material,
        mesh_size_mm: 8.0,
        rod_radius_mm: 20.0,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        friction_mu: 0.0,
        inclusion_half_width_mm: 3.0,
        inclusion_height_mm: 3.0,
        load_steps: 6,
        rod_speed_mm_per_s: 20.0 / 60.0,
        rod_shape: fingertip::RodShape::FlatEnd,
        drive: fingertip::Drive::RodAxis,
    }
}

fn far_rod() -> Rod {
    Rod::new(0.0, 0.0, 0.02, f64::INFINITY, 0.0)
}

/// Patch test (consistency): for any homogeneous deformation x = F X with the matching
/// uniform nodal pressure p = kappa (J - 1), every node away from the boundary is in
/// equilibrium, for both kinematics.
#[test]
fn patch_test_homogeneous_deformation_is_in_equilibrium() {
    for material in [Material::Linear, Material::NeoHookean] {
        let mut ft = Fingertip::new(coarse(material)).unwrap();
        let f = [[1.05, 0.02, -0.03], [0.01, 0.97, 0.04], [0.02, -0.01, 1.01]];
        let s = &mut ft.solver;
        let kin = s.model.material.kinematics;
        let fm = fingertip::material::volume_measure(kin, &f);
        let p = s.model.material.kappa_pa * (fm.j - 1.0);
        for (x, x0) in s.state.x.iter_mut().zip(&s.model.mesh.nodes) {
            *x = [0, 1, 2].map(|i| (0..3).map(|j| f[i][j] * x0[j]).sum());
        }
        s.state.p.iter_mut().for_each(|v| *v = p);
        s.evaluate(&far_rod(), 0.0);
        let area = s.model.mesh.surface_node_areas();
        let scale = s.model.material.mu_pa * 0.02 * 0.02;
        let mut checked = 0;
        for (a, &node_area) in area.iter().enumerate() {
            let interior =
                node_area == 0.0 && !s.model.mesh.on_base[a] && !s.model.mesh.in_inclusion[a];
            if interior {
                for d in 0..3 {
                    let r = s.asm.residual[s.model.dof_x[a][d] as usize];
                    assert!(r.abs() < 1e-12 * scale, "node {a} residual {r}");
                }
                let rp = s.asm.residual[s.model.dof_p[a] as usize];
                assert!(
                    rp.abs() < 1e-12 * s.model.node_volume[a],
                    "volume residual {rp}"
                );
                checked += 1;
            }
        }
        assert!(checked > 50);
    }
}

/// y = K v with K stored as the upper triangle in CSC.
fn sym_matvec(col_ptr: &[usize], row_idx: &[usize], val: &[f64], v: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; v.len()];
    for c in 0..v.len() {
        for k in col_ptr[c]..col_ptr[c + 1] {
            let r = row_idx[k];
            y[r] += val[k] * v[c];
            if r != c {
                y[c] += val[k] * v[r];
            }
        }
    }
    y
}

/// The assembled tangent is the derivative of the assembled residual (Newton's quadratic
/// rate depends on it), at a deformed state with pressure and rod contact.
#[test]
fn global_tangent_matches_finite_differences_of_the_residual() {
    let mut ft = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
    ft.step_to(1.0, 1.0).unwrap();
    let rod = ft.rod_at(1.0e-3);
    let s = &mut ft.solver;
    s.begin_step(rod.face_m);
    s.evaluate(&rod, 0.0);
    let k = s.asm.values.clone();
    let n = s.model.n_dofs;
    // A smooth direction: a small rotation-free field on x and a pressure perturbation.
    let mut v = vec![0.0; n];
    for (a, x) in s.model.mesh.nodes.iter().enumerate() {
        for d in 0..3 {
            let dof = s.model.dof_x[a][d];
            if dof != fingertip::model::NONE {
                v[dof as usize] = 1e-4 * (x[(d + 1) % 3] * 40.0).sin();
            }
        }
        let dp = s.model.dof_p[a];
        if dp != fingertip::model::NONE {
            v[dp as usize] = 10.0 * (x[0] * 30.0).cos();
        }
    }
    let kv = sym_matvec(&s.model.col_ptr, &s.model.row_idx, &k, &v);
    let h = 1e-4;
    let shift = |s: &mut fingertip::solver::Solver, t: f64| {
        for a in 0..s.model.mesh.nodes.len() {
            for d in 0..3 {
                let dof = s.model.dof_x[a][d];
                if dof != fingertip::model::NONE {
                    s.state.x[a][d] += t * v[dof as usize];
                }
            }
            let dp = s.model.dof_p[a];
            if dp != fingertip::model::NONE {
                s.state.p[a] += t * v[dp as usize];
            }
        }
    };
    shift(s, h);
    s.evaluate(&rod, 0.0);
    let rp = s.asm.residual.clone();
    shift(s, -2.0 * h);
    s.evaluate(&rod, 0.0);
    let rm = s.asm.residual.clone();
    let mut err: f64 = 0.0;
    let mut norm: f64 = 0.0;
    for i in 0..n {
        let fd = (rp[i] - rm[i]) / (2.0 * h);
        err = err.max((fd - kv[i]).abs());
        norm = norm.max(kv[i].abs());
    }
    assert!(err < 1e-5 * norm, "tangent error {err} vs {norm}");
}

/// theta_p = 0: the model and mesh are symmetric under x -> -x and y -> -y, so the chip
/// carries no moment, to solver precision.
#[test]
fn axial_load_gives_no_moment() {
    let mut ft = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
    let p = ft.step_to(2.0, 1.0).unwrap();
    assert!(p.force_n > 0.1 && p.fz_n < 0.0);
    let m_scale = p.fz_n.abs() * 0.02;
    assert!(
        p.mx_nm.abs() < 1e-6 * m_scale && p.my_nm.abs() < 1e-6 * m_scale,
        "{p:?}"
    );
}

/// Equilibrium: the mount (base + package) carries exactly the rod's push, and the chip, which
/// sees only the pillar top (`fingertip::loads`), carries a share of its Fz that is larger than
/// the top's share of the base area (the stiff package under the load draws the pressure) and
/// below 1; the side walls' part is what the whole package carries beyond it.
#[test]
fn chip_carries_the_pillar_share_of_the_mount_reaction() {
    let mut c = coarse(Material::NeoHookean);
    c.contact_angle_deg = 20.0;
    c.azimuth_deg = 60.0;
    let mut ft = Fingertip::new(c.clone()).unwrap();
    let p = ft.step_to(3.0, 1.0).unwrap();
    let axis = ft.rod_at(3e-3).axis;
    let mount = ft.mount_reaction();
    for d in 0..3 {
        assert!(
            (mount[d] + p.force_n * axis[d]).abs() < 1e-4 * p.force_n,
            "mount {mount:?} vs rod {} N along {axis:?}",
            p.force_n
        );
    }
    let s = &ft.solver;
    let package = fingertip::loads::chip_loads(&s.model, &s.asm.node_force);
    let chip = ft.chip_loads();
    let share = chip.fz_n / mount[2];
    let area_share =
        (2.0 * c.inclusion_half_width_mm).powi(2) / (std::f64::consts::PI * c.radius_mm.powi(2));
    println!("pillar share of the mount's Fz {share:.4} (top-face area share {area_share:.4}, whole package {:.4})", package.fz_n / mount[2]);
    assert!(share > area_share && share < 1.0, "pillar share {share}");
    assert!(
        (chip.fz_n - package.fz_n).abs() > 1e-3 * chip.fz_n.abs(),
        "the side walls carry nothing: {chip:?} vs {package:?}"
    );
}

/// Rotating the azimuth by 90° rotates (Mx, My) by 90° and leaves Fz and the rod force
/// unchanged (the mesh has the square's symmetry exactly).
#[test]
fn azimuth_rotates_the_moment() {
    let run = |phi: f64| {
        let mut c = coarse(Material::NeoHookean);
        c.contact_angle_deg = 20.0;
        c.azimuth_deg = phi;
        Fingertip::new(c).unwrap().step_to(1.5, 1.0).unwrap()
    };
    let (a, b) = (run(30.0), run(120.0));
    let m = a.mx_nm.hypot(a.my_nm);
    assert!(m > 0.0);
    assert!(
        (b.mx_nm + a.my_nm).abs() < 1e-5 * m && (b.my_nm - a.mx_nm).abs() < 1e-5 * m,
        "{a:?} {b:?}"
    );
    assert!((a.fz_n - b.fz_n).abs() < 1e-5 * a.fz_n.abs());
    // In the tilt plane at phi, the moment vector is about the in-plane normal (sin phi, -cos phi).
    let phi = 30f64.to_radians();
    let along = a.mx_nm * phi.sin() - a.my_nm * phi.cos();
    assert!(
        along.abs() > 0.9 * m,
        "moment not about the tilt-plane normal: {a:?}"
    );
}

/// Every stress of the model is proportional to E at fixed nu and geometry: doubling E
/// doubles forces and moments at the same rod travel (the diagnosis calibrates E with this).
#[test]
fn response_scales_linearly_with_youngs_modulus() {
    let run = |e: f64| {
        let mut c = coarse(Material::NeoHookean);
        c.youngs_modulus_pa = e;
        c.contact_angle_deg = 10.0;
        Fingertip::new(c).unwrap().step_to(2.0, 1.0).unwrap()
    };
    let (a, b) = (run(0.1e6), run(0.3e6));
    // Mx is zero by symmetry (tilt plane y = 0): compare it on the scale of the moment.
    let m = b.mx_nm.hypot(b.my_nm);
    for (x, y, scale) in [
        (a.force_n, b.force_n, b.force_n),
        (a.fz_n, b.fz_n, b.fz_n),
        (a.mx_nm, b.mx_nm, m),
        (a.my_nm, b.my_nm, m),
    ] {
        assert!((y - 3.0 * x).abs() < 1e-5 * scale.abs(), "{x} {y}");
    }
}

/// The penalty is stiff enough not to matter: twice the penalty moves the force < 1 %.
#[test]
fn penalty_does_not_drive_the_answer() {
    let run = |factor: f64| {
        let mut ft = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
        ft.solver.contact_k.iter_mut().for_each(|k| *k *= factor);
        ft.step_to(2.0, 1.0).unwrap().force_n
    };
    let (a, b) = (run(1.0), run(2.0));
    assert!((a - b).abs() < 0.01 * a, "{a} {b}");
}

/// Compression reaches the peak with the requested number of steps and a rising curve.
#[test]
fn compression_reaches_the_peak_monotonically() {
    let mut c = coarse(Material::NeoHookean);
    c.contact_angle_deg = 20.0;
    c.azimuth_deg = 60.0;
    let curve = fingertip::compress(&c, 10.0).unwrap();
    let last = curve.points.last().unwrap();
    assert!((last.force_n - 10.0).abs() < 0.05, "{last:?}");
    assert!(curve.points.len() > c.load_steps);
    assert!(curve
        .points
        .windows(2)
        .all(|w| w[1].force_n > w[0].force_n && w[1].rod_mm > w[0].rod_mm));
    // Tilt plane at 60°: the x moment dominates (paper observation 4).
    assert!(last.mx_nm.abs() > last.my_nm.abs());
}

/// Haptic mode: the condensed model reproduces the base state exactly and a small extra
/// travel to within 2 % of a full nonlinear solve.
#[test]
fn haptic_update_tracks_the_full_model() {
    let mut ft = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
    let base = ft.step_to(2.0, 1.0).unwrap();
    let mut h = fingertip::Haptic::new(&mut ft, 1.0).unwrap();
    let s0 = h.update(2.0);
    assert!((s0.force_n - base.force_n).abs() < 1e-6 * base.force_n);
    let s1 = h.update(2.1);
    let full = ft.step_to(2.1, 1.0).unwrap();
    assert!(
        (s1.force_n - full.force_n).abs()
            < 0.02 * (full.force_n - base.force_n).abs() + 0.005 * full.force_n,
        "{s1:?} {full:?}"
    );
    assert!(
        (s1.fz_n - full.fz_n).abs() < 0.03 * full.fz_n.abs(),
        "{s1:?} {full:?}"
    );
}

/// The mesh is valid and reasonably shaped, and its volume converges to the hemisphere's.
#[test]
fn mesh_quality_is_reasonable() {
    let quality = |h: f64| {
        let c = coarse(Material::Linear);
        let mesh = fingertip::mesh::generate(&fingertip::mesh::MeshParams {
            radius_mm: c.radius_mm,
            size_mm: h,
            inclusion_half_width_mm: c.inclusion_half_width_mm,
            inclusion_height_mm: c.inclusion_height_mm,
        });
        fingertip::quality::report(&mesh)
    };
    let (q8, q4, q2) = (quality(8.0), quality(4.0), quality(2.0));
    for q in [q8, q4, q2] {
        assert!(q.min_volume_m3 > 0.0);
        assert!(
            q.min_dihedral_deg > 5.0 && q.max_dihedral_deg < 170.0,
            "{q:?}"
        );
        assert!(q.max_aspect_ratio < 10.0, "{q:?}");
    }
    // Chords of the sphere cut volume off; the deficit falls like h^2.
    let (e8, e4, e2) = (
        1.0 - q8.volume_ratio,
        1.0 - q4.volume_ratio,
        1.0 - q2.volume_ratio,
    );
    assert!(
        e8 > e4 && e4 > e2 && e2 > 0.0 && e2 < 0.01,
        "{e8} {e4} {e2}"
    );
    assert!(q2.tets > q4.tets && q4.tets > q8.tets);
}

/// Deformed-mesh export writes a complete legacy VTK file.
#[test]
fn vtk_export_lists_every_point_and_cell() {
    let mut ft = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
    ft.step_to(1.0, 1.0).unwrap();
    let path = std::env::temp_dir().join(format!("fingertip-test-{}.vtk", std::process::id()));
    ft.write_vtk(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let q = ft.quality();
    assert!(text.contains(&format!("POINTS {} double", q.nodes)));
    assert!(text.contains(&format!("CELLS {} {}", q.tets, 5 * q.tets)));
}

/// Out-of-range configuration values are rejected with the field named.
#[test]
fn invalid_config_names_the_field() {
    let mut c = coarse(Material::Linear);
    c.poisson = 0.5;
    let err = Fingertip::new(c).unwrap_err().to_string();
    assert!(err.contains("poisson"), "{err}");
}

/// Prony-series viscoelasticity: pressed quickly, the gel is stiffer than the relaxed elastic
/// model; held at constant travel the force relaxes towards the relaxed model's force, and
/// the relaxed force is reached after many relaxation times.
#[test]
fn viscoelastic_gel_relaxes_towards_the_elastic_response() {
    let terms = vec![fingertip::PronyTerm { g: 0.4, tau_s: 1.0 }];
    let mut elastic = Fingertip::new(coarse(Material::NeoHookean)).unwrap();
    let relaxed = elastic.step_to(2.0, 1.0).unwrap().force_n;
    let mut visco = Fingertip::new(coarse(Material::ViscoNeoHookean(terms))).unwrap();
    let history: Vec<(f64, f64)> = [
        (0.05, 1.0),
        (0.1, 2.0),
        (0.6, 2.0),
        (1.6, 2.0),
        (4.0, 2.0),
        (30.0, 2.0),
    ]
    .to_vec();
    let pts = visco.follow(&history).unwrap();
    let fast = pts[1].force_n;
    assert!(fast > 1.3 * relaxed, "fast {fast} relaxed {relaxed}");
    assert!(
        pts.windows(2).skip(1).all(|w| w[1].force_n < w[0].force_n),
        "{pts:?}"
    );
    let last = pts.last().unwrap().force_n;
    assert!(
        (last - relaxed).abs() < 0.01 * relaxed,
        "{last} vs {relaxed}"
    );
}

/// Coulomb friction under an axial platen holds the contact patch from spreading outwards,
/// which stiffens the response; it keeps the axial symmetry (no moment).
#[test]
fn friction_stiffens_axial_indentation_and_keeps_symmetry() {
    let run = |mu: f64| {
        let mut c = coarse(Material::NeoHookean);
        c.friction_mu = mu;
        let mut ft = Fingertip::new(c).unwrap();
        ft.step_to(1.0, 1.0).unwrap();
        ft.step_to(2.0, 1.0).unwrap()
    };
    let (a, b) = (run(0.0), run(0.5));
    assert!(b.force_n > a.force_n, "{a:?} {b:?}");
    assert!(
        b.mx_nm.abs() < 1e-6 * b.fz_n.abs() * 0.02 && b.my_nm.abs() < 1e-6 * b.fz_n.abs() * 0.02,
        "{b:?}"
    );
}
