//! `tactile chip`: the chip's sensitivities, crosstalk, strength and stiffness for the geometry
//! in `hardware/chip.toml`, next to the paper's Table I, and the frame-FE check of the model
//! (computed by `chip::report`, which the Python package shares).

use anyhow::Context;
use serde_json::Value;
use sysexit::ResultExt as _;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let hw = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let report = chip::report::from_hardware(&hw).coded()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_text(&report);
    }
    Ok(())
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
