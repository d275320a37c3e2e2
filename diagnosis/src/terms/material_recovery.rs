//! The material recovers load with time: a tendon or a hydrogel that dries under the rod (or
//! an elastomer that cures, a sample that swells) stiffens, so the load it carries rises by a
//! share of itself that grows towards b with a time constant tau:
//!
//! ```text
//! F(t) = F_model(t) (1 + b (1 - e^(-t/tau))),     b > 0
//! ```
//!
//! in the material, a function of time and load, on the load cell; t from the recording's
//! start, tau on a logarithmic grid from 5 s to ten recordings' length. It may stand beside the
//! catalogue's relaxation (with the catalogue's parameters refitted to first order beside it,
//! [`super::fitting::Context::catalogue`]): a relaxation only lowers the load under a hold, and
//! a spectrum of relaxation times that one Prony term misses leaves a further fall, never a
//! rise, so a load that climbs back is what no catalogue effect's misfit takes.

use super::fitting::{admitted_term, Columns, Context};
use super::{Description, Term, TermKind};

fn column(ctx: &Context, s: &[f64], tau_s: f64) -> Columns {
    let t0 = ctx.t_s().first().copied().unwrap_or(0.0);
    let x = ctx
        .t_s()
        .iter()
        .zip(s)
        .map(|(t, s)| s * (1.0 - (-(t - t0) / tau_s).exp()))
        .collect();
    Columns {
        x: vec![x],
        fixed: None,
    }
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let span_s = ctx.t_s().last()? - ctx.t_s().first()?;
    let longest_s = (10.0 * span_s).max(10.0);
    let s = ctx.signal(c);
    let shapes = (0..=24).map(|j| {
        let tau = 5.0 * (longest_s / 5.0).powf(f64::from(j) / 24.0);
        (vec![tau], column(ctx, &s, tau))
    });
    // A load that falls with time is a relaxation (the catalogue's) or a softening: not this.
    admitted_term(ctx, c, others, TermKind::MaterialRecovery, shapes)
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "material_recovers_load".into(),
        params: vec![
            ("share", t.beta[0], "1".into()),
            ("tau_s", t.shape[0], "s".into()),
        ],
        depends_on: vec!["time", "load_N"],
        form: format!(
            "load x (1 + {:.3} (1 - e^(-t / {:.1} s))): the material stiffens as it dries or cures",
            t.beta[0], t.shape[0]
        ),
    }
}
