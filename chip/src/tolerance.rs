//! What the nominal (perfectly symmetric) chip hides: crosstalk from a misaligned resistor mask,
//! and the transfer of loads from the pillar tip to the chip surface.

use crate::params::{ChipParams, Load};
use crate::sensitivity::{crosstalk, sensitivity_matrix, Matrix3};

/// The chip with every resistor moved by the in-plane mask offset (dx, dy): a resistor on a
/// beam with outward direction e moves outward by d·e, i.e. towards the frame, so its distance
/// from the frame end changes by -(d·e).
pub fn with_mask_offset(p: &ChipParams, dx_m: f64, dy_m: f64) -> ChipParams {
    let mut q = *p;
    for bridge in &mut q.bridges {
        for r in &mut bridge.resistors {
            let (ex, ey) = r.beam.direction();
            r.x_m -= dx_m * ex + dy_m * ey;
        }
    }
    q
}

/// Largest crosstalk magnitude |S_ij / S_jj| per entry for a mask offset of `offset_m` along x,
/// along y and along the diagonal (both signs): the worst case of the three directions.
pub fn crosstalk_at_mask_offset(p: &ChipParams, offset_m: f64) -> Matrix3 {
    let d = offset_m / core::f64::consts::SQRT_2;
    let offsets = [(offset_m, 0.0), (0.0, offset_m), (d, d), (d, -d)];
    let mut worst = [[0.0_f64; 3]; 3];
    for (dx, dy) in offsets {
        let x = crosstalk(&sensitivity_matrix(&with_mask_offset(p, dx, dy)));
        for i in 0..3 {
            for j in 0..3 {
                worst[i][j] = worst[i][j].max(x[i][j].abs());
            }
        }
    }
    worst
}

/// The load on the chip (at its top surface, the block centre) from a load at the tip of the
/// pillar of height H: a lateral force (Fx, Fy) at the tip adds r x F with r = (0, 0, H), i.e.
/// Mx -= H Fy and My += H Fx. The lateral force itself (which strains the beams axially and
/// in-plane) is not sensed by this three-axis model.
pub fn load_at_chip(p: &ChipParams, tip: Load, fx_n: f64, fy_n: f64) -> Load {
    let h = p.geometry.pillar_height_m;
    Load::new(tip.fz_n, tip.mx_nm - h * fy_n, tip.my_nm + h * fx_n)
}
