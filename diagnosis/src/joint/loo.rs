//! Leave-one-recording-out validation: the session's shared physics fitted to the other
//! recordings alone, then held while only the left-out recording's own calibration (offsets,
//! its own effects and per-recording scales) is fitted to its fitting stretch; its held-out
//! stretch is then predicted. The baseline calibrated to that recording alone, on the same
//! stretch, is the comparison.

use baseline::Outputs;
use rayon::prelude::*;

use super::output::{Change, LeaveOneOut, Validation};
use super::search::{Fitted, Search};
use super::seen::Frame;
use super::update::Parts;
use super::Members;
use crate::candidate::{heldout_needed, sum_deviation, MIN_HELDOUT_SHARE};
use crate::fit::{Model, SCALE_AT};

/// The validation of `fitted` over the session's recordings (none below two).
pub(crate) fn leave_one_out(m: &Members, fitted: &Fitted) -> Validation {
    let n = m.setups.len();
    if n < 2 {
        return Validation {
            leave_one_out: Vec::new(),
            note: Some(
                "one recording analysed: there is no other to fit the shared physics to".into(),
            ),
        };
    }
    let search = Search {
        setups: m.setups.clone(),
        tried: Vec::new(),
    };
    let parts = Parts::of(&search, fitted);
    let rows = (0..n)
        .into_par_iter()
        .map(|r| one(m, &search, &parts, fitted, r))
        .collect();
    Validation {
        leave_one_out: rows,
        note: None,
    }
}

fn one(m: &Members, search: &Search, parts: &Parts, fitted: &Fitted, r: usize) -> LeaveOneOut {
    let keep: Vec<usize> = (0..m.setups.len()).filter(|&i| i != r).collect();
    let others = parts.without(r);
    // A scale per recording is the session's angle law, not a calibration: the left-out
    // recording's is predicted from the others' along the contact angle (or azimuth).
    let mut alone = fitted.layout.only(&[r]);
    let mut frozen = others.shared;
    for c in std::mem::take(&mut alone.own_scales) {
        let i = SCALE_AT + c;
        let points: Vec<(usize, f64)> = keep
            .iter()
            .enumerate()
            .filter(|&(_, &k)| m.setups[k].used[c + 1])
            .map(|(j, &k)| (k, others.full[j][i]))
            .collect();
        if let Some(v) = predicted_scale(m, &points, r, c) {
            frozen.insert(i, v);
        }
    }
    let own = search.recording_alone(fitted, r, alone, frozen);
    let full = &own.fit.full[0];
    let setup = m.setups[r];
    let model = own.model(setup);
    let predicted = model.outputs(full, &m.prepared[r].full_drive(setup));
    let (rmse_before, rmse_after) = (
        m.diags[r].report.fit.heldout.rmse_before,
        m.prepared[r].rmse(&predicted).1,
    );
    // The held-out test's share, on the misfit the row shows: a change of its square by less
    // than that share moves the RMSE by less than a quarter percent, and is no change.
    let moved = (rmse_before.powi(2) - rmse_after.powi(2)).abs()
        > MIN_HELDOUT_SHARE * rmse_before.max(rmse_after).powi(2);
    LeaveOneOut {
        file: m.files[r].clone(),
        rmse_before,
        rmse_after,
        change: match change(m, r, &model, full) {
            Change::Better if moved && rmse_after < rmse_before => Change::Better,
            Change::Worse if moved && rmse_after > rmse_before => Change::Worse,
            _ => Change::NoChange,
        },
    }
}

/// Whether the prediction (`model` at `full`) beats recording `r`'s baseline calibrated alone
/// on the held-out stretch by the held-out test's own margin ([`heldout_needed`]: twice the
/// noise of the misfits' difference, and half a percent of the larger misfit), or loses by it,
/// on the fitting series the test weighs. A change within the margin is no change: held-out
/// stretches at rest, where neither model can be told from the other, had read "fit better"
/// by 0.02 %.
fn change(m: &Members, r: usize, model: &Model, full: &[f64]) -> Change {
    let setup = m.setups[r];
    let mask = &setup.heldout_mask;
    let baseline = &m.diags[r].plots.baseline;
    if baseline[0].len() != mask.len() {
        return Change::NoChange;
    }
    // The baseline in the frame the session's fit reads the recording in.
    let frame = Frame::of(m, r);
    let base = Outputs {
        load_n: frame.to_session(0, &baseline[0]),
        volts: std::array::from_fn(|c| frame.to_session(c + 1, &baseline[c + 1])),
    };
    let (mut before, mut after) = (Vec::new(), Vec::new());
    model.weighted_of(&base, mask, &mut before);
    model.weighted(full, mask, &mut after);
    let chi2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
    let (b, a) = (chi2(&before), chi2(&after));
    let d: Vec<f64> = after.iter().zip(&before).map(|(x, y)| x - y).collect();
    let noise = sum_deviation(setup, mask, &d);
    if b - a > heldout_needed(noise, b) {
        Change::Better
    } else if a - b > heldout_needed(noise, a) {
        Change::Worse
    } else {
        Change::NoChange
    }
}

/// The scale of output `c` (relative to the model) predicted for recording `r` from the others'
/// `(recording, scale)`: along a straight line in the session's variation, either of the scale
/// itself (the model's law wrong by a straight correction) or of the scale times the model's own
/// share at each test (the measured law straight), whichever line the others follow more
/// closely. Where both pass through every point (two others), the correction's.
fn predicted_scale(m: &Members, points: &[(usize, f64)], r: usize, c: usize) -> Option<f64> {
    let x = |k: usize| axis(m, k);
    let correction: Vec<(f64, f64)> = points.iter().map(|&(k, s)| (x(k), s)).collect();
    let shares: Option<Vec<f64>> = points.iter().map(|&(k, _)| model_share(m, k, c)).collect();
    let (Some(shares), Some(own)) = (shares, model_share(m, r, c)) else {
        return line_at(&correction, x(r));
    };
    let measured: Vec<(f64, f64)> = correction
        .iter()
        .zip(&shares)
        .map(|(&(a, s), &h)| (a, s * h))
        .collect();
    let scale = |pts: &[(f64, f64)]| pts.iter().map(|p| p.1 * p.1).sum::<f64>().sqrt();
    let misfit = |pts: &[(f64, f64)]| line_misfit(pts) / scale(pts).max(1e-300);
    if misfit(&measured) < misfit(&correction) - 1e-9 {
        line_at(&measured, x(r)).map(|v| v / own)
    } else {
        line_at(&correction, x(r))
    }
}

/// The model's own share of the load on output `c` in recording `k`: the output per unit of
/// the rod's force at the test's peak, at unit modulus; `None` without contact.
fn model_share(m: &Members, k: usize, c: usize) -> Option<f64> {
    let u = m.setups[k]
        .drive
        .units()
        .max_by(|a, b| a.force_n.total_cmp(&b.force_n))?;
    (u.force_n > 0.0 && u.chip[c] != 0.0).then(|| (u.chip[c] / u.force_n).abs())
}

/// The root-mean-square distance of `points` from their least-squares line.
fn line_misfit(points: &[(f64, f64)]) -> f64 {
    let n = points.len().max(1) as f64;
    let sum: f64 = points
        .iter()
        .map(|&(x, y)| (y - line_at(points, x).unwrap_or(y)).powi(2))
        .sum();
    (sum / n).sqrt()
}

/// Where recording `k` lies along the session's variation: its contact angle when the session
/// varies it, else its azimuth.
fn axis(m: &Members, k: usize) -> f64 {
    let angles = super::distinct(m.protocols.iter().map(|p| p.contact_angle_deg), 0.0);
    if angles.len() > 1 {
        m.protocols[k].contact_angle_deg
    } else {
        m.protocols[k].azimuth_deg
    }
}

/// The least-squares line through `points` at `x`; their mean where they do not span the axis.
fn line_at(points: &[(f64, f64)], x: f64) -> Option<f64> {
    let n = points.len() as f64;
    if points.is_empty() {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx < 1e-9 {
        return Some(my);
    }
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    Some(my + sxy / sxx * (x - mx))
}
