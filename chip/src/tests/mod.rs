//! The model against hand-computed textbook cases, its symmetries, the bridges' isolation, the
//! frame finite-element check, Table I, and the calibration fit.

use crate::bridge::{bridge_outputs_v, output_v};
use crate::frame_fe::{self, FrameOptions};
use crate::params::*;
use crate::sensitivity::{inverse, multiply, sensitivity_matrix};
use crate::strength::strengths;
use crate::stress::{surface_stress_pa, torsion_shear_pa};
use crate::{fz, moment};

fn shipped() -> ChipParams {
    ChipParams::load_default().expect("hardware/chip.toml loads")
}

/// A textbook cross-beam: square 100 um beams 1 mm long, c as given.
fn textbook(c_m: f64) -> ChipParams {
    let mut p = shipped();
    p.geometry = Geometry {
        beam_length_m: 1e-3,
        beam_width_m: 100e-6,
        beam_thickness_m: 100e-6,
        block_half_width_m: c_m,
        pillar_height_m: 0.0,
        block_thickness_m: 525e-6,
    };
    p.silicon.youngs_modulus_pa = 169e9;
    p.silicon.shear_modulus_pa = 63.7e9;
    p
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
fn fz_guided_beam_matches_hand_calculation() {
    let p = textbook(0.2e-3);
    // P = 0.04/4 = 0.01 N; M(0) = P L/2 = 5e-6 N·m; Z = b h^2/6 = 1.6667e-13 m^3 -> 30 MPa.
    let s0 = surface_stress_pa(&p, Load::new(0.04, 0.0, 0.0), Beam::A, 0.0);
    assert!(close(s0, 30.0e6, 1e-9), "{s0}");
    let s_mid = surface_stress_pa(&p, Load::new(0.04, 0.0, 0.0), Beam::C, 0.5e-3);
    assert!(s_mid.abs() < 1e-6, "zero at mid-span: {s_mid}");
    let s_l = surface_stress_pa(&p, Load::new(0.04, 0.0, 0.0), Beam::D, 1e-3);
    assert!(close(s_l, -30.0e6, 1e-9), "{s_l}");
    // delta = Fz L^3 / (48 E I) = 0.04e-9 / (48 * 169e9 * 8.3333e-18) = 5.917e-7 m.
    let d = fz::block_deflection_m(&p.geometry, &p.silicon, 0.04);
    assert!(close(d, 5.9172e-7, 1e-4), "{d}");
}

#[test]
fn moment_without_block_matches_hand_calculation() {
    // c = 0: theta = M / (8EI/L + 2KG/L), K = 0.140833 b^4 (Roark), M = 1e-4 N·m.
    // EI = 1.408333e-6, 8EI/L = 1.126667e-2, 2KG/L = 1.794217e-3 -> theta = 7.65645e-3 rad.
    // Block end: M_RY = 4EI theta/L -> sigma = 258.788 MPa; frame end: -2EI theta/L -> -129.394 MPa.
    let p = textbook(0.0);
    let theta = moment::block_rotation_rad(&p.geometry, &p.silicon, 1e-4);
    assert!(close(theta, 7.656_450e-3, 1e-5), "{theta}");
    let load = Load::new(0.0, 0.0, 1e-4);
    // +My lowers beam A (its edge slopes down): compression at A's block end.
    let a_block = surface_stress_pa(&p, load, Beam::A, 1e-3);
    let a_frame = surface_stress_pa(&p, load, Beam::A, 0.0);
    assert!(close(a_block, -258.788e6, 1e-5), "{a_block}");
    assert!(close(a_frame, 129.394e6, 1e-5), "{a_frame}");
    // Torsion of C: T = K G theta / L = 6.8687e-6 N·m, tau = T / (0.208 b^3) = 33.02 MPa.
    let tau = torsion_shear_pa(&p, load, Beam::C);
    assert!(close(tau, 33.02e6, 5e-3), "{tau}");
}

#[test]
fn moment_with_block_matches_hand_calculation() {
    // c = 0.2 mm: theta = M / [(8EI/L)(1 + 3c/L + 3c^2/L^2) + 2KG/L] = 4.72302e-3 rad,
    // block end EI theta (6c/L^2 + 4/L)/Z = 207.530 MPa, frame end -EI theta (6c/L^2 + 2/L)/Z.
    let p = textbook(0.2e-3);
    let load = Load::new(0.0, 1e-4, 0.0);
    // +Mx lifts beam C: tension at its block end.
    let c_block = surface_stress_pa(&p, load, Beam::C, 1e-3);
    let c_frame = surface_stress_pa(&p, load, Beam::C, 0.0);
    assert!(close(c_block, 207.5296e6, 1e-5), "{c_block}");
    assert!(close(c_frame, -127.7105e6, 1e-5), "{c_frame}");
}

#[test]
fn beams_a_b_and_c_d_are_stressed_equal_and_opposite_under_moments() {
    let p = shipped();
    let l = p.geometry.beam_length_m;
    for i in 0..=10 {
        let x = l * i as f64 / 10.0;
        let my = Load::new(0.0, 0.0, 1e-4);
        let (a, b) = (
            surface_stress_pa(&p, my, Beam::A, x),
            surface_stress_pa(&p, my, Beam::B, x),
        );
        assert!(
            (a + b).abs() <= 1e-12 * a.abs().max(1.0),
            "My: A {a} B {b} at {x}"
        );
        assert_eq!(
            surface_stress_pa(&p, my, Beam::C, x),
            0.0,
            "C only twists under My"
        );
        let mx = Load::new(0.0, 1e-4, 0.0);
        let (c, d) = (
            surface_stress_pa(&p, mx, Beam::C, x),
            surface_stress_pa(&p, mx, Beam::D, x),
        );
        assert!(
            (c + d).abs() <= 1e-12 * c.abs().max(1.0),
            "Mx: C {c} D {d} at {x}"
        );
        assert_eq!(
            surface_stress_pa(&p, mx, Beam::A, x),
            0.0,
            "A only twists under Mx"
        );
        let fz = Load::new(1.0, 0.0, 0.0);
        let sa = surface_stress_pa(&p, fz, Beam::A, x);
        for beam in Beam::ALL {
            assert_eq!(
                surface_stress_pa(&p, fz, beam, x),
                sa,
                "Fz stresses all beams alike"
            );
        }
    }
}

#[test]
fn combined_load_is_the_sum_of_its_parts() {
    let p = shipped();
    let parts = [
        Load::new(2.0, 0.0, 0.0),
        Load::new(0.0, 3e-4, 0.0),
        Load::new(0.0, 0.0, -2e-4),
    ];
    let all = Load::new(2.0, 3e-4, -2e-4);
    for beam in Beam::ALL {
        let x = 0.37 * p.geometry.beam_length_m;
        let sum: f64 = parts
            .iter()
            .map(|l| surface_stress_pa(&p, *l, beam, x))
            .sum();
        assert!(close(surface_stress_pa(&p, all, beam, x), sum, 1e-12));
    }
}

#[test]
fn each_bridge_ignores_the_other_loads() {
    let p = shipped();
    let fz_only = bridge_outputs_v(&p, Load::new(5.0, 0.0, 0.0));
    let mx_only = bridge_outputs_v(&p, Load::new(0.0, 8e-4, 0.0));
    let my_only = bridge_outputs_v(&p, Load::new(0.0, 0.0, 8e-4));
    // Full-scale loads, exact (nonlinear) dividers: the cancellation is exact by placement.
    let tol = 1e-12;
    assert!(
        fz_only[0] > 0.1 && mx_only[1] > 0.1 && my_only[2] > 0.1,
        "{fz_only:?} {mx_only:?} {my_only:?}"
    );
    assert!(
        fz_only[1].abs() < tol && fz_only[2].abs() < tol,
        "moment bridges under Fz: {fz_only:?}"
    );
    assert!(
        mx_only[0].abs() < tol && mx_only[2].abs() < tol,
        "Fz, My bridges under Mx: {mx_only:?}"
    );
    assert!(
        my_only[0].abs() < tol && my_only[1].abs() < tol,
        "Fz, Mx bridges under My: {my_only:?}"
    );
}

#[test]
fn small_signal_output_follows_the_sensitivity_matrix() {
    let p = shipped();
    let s = sensitivity_matrix(&p);
    let load = Load::new(1e-3, -2e-7, 3e-7);
    let v = bridge_outputs_v(&p, load);
    for i in 0..3 {
        let linear: f64 = (0..3).map(|j| s[i][j] * load.to_array()[j]).sum();
        assert!(
            close(v[i], linear, 1e-3),
            "bridge {i}: {} vs {linear}",
            v[i]
        );
    }
    let c = inverse(&s).expect("S is invertible");
    let identity = multiply(&c, &s);
    for (i, row) in identity.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            assert!(
                (v - f64::from(u8::from(i == j))).abs() < 1e-12,
                "{identity:?}"
            );
        }
    }
}

#[test]
fn shipped_geometry_reproduces_table_one_within_ten_percent() {
    // Table I: S_Fz = 0.2 mV/mN = 0.2 V/N, S_Mx = S_My = 2.83 mV/(N·um) = 2830 V/(N·m), raw
    // bridge output at the excitation in chip.toml; strength 5000 mN and 800 N·um.
    let p = shipped();
    let s = sensitivity_matrix(&p);
    let [f, mx, my] = strengths(&p);
    for (name, got, want) in [
        ("S_Fz", s[0][0], 0.2),
        ("S_Mx", s[1][1], 2830.0),
        ("S_My", s[2][2], 2830.0),
        ("Fz strength", f, 5.0),
        ("Mx strength", mx, 800e-6),
        ("My strength", my, 800e-6),
    ] {
        assert!(
            close(got, want, 0.10),
            "{name}: model {got}, Table I {want}"
        );
    }
}

#[test]
fn frame_fe_euler_bernoulli_reproduces_the_analytical_model() {
    let p = shipped();
    let opt = FrameOptions {
        shear_deformation: false,
        block_stiffness_factor: 1e6,
        ..FrameOptions::default()
    };
    for load in [
        Load::new(1.0, 0.0, 0.0),
        Load::new(0.0, 1e-4, 0.0),
        Load::new(0.0, 0.0, 1e-4),
    ] {
        let fe = frame_fe::solve(&p, load, opt).expect("frame solves");
        for bridge in &p.bridges {
            for r in &bridge.resistors {
                let a = surface_stress_pa(&p, load, r.beam, r.x_m);
                let n = fe.surface_stress_pa(r.beam, r.x_m);
                let scale = peak(&p, load);
                assert!(
                    (a - n).abs() < 1e-4 * scale,
                    "{load:?} {r:?}: analytic {a}, FE {n}"
                );
            }
        }
    }
}

#[test]
fn frame_fe_timoshenko_agrees_within_five_percent_at_the_resistors() {
    // Shear deformation with a rigid block, then also with the block as stubs of its own
    // (wafer-thick) section.
    let p = shipped();
    for options in [FrameOptions::default(), FrameOptions::with_real_block()] {
        timoshenko_case(&p, options);
    }
}

fn timoshenko_case(p: &ChipParams, options: FrameOptions) {
    for load in [
        Load::new(1.0, 0.0, 0.0),
        Load::new(0.0, 1e-4, 0.0),
        Load::new(0.0, 0.0, 1e-4),
    ] {
        let fe = frame_fe::solve(p, load, options).expect("frame solves");
        let mut worst = 0.0_f64;
        for bridge in &p.bridges {
            for r in &bridge.resistors {
                let a = surface_stress_pa(p, load, r.beam, r.x_m);
                if a.abs() < 1e-3 * peak(p, load) {
                    continue; // a resistor this load does not stress (the other bridges)
                }
                let n = fe.surface_stress_pa(r.beam, r.x_m);
                worst = worst.max(((n - a) / a).abs());
            }
        }
        println!(
            "{options:?} {load:?}: largest |FE/analytic - 1| at the resistors = {:.4}",
            worst
        );
        assert!(worst < 0.05, "{options:?} {load:?}: {worst}");
    }
}

fn peak(p: &ChipParams, load: Load) -> f64 {
    crate::strength::peak_stress_pa(p, load)
}

#[test]
fn fz_bridge_output_rises_monotonically_up_to_the_strength() {
    // The divider is exact: at Table I's strength the Fz output departs from S*F (the outputs'
    // own nonlinearity). Check it stays a bounded, monotonic function of the load.
    let p = shipped();
    let mut last = 0.0;
    for i in 1..=10 {
        let v = output_v(&p, &p.bridges[0], Load::new(0.5 * i as f64, 0.0, 0.0));
        assert!(v > last && v < p.excitation_v / 2.0, "{v}");
        last = v;
    }
}

#[test]
fn mask_misalignment_creates_crosstalk_in_proportion() {
    use crate::tolerance::{crosstalk_at_mask_offset, with_mask_offset};
    let p = shipped();
    let one = crosstalk_at_mask_offset(&p, 1e-6);
    let two = crosstalk_at_mask_offset(&p, 2e-6);
    // A shift along x moves the A and B resistors the opposite way along their beams: under My
    // (A and B stressed equal and opposite, with a slope along x) the Fz arm no longer cancels.
    assert!(one[0][2] > 1e-4, "My into the Fz bridge: {one:?}");
    assert!(
        close(two[0][2], 2.0 * one[0][2], 0.02),
        "first order in the offset: {one:?} {two:?}"
    );
    // An x shift moves A's resistors towards the frame and B's towards the block: under Fz
    // (stress sloping along every beam) the My bridge's A and B halves no longer cancel, while
    // the Mx bridge on C and D, not moved along their axes, stays balanced.
    let q = with_mask_offset(&p, 1e-6, 0.0);
    let v = bridge_outputs_v(&q, Load::new(1.0, 0.0, 0.0));
    assert!(v[1].abs() < 1e-12, "{v:?}");
    assert!(v[2].abs() > 1e-3 * v[0], "{v:?}");
}

#[test]
fn pillar_tip_force_becomes_a_moment_at_the_chip() {
    let mut p = shipped();
    p.geometry.pillar_height_m = 1e-3;
    let at_chip = crate::tolerance::load_at_chip(&p, Load::new(1.0, 0.0, 0.0), 0.2, -0.1);
    assert!(
        close(at_chip.my_nm, 2e-4, 1e-12) && close(at_chip.mx_nm, 1e-4, 1e-12),
        "{at_chip:?}"
    );
}

#[test]
fn inverse_is_scale_free_and_refuses_singular_matrices() {
    let tiny = [[1e-9, 0.0, 0.0], [0.0, 2e-13, 0.0], [0.0, 1e-14, 3e-13]];
    let inv = inverse(&tiny).expect("well conditioned, only small");
    assert!(close(inv[1][1], 5e12, 1e-12));
    let singular = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]];
    assert_eq!(inverse(&singular), None);
}

mod calibration_fit;
