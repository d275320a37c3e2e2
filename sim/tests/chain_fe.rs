//! The FE path of the chain: the fingertip FE (crate `fingertip`) compresses the gel with the
//! standard test's rod; its resultant on the package inclusion at each step becomes the load
//! history (`load::Table::from_resultants`), the pillar takes the mean traction over its top, and
//! the chain turns it into ADC-input volts. The check the HIL issue asks for: does the 60 N test
//! stay inside the ADC's +-1.2 V at 0 and 20 deg? The FE takes minutes, so it is ignored by
//! default: `cargo test -p sim --test chain_fe -- --ignored --nocapture`.

use sim::chain::Chain;
use sim::load::Table;

/// FE rows `(t_s, rod_mm, load_n, [fx, fy, fz])`: unloaded, then at the peak load.
fn fe_rows(
    p: &hardware::Params,
    contact_angle_deg: f64,
    rod_radius_mm: f64,
) -> Vec<(f64, f64, f64, [f64; 3])> {
    let f = &p.fingertip;
    let config = fingertip::Config {
        rod_radius_mm,
        contact_angle_deg,
        ..fingertip::Config::from_hardware(f, 5.0)
    };
    let mut ft = fingertip::Fingertip::new(config).expect("fingertip model");
    let curve = ft
        .compress_to_peak(f.test.peak_load_n)
        .expect("compress to the peak");
    let peak = curve.points.last().expect("a curve");
    // The in-plane resultant is known for the current (peak) state only: the history is the
    // unloaded start and the peak.
    let loads = ft.chip_loads();
    vec![
        (0.0, 0.0, 0.0, [0.0; 3]),
        (
            1.0,
            peak.rod_mm,
            peak.force_n,
            [loads.fx_n, loads.fy_n, loads.fz_n],
        ),
    ]
}

#[test]
#[ignore = "runs the fingertip FE to 60 N: cargo test -p sim --test chain_fe -- --ignored --nocapture"]
fn fe_sixty_newton_test_against_the_adc_range() {
    let p = hardware::Params::load_default().unwrap();
    let radius_m = p.fingertip.inclusion_radius_mm * 1e-3;
    // fingertip.toml's 5 mm rod lets the gel wrap round its rim before 60 N (`tactile fe`); a
    // platen as wide as the fingertip reaches the peak.
    let rod_radius_mm = std::env::var("TACTILE_FE_ROD_RADIUS_MM")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(p.fingertip.radius_mm);
    for angle in [0.0, 20.0] {
        let rows = fe_rows(&p, angle, rod_radius_mm);
        let end = rows.last().unwrap().0;
        let mut chain = Chain::from_params(&p, Table::from_resultants(&rows, radius_m)).unwrap();
        chain.dac_codes = chain.front_end.null_codes();
        let c = chain.contact(end);
        let load = chain.chip_load(end);
        let v = chain.truth_v(end);
        let fs = chain.front_end.adc.full_scale_v(0);
        eprintln!(
            "FE, theta_p {angle} deg, rod {rod_radius_mm} mm, {:.1} N: package traction ({:.0}, {:.0}, {:.0}) Pa; \
             chip Fz {:.3} mN, Mx {:.3} N·um, My {:.3} N·um; ADC input Fz {:+.3} V, Mx {:+.3} V, My {:+.3} V of +-{fs} V",
            c.load_n,
            c.traction.tx_pa,
            c.traction.ty_pa,
            c.traction.tz_pa,
            load.fz_n * 1e3,
            load.mx_nm * 1e6,
            load.my_nm * 1e6,
            v[0],
            v[1],
            v[2]
        );
        assert!(
            (c.load_n - p.fingertip.test.peak_load_n).abs() < 1.0,
            "the FE reached {} N",
            c.load_n
        );
        assert!(load.fz_n > 0.0, "the gel presses on the pillar");
    }
}
