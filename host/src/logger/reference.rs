//! Merging a test machine's export (time, rod position, load; read by `recording::machine`)
//! into a recording: its `rod_mm` and `load_N` columns. Aligned either by timestamps (the machine's time
//! zero is the recording's, plus an optional offset) or by the lag that maximises the
//! cross-correlation of the machine's load with the sensor's Fz.

use std::path::Path;

use recording::machine::MachineExport;
use recording::Recording;

use super::FileError;

/// Linear interpolation of `y(x)` at `at`; `None` outside the sampled range (the importers'
/// one implementation).
pub use recording::import::resample::interpolate;

/// How to align the machine's clock with the recording's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Align {
    /// Machine time = recording `t_s` + offset.
    Time { offset_s: f64 },
    /// Search the offset within ±`max_lag_s` that best correlates load with Fz.
    Xcorr { max_lag_s: f64 },
    /// The machine was started by the start of the stream (a trigger): its time zero is the
    /// recording's first sample. Exact where the trigger is; cross-correlation is biased by any
    /// phase shift between load and sensor (AC coupling leads, relaxation lags).
    Start,
}

/// Grid step of the cross-correlation search.
const XCORR_STEP_S: f64 = 0.01;

/// The offset (machine time − recording time) that maximises the normalised correlation of
/// the machine load with the sensor signal `s(t)`.
pub fn xcorr_offset(
    t: &[f64],
    s: &[f64],
    reference: &MachineExport,
    max_lag_s: f64,
) -> Option<f64> {
    let ok: Vec<(f64, f64)> = t
        .iter()
        .zip(s)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    let (t0, t1) = (ok.first()?.0, ok.last()?.0);
    let (ts, ss): (Vec<f64>, Vec<f64>) = ok.into_iter().unzip();
    let n = ((t1 - t0) / XCORR_STEP_S) as usize;
    let grid: Vec<f64> = (0..n)
        .filter_map(|i| interpolate(&ts, &ss, t0 + i as f64 * XCORR_STEP_S))
        .collect();
    let lags = (max_lag_s / XCORR_STEP_S) as i64;
    let mut best: Option<(f64, f64)> = None;
    for k in -lags..=lags {
        let off = k as f64 * XCORR_STEP_S;
        let pairs: Vec<(f64, f64)> = grid
            .iter()
            .enumerate()
            .filter_map(|(i, v)| {
                interpolate(
                    &reference.t_s,
                    &reference.load_n,
                    t0 + i as f64 * XCORR_STEP_S + off,
                )
                .map(|r| (*v, r))
            })
            .collect();
        if pairs.len() < 10 {
            continue;
        }
        let c = pearson(&pairs);
        if best.is_none_or(|(b, _)| c > b) {
            best = Some((c, off));
        }
    }
    best.map(|(_, off)| off)
}

fn pearson(pairs: &[(f64, f64)]) -> f64 {
    let n = pairs.len() as f64;
    let (ma, mb) = pairs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in pairs {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        f64::NEG_INFINITY
    }
}

/// Fill `rod_mm` and `load_N` of `rec` from `reference`; returns the offset used. Gap rows
/// (no sensor value at all) stay gaps.
pub fn merge(rec: &mut Recording, reference: &MachineExport, align: Align) -> f64 {
    let offset = match align {
        Align::Time { offset_s } => offset_s,
        Align::Xcorr { max_lag_s } => {
            let signal = rec.column("fz_N").unwrap_or(&rec.channels.fz_v);
            xcorr_offset(&rec.channels.t_s, signal, reference, max_lag_s).unwrap_or(0.0)
        }
        Align::Start => {
            let c = &rec.channels;
            (0..c.len())
                .find(|&i| {
                    [c.fz_v[i], c.mx_v[i], c.my_v[i]]
                        .iter()
                        .any(|v| v.is_finite())
                })
                .map_or(0.0, |i| -c.t_s[i])
        }
    };
    let c = &mut rec.channels;
    for i in 0..c.len() {
        if c.fz_v[i].is_nan() && c.mx_v[i].is_nan() && c.my_v[i].is_nan() {
            continue;
        }
        let at = c.t_s[i] + offset;
        c.rod_mm[i] = interpolate(&reference.t_s, &reference.rod_mm, at).unwrap_or(f64::NAN);
        c.load_n[i] = interpolate(&reference.t_s, &reference.load_n, at).unwrap_or(f64::NAN);
    }
    offset
}

/// Rewrite the recording at `path` with the reference merged in (written beside it, then
/// renamed over it, so a crash never leaves a half-merged file).
pub fn merge_file(path: &Path, reference_path: &Path, align: Align) -> Result<f64, FileError> {
    let reference = recording::machine::read(reference_path)?;
    let mut rec = recording::read(path)?;
    let offset = merge(&mut rec, &reference, align);
    rec.meta.other.push((
        "reference".into(),
        format!("{} (offset {offset} s)", reference_path.display()),
    ));
    let tmp = path.with_extension("merging");
    let file = std::fs::File::create(&tmp).map_err(|e| FileError::write(&tmp, e))?;
    rec.write_to(file).map_err(|e| FileError::write(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| FileError::write(path, e))?;
    Ok(offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xcorr_finds_a_known_shift() {
        // Sensor sees a load pulse at t = 5 s; the machine logged it at t = 7.3 s.
        let pulse = |t: f64| (-(t - 5.0).powi(2)).exp();
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 0.01).collect();
        let s: Vec<f64> = t.iter().map(|t| pulse(*t)).collect();
        let rt: Vec<f64> = (0..1500).map(|i| i as f64 * 0.01).collect();
        let r = MachineExport {
            load_n: rt.iter().map(|t| 60.0 * pulse(t - 2.3)).collect(),
            rod_mm: rt.clone(),
            t_s: rt,
        };
        let off = xcorr_offset(&t, &s, &r, 4.0).unwrap();
        assert!((off - 2.3).abs() < 0.011, "offset {off}");
    }

    /// A triggered machine's time zero is the first sample, wherever the recording's clock was.
    #[test]
    fn start_alignment_puts_machine_zero_on_the_first_sample() {
        let mut rec = Recording::new(recording::Meta {
            sample_rate_hz: 500.0,
            contact_angle_deg: 20.0,
            azimuth_deg: 60.0,
            fingertip_radius_mm: 20.0,
            gain_fz: 1.0,
            gain_mx: 1.0,
            gain_my: 1.0,
            excitation_v: 3.3,
            rod_speed_mm_per_min: None,
            source: None,
            other: Vec::new(),
        });
        for i in 0..5 {
            let c = &mut rec.channels;
            c.t_s.push(0.94 + 0.002 * i as f64);
            c.rod_mm.push(f64::NAN);
            c.load_n.push(f64::NAN);
            c.fz_v.push(0.1);
            c.mx_v.push(0.2);
            c.my_v.push(0.3);
        }
        let t_s: Vec<f64> = (0..10).map(|i| 0.002 * i as f64).collect();
        let r = MachineExport {
            rod_mm: t_s.iter().map(|t| 100.0 * t).collect(),
            load_n: t_s.iter().map(|t| 1000.0 * t).collect(),
            t_s,
        };
        let offset = merge(&mut rec, &r, Align::Start);
        assert!((offset + 0.94).abs() < 1e-12);
        let c = &rec.channels;
        for i in 0..c.len() {
            assert!(
                (c.rod_mm[i] - 0.2 * i as f64).abs() < 1e-9,
                "rod at row {i}"
            );
            assert!(
                (c.load_n[i] - 2.0 * i as f64).abs() < 1e-9,
                "load at row {i}"
            );
        }
    }
}
