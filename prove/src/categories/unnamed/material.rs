//! The material kinds: each changes where the gel sits or the force it gives, and the recording
//! is simulated at the travel that gives that force, so the outputs follow the load through the
//! model's own chain. The rod's column keeps the encoder's travel.

use std::f64::consts::TAU;

use sim::compression::RodHistory;

use super::signal::{copy, presses, speed_mm_per_min, Draw, LoadTable, Params};
use super::{Hidden, Kind};
use baseline::synth::{simulate_path, Noise, SimSpec};
use recording::Recording;

/// The travel at which the gel behaves as the kind has it, for each sample of `history`
/// (the rod's own for the kinds of other stages). `clean` is the noise-free recording at the
/// rod's travel.
pub(super) fn travel(
    hidden: &Hidden,
    spec: &SimSpec,
    history: &RodHistory,
    clean: &Recording,
    u: Draw,
    p: &mut Params,
) -> Vec<f64> {
    let rod = &history.rod_mm;
    let Some(kind) = hidden.kind.filter(|k| k.is_material()) else {
        return rod.clone();
    };
    let want = match kind {
        Kind::RigZeroDrift => return zero_drift(history, u, p),
        Kind::DriveBacklash => return backlash(rod, u, p),
        Kind::ModulusFollowsTemperature => modulus(clean, u, p),
        Kind::WorkSoftening => softening(clean, u, p),
        _ => ringing(spec, clean, u, p),
    };
    let table = load_table(spec, rod);
    // Where the law leaves the force as it is, the rod's own travel (not the table's
    // interpolation of it).
    rod.iter()
        .zip(&want)
        .zip(&clean.channels.load_n)
        .map(|((&r, &f), &was)| if f == was { r } else { table.travel(f, r) })
        .collect()
}

/// The load along a slow noise-free ramp to twice the path's largest travel.
fn load_table(spec: &SimSpec, rod_mm: &[f64]) -> LoadTable {
    let top = 2.0 * rod_mm.iter().cloned().fold(1e-3, f64::max);
    let n = 4000;
    let grid: Vec<f64> = (0..=n).map(|i| top * i as f64 / n as f64).collect();
    let ramp = RodHistory {
        t_s: (0..=n).map(|i| i as f64).collect(),
        rod_mm: grid.clone(),
    };
    let quiet = SimSpec {
        noise: Noise::default(),
        effects: Vec::new(),
        ambient_swing: None,
        ..copy(spec)
    };
    let rec = simulate_path(&quiet, ramp);
    LoadTable::new(grid, rec.channels.load_n)
}

/// The gel's modulus falls as it warms: F (1 - kappa (T - T_0)), T_0 the first sample's.
fn modulus(clean: &Recording, u: Draw, p: &mut Params) -> Vec<f64> {
    let kappa_per_c = u(0.025, 0.05);
    p.push(("kappa_per_C", kappa_per_c));
    let temp = clean.temp_c.clone().unwrap_or_default();
    let t0 = temp.first().copied().unwrap_or(0.0);
    clean
        .channels
        .load_n
        .iter()
        .zip(&temp)
        .map(|(f, tc)| f * (1.0 - kappa_per_c * (tc - t0)))
        .collect()
}

/// The gel's network is damaged by the work of its loadings: F (1 - c 2W / (W + W_1)), a
/// damage that grows with the work and saturates at 2c.
fn softening(clean: &Recording, u: Draw, p: &mut Params) -> Vec<f64> {
    let c = u(0.06, 0.14);
    p.push(("c", c));
    let ch = &clean.channels;
    let mut w = 0.0;
    let work: Vec<f64> = (0..ch.t_s.len())
        .map(|i| {
            if i > 0 {
                let step = (ch.rod_mm[i] - ch.rod_mm[i - 1]).max(0.0);
                w += 0.5 * (ch.load_n[i] + ch.load_n[i - 1]) * step;
            }
            w
        })
        .collect();
    let first_end = presses(&ch.rod_mm)
        .first()
        .map_or(work.len() - 1, |r| r.end.min(work.len() - 1));
    let w1 = work[first_end].max(f64::MIN_POSITIVE);
    p.push(("first_work_Nmm", w1));
    ch.load_n
        .iter()
        .zip(&work)
        .map(|(f, w)| f * (1.0 - c * 2.0 * w / (w + w1)))
        .collect()
}

/// The frame's length changes as it warms: the gel sits z (1 - e^(-t/tau)) further in, z of
/// either sign, at most 0.4 mm (the rod starts 0.5 mm clear of the gel).
fn zero_drift(history: &RodHistory, u: Draw, p: &mut Params) -> Vec<f64> {
    let top = history.rod_mm.iter().cloned().fold(0.0, f64::max);
    let sign = if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
    let z_mm = sign * (u(0.03, 0.06) * top).min(0.4);
    let tau_s = u(40.0, 150.0);
    p.extend([("z_mm", z_mm), ("tau_s", tau_s)]);
    history
        .t_s
        .iter()
        .zip(&history.rod_mm)
        .map(|(t, r)| r + z_mm * (1.0 - (-t / tau_s).exp()))
        .collect()
}

/// Play of width b in the drive: the tip stays put until the encoder has moved b/2 past it,
/// then follows b/2 behind. It starts as if it had last moved in.
fn backlash(rod_mm: &[f64], u: Draw, p: &mut Params) -> Vec<f64> {
    let top = rod_mm.iter().cloned().fold(0.0, f64::max);
    let b_mm = u(0.04, 0.08) * top;
    p.push(("b_mm", b_mm));
    let half = 0.5 * b_mm;
    let mut tip = rod_mm.first().copied().unwrap_or(0.0) - half;
    rod_mm
        .iter()
        .map(|&r| {
            tip = tip.clamp(r - half, r + half);
            tip
        })
        .collect()
}

/// The load train rings after each sudden change dv of the rod's speed: a sinusoid of f that
/// decays with tau, of size a F(t_e) (-dv / v_return) (a stop or a pull-back leaves the train
/// pressing on), the force never below zero.
fn ringing(spec: &SimSpec, clean: &Recording, u: Draw, p: &mut Params) -> Vec<f64> {
    let (a, freq_hz, tau_s) = (u(0.1, 0.2), u(6.0, 14.0), u(0.15, 0.4));
    p.extend([("a", a), ("freq_hz", freq_hz), ("tau_s", tau_s)]);
    let ch = &clean.channels;
    let v = speed_mm_per_min(&ch.t_s, &ch.rod_mm);
    let v_return = spec.test.return_speed_mm_per_min;
    let mut force = ch.load_n.clone();
    for e in 1..v.len() {
        let dv = v[e] - v[e - 1];
        if dv.abs() < 0.5 {
            continue;
        }
        let size = -a * ch.load_n[e - 1] * dv / v_return;
        for (f, t) in force[e..].iter_mut().zip(&ch.t_s[e..]) {
            let s = t - ch.t_s[e - 1];
            if s > 10.0 * tau_s {
                break;
            }
            *f += size * (-s / tau_s).exp() * (TAU * freq_hz * s).sin();
        }
    }
    force.iter_mut().for_each(|f| *f = f.max(0.0));
    force
}
