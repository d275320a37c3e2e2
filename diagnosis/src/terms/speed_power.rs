//! A force or output that depends on a power of the rod's speed: a viscous or inertial
//! contribution, a gel stiffer when pressed faster, a rate-sensitive sensing element:
//!
//! ```text
//! y = offset + s (1 + a |v / v_max|^p)            (even: the same on loading and unloading)
//! y = offset + s (1 + a sign(v) |v / v_max|^p)    (odd: more on loading, less on unloading)
//! ```
//!
//! with s the model's signal, v the rod's speed and v_max its largest magnitude on the fitting
//! stretch; p on a grid from 0.5 to 3. On the load cell it acts in the material; on an output
//! alone, in the transducer.

use super::fitting::{best_shape, Columns, Context};
use super::{Description, Term, TermKind};

const POWERS: [f64; 6] = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0];

fn column(ctx: &Context, s: &[f64], v_max: f64, p: f64, odd: bool) -> Columns {
    let x = ctx
        .rod_speed
        .iter()
        .zip(s)
        .map(|(v, s)| {
            let sign = if odd { v.signum() } else { 1.0 };
            s * sign * (v.abs() / v_max).powf(p)
        })
        .collect();
    Columns {
        x: vec![x],
        fixed: None,
    }
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let v_max = (0..ctx.len())
        .filter(|&k| ctx.fit_mask[k])
        .map(|k| ctx.rod_speed[k].abs())
        .fold(0.0, f64::max);
    if v_max <= 0.0 {
        return None;
    }
    let s = ctx.signal(c);
    // Odd in the speed it opens a loop: with a power below one it is Coulomb-like friction,
    // the catalogue's `hysteresis`, and beside a loop effect of the model it is that effect's
    // misfit ([`Context::loop_in_model`]).
    let s = &s;
    let shapes = POWERS.iter().flat_map(|&p| {
        [false, true]
            .into_iter()
            .filter(move |&odd| !odd || (p >= 1.0 && !ctx.loop_in_model))
            .map(move |odd| {
                (
                    vec![p, f64::from(odd), v_max],
                    column(ctx, s, v_max, p, odd),
                )
            })
    });
    let (shape, columns, beta, _) = best_shape(ctx, c, others, shapes)?;
    Some(Term {
        kind: TermKind::SpeedPower,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 3,
        info: None,
    })
}

pub(crate) fn describe(t: &Term) -> Description {
    let (p, odd, v_max) = (t.shape[0], t.shape[1] > 0.5, t.shape[2]);
    let a = t.beta[0];
    let v_ref = 60.0 * v_max;
    Description {
        name: "speed_power".into(),
        params: vec![
            ("coefficient", a, "1".into()),
            ("exponent", p, "1".into()),
            ("v_ref_mm_per_min", v_ref, "mm/min".into()),
        ],
        depends_on: vec!["rod_speed", "load_N"],
        form: format!(
            "load x (1 {a:+.3} {}(v / {v_ref:.0} mm/min)^{p})",
            if odd { "sign(v) " } else { "" }
        ),
    }
}
