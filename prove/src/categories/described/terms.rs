//! Each kind's truth (stage, channels, dependence) and its terms on the recorded channels.

use super::signal::{column, column_mut, first_release, lag, Ctx};
use super::{Injection, Physics, Truth, ELECTRONICS, MATERIAL, OUTPUTS, TRANSDUCER};
use baseline::synth::SimSpec;
use recording::Recording;

use std::f64::consts::TAU;

/// Stage, channels and dependence of `inj`'s kind; the parameters follow as they are drawn.
pub(super) fn truth(inj: &Injection, spec: &SimSpec) -> Truth {
    use Physics::*;
    let on = inj.target.columns();
    let with_outputs = if inj.material_alone {
        Vec::new()
    } else {
        OUTPUTS.to_vec()
    };
    let (stages, channels, also, any, allowed, name) = match inj.physics.group() {
        super::Group::OutOfCatalogue => shape(inj.physics, on, with_outputs),
        super::Group::NewStage => named_shape(inj.physics),
    };
    let mut hidden: Vec<String> = spec
        .effects
        .iter()
        .map(|e| e.kind().name().to_string())
        .collect();
    if matches!(inj.physics, TendonRecovery | SensingElementRelaxation) {
        hidden.push("viscoelastic_relaxation".into());
    }
    Truth {
        physics: inj.physics,
        stages,
        channels,
        channels_also: also,
        depends_any: any,
        depends_allowed: allowed,
        catalogue_name: name,
        hidden,
        params: Vec::new(),
        material_alone: inj.material_alone,
    }
}

/// Stage, channels and dependence of a kind out of the catalogue acting on `on`;
/// `with_outputs` are the outputs a material's term may list besides the load.
fn shape(physics: Physics, on: Vec<&'static str>, with_outputs: Vec<&'static str>) -> Tuple {
    use Physics::*;
    match physics {
        OffsetStep | Wander | LineNotMains => (
            vec![ELECTRONICS],
            on,
            vec![],
            vec!["time"],
            vec!["time"],
            None,
        ),
        // The frame's vibration moves the force on the fingertip, so the outputs follow it;
        // with the load cell alone nothing tells it from the load cell's own pickup.
        FrameVibration => {
            let stages = if with_outputs.is_empty() {
                vec![MATERIAL, ELECTRONICS]
            } else {
                vec![MATERIAL]
            };
            (stages, on, with_outputs, vec!["time"], vec!["time"], None)
        }
        StuckChannel => {
            let mut allowed = vec!["time", "load_N", "rod_mm"];
            allowed.extend(on.iter().copied());
            (vec![ELECTRONICS], on, vec![], vec!["time"], allowed, None)
        }
        DeadSensor => (
            vec![ELECTRONICS, TRANSDUCER],
            OUTPUTS.to_vec(),
            vec![],
            vec![],
            vec!["load_N", "rod_mm"],
            None,
        ),
        SignFlip => {
            let mut any = vec!["load_N", "rod_mm"];
            any.extend(on.iter().copied());
            (vec![ELECTRONICS], on, vec![], any.clone(), any, None)
        }
        RateDependentLoad => (
            vec![MATERIAL],
            vec!["load_N"],
            with_outputs,
            vec!["rod_speed"],
            vec!["rod_speed", "load_N", "rod_mm"],
            None,
        ),
        SpanFollowsTemperature => span_shape(),
        PermanentSet => (
            vec![MATERIAL],
            vec!["load_N"],
            with_outputs,
            vec!["rod_mm"],
            vec!["rod_mm", "time", "load_N"],
            None,
        ),
        SensingElementSet => (
            vec![TRANSDUCER],
            OUTPUTS.to_vec(),
            vec![],
            vec!["load_N", "load_rate"],
            vec!["load_N", "load_rate", "time"],
            None,
        ),
        TendonRecovery => (
            vec![MATERIAL],
            vec!["load_N"],
            vec![],
            vec!["time"],
            vec!["time", "load_N", "rod_mm"],
            None,
        ),
        _ => named_shape(physics),
    }
}

/// The outputs' span following the temperature: the bridges' or the amplifiers', a function
/// of the temperature and of what the span multiplies.
fn span_shape() -> Tuple {
    let mut allowed = vec!["temp_C", "load_N", "rod_mm"];
    allowed.extend(OUTPUTS);
    let stages = vec![TRANSDUCER, ELECTRONICS];
    (
        stages,
        OUTPUTS.to_vec(),
        vec![],
        vec!["temp_C"],
        allowed,
        None,
    )
}

/// A catalogue entry at its new stage, on its channels.
fn named_shape(physics: Physics) -> Tuple {
    use Physics::*;
    match physics {
        MainsOnLoadCell => named(ELECTRONICS, "mains_interference"),
        SaturationOnLoadCell => named(ELECTRONICS, "amplifier_saturation"),
        StiffeningAlone => named(MATERIAL, "stiffening"),
        RelaxationAlone => named(MATERIAL, "viscoelastic_relaxation"),
        SensingElementRelaxation => (
            vec![TRANSDUCER],
            OUTPUTS.to_vec(),
            vec![],
            vec![],
            vec![],
            Some("viscoelastic_relaxation"),
        ),
        // The kinds out of the catalogue have no name.
        _ => (vec![], vec![], vec![], vec![], vec![], None),
    }
}

type Tuple = (
    Vec<&'static str>,
    Vec<&'static str>,
    Vec<&'static str>,
    Vec<&'static str>,
    Vec<&'static str>,
    Option<&'static str>,
);

/// A catalogue entry on the load cell's channel at `stage`.
fn named(stage: &'static str, name: &'static str) -> Tuple {
    (
        vec![stage],
        vec!["load_N"],
        vec![],
        vec![],
        vec![],
        Some(name),
    )
}

/// The kind's terms on the recorded channels (the material's are in the travel already).
pub(super) fn apply(
    inj: &Injection,
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    z: &mut dyn FnMut() -> f64,
    truth: &mut Truth,
) {
    use Physics::*;
    let t = ctx.clean.channels.t_s.clone();
    let end_s = t.last().copied().unwrap_or(0.0);
    let sign = |u: &mut dyn FnMut(f64, f64) -> f64| if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
    let p = &mut truth.params;
    match inj.physics {
        OffsetStep => {
            let col = inj.target.columns()[0];
            let t_step_s = u(0.3, 0.7) * end_s;
            let size = sign(u) * u(15.0, 40.0) * ctx.sigma(col);
            p.extend([("t_step_s", t_step_s), ("size", size)]);
            for (ts, x) in t.iter().zip(column_mut(rec, col).iter_mut()) {
                if *ts >= t_step_s {
                    *x += size;
                }
            }
        }
        StuckChannel => {
            let col = inj.target.columns()[0];
            let from = hold_middle(&ctx.history.rod_mm);
            p.push(("from_s", t[from]));
            let sigma = ctx.sigma(col);
            let x = column_mut(rec, col);
            let held = x[from];
            for v in &mut x[from..] {
                *v = if inj.alternate { held } else { sigma * z() };
            }
        }
        DeadSensor => {
            for col in OUTPUTS {
                let sigma = ctx.sigma(col);
                column_mut(rec, col)
                    .iter_mut()
                    .for_each(|x| *x = sigma * z());
            }
        }
        SignFlip => {
            let col = inj.target.columns()[0];
            column_mut(rec, col).iter_mut().for_each(|x| *x = -*x);
        }
        SpanFollowsTemperature => {
            let s = sign(u);
            span(rec, ctx, u, s, p);
        }
        FrameVibration | LineNotMains | Wander | MainsOnLoadCell => {
            line(inj, rec, ctx, u, p);
        }
        SensingElementSet => sensing_set(rec, ctx, u, p),
        SensingElementRelaxation => sensing_relaxation(rec, ctx, u, p),
        TendonRecovery => tendon(rec, ctx, u, p),
        StiffeningAlone => {
            let exponent = u(2.0, 3.0);
            p.push(("exponent", exponent));
            let clean = &ctx.clean.channels.load_n;
            let peak = clean.iter().cloned().fold(f64::MIN_POSITIVE, f64::max);
            let law = |f: f64| peak * f.signum() * (f.abs() / peak).powf(exponent);
            replace_load(rec, clean, law);
        }
        SaturationOnLoadCell => {
            let second = second_peak(&ctx.clean.channels.load_n, &ctx.history.rod_mm);
            let limit_n = u(0.6, 0.9) * second;
            p.push(("limit_N", limit_n));
            rec.channels
                .load_n
                .iter_mut()
                .for_each(|f| *f = f.min(limit_n));
        }
        RateDependentLoad | PermanentSet | RelaxationAlone => {}
    }
}

/// The load replaced by `law` of its clean value, the noise kept.
fn replace_load(rec: &mut Recording, clean: &[f64], law: impl Fn(f64) -> f64) {
    for (f, &c) in rec.channels.load_n.iter_mut().zip(clean) {
        *f = law(c) + (*f - c);
    }
}

/// The outputs' span times 1 + beta (T - T_0), T_0 the temperature at the start.
fn span(
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    sign: f64,
    p: &mut Vec<(&'static str, f64)>,
) {
    let beta_per_c = sign * u(0.01, 0.03);
    p.push(("beta_per_C", beta_per_c));
    let temp = ctx.clean.temp_c.clone().unwrap_or_default();
    let t0 = temp.first().copied().unwrap_or(0.0);
    for col in OUTPUTS {
        for (x, tc) in column_mut(rec, col).iter_mut().zip(&temp) {
            *x *= 1.0 + beta_per_c * (tc - t0);
        }
    }
}

/// A sinusoid on the kind's channels: a frame's vibration (2.5-4.5 Hz), a line at no mains
/// frequency (11-23 Hz), a wander (0.03-0.07 Hz), mains (50 or 60 Hz).
fn line(
    inj: &Injection,
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    p: &mut Vec<(&'static str, f64)>,
) {
    let (freq_hz, size) = match inj.physics {
        Physics::FrameVibration => (u(2.5, 4.5), u(5.0, 12.0)),
        Physics::LineNotMains => (u(11.0, 23.0), u(3.0, 8.0)),
        Physics::Wander => (u(0.03, 0.07), u(10.0, 25.0)),
        _ => {
            let mains = if u(0.0, 1.0) < 0.5 { 50.0 } else { 60.0 };
            (mains + u(-0.1, 0.1), u(5.0, 15.0))
        }
    };
    let phase = u(0.0, TAU);
    p.push(("freq_hz", freq_hz));
    let t = ctx.clean.channels.t_s.clone();
    let mut lines: Vec<(&str, f64)> = inj
        .target
        .columns()
        .into_iter()
        .map(|col| (col, size * ctx.sigma(col)))
        .collect();
    if inj.physics == Physics::FrameVibration && !inj.material_alone {
        lines.extend(followers(ctx, size * ctx.sigma("load_N")));
    }
    for (col, amplitude) in lines {
        p.push(("amplitude", amplitude));
        for (x, ts) in column_mut(rec, col).iter_mut().zip(&t) {
            *x += amplitude * (TAU * freq_hz * ts + phase).sin();
        }
    }
}

/// The outputs' share of a force oscillation of `load_amplitude` N: each output's swing per
/// newton of the clean recording's first loading.
fn followers(ctx: &Ctx, load_amplitude: f64) -> Vec<(&'static str, f64)> {
    let load = &ctx.clean.channels.load_n;
    let (at_peak, _) = argmax(load);
    let swing = load[at_peak] - load[0];
    OUTPUTS
        .iter()
        .map(|&col| {
            let out = column(ctx.clean, col);
            (col, load_amplitude * (out[at_peak] - out[0]) / swing)
        })
        .collect()
}

/// The sensing element's set s: it follows the normalised load with `tau_up_s` while the load
/// is above it and creeps back with `tau_down_s`; each output gains c s times its swing at the
/// peak load.
fn sensing_set(
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    p: &mut Vec<(&'static str, f64)>,
) {
    let (c, tau_up_s, tau_down_s) = (u(0.08, 0.15), u(5.0, 15.0), u(30.0, 90.0));
    p.extend([("c", c), ("tau_up_s", tau_up_s), ("tau_down_s", tau_down_s)]);
    let clean = &ctx.clean.channels;
    let (at_peak, peak) = argmax(&clean.load_n);
    let mut s = 0.0;
    let set: Vec<f64> = (0..clean.t_s.len())
        .map(|i| {
            if i > 0 {
                let f = clean.load_n[i] / peak;
                let tau = if f > s { tau_up_s } else { tau_down_s };
                s += (1.0 - (-(clean.t_s[i] - clean.t_s[i - 1]) / tau).exp()) * (f - s);
            }
            s
        })
        .collect();
    for col in OUTPUTS {
        let v = column(ctx.clean, col);
        let swing = v[at_peak] - v[0];
        for (x, s) in column_mut(rec, col).iter_mut().zip(&set) {
            *x += c * swing * s;
        }
    }
}

/// The outputs' load-driven part relaxes by `fraction` with `tau_s` (the load does not).
fn sensing_relaxation(
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    p: &mut Vec<(&'static str, f64)>,
) {
    let (fraction, tau_s) = (u(0.12, 0.22), u(10.0, 30.0));
    p.extend([("fraction", fraction), ("tau_s", tau_s)]);
    let t = &ctx.clean.channels.t_s;
    for col in OUTPUTS {
        let v = column(ctx.clean, col);
        let driven: Vec<f64> = v.iter().map(|x| x - v[0]).collect();
        let relaxed = lag(t, &driven, tau_s);
        for (x, r) in column_mut(rec, col).iter_mut().zip(&relaxed) {
            *x -= fraction * r;
        }
    }
}

/// A tendon: F - a lag(F, tau_1) relaxes, and the whole recovers by (1 + b (1 - e^(-t/tau_2)))
/// as it dries. It cannot push back: once the relaxed tendon lags behind a fast return it goes
/// slack and the load is zero (as `sim::effects` opens the contact of a relaxing gel).
fn tendon(
    rec: &mut Recording,
    ctx: &Ctx,
    u: &mut dyn FnMut(f64, f64) -> f64,
    p: &mut Vec<(&'static str, f64)>,
) {
    let (a, tau_1_s, b, tau_2_s) = (u(0.25, 0.35), u(15.0, 40.0), u(0.1, 0.25), u(60.0, 200.0));
    p.extend([
        ("a", a),
        ("tau_1_s", tau_1_s),
        ("b", b),
        ("tau_2_s", tau_2_s),
    ]);
    let clean = &ctx.clean.channels;
    let lagged = lag(&clean.t_s, &clean.load_n, tau_1_s);
    let rows = clean.t_s.iter().zip(&clean.load_n).zip(&lagged);
    for (f, ((t, c), l)) in rec.channels.load_n.iter_mut().zip(rows) {
        let dried = 1.0 + b * (1.0 - (-t / tau_2_s).exp());
        *f += ((c - a * l) * dried).max(0.0) - c;
    }
}

/// Index and value of the largest element.
fn argmax(x: &[f64]) -> (usize, f64) {
    x.iter()
        .enumerate()
        .fold((0, f64::MIN_POSITIVE), |(bi, bv), (i, &v)| {
            if v > bv {
                (i, v)
            } else {
                (bi, bv)
            }
        })
}

/// The largest load after the first release (the second cycle's peak; the first's when there
/// is none).
fn second_peak(load_n: &[f64], rod_mm: &[f64]) -> f64 {
    let from = first_release(rod_mm);
    let after = load_n[from..].iter().cloned().fold(0.0, f64::max);
    let release_load = load_n[from];
    if after < 0.9 * release_load && after > 0.2 * release_load {
        after
    } else {
        argmax(load_n).1
    }
}

/// The sample in the middle of the first hold (the rod still at the top of its first loading),
/// or of its first turn when it does not hold.
fn hold_middle(rod_mm: &[f64]) -> usize {
    let release = first_release(rod_mm);
    let top = rod_mm[release.saturating_sub(1)];
    let start = (0..release)
        .rev()
        .take_while(|&i| (rod_mm[i] - top).abs() < 1e-9)
        .last()
        .unwrap_or(release);
    (start + release) / 2
}
