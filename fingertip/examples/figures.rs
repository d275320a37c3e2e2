//! The paper's qualitative observations, reproduced and plotted to `fingertip/figures/`:
//! power-law growth with rod travel (fitted exponents), Fz at theta_p = 20° against 0°,
//! Mx > My at phi = 60°, and the tilt-plane moment growing with theta_p.
//!
//! `cargo run --release -p fingertip --example figures [mesh_mm]`
//!
//! Gel, radius, package, peak load and angles come from `hardware/fingertip.toml`; the rod is a
//! platen of radius R (see the crate notes on the toml's 5 mm rod).

use std::fmt::Write as _;

use fingertip::{Config, Curve, Fingertip};
use plotters::prelude::*;

fn config(hw: &hardware::Fingertip, mesh_mm: f64, theta: f64, phi: f64) -> Config {
    Config {
        rod_radius_mm: hw.radius_mm,
        contact_angle_deg: theta,
        azimuth_deg: phi,
        load_steps: 30,
        ..Config::from_hardware(hw, mesh_mm)
    }
}

/// Least-squares exponent n of |y| = c x^n over the points above 10 % of the final travel.
fn power_law_exponent(curve: &Curve, f: impl Fn(&fingertip::CurvePoint) -> f64) -> f64 {
    let dmax = curve.points.last().map_or(0.0, |p| p.rod_mm);
    let pts: Vec<(f64, f64)> = curve
        .points
        .iter()
        .filter(|p| p.rod_mm > 0.1 * dmax && f(p).abs() > 0.0)
        .map(|p| (p.rod_mm.ln(), f(p).abs().ln()))
        .collect();
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / n, sy / n);
    let num: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let den: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    num / den
}

/// Moment about the tilt-plane normal (sin phi, -cos phi): the moment the tilt produces.
fn tilt_moment(p: &fingertip::CurvePoint, phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    p.mx_nm * phi.sin() - p.my_nm * phi.cos()
}

type Series<'a> = (&'a str, Vec<(f64, f64)>, RGBColor);

fn plot(
    path: &str,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (720, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let xmax = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.0))
        .fold(0.0, f64::max);
    let (ymin, ymax) = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.1))
        .fold((0.0f64, 0.0f64), |a, y| (a.0.min(y), a.1.max(y)));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..xmax * 1.02, (ymin * 1.05)..(ymax * 1.05))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()?;
    for (name, pts, color) in series {
        let c = *color;
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c));
        chart.draw_series(pts.iter().map(|p| Circle::new(*p, 2, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    root.present()?;
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let hw = hardware::Params::load_default()?.fingertip;
    let mesh_mm: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5.0);
    let peak = hw.test.peak_load_n;
    let phi = hw.test.azimuth_deg;
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/figures");
    std::fs::create_dir_all(dir)?;
    let mut summary = String::new();
    writeln!(summary, "E = {} Pa, nu = {}, R = {} mm, platen rod, mesh {mesh_mm} mm, peak {peak} N, phi = {phi} deg", hw.youngs_modulus_pa, hw.poisson, hw.radius_mm)?;

    let thetas = [0.0, 10.0, 20.0, 30.0];
    let curves = compress(&hw, mesh_mm, &thetas, &mut summary)?;
    compare(&curves, (peak, phi), &mut summary)?;
    print!("{summary}");
    std::fs::write(format!("{dir}/summary.txt"), &summary)?;

    draw(dir, &thetas, &curves, (peak, phi))
}

/// One compression to `peak` per contact angle of `thetas`, each summarised in `summary`.
fn compress(
    hw: &hardware::Fingertip,
    mesh_mm: f64,
    thetas: &[f64],
    summary: &mut String,
) -> Result<Vec<Curve>, Box<dyn std::error::Error>> {
    let (peak, phi) = (hw.test.peak_load_n, hw.test.azimuth_deg);
    let mut curves = Vec::new();
    for &theta in thetas {
        let cfg = config(hw, mesh_mm, theta, phi);
        let mut ft = Fingertip::new(cfg.clone())?;
        let c = ft.compress_to_peak(peak)?;
        let last = *c.points.last().ok_or("empty curve")?;
        // What the chip's pillar top carries, and its mean traction over the top face.
        let loads = ft.chip_loads();
        let top_m2 = (2.0 * cfg.inclusion_half_width_mm * 1e-3).powi(2);
        let mount = ft.mount_reaction();
        writeln!(
            summary,
            "theta {theta:4.1}: {} tets, solve {:.1} s; at {:.2} N: travel {:.3} mm, Fz {:.4} N, Mx {:.3e} N m, My {:.3e} N m, tilt moment {:.3e} N m; \
             pillar top (Fx, Fy, Fz) ({:.4}, {:.4}, {:.4}) N = {:.3} of the mount's Fz, mean traction ({:.1}, {:.1}, {:.1}) kPa",
            c.quality.tets, c.solve_s, last.force_n, last.rod_mm, last.fz_n, last.mx_nm, last.my_nm, tilt_moment(&last, phi),
            loads.fx_n, loads.fy_n, loads.fz_n, loads.fz_n / mount[2], 1e-3 * loads.fx_n / top_m2, 1e-3 * loads.fy_n / top_m2, 1e-3 * loads.fz_n / top_m2
        )?;
        curves.push(c);
    }
    Ok(curves)
}

/// The curves at 0 and 20 deg against what the paper reports, in `summary`.
fn compare(
    curves: &[Curve],
    (peak, phi): (f64, f64),
    summary: &mut String,
) -> Result<(), Box<dyn std::error::Error>> {
    let (c0, c20) = (&curves[0], &curves[2]);
    writeln!(
        summary,
        "power-law exponents vs travel, theta 0: force {:.3}, Fz {:.3} (Mx = My = 0 by symmetry)",
        power_law_exponent(c0, |p| p.force_n),
        power_law_exponent(c0, |p| p.fz_n)
    )?;
    writeln!(
        summary,
        "power-law exponents vs travel, theta 20: force {:.3}, Fz {:.3}, Mx {:.3}, My {:.3}",
        power_law_exponent(c20, |p| p.force_n),
        power_law_exponent(c20, |p| p.fz_n),
        power_law_exponent(c20, |p| p.mx_nm),
        power_law_exponent(c20, |p| p.my_nm)
    )?;
    let (p0, p20) = (
        c0.points.last().ok_or("empty")?,
        c20.points.last().ok_or("empty")?,
    );
    writeln!(
        summary,
        "Fz(20 deg)/Fz(0 deg) at {peak} N along the rod = {:.4} (paper: larger than 1)",
        p20.fz_n / p0.fz_n
    )?;
    writeln!(
        summary,
        "at phi = {phi} deg, theta 20: |Mx|/|My| = {:.3} (paper: Mx > My; tan(phi) = {:.3})",
        p20.mx_nm.abs() / p20.my_nm.abs(),
        phi.to_radians().tan()
    )?;
    Ok(())
}

/// The figures of the curves at the contact angles `thetas`, in `dir`.
fn draw(
    dir: &str,
    thetas: &[f64],
    curves: &[Curve],
    (peak, phi): (f64, f64),
) -> Result<(), Box<dyn std::error::Error>> {
    let (c0, c20) = (&curves[0], &curves[2]);
    let xy = |c: &Curve, f: &dyn Fn(&fingertip::CurvePoint) -> f64| {
        c.points
            .iter()
            .map(|p| (p.rod_mm, f(p)))
            .collect::<Vec<_>>()
    };
    plot(
        &format!("{dir}/force_fz_vs_travel.svg"),
        "Rod force and chip Fz against rod travel (neo-Hookean)",
        "rod travel (mm)",
        "N",
        &[
            ("rod force, theta 0", xy(c0, &|p| p.force_n), BLUE),
            ("rod force, theta 20", xy(c20, &|p| p.force_n), RED),
            ("-Fz x 10, theta 0", xy(c0, &|p| -10.0 * p.fz_n), CYAN),
            ("-Fz x 10, theta 20", xy(c20, &|p| -10.0 * p.fz_n), MAGENTA),
        ],
    )?;
    plot(
        &format!("{dir}/moments_vs_travel.svg"),
        &format!("Chip moments at theta 20, phi {phi} (N mm)"),
        "rod travel (mm)",
        "N mm",
        &[
            ("Mx", xy(c20, &|p| 1e3 * p.mx_nm), RED),
            ("My", xy(c20, &|p| 1e3 * p.my_nm), BLUE),
            ("Mx at theta 0", xy(c0, &|p| 1e3 * p.mx_nm), BLACK),
        ],
    )?;
    let tilt: Vec<(f64, f64)> = thetas
        .iter()
        .zip(curves)
        .filter_map(|(t, c)| {
            c.points
                .last()
                .map(|p| (*t, 1e3 * tilt_moment(p, phi).abs()))
        })
        .collect();
    let fz: Vec<(f64, f64)> = thetas
        .iter()
        .zip(curves)
        .filter_map(|(t, c)| c.points.last().map(|p| (*t, -10.0 * p.fz_n)))
        .collect();
    plot(
        &format!("{dir}/tilt_moment_vs_angle.svg"),
        &format!("At {peak} N: tilt-plane moment and Fz against theta_p"),
        "theta_p (deg)",
        "N mm  /  N x 10",
        &[
            ("|tilt-plane moment| (N mm)", tilt, RED),
            ("-Fz x 10 (N)", fz, BLUE),
        ],
    )?;
    Ok(())
}
