//! Speed benchmarks of the fingertip model, printing ratios against limits and peers measured
//! in the same run (never asserted; timings on a shared machine vary).
//!
//! ```text
//! cargo bench -p fingertip --bench fe_bench                 # curve, haptic, literature ratio
//! bench/fe-peer/run.sh                                      # + the scikit-fem peer (needs the venv)
//! cargo bench -p fingertip --bench fe_bench -- peer         # peer only (venv already made)
//! PEER_MESH_MM=5 OUR_MESH_MM=4 cargo bench -p fingertip --bench fe_bench -- peer
//! ```
//! (peer mesh 3 mm did not finish in 30 min on the shared 2-core machine.)
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
    println!("peak: travel {:.3} mm (d/R {:.3}), force {:.3} N, Fz {:.4} N", last.rod_mm, last.rod_mm / hw.radius_mm, last.force_n, last.fz_n);
    println!("ratio wall / {CURVE_LIMIT_S} s limit = {:.2} (goal <= 1)", wall / CURVE_LIMIT_S);
    println!("cpu {cpu:.2} s over all threads (the machine is shared: wall > cpu / threads means we were starved)");
    println!("load average at the end: {}", std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim());
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
    println!("{} condensed contact dofs, condensation {:.3} s; mean update {:.2} us (checksum {acc:.3})", h.len(), setup, per * 1e6);
    println!("ratio update / {:.1} ms goal = {:.3} (goal <= 1)", HAPTIC_LIMIT_S * 1e3, per / HAPTIC_LIMIT_S);
    println!("ratio literature 10.62 ms/frame (300-tet projective dynamics) / update = {:.0}x", LITERATURE_FRAME_S / per);
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
        ft.step_to(1.0 + 0.05 * (k + 1) as f64, 0.15).expect("frame");
    }
    let per = t0.elapsed().as_secs_f64() / n as f64;
    println!("full nonlinear step on {tets} tets: {:.2} ms; ratio 10.62 ms / step = {:.1}x", per * 1e3, LITERATURE_FRAME_S / per);
}

/// CPU time of this process (all threads), s, from /proc (Linux; 100 ticks per second).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit(')').next().unwrap_or("");
    let f: Vec<f64> = after.split_whitespace().filter_map(|s| s.parse().ok()).collect();
    // Fields after the command: state is not numeric, so utime/stime are at 10/11 here.
    f.get(10).zip(f.get(11)).map_or(f64::NAN, |(u, s)| (u + s) / 100.0)
}

/// The scikit-fem peer on the same linear-elastic problem, if its venv exists.
fn peer_bench(hw: &hardware::Fingertip) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let python = root.join("bench/fe-peer/.venv/bin/python");
    let script = root.join("bench/fe-peer/peer.py");
    if !python.exists() {
        println!("== peer: skipped, run bench/fe-peer/run.sh to create the venv ==");
        return;
    }
    let peer_h = std::env::var("PEER_MESH_MM").ok().and_then(|s| s.parse().ok()).unwrap_or(4.0);
    let travels = [0.5, 1.0, 1.5, 2.0];
    let config = nominal(hw, Material::Linear, std::env::var("OUR_MESH_MM").ok().and_then(|s| s.parse().ok()).unwrap_or(4.0));
    let t0 = Instant::now();
    let c0 = cpu_s();
    let mut ft = Fingertip::new(config.clone()).expect("model");
    let ours: Vec<f64> = travels.iter().map(|&d| ft.step_to(d, 1.0).expect("step").force_n).collect();
    let our_s = t0.elapsed().as_secs_f64();
    let our_cpu = cpu_s() - c0;
    let out = Command::new(&python)
        .arg(&script)
        .args(["--radius-mm", &config.radius_mm.to_string(), "--youngs-modulus", &config.youngs_modulus_pa.to_string()])
        .args(["--poisson", &config.poisson.to_string(), "--mesh-mm", &peer_h.to_string()])
        .args(["--inclusion-half-width-mm", &config.inclusion_half_width_mm.to_string(), "--inclusion-height-mm", &config.inclusion_height_mm.to_string()])
        .arg("--travels-mm")
        .args(travels.iter().map(|t| t.to_string()))
        .output()
        .expect("running the peer");
    if !out.status.success() {
        println!("== peer failed ==\n{}", String::from_utf8_lossy(&out.stderr));
        return;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut peer = Vec::new();
    let mut peer_s = f64::NAN;
    let mut peer_cpu = f64::NAN;
    let mut peer_info = String::new();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("force ") {
            peer.push(rest.split_whitespace().nth(1).and_then(|s| s.parse::<f64>().ok()).unwrap_or(f64::NAN));
        } else if let Some(rest) = line.strip_prefix("wall_s ") {
            peer_s = rest.trim().parse().unwrap_or(f64::NAN);
        } else if let Some(rest) = line.strip_prefix("cpu_s ") {
            peer_cpu = rest.trim().parse().unwrap_or(f64::NAN);
        } else {
            peer_info.push_str(line);
            peer_info.push('\n');
        }
    }
    println!("== peer: scikit-fem (P2 tets, gmsh mesh, exact active-set contact) vs fingertip (P1 nodal-pressure tets, penalty) ==");
    print!("{peer_info}");
    let q = ft.quality();
    println!("fingertip mesh {:.2} mm: {} tets, {} nodes", config.mesh_size_mm, q.tets, q.nodes);
    println!("travel_mm  fingertip_n  peer_n  difference_%");
    for (i, d) in travels.iter().enumerate() {
        let p = peer.get(i).copied().unwrap_or(f64::NAN);
        println!("{d:9.3}  {:11.5}  {p:6.5}  {:+8.2}", ours[i], 100.0 * (ours[i] - p) / p);
    }
    println!("wall: fingertip {our_s:.3} s, peer {peer_s:.3} s; speed ratio peer/fingertip = {:.1}x (goal >= 20)", peer_s / our_s);
    println!("cpu:  fingertip {our_cpu:.2} s, peer {peer_cpu:.2} s; cpu ratio peer/fingertip = {:.1}x", peer_cpu / our_cpu);
}

fn main() {
    let hw = hardware::Params::load_default().expect("hardware/").fingertip;
    let only: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let want = |name: &str| only.is_empty() || only.iter().any(|o| o == name);
    println!("machine: {} threads, {}", std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1), std::env::consts::ARCH);
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
