//! The kinds of the transducer and the electronics: terms on the recorded channels, computed
//! from the noise-free recording (what the chain would read without them) and put on the noisy
//! one; the load's column is left alone by the transducer's.

use sim::compression::RodHistory;

use super::signal::{column, column_mut, lag, peak_abs, presses, speed_mm_per_min, Draw, Params};
use super::{Hidden, Kind, OUTPUTS};
use baseline::synth::Noise;
use recording::Recording;

/// What the channel terms read besides the recording.
pub(super) struct Ctx<'a> {
    /// The recording without noise and without the kind.
    pub clean: &'a Recording,
    pub history: &'a RodHistory,
    pub noise: Noise,
    /// The schedule's loading speed, mm/min.
    pub speed_mm_per_min: f64,
}

impl Ctx<'_> {
    /// The white noise's deviation on `column`.
    fn sigma(&self, column: &str) -> f64 {
        match column {
            "load_N" => self.noise.load_n,
            "fz_V" => self.noise.volts[0],
            "mx_V" => self.noise.volts[1],
            _ => self.noise.volts[2],
        }
    }
}

/// The kind's terms on `rec`'s channels (the material's are in the travel already).
pub(super) fn apply(hidden: &Hidden, rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let on = hidden.on.columns();
    match hidden.kind {
        Some(Kind::PillarGap) => gap(rec, ctx, u, p),
        Some(Kind::MomentAxisTurning) => turning(rec, ctx, u, p),
        Some(Kind::SupplySag) => sag(rec, ctx, u, p),
        Some(Kind::MotorPickup) => pickup(&on, rec, ctx, u, p),
        Some(Kind::LoadCellCreep) => creep(rec, ctx, u, p),
        Some(Kind::CounterWrap) => wrap(&on, rec, ctx, u, p),
        Some(Kind::GainDroop) => droop(&on, rec, ctx, u, p),
        _ => {}
    }
}

/// The outputs' part that the load drives: each output less its value at the first sample (at
/// rest in these protocols).
fn driven(ctx: &Ctx, col: &str) -> Vec<f64> {
    let v = column(ctx.clean, col);
    v.iter().map(|x| x - v[0]).collect()
}

/// A gap the gel must push `F_g` through before the pillar takes load: each output's driven
/// part times max(0, 1 - F_g / F).
fn gap(rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let load = &ctx.clean.channels.load_n;
    let f_gap_n = u(0.05, 0.12) * peak_abs(load, 0..load.len());
    p.push(("gap_N", f_gap_n));
    for col in OUTPUTS {
        let d = driven(ctx, col);
        for ((x, d), f) in column_mut(rec, col).iter_mut().zip(&d).zip(load) {
            let kept = if *f > f_gap_n { 1.0 - f_gap_n / f } else { 0.0 };
            *x += d * (kept - 1.0);
        }
    }
}

/// The moments' driven parts turned by theta_max F / F_peak (either way).
fn turning(rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let sign = if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
    let theta_max_deg = sign * u(6.0, 12.0);
    p.push(("theta_max_deg", theta_max_deg));
    let load = &ctx.clean.channels.load_n;
    let peak = peak_abs(load, 0..load.len()).max(f64::MIN_POSITIVE);
    let (mx, my) = (driven(ctx, "mx_V"), driven(ctx, "my_V"));
    for i in 0..load.len() {
        let (s, c) = (theta_max_deg.to_radians() * load[i] / peak).sin_cos();
        rec.channels.mx_v[i] += (c - 1.0) * mx[i] - s * my[i];
        rec.channels.my_v[i] += s * mx[i] + (c - 1.0) * my[i];
    }
}

/// The bridges' supply sags by s over the recording: every output (its offset cut is taken from
/// the same supply) times 1 - s t / T.
fn sag(rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let s = u(0.08, 0.2);
    p.push(("sag", s));
    let t = &ctx.clean.channels.t_s;
    let end_s = t.last().copied().unwrap_or(1.0).max(f64::MIN_POSITIVE);
    for col in OUTPUTS {
        let v = column(ctx.clean, col).to_vec();
        for ((x, v), ts) in column_mut(rec, col).iter_mut().zip(&v).zip(t) {
            *x -= v * s * ts / end_s;
        }
    }
}

/// The drive's current picked up on each channel of `on`: a tanh(v / v_0), v_0 the loading
/// speed, a of 20-50 noise deviations and either sign (the cable's routing).
fn pickup(on: &[&str], rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let v = speed_mm_per_min(&ctx.history.t_s, &ctx.history.rod_mm);
    p.push(("v0_mm_per_min", ctx.speed_mm_per_min));
    for col in on {
        let sign = if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
        let a = sign * u(20.0, 50.0) * ctx.sigma(col);
        p.push(("a", a));
        for (x, v) in column_mut(rec, col).iter_mut().zip(&v) {
            *x += a * (v / ctx.speed_mm_per_min).tanh();
        }
    }
}

/// The load cell creeps: it reads F + c lag(F, tau).
fn creep(rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let (c, tau_s) = (u(0.05, 0.12), u(8.0, 30.0));
    p.extend([("c", c), ("tau_s", tau_s)]);
    let ch = &ctx.clean.channels;
    let memory = lag(&ch.t_s, &ch.load_n, tau_s);
    for (x, m) in rec.channels.load_n.iter_mut().zip(&memory) {
        *x += c * m;
    }
}

/// The reading is kept in an integer of range +-L that wraps round: L is 0.6-0.9 of the least
/// press's peak, so every press wraps.
fn wrap(on: &[&str], rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    for col in on {
        let clean = column(ctx.clean, col);
        let least = presses(&ctx.history.rod_mm)
            .into_iter()
            .map(|r| peak_abs(clean, r))
            .fold(f64::INFINITY, f64::min);
        let limit = u(0.6, 0.9) * least;
        p.push(("limit", limit));
        for x in column_mut(rec, col).iter_mut() {
            *x -= 2.0 * limit * (*x / (2.0 * limit)).round();
        }
    }
}

/// The amplifier's gain droops with a memory of its output's power: x (1 - g lag((x / x_peak)^2,
/// tau)), g 10-25 % at full output held long.
fn droop(on: &[&str], rec: &mut Recording, ctx: &Ctx, u: Draw, p: &mut Params) {
    let t = &ctx.clean.channels.t_s;
    for col in on {
        let (g, tau_s) = (u(0.1, 0.25), u(5.0, 20.0));
        p.extend([("g", g), ("tau_s", tau_s)]);
        let clean = column(ctx.clean, col);
        let peak = peak_abs(clean, 0..clean.len()).max(f64::MIN_POSITIVE);
        let power: Vec<f64> = clean.iter().map(|x| (x / peak).powi(2)).collect();
        let heat = lag(t, &power, tau_s);
        for (x, h) in column_mut(rec, col).iter_mut().zip(&heat) {
            *x *= 1.0 - g * h;
        }
    }
}
