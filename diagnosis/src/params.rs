//! Honest parameters: every fitted value with its standard error, unit, the bounds the fit was
//! allowed and whether it ended on one ([`ParamDetail`]), and the rule that decides whether an
//! effect whose primary parameter the data did not resolve may still be named ([`resolved`]).

use sim::effects::EffectKind;

use crate::candidate::Candidate;
use crate::data::Data;
use crate::fit::{physical, stderr, Model, BLEND_AT, N_BASE, OFFSET_AT, SCALE_AT};
use crate::output::ParamDetail;
use crate::preconditions::Features;
use crate::specs::unit;
use crate::specs::ParamSpec;
use crate::static_shape::Span;
use crate::stats;

/// A value within this share of its range from a bound sits on it (LM clamps at the bound, so
/// a resolved optimum is never this close by chance).
const AT_BOUND_SHARE: f64 = 1e-3;

/// The baseline's names and units, in parameter-vector order.
const BASELINE: [(&str, &str); N_BASE] = [
    ("youngs_modulus_Pa", "Pa"),
    ("force_exponent_shift", "1"),
    ("scale_fz", "1"),
    ("scale_mx", "1"),
    ("scale_my", "1"),
    ("offset_load_N", "N"),
    ("offset_fz_V", "V"),
    ("offset_mx_V", "V"),
    ("offset_my_V", "V"),
    ("force_exponent_curvature", "1"),
    ("force_warp_at_60pct", "1"),
    ("force_warp_at_30pct", "1"),
    ("force_warp_at_10pct", "1"),
    ("map_blend_fz", "1"),
    ("map_blend_mx", "1"),
    ("map_blend_my", "1"),
    ("force_law_blend", "1"),
    ("map_load_share", "1"),
    ("map_load_level", "1"),
];

/// Lag-1 correlation of the fit's weighted residual (inflates the standard errors).
fn residual_rho(c: &Candidate) -> f64 {
    stats::lag1(&c.fit_residual)
}

/// Duration of the recording, s.
fn record_s(data: &Data) -> f64 {
    let t = &data.full.t_s;
    t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0)
}

/// Parameter `i` of `c` in full; `name` as reported.
/// Whether the internal value `v` sits on `spec`'s lower and upper bound (within
/// `AT_BOUND_SHARE` of its range).
pub(crate) fn on_bound(spec: &ParamSpec, v: f64) -> (bool, bool) {
    let tol = AT_BOUND_SHARE * (spec.upper - spec.lower);
    (v <= spec.lower + tol, v >= spec.upper - tol)
}

/// The 95 % interval of parameter `i` of `c` where it is held fixed at a value fitted
/// elsewhere: the drift's time constant, the measured temperature's (its profile interval).
fn fixed_interval(c: &Candidate, i: usize) -> Option<(f64, f64)> {
    let at = crate::fit::param_index(&c.model.kinds, EffectKind::ThermalDrift, 1)?;
    let th = c.model.setup.thermal.as_ref()?;
    (at == i && c.model.is_fixed(i)).then_some(th.tau_ci_s)
}

fn detail(c: &Candidate, i: usize, name: &str, unit: &str, rho: f64, data: &Data) -> ParamDetail {
    let model: &Model = &c.model;
    let spec = &model.specs()[i];
    let v = c.fitted.full[i];
    let (on_lower, on_upper) = on_bound(spec, v);
    let phys = |x: f64| if spec.log { x.exp() } else { x };
    let value = physical(model, &c.fitted.full, i);
    let fixed = model.is_fixed(i);
    let beyond_record = i >= N_BASE && name.starts_with("tau") && value > record_s(data);
    let note = if fixed_interval(c, i).is_some() {
        Some("the measured temperature's warm-up time constant (the drift is regressed on temp_C); the interval is its fit's 95 % profile interval".to_string())
    } else if fixed {
        Some("held fixed, not fitted (see the effect's evidence)".to_string())
    } else if on_lower || on_upper {
        Some(format!(
            "at its {} bound {}: the data did not resolve it, so the value is {} bound only",
            if on_lower { "lower" } else { "upper" },
            fmt(phys(if on_lower { spec.lower } else { spec.upper })),
            if on_lower { "an upper" } else { "a lower" },
        ))
    } else if beyond_record {
        Some(format!(
            "longer than the record ({:.0} s): the recording shows only the start of the decay, so {} s is a lower bound",
            record_s(data),
            fmt(value)
        ))
    } else {
        None
    };
    ParamDetail {
        name: name.to_string(),
        value,
        stderr: if fixed {
            None
        } else {
            stderr(model, &c.fitted, i, rho).filter(|s| s.is_finite())
        },
        ci_low: fixed_interval(c, i).map(|r| r.0),
        ci_high: fixed_interval(c, i).map(|r| r.1),
        unit: unit.to_string(),
        lower: phys(spec.lower),
        upper: phys(spec.upper),
        at_bound: !fixed && (on_lower || on_upper || beyond_record),
        note,
    }
}

fn fmt(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e4 || v.abs() < 1e-2) {
        format!("{v:.2e}")
    } else {
        format!("{v:.3}")
    }
}

/// The one recording channel a baseline parameter calibrates (none for the contact law).
fn channel_of(i: usize) -> Option<usize> {
    let within = |at: usize, n: usize| (at..at + n).contains(&i);
    if within(SCALE_AT, 3) {
        Some(i - SCALE_AT + 1)
    } else if within(OFFSET_AT, 4) {
        Some(i - OFFSET_AT)
    } else if within(BLEND_AT, 3) {
        Some(i - BLEND_AT + 1)
    } else {
        None
    }
}

/// The name of the modulus's place when the baseline is a user's simulation: the factor its
/// load (and with it its outputs) is scaled by.
const LOAD_SCALE: (&str, &str) = ("load_scale", "1");

/// The baseline parameters `c` reports, each with its index, name and unit: every one of our
/// FE's; of a user's simulation the load scale, the output scales and the offsets (its
/// contact law and maps are its own, held).
fn reported(c: &Candidate) -> Vec<(usize, &'static str, &'static str)> {
    let simulated = c.model.setup.user_simulation;
    BASELINE
        .iter()
        .enumerate()
        .filter(|(i, _)| !simulated || *i == 0 || (SCALE_AT..OFFSET_AT + 4).contains(i))
        .map(|(i, &(name, unit))| match i {
            0 if simulated => (i, LOAD_SCALE.0, LOAD_SCALE.1),
            _ => (i, name, unit),
        })
        .collect()
}

/// Every baseline parameter by its reported name, at its physical value (the JSON's
/// `baseline.params`).
pub fn baseline_values(base: &Candidate) -> Vec<(&'static str, f64)> {
    reported(base)
        .into_iter()
        .map(|(i, name, _)| (name, physical(&base.model, &base.fitted.full, i)))
        .collect()
}

/// Every calibration parameter of the baseline in full (the compared channels' offsets only).
pub fn baseline(base: &Candidate, data: &Data) -> Vec<ParamDetail> {
    let rho = residual_rho(base);
    reported(base)
        .into_iter()
        .filter(|(i, _, _)| channel_of(*i).is_none_or(|c| base.model.setup.used[c]))
        .map(|(i, name, u)| detail(base, i, name, u, rho, data))
        .collect()
}

/// Each effect of `c` with its parameters in full, in `c.kinds` order.
pub fn effects(c: &Candidate, data: &Data) -> Vec<(EffectKind, Vec<ParamDetail>)> {
    let rho = residual_rho(c);
    let mut at = N_BASE;
    let mut out = Vec::new();
    for &kind in &c.kinds {
        let ps = kind
            .param_names()
            .iter()
            .enumerate()
            .map(|(j, name)| detail(c, at + j, name, unit(name), rho, data))
            .collect();
        at += kind.param_names().len();
        out.push((kind, ps));
    }
    out
}

/// Whether every effect of `c` may be named with the parameters it has.
///
/// An effect's primary parameter is what the data must show to tell it from the others. When it
/// ends on a bound the data did not resolve it, and the effect is named only if its signature is
/// unambiguous without that value:
/// - a relaxation whose time constant is at the upper bound, or longer than the record, still
///   shows as decay under a held rod, which no other catalogue entry makes with the load cell:
///   named (with a hold), tau reported as a lower bound;
/// - AC coupling likewise still shows as sag or undershoot of the outputs alone (its
///   precondition, a hold or unloading, is already checked);
/// - any other primary parameter on a bound (a lag, a loop width, an exponent, a rail, an
///   angle, a drift's amplitude, a time constant at its *lower* bound) means the operator was
///   bent as far as allowed towards some other misfit: not named.
///
/// And a static-shape effect (`stiffening`, `bridge_nonlinearity`) is named only where it bends
/// an output beyond what the calibration's map may take ([`absorbed_static_shape`]).
pub fn resolved(c: &Candidate, protocol: &Features) -> Result<(), String> {
    at_bounds(c, protocol)?;
    match absorbed_static_shape(c) {
        Some((_, why)) => Err(why),
        None => Ok(()),
    }
}

/// How many standard errors towards the identity the strength of a static shape is moved
/// before its bend is judged: the two of a 95 % interval.
pub(crate) const STRENGTH_Z: f64 = 2.0;

/// The documented threshold of the static-shape effects (`hardware/fit-bounds.toml`,
/// [`crate::static_shape`]): of the static-shape effects of `c` that, at their strength moved
/// two (`STRENGTH_Z`) standard errors towards the identity, bend no compared output beyond the
/// calibration's span, the one closest to the identity (in standard errors): its index in
/// `c.kinds` and why in words. `None` when every one bends beyond it.
///
/// Only the static shapes are held to this: they alone are shapes a calibration of the static
/// maps also makes. Whether any effect is there at all is the nested comparison's question
/// (BIC and held-out misfit), which stays sound where a large structured misfit makes a single
/// parameter's standard error meaningless (a real rig's relaxation at 0.18 +- 0.40).
pub fn absorbed_static_shape(c: &Candidate) -> Option<(usize, String)> {
    let is_static =
        |k: &EffectKind| matches!(k, EffectKind::Stiffening | EffectKind::BridgeNonlinearity);
    // Most models hold no static shape: spare them the residual and the span.
    if !c.kinds.iter().any(is_static) {
        return None;
    }
    let rho = residual_rho(c);
    let span = Span::of(&c.model.setup.drive, &c.model.setup.fit_bounds);
    let mut at = N_BASE;
    let mut worst: Option<(usize, f64, String)> = None;
    for (e, &kind) in c.kinds.iter().enumerate() {
        let first = at;
        at += kind.param_names().len();
        let neutral = match kind {
            EffectKind::Stiffening => 1.0,
            EffectKind::BridgeNonlinearity => 0.0,
            _ => continue,
        };
        let Some(se) = stderr(&c.model, &c.fitted, first, rho) else {
            continue;
        };
        let value = physical(&c.model, &c.fitted.full, first);
        let z = (value - neutral).abs() / se.max(f64::MIN_POSITIVE);
        if worst.as_ref().is_some_and(|w| w.1 <= z) {
            continue;
        }
        let sure = if z <= STRENGTH_Z {
            neutral
        } else {
            value - (value - neutral).signum() * STRENGTH_Z * se
        };
        let Some(words) = within_calibration(c, &span, kind, sure) else {
            continue;
        };
        let why = format!(
            "{} of {} is {} +- {}: {words}",
            kind.param_names()[0],
            kind.name(),
            fmt(value),
            fmt(se)
        );
        worst = Some((e, z, why));
    }
    worst.map(|(e, _, why)| (e, why))
}

/// For a static-shape effect of strength `sure` that bends no compared output beyond the span
/// the calibration's map may take ([`Span`]), why in words; `None` when it bends one beyond it
/// or is not a static shape.
fn within_calibration(c: &Candidate, span: &Span, kind: EffectKind, sure: f64) -> Option<String> {
    let setup = c.model.setup;
    let mut largest: Option<(f64, f64)> = None;
    for k in (0..3).filter(|&k| setup.used[k + 1]) {
        let bend = span.bend(kind, sure, k)?;
        if bend > span.span[k] {
            return None;
        }
        if largest.is_none_or(|(b, _)| bend > b) {
            largest = Some((bend, span.span[k]));
        }
    }
    let (bend, allowed) = largest?;
    Some(format!(
        "two standard errors towards none it bends the outputs by at most {:.1} % over 5-100 % of full load, within the {:.1} % the calibration's map from the load may take there (hardware/fit-bounds.toml)",
        100.0 * bend.exp_m1(),
        100.0 * allowed.exp_m1()
    ))
}

/// An effect whose strength ended on zero, where it is the identity at any time constant (a
/// relaxation's fraction, a drift's amplitude), is not there: the fit wanted less of it than any.
/// Its time constant then only shapes a vanishing term (at 5 kHz a relaxation of 1e-4 of the load
/// passed both tests on another model's baseline, and was named).
fn vanished(c: &Candidate, first: usize, kind: EffectKind) -> Result<(), String> {
    let strength = match kind {
        EffectKind::ViscoelasticRelaxation => 1,
        EffectKind::ThermalDrift => 0,
        _ => return Ok(()),
    };
    let i = first + strength;
    let spec = &c.model.specs()[i];
    let (on_lower, on_upper) = on_bound(spec, c.fitted.full[i]);
    let at_zero = (on_lower && spec.lower == 0.0) || (on_upper && spec.upper == 0.0);
    if at_zero && !c.model.is_fixed(i) {
        return Err(format!(
            "{} of {} at zero, its bound: the effect is the identity there",
            kind.param_names()[strength],
            kind.name()
        ));
    }
    Ok(())
}

/// The primary parameters' bounds: see [`resolved`]. The search's forward step asks only
/// this: while other effects are missing, the residual's structure inflates every standard
/// error, and the strength test waits for the search's last model.
pub fn at_bounds(c: &Candidate, protocol: &Features) -> Result<(), String> {
    let data = c.model.setup.data;
    let mut at = N_BASE;
    for &kind in &c.kinds {
        let p = detail(c, at, kind.param_names()[0], "", 0.0, data);
        let spec = &c.model.specs()[at];
        let upper = c.fitted.full[at] > 0.5 * (spec.lower + spec.upper);
        vanished(c, at, kind)?;
        at += kind.param_names().len();
        if !p.at_bound {
            continue;
        }
        let allowed = match kind {
            EffectKind::ViscoelasticRelaxation => upper && protocol.hold,
            EffectKind::HighpassCoupling => upper,
            _ => false,
        };
        if !allowed {
            return Err(format!(
                "primary parameter {} of {} at its bound ({}): unresolved, and its signature is ambiguous without it",
                p.name,
                kind.name(),
                fmt(p.value)
            ));
        }
    }
    Ok(())
}
