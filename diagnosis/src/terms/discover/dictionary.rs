//! The dictionary of candidate features a missing term may be built from: functions of what the
//! recording holds, on the decimated series. Nothing here names a physics; each feature says
//! which recorded quantities it is a function of (`depends_on` in the contract's words), its
//! expression and its unit, and whether it follows the rod's drive (the stage needs that).
//!
//! The quantities: time t; the rod's travel x, its speed v, |v| and the direction of motion
//! sgn v; the load L (the calibrated model's load signal: the recorded load would put the load
//! cell's own noise in a column fitted to it) and its rate dL/dt; the temperature T where it
//! moves; the channel's own model signal s (a gain that changes); the other recorded channels
//! (a leak between channels); the load through first-order memories at time scales spread over
//! the record (h_tau(L): what a relaxation, a creep or a self-heating is a function of); the time
//! since the last regime change, plain and as a damped oscillation (a rig that rings after a
//! sudden change); the largest travel so far (a material softened where it has been before).
//! Products of the drive's quantities and of the channel's signal with time, temperature and
//! motion write the forms nobody listed (a gain that drifts, a modulus that follows the
//! temperature, a loss that depends on the direction of motion).

use super::super::fitting::{derivative, Context};

/// A recorded quantity a feature is a function of (the contract's `depends_on` vocabulary).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Quantity {
    Time,
    RodMm,
    RodSpeed,
    LoadN,
    LoadRate,
    TempC,
    /// A recorded channel (0 load, 1..4 the outputs) as itself.
    Channel(usize),
    TimeSinceChange,
    LoadHistory,
}

impl Quantity {
    /// The contract's name.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::RodMm => "rod_mm",
            Quantity::RodSpeed => "rod_speed",
            Quantity::LoadN => "load_N",
            Quantity::LoadRate => "load_rate",
            Quantity::TempC => "temp_C",
            Quantity::Channel(c) => crate::data::CHANNELS[c],
            Quantity::TimeSinceChange => "time_since_change",
            Quantity::LoadHistory => "load_history",
        }
    }

    /// Whether the quantity follows the rod's drive (a term of only time or temperature does not:
    /// the stage of such a term is that channel's electronics).
    pub fn follows_drive(self) -> bool {
        !matches!(self, Quantity::Time | Quantity::TempC)
    }
}

/// One candidate feature: a column on the decimated series and what it means.
#[derive(Debug, Clone)]
pub(crate) struct Feature {
    /// Its family: features of one family differ only by a time constant or a frequency on a
    /// grid (a bootstrap resample that picks a neighbour on the grid keeps the family).
    pub family: String,
    /// The grid value (a time constant, s; for a damped oscillation its frequency, Hz), if any.
    pub grid: Option<f64>,
    /// The expression, with the grid value written in.
    pub expr: String,
    /// The unit of the feature's values.
    pub unit: String,
    pub depends: Vec<Quantity>,
    /// The column, scaled to unit weighted RMS over the fitting stretch: a coefficient of the
    /// scaled column is `coefficient x scale` in the feature's own unit.
    pub column: Vec<f64>,
    /// The column's scale: raw = column x scale.
    pub scale: f64,
}

impl Feature {
    /// Whether the feature follows the rod's drive.
    pub fn follows_drive(&self) -> bool {
        self.depends.iter().any(|q| q.follows_drive())
    }
}

/// A raw series with its meaning, before scaling.
struct Raw {
    family: String,
    grid: Option<f64>,
    expr: String,
    unit: String,
    depends: Vec<Quantity>,
    values: Vec<f64>,
}

fn raw(family: &str, expr: &str, unit: &str, depends: &[Quantity], values: Vec<f64>) -> Raw {
    Raw {
        family: family.into(),
        grid: None,
        expr: expr.into(),
        unit: unit.into(),
        depends: depends.to_vec(),
        values,
    }
}

/// The quantities of the recording every feature is built from.
pub(crate) struct Quantities {
    pub t: Vec<f64>,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub load: Vec<f64>,
    pub load_rate: Vec<f64>,
    pub temp: Option<Vec<f64>>,
    /// Indices where the regime changes (the start of every segment but the first).
    pub changes: Vec<usize>,
    /// The frequency of the rod's periodic drive, Hz, if it has one.
    pub drive_hz: Option<f64>,
}

impl Quantities {
    pub fn of(ctx: &Context) -> Self {
        let d = &ctx.data.fit;
        let t0 = d.t_s.first().copied().unwrap_or(0.0);
        let t: Vec<f64> = d.t_s.iter().map(|t| t - t0).collect();
        let load = ctx.signal(0);
        let load_rate = derivative(&d.t_s, &load);
        // A temperature that does not move carries no feature.
        let temp = d.temp_c.as_ref().filter(|tc| moves(tc)).map(|tc| {
            let first = tc[0];
            tc.iter().map(|v| v - first).collect()
        });
        let changes = ctx.data.segments.iter().skip(1).map(|s| s.start).collect();
        Self {
            t,
            x: d.rod_mm.clone(),
            v: ctx.rod_speed.clone(),
            load,
            load_rate,
            temp,
            changes,
            drive_hz: super::super::line::drive_hz(ctx),
        }
    }

    fn len(&self) -> usize {
        self.t.len()
    }

    fn span_s(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0).max(1e-9)
    }

    /// The shortest step of the series, s.
    fn step_s(&self) -> f64 {
        self.t
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|d| *d > 0.0)
            .fold(f64::INFINITY, f64::min)
            .min(self.span_s())
    }
}

/// A series that moves beyond a hundredth of its own level's scale: 0.1 K on a room temperature.
fn moves(v: &[f64]) -> bool {
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    hi - lo > 0.1
}

/// Time constants spread over the record: from a few steps of the series to the record's span,
/// even in ln tau (eight per decade would separate neighbours no fit can tell apart).
fn time_constants(q: &Quantities) -> Vec<f64> {
    let (lo, hi) = ((4.0 * q.step_s()).max(0.05), q.span_s());
    let n = ((hi / lo).log10() * 3.0).ceil().max(1.0) as usize;
    (0..=n)
        .map(|i| lo * (hi / lo).powf(i as f64 / n as f64))
        .collect()
}

/// The first-order low-pass of `x` with time constant `tau_s`, exact for a signal linear
/// between the samples of any time base.
pub(crate) fn low_pass(t: &[f64], x: &[f64], tau_s: f64) -> Vec<f64> {
    let mut y = Vec::with_capacity(x.len());
    let mut prev = x.first().copied().unwrap_or(0.0);
    for (k, &xk) in x.iter().enumerate() {
        if k > 0 {
            let dt = (t[k] - t[k - 1]).max(0.0);
            let a = (-dt / tau_s).exp();
            // Exact for x linear over the step: y' = (x - y) / tau.
            let b = if dt > 0.0 {
                (1.0 - a) * tau_s / dt
            } else {
                1.0
            };
            let slope = xk - x[k - 1];
            prev = a * prev + (1.0 - a) * x[k - 1] + slope * (1.0 - b);
        }
        y.push(prev);
    }
    y
}

fn product(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a * b).collect()
}

/// The recorded quantities at each instant, each a feature alone and with every other as a
/// product: the drive (x, v, |v|, sgn v), the load (L, dL/dt), the load's stiffness at the
/// travel (dL/dx: a travel read with an error d moves the load by dL/dx d), whether the travel
/// is below the largest so far (a material that has been there before), time, the temperature
/// where it moves, the channel's own signal and the other outputs.
fn instantaneous(ctx: &Context, q: &Quantities, c: usize) -> Vec<Raw> {
    use Quantity::*;
    let v_max = q.v.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
    // The direction of motion, smooth through the rod's stops (a twentieth of its top speed).
    let sgn: Vec<f64> = q.v.iter().map(|v| v / v.hypot(0.05 * v_max)).collect();
    let abs_v: Vec<f64> = q.v.iter().map(|v| v.abs()).collect();
    let x_in: Vec<f64> = q.x.iter().map(|x| x.max(0.0)).collect();
    let mut top = 0.0f64;
    let below: Vec<f64> = x_in
        .iter()
        .map(|&x| {
            top = top.max(x);
            if top > 0.0 {
                1.0 - x / top
            } else {
                0.0
            }
        })
        .collect();
    let mut b = vec![
        raw("x", "x", "mm", &[RodMm], x_in.clone()),
        raw("v", "v", "mm/s", &[RodSpeed], q.v.clone()),
        raw("|v|", "|v|", "mm/s", &[RodSpeed], abs_v),
        raw("sgn v", "sgn(v)", "1", &[RodSpeed], sgn),
        raw("L", "L", "N", &[LoadN], q.load.clone()),
        raw("dL/dt", "dL/dt", "N/s", &[LoadRate], q.load_rate.clone()),
        raw(
            "dL/dx",
            "dL/dx",
            "N/mm",
            &[RodMm],
            stiffness(&x_in, &q.load),
        ),
        raw("below", "(1 - x / max past x)", "1", &[RodMm], below),
        raw("t", "t", "s", &[Time], q.t.clone()),
    ];
    if let Some(temp) = &q.temp {
        b.push(raw("T", "(T - T0)", "K", &[TempC], temp.clone()));
    }
    if c > 0 {
        let name = crate::data::CHANNELS[c];
        b.push(raw("s", name, "V", &[Channel(c)], ctx.signal(c)));
    }
    // Another output leaking into an output (a shared reference, a shared supply); the load
    // cell's chain shares nothing with the sensor's.
    for j in (1..4).filter(|&j| c > 0 && j != c && ctx.used[j]) {
        let y: Vec<f64> = ctx.data.fit.y[j]
            .iter()
            .map(|y| y - ctx.offset[j])
            .collect();
        let name = crate::data::CHANNELS[j];
        b.push(raw(&format!("y {name}"), name, "V", &[Channel(j)], y));
    }
    b
}

/// The load's stiffness against the travel, dL/dx, from the local exponent of the load's law:
/// ln L fitted by a quadratic in ln x where in contact, so n(x) = d ln L / d ln x and dL/dx =
/// n(x) L / x (smooth where the rod stands still, where a difference quotient has no value).
fn stiffness(x: &[f64], load: &[f64]) -> Vec<f64> {
    let top = load.iter().fold(0.0f64, |m, v| m.max(*v));
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(load)
        .filter(|(x, l)| **x > 0.0 && **l > 0.01 * top)
        .map(|(x, l)| (x.ln(), l.ln()))
        .collect();
    let Some(coef) = quadratic(&pts) else {
        return vec![0.0; x.len()];
    };
    x.iter()
        .zip(load)
        .map(|(&x, &l)| {
            if x > 0.0 && l > 0.01 * top {
                let n = coef[1] + 2.0 * coef[2] * x.ln();
                n * l / x
            } else {
                0.0
            }
        })
        .collect()
}

/// Least-squares coefficients of y = a + b u + c u^2 over `pts` (u, y).
fn quadratic(pts: &[(f64, f64)]) -> Option<[f64; 3]> {
    use nalgebra::{Matrix3, Vector3};
    if pts.len() < 3 {
        return None;
    }
    let mut a = Matrix3::zeros();
    let mut r = Vector3::zeros();
    for &(u, y) in pts {
        let v = Vector3::new(1.0, u, u * u);
        a += v * v.transpose();
        r += v * y;
    }
    let s = a.try_inverse()? * r;
    Some([s[0], s[1], s[2]])
}

/// Pairs whose product is another quantity or says nothing new: v |v|, v sgn v, |v| sgn v.
fn redundant(a: &str, b: &str) -> bool {
    let speed = |f: &str| matches!(f, "v" | "|v|" | "sgn v");
    speed(a) && speed(b)
}

/// Every instantaneous quantity alone, with every other as a product, and the load's and the
/// channel's own square and cube (a gain that changes with the level).
fn products(base: &[Raw], out: &mut Vec<Raw>) {
    for (i, a) in base.iter().enumerate() {
        for b in &base[i + 1..] {
            if redundant(&a.family, &b.family) {
                continue;
            }
            let mut depends = a.depends.clone();
            depends.extend(b.depends.iter().copied());
            depends.sort();
            depends.dedup();
            out.push(raw(
                &format!("{} * {}", a.family, b.family),
                &format!("{} {}", a.expr, b.expr),
                &product_unit(&a.unit, &b.unit),
                &depends,
                product(&a.values, &b.values),
            ));
        }
    }
    for r in base.iter().filter(|r| r.family == "L" || r.family == "s") {
        for (k, name) in [(2, "^2"), (3, "^3")] {
            out.push(raw(
                &format!("{}{name}", r.family),
                &format!("{}{name}", r.expr),
                &format!("{}{name}", r.unit),
                &r.depends,
                r.values.iter().map(|v| v.powi(k)).collect(),
            ));
        }
    }
}

fn product_unit(a: &str, b: &str) -> String {
    match (a, b) {
        ("1", u) | (u, "1") => u.to_string(),
        (a, b) => format!("{a} {b}"),
    }
}

/// Time alone, beyond the instantaneous quantities: its square and decays over the record (a
/// warm-up, a settling), of a time constant beyond a thirtieth of the record.
fn time_features(q: &Quantities, out: &mut Vec<Raw>) {
    use Quantity::*;
    let span = q.span_s();
    let t2: Vec<f64> = q.t.iter().map(|t| t * t).collect();
    out.push(raw("t^2", "t^2", "s^2", &[Time], t2));
    for tau in time_constants(q)
        .into_iter()
        .filter(|&tau| tau > span / 30.0)
    {
        let e: Vec<f64> = q.t.iter().map(|t| (-t / tau).exp()).collect();
        out.push(Raw {
            grid: Some(tau),
            ..raw("e^-t/tau", &format!("e^(-t / {tau:.3} s)"), "1", &[Time], e)
        });
    }
}

/// The load through first-order memories, and what follows each regime change.
fn history_features(q: &Quantities, out: &mut Vec<Raw>) {
    use Quantity::*;
    for tau in time_constants(q) {
        let lp = low_pass(&q.t, &q.load, tau);
        let hp: Vec<f64> = q.load.iter().zip(&lp).map(|(l, m)| l - m).collect();
        out.push(Raw {
            grid: Some(tau),
            ..raw(
                "L - h(L)",
                &format!("(L - h_{tau:.3}s(L))"),
                "N",
                &[LoadHistory],
                hp,
            )
        });
        out.push(Raw {
            grid: Some(tau),
            ..raw("h(L)", &format!("h_{tau:.3}s(L)"), "N", &[LoadHistory], lp)
        });
    }
    let since = time_since_change(q);
    for tau in time_constants(q).into_iter().take(8) {
        let e: Vec<f64> = since
            .iter()
            .map(|s| s.map_or(0.0, |s| (-s / tau).exp()))
            .collect();
        out.push(Raw {
            grid: Some(tau),
            ..raw(
                "e^-dt/tau",
                &format!("e^(-dt / {tau:.3} s)"),
                "1",
                &[TimeSinceChange],
                e,
            )
        });
    }
    ringing(q, &since, out);
}

/// The channel's own level times the load's memory at each time constant: a gain (or, on the
/// load, a stiffness) that follows what the load has done (a gel softened by the work done on
/// it, an amplifier whose gain droops while its output stays high).
fn level_with_memory(base: &[Raw], out: &mut Vec<Raw>) {
    let level = base
        .iter()
        .find(|r| r.family == "s")
        .or_else(|| base.iter().find(|r| r.family == "L"));
    let Some(level) = level else {
        return;
    };
    let memories: Vec<Raw> = out
        .iter()
        .filter(|r| r.family == "h(L)")
        .map(|m| {
            let mut depends = level.depends.clone();
            depends.push(Quantity::LoadHistory);
            Raw {
                grid: m.grid,
                ..raw(
                    &format!("{} * h(L)", level.family),
                    &format!("{} {}", level.expr, m.expr),
                    &product_unit(&level.unit, &m.unit),
                    &depends,
                    product(&level.values, &m.values),
                )
            }
        })
        .collect();
    out.extend(memories);
}

/// Time since the last regime change at each sample (none before the first).
fn time_since_change(q: &Quantities) -> Vec<Option<f64>> {
    let mut last: Option<f64> = None;
    let mut next = q.changes.iter().peekable();
    (0..q.len())
        .map(|k| {
            while next.peek().is_some_and(|&&i| i <= k) {
                last = next.next().map(|&i| q.t[i]);
            }
            last.map(|t0| q.t[k] - t0)
        })
        .collect()
}

/// The median time between one regime change and the next, s (the record's span without two).
fn median_stretch_s(q: &Quantities) -> f64 {
    let mut gaps: Vec<f64> = q
        .changes
        .windows(2)
        .map(|w| q.t[w[1]] - q.t[w[0]])
        .collect();
    if gaps.is_empty() {
        return q.span_s();
    }
    let mid = gaps.len() / 2;
    *gaps.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Damped oscillations after each regime change, e^(-dt/tau) sin and cos(2 pi f dt), at
/// frequencies the series resolves (below a quarter of its sample rate) and decays of a few
/// periods.
fn ringing(q: &Quantities, since: &[Option<f64>], out: &mut Vec<Raw>) {
    let f_top = 0.25 / q.step_s();
    // An oscillation rings: at least two periods fit between one regime change and the next
    // (in the median stretch); slower, a damped sinusoid from each change is only a shape of
    // each stretch (a loop's), which the load's memories and the catalogue describe.
    let mut f = 0.25_f64.max(2.0 / median_stretch_s(q));
    while f <= f_top {
        // Near a multiple of a periodic drive an oscillation is the material's response to the
        // drive (its phase, its loss), which the catalogue's relaxation and hysteresis
        // describe; the library offers no line there either (`line::harmonic_of`), within the
        // band it keeps free beside the catalogue (a quarter of the drive's frequency).
        if q.drive_hz.is_some_and(|d| {
            let n = (f / d).round().max(1.0);
            (f - n * d).abs() <= 0.25 * d
        }) {
            f *= 1.5;
            continue;
        }
        for periods in [1.0, 3.0] {
            let tau = periods / f;
            for (name, phase) in [("sin", 0.0), ("cos", std::f64::consts::FRAC_PI_2)] {
                let col: Vec<f64> = since
                    .iter()
                    .map(|s| {
                        s.map_or(0.0, |s| {
                            (-s / tau).exp() * (std::f64::consts::TAU * f * s + phase).sin()
                        })
                    })
                    .collect();
                out.push(Raw {
                    grid: Some(f),
                    ..raw(
                        &format!("ring {name} {periods}"),
                        &format!("e^(-dt / {tau:.3} s) {name}(2 pi {f:.3} Hz dt)"),
                        "1",
                        &[Quantity::TimeSinceChange],
                        col,
                    )
                });
            }
        }
        f *= 1.5;
    }
}

/// Every feature for channel `c`, each scaled to unit weighted RMS on the fitting stretch;
/// features that do not reach the fitting stretch (all zero there) are left out.
/// Which quantities a term of this recording can depend on and be told from the travel. Where
/// the catalogue's own precondition rejects relaxation (no hold and no change of rod speed: a
/// single monotone ramp), the load's memory and the time since a change move with the travel,
/// and so does time where the rod never leaves contact: a term in them is a static shape of
/// the travel here, which only a hold, an unloading or a second speed would tell apart. They
/// are not offered, so that discovery does not bring back what the precondition rejected.
fn identifiable(ctx: &Context) -> impl Fn(Quantity) -> bool {
    let one_ramp = ctx
        .forbidden
        .contains(&sim::effects::EffectKind::ViscoelasticRelaxation);
    let free = (0..ctx.len()).any(|k| ctx.fit_mask[k] && ctx.data.fit.rod_mm[k] < 0.0);
    move |q| match q {
        Quantity::LoadHistory | Quantity::TimeSinceChange => !one_ramp,
        Quantity::Time => !one_ramp || free,
        _ => true,
    }
}

pub(crate) fn features(ctx: &Context, q: &Quantities, c: usize) -> Vec<Feature> {
    let base = instantaneous(ctx, q, c);
    let mut raws = Vec::new();
    products(&base, &mut raws);
    time_features(q, &mut raws);
    history_features(q, &mut raws);
    level_with_memory(&base, &mut raws);
    raws.extend(base);
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
    let identifiable = identifiable(ctx);
    raws.into_iter()
        .filter(|r| r.depends.iter().all(|q| identifiable(*q)))
        .filter_map(|r| {
            let ss: f64 = rows
                .iter()
                .map(|&k| (r.values[k] * ctx.data.weight(c, k)).powi(2))
                .sum();
            let scale = (ss / rows.len().max(1) as f64).sqrt();
            (scale.is_finite() && scale > 0.0).then(|| Feature {
                family: r.family,
                grid: r.grid,
                expr: r.expr,
                unit: r.unit,
                depends: r.depends,
                column: r.values.iter().map(|v| v / scale).collect(),
                scale,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The low-pass of a ramp lags it by tau once settled, on an uneven time base.
    #[test]
    fn low_pass_of_a_ramp_lags_by_tau() {
        let t: Vec<f64> = (0..4000)
            .map(|k| f64::from(k) * 0.01 + if k % 2 == 0 { 0.0 } else { 0.003 })
            .collect();
        let x: Vec<f64> = t.iter().map(|t| 2.0 * t).collect();
        let y = low_pass(&t, &x, 1.5);
        let k = t.len() - 1;
        assert!((x[k] - y[k] - 2.0 * 1.5).abs() < 1e-6, "{}", x[k] - y[k]);
    }

    /// A step is followed by e^(-t/tau) exactly.
    #[test]
    fn low_pass_of_a_step() {
        let t: Vec<f64> = (0..1000).map(|k| f64::from(k) * 0.01).collect();
        let x: Vec<f64> = t.iter().map(|&t| if t > 0.0 { 1.0 } else { 0.0 }).collect();
        let y = low_pass(&t, &x, 2.0);
        // Linear between the first two samples: the ramp's response, then the decay.
        let at = |t: f64| 1.0 - (-(t - 0.01) / 2.0).exp() * (1.0 - y[1]);
        assert!((y[500] - at(5.0)).abs() < 1e-9);
    }
}
