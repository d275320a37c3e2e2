//! `tactile chip`: the chip's sensitivities, crosstalk, strength and stiffness for the geometry
//! in `hardware/chip.toml`, next to the paper's Table I, and the frame-FE check of the model.

use anyhow::Context;
use chip::frame_fe::{self, FrameOptions};
use chip::sensitivity::{crosstalk, inverse, sensitivity_matrix, Matrix3};
use chip::{fz, moment, strength, stress, tolerance, ChipParams, Load};
use serde_json::{json, Value};

/// Table I of the paper: S_Fz in V/N, S_Mx = S_My in V/(N·m), strengths in N and N·m.
const TABLE_I: [(&str, f64); 4] = [
    ("s_fz_mv_per_mn", 0.2),
    ("s_mxy_mv_per_n_um", 2.83),
    ("strength_fz_mn", 5000.0),
    ("strength_mxy_n_um", 800.0),
];

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let hw = hardware::Params::load_default().context("loading hardware/")?;
    let p = ChipParams::try_from(&hw.chip)?;
    let report = report(&p, hw.chip.mask_misalignment_um * 1e-6)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_text(&report);
    }
    Ok(())
}

/// Everything the command prints, as JSON; `mask_offset_m` is the resistor mask's overlay
/// tolerance for the crosstalk estimate.
pub fn report(p: &ChipParams, mask_offset_m: f64) -> anyhow::Result<Value> {
    let s = sensitivity_matrix(p);
    let c = inverse(&s)
        .context("the sensitivity matrix is singular: the bridges cannot separate the loads")?;
    let [f_s, mx_s, my_s] = strength::strengths(p);
    let (g, si) = (&p.geometry, &p.silicon);
    let model = [
        s[0][0] * 1.0,
        0.5 * (s[1][1] + s[2][2]) * 1e-6 * 1e3,
        f_s * 1e3,
        0.5 * (mx_s + my_s) * 1e6,
    ];
    let table: Vec<Value> = TABLE_I
        .iter()
        .zip(model)
        .map(|((name, paper), got)| json!({"figure": name, "model": got, "paper": paper, "ratio": got / paper}))
        .collect();
    Ok(json!({
        "excitation_v": p.excitation_v,
        "reading": "Table I sensitivities compared as raw bridge output (before the amplifier) at excitation_v; see hardware/chip-design.md",
        "table_i": table,
        "s_fz_mv_per_mn": s[0][0],
        "s_mx_mv_per_n_um": s[1][1] * 1e-3,
        "s_my_mv_per_n_um": s[2][2] * 1e-3,
        "strength_fz_mn": f_s * 1e3,
        "strength_mx_n_um": mx_s * 1e6,
        "strength_my_n_um": my_s * 1e6,
        "sensitivity_matrix": {"units": "V/N (Fz column), V/(N·m) (Mx, My columns); rows Fz, Mx, My bridges", "value": s},
        "calibration_matrix": {"units": "N and N·m per bridge volt (before amplifiers); rows Fz, Mx, My", "value": c},
        "crosstalk": {"definition": "S[i][j] / S[j][j]", "value": crosstalk(&s)},
        "crosstalk_at_mask_misalignment": {
            "definition": "worst |S[i][j] / S[j][j]| for a resistor mask shifted along x, y or a diagonal",
            "misalignment_um": mask_offset_m * 1e6,
            "value": tolerance::crosstalk_at_mask_offset(p, mask_offset_m),
        },
        "full_scale_outputs_v": full_scale_outputs(p, [f_s, mx_s, my_s]),
        "block_deflection_stiffness_n_per_um": 1e-6 / fz::block_deflection_m(g, si, 1.0),
        "block_rotation_stiffness_nm_per_rad": moment::rotational_stiffness_nm_per_rad(g, si),
        "frame_fe_check": {
            "rigid_block": frame_check(p, FrameOptions::default())?,
            "real_block": frame_check(p, FrameOptions::with_real_block())?,
        },
    }))
}

/// Bridge outputs (exact divider) at each strength load alone.
fn full_scale_outputs(p: &ChipParams, strengths: [f64; 3]) -> Matrix3 {
    let loads = [
        Load::new(strengths[0], 0.0, 0.0),
        Load::new(0.0, strengths[1], 0.0),
        Load::new(0.0, 0.0, strengths[2]),
    ];
    loads.map(|l| chip::bridge_outputs_v(p, l))
}

/// Largest relative difference between the shear-deformable frame FE and the analytical model
/// at the stressed resistor sites, per load case.
fn frame_check(p: &ChipParams, options: FrameOptions) -> anyhow::Result<Value> {
    let cases = [
        ("fz", Load::new(1.0, 0.0, 0.0)),
        ("mx", Load::new(0.0, 1e-4, 0.0)),
        ("my", Load::new(0.0, 0.0, 1e-4)),
    ];
    let mut out = serde_json::Map::new();
    for (name, load) in cases {
        let fe = frame_fe::solve(p, load, options)?;
        let peak = strength::peak_stress_pa(p, load);
        let worst = p
            .bridges
            .iter()
            .flat_map(|b| b.resistors.iter())
            .map(|r| {
                (
                    stress::surface_stress_pa(p, load, r.beam, r.x_m),
                    fe.surface_stress_pa(r.beam, r.x_m),
                )
            })
            .filter(|(a, _)| a.abs() > 1e-3 * peak)
            .map(|(a, n)| ((n - a) / a).abs())
            .fold(0.0_f64, f64::max);
        out.insert(name.into(), json!({"max_rel_diff_at_resistors": worst}));
    }
    Ok(Value::Object(out))
}

fn print_text(r: &Value) {
    println!(
        "chip at {} V excitation (raw bridge output, before amplifiers)",
        r["excitation_v"]
    );
    println!(
        "{:<22} {:>12} {:>12} {:>8}",
        "Table I figure", "model", "paper", "ratio"
    );
    for row in r["table_i"].as_array().into_iter().flatten() {
        let num = |k: &str| row[k].as_f64().unwrap_or(f64::NAN);
        println!(
            "{:<22} {:>12.4} {:>12.4} {:>8.3}",
            row["figure"].as_str().unwrap_or("?"),
            num("model"),
            num("paper"),
            num("ratio")
        );
    }
    for key in [
        "sensitivity_matrix",
        "calibration_matrix",
        "crosstalk",
        "crosstalk_at_mask_misalignment",
    ] {
        print_matrix(r, key);
    }
    println!(
        "block deflection stiffness: {:.4} N/um",
        r["block_deflection_stiffness_n_per_um"]
            .as_f64()
            .unwrap_or(f64::NAN)
    );
    println!(
        "block rotation stiffness:   {:.4e} N·m/rad",
        r["block_rotation_stiffness_nm_per_rad"]
            .as_f64()
            .unwrap_or(f64::NAN)
    );
    for block in ["rigid_block", "real_block"] {
        for case in ["fz", "mx", "my"] {
            let d = r["frame_fe_check"][block][case]["max_rel_diff_at_resistors"]
                .as_f64()
                .unwrap_or(f64::NAN);
            println!(
                "frame FE ({block}) vs analytical, {case}: {:.2} % at the resistors",
                100.0 * d
            );
        }
    }
}

/// The 3x3 matrix `r[key]` with its units.
fn print_matrix(r: &Value, key: &str) {
    println!(
        "{key} ({}):",
        r[key]["units"]
            .as_str()
            .or(r[key]["definition"].as_str())
            .unwrap_or("")
    );
    for row in r[key]["value"].as_array().into_iter().flatten() {
        let cells: Vec<String> = row
            .as_array()
            .into_iter()
            .flatten()
            .map(|v| format!("{:>13.5e}", v.as_f64().unwrap_or(f64::NAN)))
            .collect();
        println!("  {}", cells.join(" "));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_report_carries_table_one_and_the_matrices() {
        let p = ChipParams::load_default().unwrap();
        let r = report(&p, 1e-6).unwrap();
        for (key, paper) in [
            ("s_fz_mv_per_mn", 0.2),
            ("s_mx_mv_per_n_um", 2.83),
            ("s_my_mv_per_n_um", 2.83),
            ("strength_fz_mn", 5000.0),
            ("strength_mx_n_um", 800.0),
            ("strength_my_n_um", 800.0),
        ] {
            let got = r[key].as_f64().unwrap();
            assert!((got / paper - 1.0).abs() < 0.10, "{key}: {got} vs {paper}");
        }
        let s = &r["sensitivity_matrix"]["value"];
        let c = &r["calibration_matrix"]["value"];
        // C S = I, through the JSON.
        for i in 0..3 {
            for j in 0..3 {
                let v: f64 = (0..3)
                    .map(|k| c[i][k].as_f64().unwrap() * s[k][j].as_f64().unwrap())
                    .sum();
                assert!(
                    (v - f64::from(u8::from(i == j))).abs() < 1e-9,
                    "({i},{j}) {v}"
                );
            }
        }
        assert!(
            r["crosstalk_at_mask_misalignment"]["value"][1][0]
                .as_f64()
                .unwrap()
                > 0.0
        );
    }
}
