//! Plots of the observation scorecard to `fingertip/figures/`: Fz against the inclination,
//! the moments against the rod travel, the recovery after the fast return, and the elastic
//! energy along the inclination (LMEE), for the default model and the causes that change them.
//!
//! `cargo run --release -p fingertip --example observations [mesh_mm]`

use fingertip::observations::{self, causes, energy, tilt_moment_nm, Scorecard, Setup};
use fingertip::{Config, CurvePoint};
use plotters::prelude::*;
use sim::effects::HighpassCoupling;

type Series = (String, Vec<(f64, f64)>, RGBColor);
const COLORS: [RGBColor; 4] = [BLUE, RED, RGBColor(0, 140, 0), RGBColor(200, 120, 0)];

fn plot(
    path: &str,
    title: &str,
    axes: (&str, &str),
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (760, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let all = || series.iter().flat_map(|s| s.1.iter().copied());
    let (x0, x1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.0), a.1.max(p.0))
    });
    let (y0, y1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.1), a.1.max(p.1))
    });
    let pad = 0.05 * (y1 - y0).abs().max(1e-12);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))?;
    chart
        .configure_mesh()
        .x_desc(axes.0)
        .y_desc(axes.1)
        .draw()?;
    for (name, pts, color) in series {
        let c = *color;
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c));
        chart.draw_series(pts.iter().map(|p| Circle::new(*p, 2, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerLeft)
        .draw()?;
    root.present()?;
    Ok(())
}

/// A cause of the table applied to `base` (the names are the library's own).
fn cause(base: &Config, name: &str) -> Config {
    causes::apply_named(base, name).unwrap_or_else(|| base.clone())
}

/// Each output over its own peak magnitude, against `x`.
fn normalised(
    card: &Scorecard,
    x: fn(&CurvePoint) -> f64,
    y: &dyn Fn(&CurvePoint) -> f64,
    loading: bool,
) -> Vec<(f64, f64)> {
    let pts = &card.series.points;
    let end = if loading {
        card.series.loading_len
    } else {
        pts.len()
    };
    let peak = y(&pts[card.series.loading_len - 1])
        .abs()
        .max(f64::MIN_POSITIVE);
    pts[..end].iter().map(|p| (x(p), y(p) / peak)).collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let hw = hardware::Params::load_default()?.fingertip;
    let mesh_mm: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5.0);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/figures");
    let base = Config::from_hardware(&hw, mesh_mm);
    let ac = |t: &[f64], y: &mut [f64]| HighpassCoupling { tau_s: 25.0 }.apply(t, y);
    let default = observations::score(&Setup::from_hardware(base.clone(), &hw, "default", None))?;
    let along_z = observations::score(&Setup::from_hardware(
        cause(&base, "drive_along_z"),
        &hw,
        "drive along z",
        None,
    ))?;
    let visco = observations::score(&Setup::from_hardware(
        cause(&base, "viscoelastic_gel"),
        &hw,
        "viscoelastic gel + AC coupling 25 s",
        Some(&ac),
    ))?;
    let phi = default.azimuth_deg;

    plot_inclination(dir, &default, &along_z)?;
    plot_travel(dir, &default, phi)?;
    plot_recovery(dir, (&default, &visco), phi)?;
    plot_lmee(dir, &base)?;
    for card in [&default, &along_z, &visco] {
        println!("{}: disagreements {:?}", card.label, card.disagreements());
    }
    Ok(())
}

/// Fz against the inclination, over Fz at 0 deg, for the jig and an upright drive.
fn plot_inclination(
    dir: &str,
    default: &Scorecard,
    along_z: &Scorecard,
) -> Result<(), Box<dyn std::error::Error>> {
    let fz_rel = |card: &Scorecard| -> Vec<(f64, f64)> {
        let f0 = card.sweep[0].1.fz_n;
        card.sweep.iter().map(|(t, p)| (*t, p.fz_n / f0)).collect()
    };
    let cos: Vec<(f64, f64)> = (0..=30)
        .map(|t| (t as f64, (t as f64).to_radians().cos()))
        .collect();
    plot(
        &format!("{dir}/obs_fz_vs_inclination.svg"),
        "Chip Fz at 60 N against theta_p, over Fz at 0 deg",
        ("theta_p [deg]", "Fz / Fz(0)"),
        &[
            (
                "default (jig, drive along the rod)".into(),
                fz_rel(default),
                COLORS[0],
            ),
            (
                "drive along z (upright, inclined rod end)".into(),
                fz_rel(along_z),
                COLORS[1],
            ),
            ("cos theta_p".into(), cos, COLORS[2]),
        ],
    )?;
    Ok(())
}

/// The chip's outputs against the rod travel, each over its peak.
fn plot_travel(dir: &str, default: &Scorecard, phi: f64) -> Result<(), Box<dyn std::error::Error>> {
    let travel = |p: &CurvePoint| p.rod_mm;
    plot(
        &format!("{dir}/obs_moments_vs_travel.svg"),
        "Chip outputs against rod travel, theta_p = 20, phi = 60 (each over its peak)",
        ("rod travel [mm]", "output / peak"),
        &[
            (
                "Fz".into(),
                normalised(default, travel, &|p| p.fz_n, true),
                COLORS[0],
            ),
            (
                "Mx".into(),
                normalised(default, travel, &|p| p.mx_nm, true),
                COLORS[1],
            ),
            (
                "My".into(),
                normalised(default, travel, &|p| p.my_nm, true),
                COLORS[2],
            ),
            (
                "tilt moment".into(),
                normalised(default, travel, &|p| tilt_moment_nm(p, phi), true),
                COLORS[3],
            ),
        ],
    )?;
    Ok(())
}

/// The recovery after the fast return, elastic and viscoelastic.
fn plot_recovery(
    dir: &str,
    (default, visco): (&Scorecard, &Scorecard),
    phi: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let time = |p: &CurvePoint| p.t_s;
    plot(
        &format!("{dir}/obs_recovery.svg"),
        "The standard test: press, 2 s hold, fast return, recovery (each over its peak)",
        ("time [s]", "output / peak"),
        &[
            (
                "Fz, default (elastic)".into(),
                normalised(default, time, &|p| p.fz_n, false),
                COLORS[0],
            ),
            (
                "Fz, viscoelastic + AC coupling".into(),
                normalised(visco, time, &|p| p.fz_n, false),
                COLORS[1],
            ),
            (
                "tilt moment, viscoelastic + AC coupling".into(),
                normalised(visco, time, &|p| tilt_moment_nm(p, phi), false),
                COLORS[2],
            ),
        ],
    )?;
    Ok(())
}

/// The elastic energy along the inclination (LMEE), jig and upright.
fn plot_lmee(dir: &str, base: &Config) -> Result<(), Box<dyn std::error::Error>> {
    let thetas = [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0];
    let mut lmee = Vec::new();
    for (k, (name, c)) in [
        ("jig (drive along the rod)", base.clone()),
        ("upright (drive along z)", cause(base, "drive_along_z")),
    ]
    .into_iter()
    .enumerate()
    {
        let pts = energy::energy_along_inclination(&c, &thetas, 8.0, 10)?;
        let u0 = pts[0].energy_j;
        println!(
            "{name}: {:?}",
            pts.iter()
                .map(|p| (p.theta_deg, p.energy_j, p.fz_n))
                .collect::<Vec<_>>()
        );
        lmee.push((
            name.to_string(),
            pts.iter().map(|p| (p.theta_deg, p.energy_j / u0)).collect(),
            COLORS[k],
        ));
    }
    plot(
        &format!("{dir}/obs_lmee.svg"),
        "Elastic potential energy at 8 mm of rod travel, over its value at 0 deg",
        ("theta_p [deg]", "U / U(0)"),
        &lmee,
    )?;
    Ok(())
}
