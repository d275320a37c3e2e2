//! The sensing element creeps where the load does not: an output relaxes under a held load and
//! creeps back after release although the load cell shows no such decay. The catalogue's
//! `viscoelastic_relaxation` (`sim::effects::ViscoelasticRelaxation`, the same operator) at the
//! transducer, on that output alone:
//!
//! ```text
//! y = offset + (1 - g) s + g h_tau(s)
//! ```
//!
//! with s the model's signal and h_tau its first-order high-pass. Linear in g for each tau, so
//! the column is h_tau(s) - s; tau on a logarithmic grid from 0.2 s to 500 s.

use super::fitting::{admitted_term, Columns, Context};
use super::{Description, Term, TermKind};
use sim::effects::ViscoelasticRelaxation;

fn column(ctx: &Context, s: &[f64], tau_s: f64) -> Columns {
    let mut h = s.to_vec();
    ViscoelasticRelaxation {
        tau_s,
        fraction: 1.0,
    }
    .apply(ctx.t_s(), &mut h);
    Columns {
        x: vec![h.iter().zip(s).map(|(h, s)| h - s).collect()],
        fixed: None,
    }
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let s = ctx.signal(c);
    let shapes = (0..=32).map(|j| {
        let tau = 0.2 * (2500f64).powf(f64::from(j) / 32.0);
        (vec![tau], column(ctx, &s, tau))
    });
    // A negative fraction is an output that overshoots, not one that relaxes.
    admitted_term(ctx, c, others, TermKind::OutputRelaxation, shapes)
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "viscoelastic_relaxation".into(),
        params: vec![
            ("tau_s", t.shape[0], "s".into()),
            ("fraction", t.beta[0], "1".into()),
        ],
        depends_on: vec!["load_N", "time"],
        form: format!(
            "output relaxes by {:.0} % of its response with tau = {:.2} s where the load does not",
            100.0 * t.beta[0],
            t.shape[0]
        ),
    }
}
