//! Checks of a logged recording against the emulator's deterministic truth.

use std::path::{Path, PathBuf};
use std::process::Command;

use host::device::Scale;
use host::logger::gap_code;
use recording::{read as read_recording, Recording};

use crate::emu::{info_for, truth_sample, truth_temp, EmuConfig};

/// A fresh scratch directory under the system temp dir.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-{name}-{}-{}", std::process::id(), nanos()));
    std::fs::create_dir_all(&d).expect("create scratch dir");
    d
}

fn nanos() -> u128 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos())
}

/// Read a recording written from the emulator `cfg` (by `tactile log` or `tactile replay`) and
/// [`verify`] it, with the ADC scale the emulator's info frame announces.
pub fn verify_file(path: &Path, cfg: &EmuConfig) -> Result<(Recording, Verified), String> {
    let rec = read_recording(path).map_err(|e| e.to_string())?;
    let scale = Scale::from_info(&info_for(cfg));
    let v = verify(
        &rec,
        usize::from(cfg.batch),
        cfg.rate_hz,
        scale.volts_per_code[0],
    )?;
    Ok((rec, v))
}

/// `tactile replay MCAP -o OUT` with the `tactile` binary at `tactile`; panics if it fails.
pub fn replay(tactile: &Path, mcap: &Path, out: &Path) {
    let st = Command::new(tactile)
        .arg("replay")
        .arg(mcap)
        .arg("-o")
        .arg(out)
        .status()
        .unwrap();
    assert!(st.success(), "tactile replay {} failed", mcap.display());
}

/// A gap that does not say how many frames it cost.
const UNKNOWN: u64 = u64::MAX;

/// What [`verify`] found.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Verified {
    pub samples: usize,
    pub frames: usize,
    /// (gap code, missing frames) of every gap row, in order.
    pub gaps: Vec<(u32, Option<u64>)>,
    pub first_seq: u32,
    pub last_seq: u32,
}

/// Every data row must carry exactly the emulator's sample for its sequence and position in
/// the frame; consecutive frames must follow each other by sequence unless a gap row between
/// them accounts for every missing frame. Volts are converted back to codes with the
/// emulator's ADC scale (`volts_per_code`); the raw temperature code must be the frame's.
pub fn verify(
    rec: &Recording,
    batch: usize,
    rate_hz: u32,
    volts_per_code: f64,
) -> Result<Verified, String> {
    let col = |n: &str| rec.column(n).ok_or(format!("no column {n}"));
    let (seq_c, gap_c, miss_c) = (col("seq")?, col("gap")?, col("missing")?);
    let temp_c = col("temp_code")?;
    let c = &rec.channels;
    let ch = [&c.fz_v, &c.mx_v, &c.my_v];
    let mut v = Verified::default();
    let mut prev: Option<(u32, usize)> = None;
    let mut allowance: Option<u64> = None;
    for i in 0..c.len() {
        let gap = gap_c[i];
        if gap != gap_code::NONE {
            let missing = miss_c[i].is_finite().then(|| miss_c[i] as u64);
            v.gaps.push((gap as u32, missing));
            // A sequence gap adds its missing frames; a reconnection states exactly how many
            // frames the outage cost (None: the device restarted, any jump is accounted for).
            allowance = Some(match missing {
                Some(m) if gap == gap_code::SEQUENCE => allowance.unwrap_or(0).saturating_add(m),
                Some(m) if gap == gap_code::RECONNECTED => m,
                _ => UNKNOWN,
            });
            continue;
        }
        let seq = seq_c[i] as u32;
        let k = match prev {
            Some((s, k)) if s == seq => k + 1,
            _ => 0,
        };
        if k >= batch {
            return Err(format!(
                "row {i}: sample {k} of frame {seq}: more than {batch} (duplicate?)"
            ));
        }
        if k == 0 {
            match prev {
                Some((s, kp)) => frame_follows(i, (s, kp + 1), seq, batch, allowance)?,
                None => v.first_seq = seq,
            }
            allowance = None;
            v.frames += 1;
        }
        if temp_c[i] != f64::from(truth_temp(seq)) {
            return Err(format!(
                "row {i}: frame {seq}: temperature code {} != truth {}",
                temp_c[i],
                truth_temp(seq)
            ));
        }
        let volts = [ch[0][i], ch[1][i], ch[2][i]];
        let truth = truth_sample(u64::from(seq) * batch as u64 + k as u64, rate_hz);
        for (c, v) in volts.iter().enumerate() {
            let code = (v / volts_per_code).round() as i32;
            if code != truth.ch[c] {
                return Err(format!(
                    "row {i}: frame {seq} sample {k} channel {c}: {code} != truth {}",
                    truth.ch[c]
                ));
            }
        }
        prev = Some((seq, k));
        v.last_seq = seq;
        v.samples += 1;
    }
    Ok(v)
}

/// Frame `seq` starting at row `i` may follow frame `previous` (its sequence and sample count)
/// if the previous one was whole and the jump is one, or what the gap rows between allow.
fn frame_follows(
    i: usize,
    (s, samples): (u32, usize),
    seq: u32,
    batch: usize,
    allowance: Option<u64>,
) -> Result<(), String> {
    if samples != batch {
        return Err(format!("row {i}: frame {s} has {samples} samples"));
    }
    let jump = u64::from(seq.wrapping_sub(s));
    let ok = jump == 1 || allowance.is_some_and(|a| jump >= 1 && (a == UNKNOWN || jump - 1 == a));
    if !ok {
        return Err(format!(
            "row {i}: frame {seq} follows {s} without a gap row accounting for it"
        ));
    }
    match allowance {
        Some(a) if a != UNKNOWN && jump - 1 != a => Err(format!(
            "row {i}: gap says {a} frames missing, sequence says {}",
            jump - 1
        )),
        _ => Ok(()),
    }
}
