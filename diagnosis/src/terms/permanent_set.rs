//! A permanent set after the first loading: the gel (or the rig's seating) does not return to
//! its first shape, so from the first reversal on the load at a travel d is the first loading's
//! load at d - delta. For a set small against the travel,
//!
//! ```text
//! F(d, t) = F(d) - H(t - t_rev) delta dF/dd
//! ```
//!
//! in the material, a function of the rod's travel; dF/dd from the model's load along its
//! first loading, t_rev the rod's first reversal.

use super::fitting::{solve, Columns, Context};
use super::{Description, Term, TermKind};

/// dF/dd at each sample: the model's load on the first loading, as a function of the travel,
/// differentiated over a hundredth of the largest travel either side.
fn slope(ctx: &Context, c: usize, t_rev: f64) -> Option<Vec<f64>> {
    let d = &ctx.data.fit.rod_mm;
    let s = ctx.signal(c);
    let mut curve: Vec<(f64, f64)> = (0..ctx.len())
        .filter(|&k| ctx.t_s()[k] < t_rev && ctx.rod_speed[k] > 0.0)
        .map(|k| (d[k], s[k]))
        .collect();
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    curve.dedup_by(|a, b| a.0 <= b.0);
    if curve.len() < 4 {
        return None;
    }
    let (xs, ys): (Vec<f64>, Vec<f64>) = curve.into_iter().unzip();
    let eps = 0.01 * xs[xs.len() - 1].abs().max(1e-9);
    let at = |x: f64| sim::effects::interpolate(&xs, &ys, x);
    Some(
        d.iter()
            .map(|&x| (at(x + eps) - at(x - eps)) / (2.0 * eps))
            .collect(),
    )
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let t_rev = ctx.first_reversal_s()?;
    let slope = slope(ctx, c, t_rev)?;
    let x = ctx
        .t_s()
        .iter()
        .zip(&slope)
        .map(|(&t, g)| if t >= t_rev { -g } else { 0.0 })
        .collect();
    let columns = Columns {
        x: vec![x],
        fixed: None,
    };
    let (beta, _) = solve(ctx, c, &columns.joined(others))?;
    // A negative set would be a gel that grew: not this physics.
    if beta[0] <= 0.0 {
        return None;
    }
    Some(Term {
        kind: TermKind::PermanentSet,
        channel: c,
        shape: vec![t_rev],
        columns,
        beta: beta[..1].to_vec(),
        n_params: 1,
        info: None,
    })
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "permanent_set".into(),
        params: vec![
            ("set_mm", t.beta[0], "mm".into()),
            ("t_s", t.shape[0], "s".into()),
        ],
        depends_on: vec!["rod_mm", "time"],
        form: format!(
            "after the first loading (t = {:.1} s) the load follows the travel less {:.3} mm",
            t.shape[0], t.beta[0]
        ),
    }
}
