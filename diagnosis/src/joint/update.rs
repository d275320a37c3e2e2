//! Leave-one-out by update: the session fitted without one recording, started where the whole
//! session's fit left it. The session's normal equations are a sum over its recordings (each
//! recording's residuals move with the shared parameters and its own alone), so those of the
//! session without recording `r` are the whole session's with `r`'s part taken out: one
//! Levenberg–Marquardt step from the whole session's optimum, with them, is the fit of the
//! others wherever its quadratic model holds there. Each recording's part is worked out once
//! for all the recordings left out; refitting the others from scratch for each had made the
//! validation grow as the square of the session.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::model::{Joint, JointFit, Layout, Part, Slot};
use super::search::{Fitted, Gain, Search};
use crate::fit::MIN_BIC_STEP;
use crate::lm;

/// The first step's damping of a fit (`lm::solve`'s): the update is that fit's first step.
const FIRST_DAMPING: f64 = 1e-3;

/// The session's shared physics fitted to its recordings but one: the shared values (by index
/// of a recording's vector) and the others' full vectors, in input order.
pub(crate) struct Others {
    pub shared: BTreeMap<usize, f64>,
    pub full: Vec<Vec<f64>>,
}

/// A fitted session taken apart recording by recording at its optimum.
pub(crate) struct Parts<'s, 'a> {
    search: &'s Search<'s, 'a>,
    fitted: &'s Fitted,
    joint: Joint<'s, 'a>,
    p: Vec<f64>,
    parts: Vec<Part>,
    opt: lm::Options,
}

impl<'s, 'a> Parts<'s, 'a> {
    /// `fitted`'s normal equations on `search`'s recordings, recording by recording.
    pub fn of(search: &'s Search<'s, 'a>, fitted: &'s Fitted) -> Self {
        let joint = Joint::new(
            &search.setups,
            fitted.layout.clone(),
            &fitted.fit.full,
            BTreeMap::new(),
        );
        let p = joint.vector_of(&fitted.fit.full);
        let opt = joint.options(super::search::ITERATIONS);
        let h = lm::steps(&p, &opt);
        let parts = (0..joint.models.len())
            .into_par_iter()
            .map(|r| {
                let base = joint.block(r, &p);
                joint.part(r, &p, &base, &h)
            })
            .collect();
        Self {
            search,
            fitted,
            joint,
            p,
            parts,
            opt,
        }
    }

    /// The session fitted to its recordings other than `r`: the update's step where its
    /// quadratic model predicts the others' misfit there within what a fit's iteration counts
    /// ([`MIN_BIC_STEP`], in deviance), else a fit of the others started from the better of
    /// the step and the whole session's optimum.
    pub fn without(&self, r: usize) -> Others {
        let k = self.p.len();
        let mut normal = (DMatrix::zeros(k, k), DVector::zeros(k));
        let (mut sse, mut n) = (0.0, 0);
        for (_, part) in self.parts.iter().enumerate().filter(|&(b, _)| b != r) {
            part.add_to(&mut normal);
            sse += part.sse;
            n += part.n;
        }
        let keep: Vec<usize> = (0..self.parts.len()).filter(|&b| b != r).collect();
        let q = lm::damped(&self.p, &normal, FIRST_DAMPING, &self.opt).unwrap_or(self.p.clone());
        let delta = DVector::from_iterator(k, q.iter().zip(&self.p).map(|(a, b)| a - b));
        let predicted = sse + 2.0 * delta.dot(&normal.1) + (&normal.0 * &delta).dot(&delta);
        let actual: f64 = keep
            .par_iter()
            .map(|&b| lm::sse(&self.joint.block(b, &q)))
            .sum();
        let holds =
            actual <= sse && n as f64 * (actual / predicted.max(1e-300)).ln().abs() < MIN_BIC_STEP;
        if holds {
            return self.others(&keep, &q);
        }
        let from = if actual < sse { &q } else { &self.p };
        let layout: Layout = self.fitted.layout.only(&keep);
        let start = Fitted {
            layout: layout.clone(),
            fit: JointFit::start(keep.iter().map(|&b| self.joint.full_of(b, from)).collect()),
        };
        let refit = self.search.fit_subset(&start, &keep);
        Others {
            shared: refit.fit.shared_values(),
            full: refit.fit.full,
        }
    }

    /// The shared values and the full vectors of recordings `keep` at the session vector `q`.
    fn others(&self, keep: &[usize], q: &[f64]) -> Others {
        let shared = self
            .joint
            .slots
            .iter()
            .zip(q)
            .filter_map(|(s, &v)| match *s {
                Slot::Shared(i) => Some((i, v)),
                Slot::Own(..) => None,
            })
            .collect();
        Others {
            shared,
            full: keep.iter().map(|&b| self.joint.full_of(b, q)).collect(),
        }
    }
}

impl Search<'_, '_> {
    /// `larger` against `smaller` across recordings, where the held-out stretches cannot test
    /// it: each recording's fitting stretch predicted by the shared values fitted to the
    /// other recordings alone, its own calibration (offsets, its own effects and scales)
    /// fitted there, the chi-squares summed. Shared physics that is the truth predicts a test
    /// it never saw; what one recording alone cannot test, the session can. `None` below two
    /// recordings.
    pub fn across(&self, larger: &Fitted, smaller: &Fitted) -> Option<Gain> {
        let n = self.setups.len();
        if n < 2 {
            return None;
        }
        let each = |f: &Fitted| -> Vec<(f64, Vec<f64>)> {
            let parts = Parts::of(self, f);
            (0..n)
                .into_par_iter()
                .map(|r| self.predicted(f, &parts, r))
                .collect()
        };
        let (l, s) = (each(larger), each(smaller));
        let chi2 = |v: &[(f64, Vec<f64>)]| v.iter().map(|x| x.0).sum::<f64>();
        let flat = |v: &[(f64, Vec<f64>)]| v.iter().flat_map(|x| x.1.clone()).collect::<Vec<_>>();
        let g = Gain::between(
            (smaller.fit.bic(), larger.fit.bic()),
            (chi2(&s), chi2(&l)),
            (&flat(&s), &flat(&l)),
        );
        Some(Gain { across: true, ..g })
    }

    /// Recording `r`'s fitting stretch under `f`'s layout, its shared values fitted to the
    /// others: the chi-square and the weighted residuals.
    fn predicted(&self, f: &Fitted, parts: &Parts, r: usize) -> (f64, Vec<f64>) {
        let own = self.recording_alone(f, r, f.layout.only(&[r]), parts.without(r).shared);
        let full = &own.fit.full[0];
        let setup = self.setups[r];
        let model = own.model(setup);
        let mut res = Vec::new();
        model.weighted(full, &setup.fit_mask, &mut res);
        (res.iter().map(|x| x * x).sum(), res)
    }
}
