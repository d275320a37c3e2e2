//! The material stiffening against the rod, seen on the load cell: the catalogue's
//! `stiffening` met in the material, where a test of the material alone shows it on the load.
//! Only there: where outputs are compared, a gel that stiffens presses the chip harder too, and
//! the catalogue's own entry takes that up on load and outputs alike; a stiffening the load
//! alone shows beside outputs that follow the model is not the material's (the contract puts
//! this entry "in a test without sensor outputs"). The catalogue's law
//! (`sim::effects::Stiffening`) on the load's signal s, with F its largest value:
//!
//! ```text
//! F(t) = F sign(s) (|s| / F)^p
//! ```
//!
//! as a column whose amplitude is fitted beside the channel's refitted scale (the law's share
//! of the load), the exponent p from a grid.

use super::fitting::{admitted_term, Columns, Context};
use super::{Description, Term, TermKind};
use sim::effects::Stiffening;

/// The exponents tried: from a mild stiffening to a strong one (the catalogue's bounds).
const EXPONENTS: (f64, f64, usize) = (1.1, 3.5, 25);

/// The catalogue's law on the signal, as the emulator applies it.
fn law(signal: &[f64], p: f64) -> Vec<f64> {
    let mut x = signal.to_vec();
    Stiffening { exponent: p }.apply(&mut x);
    x
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    if ctx.used[1..].iter().any(|&u| u) {
        return None;
    }
    let signal = ctx.signal(c);
    let (lo, hi, n) = EXPONENTS;
    let shapes = (0..n).map(|i| {
        let p = lo + (hi - lo) * i as f64 / (n - 1) as f64;
        (
            vec![p],
            Columns {
                x: vec![law(&signal, p)],
                fixed: None,
            },
        )
    });
    // A law that takes load away where the load is high is a softening: not this physics.
    admitted_term(ctx, c, others, TermKind::LoadStiffening, shapes)
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "stiffening".into(),
        params: vec![
            ("exponent", t.shape[0], String::new()),
            ("share", t.beta[0], String::new()),
        ],
        depends_on: vec!["rod_mm"],
        form: format!(
            "the load stiffens against the rod: {:.2} of it follows (load / peak)^{:.2}",
            t.beta[0], t.shape[0]
        ),
    }
}
