//! The chip's figures that `tactile chip` prints and the Python package's `tactile.chip()`
//! returns: sensitivities, crosstalk, strength and stiffness for the geometry in
//! `hardware/chip.toml`, next to the paper's Table I, and the frame-FE check of the model (std
//! only: it builds JSON).

use crate::frame_fe::{self, FrameError, FrameOptions};
use crate::from_hardware::FromHardwareError;
use crate::sensitivity::{crosstalk, inverse, sensitivity_matrix, Matrix3};
use crate::{fz, moment, strength, stress, tolerance, ChipParams, Load};
use serde_json::{json, Value};

/// Table I of the paper: S_Fz in V/N, S_Mx = S_My in V/(N·m), strengths in N and N·m.
const TABLE_I: [(&str, f64); 4] = [
    ("s_fz_mv_per_mn", 0.2),
    ("s_mxy_mv_per_n_um", 2.83),
    ("strength_fz_mn", 5000.0),
    ("strength_mxy_n_um", 800.0),
];

/// Why the chip's figures could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum ChipReportError {
    /// `hardware/chip.toml` does not make a chip.
    #[error(transparent)]
    Params(#[from] FromHardwareError),
    /// The bridges cannot separate the loads.
    #[error("the sensitivity matrix is singular: the bridges cannot separate the loads")]
    Singular,
    /// The frame FE check could not be solved.
    #[error(transparent)]
    Frame(#[from] FrameError),
}

/// A chip description the model cannot use is bad data; a failed check, the program's own.
impl sysexit::ExitStatus for ChipReportError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Params(_) => sysexit::DATA,
            _ => sysexit::SOFTWARE,
        }
    }
}

/// The figures for the chip of `hw` (its `chip.toml`, with the resistor mask's misalignment as
/// the overlay tolerance of the crosstalk estimate).
pub fn from_hardware(hw: &hardware::Params) -> Result<Value, ChipReportError> {
    let p = ChipParams::try_from(&hw.chip)?;
    report(&p, hw.chip.mask_misalignment_um * 1e-6)
}

/// Everything the command prints, as JSON; `mask_offset_m` is the resistor mask's overlay
/// tolerance for the crosstalk estimate.
pub fn report(p: &ChipParams, mask_offset_m: f64) -> Result<Value, ChipReportError> {
    let s = sensitivity_matrix(p);
    let c = inverse(&s).ok_or(ChipReportError::Singular)?;
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
    loads.map(|l| crate::bridge_outputs_v(p, l))
}

/// Largest relative difference between the shear-deformable frame FE and the analytical model
/// at the stressed resistor sites, per load case.
fn frame_check(p: &ChipParams, options: FrameOptions) -> Result<Value, FrameError> {
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
