//! Speed benchmarks of the fingertip model, printing ratios against limits and peers measured
//! in the same run (never asserted; timings on a shared machine vary).
//!
//! ```text
//! cargo bench -p fingertip --bench fe_bench                 # curve, haptic, literature ratio
//! bench/fe-peer/run.sh                                      # + the scikit-fem peer (needs the venv)
//! cargo bench -p fingertip --bench fe_bench -- peer         # peer only (venv already made)
//! PEER_MESH_MM=5 OUR_MESH_MM=4 cargo bench -p fingertip --bench fe_bench -- peer
//! ```
//! The peer section takes ~13 minutes on 2 cores, nearly all of it the peer's fine run
//! (42,582 P2 dofs, one sparse LU per active-set change); a peer mesh of 3 mm everywhere did
//! not finish in 30 minutes.
//!
//! Parameters come from `hardware/fingertip.toml` (gel, radius, package); the rod is a platen
//! of radius R (the toml's 5 mm rod cannot reach 60 N without the gel wrapping round it, see
//! the crate notes).

use std::process::Command;
use std::time::Instant;

use fingertip::{Config, Fingertip, Haptic, Material};

/// The issue's goal for the full 60 N neo-Hookean curve.
const CURVE_LIMIT_S: f64 = 5.0;
/// The haptic goal per 1 kHz update.
const HAPTIC_LIMIT_S: f64 = 0.2e-3;
/// Projective dynamics, 300 tetrahedra, per frame (Kang et al., Sensors 2022, 22, 7225).
const LITERATURE_FRAME_S: f64 = 10.62e-3;
const MIN_TETS: usize = 10_000;

fn nominal(hw: &hardware::Fingertip, material: Material, mesh_size_mm: f64) -> Config {
    Config {
        material,
        rod_radius_mm: hw.radius_mm,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        ..Config::from_hardware(hw, mesh_size_mm)
    }
}

/// The coarsest nominal mesh size with at least `MIN_TETS` tetrahedra.
fn mesh_size_for_min_tets(hw: &hardware::Fingertip) -> f64 {
    let mut h = 8.0;
    while h > 1.0 {
        let c = nominal(hw, Material::NeoHookean, h);
        let mesh = fingertip::mesh::generate(&fingertip::mesh::MeshParams {
            radius_mm: c.radius_mm,
            size_mm: h,
            inclusion_half_width_mm: c.inclusion_half_width_mm,
            inclusion_height_mm: c.inclusion_height_mm,
        });
        if mesh.tets.len() >= MIN_TETS {
            return h;
        }
        h *= 0.95;
    }
    h
}

fn curve_bench(hw: &hardware::Fingertip) {
    let h = mesh_size_for_min_tets(hw);
    let config = nominal(hw, Material::NeoHookean, h);
    let t0 = Instant::now();
    let c0 = cpu_s();
    let curve = fingertip::compress(&config, hw.test.peak_load_n).expect("nominal curve");
    let wall = t0.elapsed().as_secs_f64();
    let cpu = cpu_s() - c0;
    let q = &curve.quality;
    let s = &curve.stats;
    println!("== full {} N neo-Hookean curve ==", hw.test.peak_load_n);
    println!(
        "mesh {:.2} mm: {} tets, {} nodes, {} dofs, factor nnz {}; {} load steps, {} Newton its, {} factorisations ({} in the background), {} GMRES its, {} cutbacks",
        h,
        q.tets,
        q.nodes,
        curve.dofs,
        curve.factor_nnz,
        curve.points.len() - 1,
        s.newton_iterations,
        s.factorizations,
        s.background_factorizations,
        s.krylov_iterations,
        s.cutbacks
    );
    println!("wall {wall:.3} s (assembly {:.3} s, factor {:.3} s on the Newton path, solve {:.3} s), rayon threads {}", s.assembly_s, s.factor_s, s.solve_s, rayon::current_num_threads());
    let last = curve.points.last().expect("points");
    println!(
        "peak: travel {:.3} mm (d/R {:.3}), force {:.3} N, Fz {:.4} N",
        last.rod_mm,
        last.rod_mm / hw.radius_mm,
        last.force_n,
        last.fz_n
    );
    println!(
        "ratio wall / {CURVE_LIMIT_S} s limit = {:.2} (goal <= 1)",
        wall / CURVE_LIMIT_S
    );
    println!("cpu {cpu:.2} s over all threads (the machine is shared: wall > cpu / threads means we were starved)");
    println!(
        "load average at the end: {}",
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
}

fn haptic_bench(hw: &hardware::Fingertip) {
    let mut config = nominal(hw, Material::NeoHookean, mesh_size_for_min_tets(hw));
    config.contact_angle_deg = hw.test.contact_angle_deg;
    config.azimuth_deg = hw.test.azimuth_deg;
    let mut ft = Fingertip::new(config).expect("model");
    let base_mm = 3.0;
    ft.step_to(1.5, 1.0).expect("half way");
    ft.step_to(base_mm, 1.0).expect("base state");
    let t0 = Instant::now();
    let mut h = Haptic::new(&mut ft, 1.0).expect("condensation");
    let setup = t0.elapsed().as_secs_f64();
    let n = 20_000;
    let t1 = Instant::now();
    let mut acc = 0.0;
    for k in 0..n {
        // A 1 kHz trajectory: +-0.2 mm, 5 Hz sine around the base state.
        let d = base_mm + 0.2 * (2.0 * std::f64::consts::PI * 5.0 * k as f64 * 1e-3).sin();
        acc += h.update(d).force_n;
    }
    let per = t1.elapsed().as_secs_f64() / n as f64;
    println!("== haptic mode ==");
    println!(
        "{} condensed contact dofs, condensation {:.3} s; mean update {:.2} us (checksum {acc:.3})",
        h.len(),
        setup,
        per * 1e6
    );
    println!(
        "ratio update / {:.1} ms goal = {:.3} (goal <= 1)",
        HAPTIC_LIMIT_S * 1e3,
        per / HAPTIC_LIMIT_S
    );
    println!(
        "ratio literature 10.62 ms/frame (300-tet projective dynamics) / update = {:.0}x",
        LITERATURE_FRAME_S / per
    );
    literature_full_step(hw);
}

/// A full nonlinear frame on a ~300-tetrahedron mesh, for a like-for-like comparison with the
/// 300-tet projective-dynamics figure.
fn literature_full_step(hw: &hardware::Fingertip) {
    let mut c = nominal(hw, Material::NeoHookean, 10.0);
    c.inclusion_half_width_mm = 5.0;
    c.inclusion_height_mm = 5.0;
    let mut ft = Fingertip::new(c).expect("small model");
    let tets = ft.quality().tets;
    ft.step_to(1.0, 1.0).expect("first step");
    let n = 20;
    let t0 = Instant::now();
    for k in 0..n {
        ft.step_to(1.0 + 0.05 * (k + 1) as f64, 0.15)
            .expect("frame");
    }
    let per = t0.elapsed().as_secs_f64() / n as f64;
    println!(
        "full nonlinear step on {tets} tets: {:.2} ms; ratio 10.62 ms / step = {:.1}x",
        per * 1e3,
        LITERATURE_FRAME_S / per
    );
}

/// CPU time of this process (all threads), s, from /proc (Linux; 100 ticks per second).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit(')').next().unwrap_or("");
    let f: Vec<f64> = after
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    // Fields after the command: state is not numeric, so utime/stime are at 10/11 here.
    f.get(10)
        .zip(f.get(11))
        .map_or(f64::NAN, |(u, s)| (u + s) / 100.0)
}

/// Rod travels of the peer comparison, mm.
const PEER_TRAVELS_MM: [f64; 4] = [0.5, 1.0, 1.5, 2.0];
/// The goal for the difference of the converged curves.
const PEER_DIFFERENCE_GOAL: f64 = 0.03;
/// A curve point counts as converged when it moved less than this between the two meshes.
const CONVERGED_CHANGE: f64 = 0.02;

/// One force–travel curve and what it cost.
struct Run {
    forces: Vec<f64>,
    wall_s: f64,
    cpu_s: f64,
    mesh: String,
}

fn env_mm(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// Our linear curve at nominal mesh size `h_mm`.
fn our_run(hw: &hardware::Fingertip, h_mm: f64) -> Run {
    let t0 = Instant::now();
    let c0 = cpu_s();
    let mut ft = Fingertip::new(nominal(hw, Material::Linear, h_mm)).expect("model");
    let forces = PEER_TRAVELS_MM
        .iter()
        .map(|&d| ft.step_to(d, 1.0).expect("step").force_n)
        .collect();
    let q = ft.quality();
    Run {
        forces,
        wall_s: t0.elapsed().as_secs_f64(),
        cpu_s: cpu_s() - c0,
        mesh: format!("fingertip {h_mm} mm: {} tets, {} nodes", q.tets, q.nodes),
    }
}

/// The peer's curve (a separate process), or why it failed.
fn peer_run(hw: &hardware::Fingertip, mesh_mm: f64, pole_mm: f64) -> Result<Run, String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let config = nominal(hw, Material::Linear, mesh_mm);
    let out = Command::new(root.join("bench/fe-peer/.venv/bin/python"))
        .arg(root.join("bench/fe-peer/peer.py"))
        .args([
            "--radius-mm",
            &config.radius_mm.to_string(),
            "--youngs-modulus",
            &config.youngs_modulus_pa.to_string(),
        ])
        .args([
            "--poisson",
            &config.poisson.to_string(),
            "--mesh-mm",
            &mesh_mm.to_string(),
            "--pole-mm",
            &pole_mm.to_string(),
        ])
        .args([
            "--inclusion-half-width-mm",
            &config.inclusion_half_width_mm.to_string(),
            "--inclusion-height-mm",
            &config.inclusion_height_mm.to_string(),
        ])
        .arg("--travels-mm")
        .args(PEER_TRAVELS_MM.iter().map(|t| t.to_string()))
        .output()
        .map_err(|e| format!("running the peer: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    let mut run = Run {
        forces: Vec::new(),
        wall_s: f64::NAN,
        cpu_s: f64::NAN,
        mesh: String::new(),
    };
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let value = |rest: &str| {
            rest.split_whitespace()
                .last()
                .and_then(|s| s.parse::<f64>().ok())
                .unwrap_or(f64::NAN)
        };
        if let Some(rest) = line.strip_prefix("force ") {
            run.forces.push(value(rest));
        } else if let Some(rest) = line.strip_prefix("wall_s ") {
            run.wall_s = value(rest);
        } else if let Some(rest) = line.strip_prefix("cpu_s ") {
            run.cpu_s = value(rest);
        } else {
            run.mesh.push_str(line);
        }
    }
    match run.forces.len() == PEER_TRAVELS_MM.len() {
        true => Ok(run),
        false => Err(format!(
            "the peer printed {} forces for {} travels",
            run.forces.len(),
            PEER_TRAVELS_MM.len()
        )),
    }
}

/// The scikit-fem peer on the same linear-elastic problem, if its venv exists: each side on a
/// coarse and a fine mesh (ours: nominal size halved; the peer: P2 elements, its size under
/// the contact halved), the fine curves compared where both moved < CONVERGED_CHANGE, and the
/// wall-time ratios at both levels.
fn peer_bench(hw: &hardware::Fingertip) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    if !root.join("bench/fe-peer/.venv/bin/python").exists() {
        println!("== peer: skipped, run bench/fe-peer/run.sh to create the venv ==");
        return;
    }
    let peer_h = env_mm("PEER_MESH_MM", 4.0);
    let (peer_pole_coarse, peer_pole_fine) = (
        env_mm("PEER_POLE_MM", peer_h / 2.0),
        env_mm("PEER_FINE_POLE_MM", peer_h / 4.0),
    );
    let (our_coarse, our_fine) = (env_mm("OUR_MESH_MM", 4.0), env_mm("OUR_FINE_MESH_MM", 2.0));
    let ours = [our_run(hw, our_coarse), our_run(hw, our_fine)];
    let peer = match (
        peer_run(hw, peer_h, peer_pole_coarse),
        peer_run(hw, peer_h, peer_pole_fine),
    ) {
        (Ok(a), Ok(b)) => [a, b],
        (Err(e), _) | (_, Err(e)) => {
            println!("== peer failed ==\n{e}");
            return;
        }
    };
    println!("== peer: scikit-fem (P2 tets, gmsh mesh, exact active-set contact) vs fingertip (P1 nodal-pressure tets, penalty) ==");
    for r in ours.iter().chain(&peer) {
        println!("{}", r.mesh);
    }
    println!("travel_mm  ours_coarse  ours_fine  change_%  peer_coarse  peer_fine  change_%  fine_difference_%  converged");
    let mut worst: f64 = 0.0;
    for (i, d) in PEER_TRAVELS_MM.iter().enumerate() {
        let (o0, o1, p0, p1) = (
            ours[0].forces[i],
            ours[1].forces[i],
            peer[0].forces[i],
            peer[1].forces[i],
        );
        let (co, cp, diff) = (o1 / o0 - 1.0, p1 / p0 - 1.0, o1 / p1 - 1.0);
        let converged = co.abs() < CONVERGED_CHANGE && cp.abs() < CONVERGED_CHANGE;
        if converged {
            worst = worst.max(diff.abs());
        }
        println!("{d:9.3}  {o0:11.5}  {o1:9.5}  {:+8.2}  {p0:11.5}  {p1:9.5}  {:+8.2}  {:+17.2}  {converged}", 100.0 * co, 100.0 * cp, 100.0 * diff);
    }
    println!(
        "largest difference where both moved < {:.0} %: {:.2} % (goal <= {:.0} %)",
        100.0 * CONVERGED_CHANGE,
        100.0 * worst,
        100.0 * PEER_DIFFERENCE_GOAL
    );
    for (level, o, p) in [("coarse", &ours[0], &peer[0]), ("fine", &ours[1], &peer[1])] {
        println!("{level}: wall fingertip {:.3} s, peer {:.3} s, speed ratio peer/fingertip = {:.1}x (goal >= 20); cpu {:.2} s vs {:.2} s = {:.1}x", o.wall_s, p.wall_s, p.wall_s / o.wall_s, o.cpu_s, p.cpu_s, p.cpu_s / o.cpu_s);
    }
}

fn main() {
    let hw = hardware::Params::load_default()
        .expect("hardware/")
        .fingertip;
    let only: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let want = |name: &str| only.is_empty() || only.iter().any(|o| o == name);
    println!(
        "machine: {} threads, {}",
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
        std::env::consts::ARCH
    );
    if want("curve") {
        curve_bench(&hw);
    }
    if want("haptic") {
        haptic_bench(&hw);
    }
    if want("peer") {
        peer_bench(&hw);
    }
}
