//! The session's selection, by the single diagnosis's two tests (the criterion, then the
//! held-out stretches), over session models ([`Layout`]s):
//! 1. each output's scale shared or per recording (per recording: a sensitivity that changes
//!    between tests, which is `angle_dependence` when the tests' contact angles differ);
//! 2. forward: the shared effect that lowers the session's BIC most, while one does by more
//!    than [`MIN_BIC_GAIN`];
//! 3. backward: each shared effect must lower the held-out misfit beyond its noise;
//! 4. each shared effect tried per recording: kept shared unless per recording passes both tests.

use std::collections::BTreeMap;

use rayon::prelude::*;
use sim::effects::EffectKind;

use super::distinct_kinds;
use super::model::{Joint, JointFit, Layout};
use super::output::SessionCandidate;
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};
use crate::fit::Setup;
use crate::static_shape::Span;

/// Iterations of a session fit (each starts at a fitted session or at calibrated recordings).
pub(super) const ITERATIONS: usize = 40;

/// Starts of the session's first model that race (`lm::solve_best`): the recordings' medians
/// and the recordings' own laws that misfit the session least as they stand. A recording's
/// law that misfits the others most is the least likely to be the session's; ten such starts
/// racing cost a third of a session's time.
const FIRST_STARTS: usize = 4;

/// A fitted session model.
#[derive(Clone)]
pub struct Fitted {
    pub layout: Layout,
    pub fit: JointFit,
}

/// One model against a smaller one it contains.
#[derive(Debug, Clone, Copy)]
pub struct Gain {
    /// BIC of the smaller minus the larger's.
    pub bic: f64,
    /// Held-out chi-square of the smaller minus the larger's, and the least that counts.
    pub heldout: f64,
    pub needed: f64,
    /// The smaller model's held-out chi-square, which `heldout` and `needed` are parts of.
    pub before: f64,
    /// The held-out gain the larger would make were it the truth (the squared norm of the
    /// two models' difference on the held-out stretches).
    pub reach: f64,
    /// Whether `heldout` and `needed` are across recordings ([`Search::across`]).
    pub across: bool,
}

impl Gain {
    pub fn of(larger: &Fitted, smaller: &Fitted) -> Self {
        Self::between(
            (smaller.fit.bic(), larger.fit.bic()),
            (smaller.fit.heldout(), larger.fit.heldout()),
            (&smaller.fit.heldout_r, &larger.fit.heldout_r),
        )
    }

    /// From the two models' BICs, held-out chi-squares and held-out residuals (smaller,
    /// larger).
    pub(super) fn between(bic: (f64, f64), chi2: (f64, f64), r: (&[f64], &[f64])) -> Self {
        let reach: f64 = r.1.iter().zip(r.0).map(|(a, b)| (a - b) * (a - b)).sum();
        Self {
            bic: bic.0 - bic.1,
            heldout: chi2.0 - chi2.1,
            needed: heldout_needed(reach.sqrt(), chi2.0),
            before: chi2.0,
            reach,
            across: false,
        }
    }

    pub fn passes(&self) -> bool {
        self.bic > MIN_BIC_GAIN && self.heldout > self.needed
    }

    /// The criterion keeps the larger model, and the held-out stretches cannot test it: were
    /// it the truth its gain there would not count (a hysteresis, with every recording held
    /// out at rest).
    pub fn untestable(&self) -> bool {
        self.bic > MIN_BIC_GAIN && self.heldout <= self.needed && self.reach <= self.needed
    }

    /// The two tests in words a reader weighs: the BIC's drop, and the held-out misfit's
    /// change as a share of the smaller model's with the share the test asks for (a chi-square
    /// sum means nothing outside its fit).
    pub fn words(&self, what: &str) -> String {
        let stretch = if self.across {
            "the held-out stretches cannot test it; each recording predicted from the others': RMS misfit"
        } else {
            "held-out RMS misfit"
        };
        format!(
            "BIC {} vs {what}, {stretch} {}",
            signed_whole(-self.bic),
            misfit_change(self.heldout, self.needed, self.before)
        )
    }
}

/// `+12` or `−60 795`: a BIC difference with its sign.
fn signed_whole(v: f64) -> String {
    let s = figures::number::fixed(v, 0);
    if v >= 0.5 {
        format!("+{s}")
    } else {
        s
    }
}

/// A held-out misfit's drop `gain` (chi-square) against the least that counts, `needed`, in
/// terms of the smaller model's `before`, as RMS misfits (the square roots, as a reader
/// compares RMSEs): "12 % lower (0.25 % counts)", or where it halves or more the factor, "57
/// times lower (0.25 % counts)".
fn misfit_change(gain: f64, needed: f64, before: f64) -> String {
    let before = before.max(1e-300);
    // The RMS's change for a chi-square change `v`, percent.
    let rms = |v: f64| 100.0 * (1.0 - (1.0 - v / before).max(0.0).sqrt());
    let pct = |v: f64| figures::number::significant(rms(v).abs(), 2);
    let change = if rms(gain) >= 50.0 {
        let ratio = (before / (before - gain).max(1e-300)).sqrt();
        format!("{} times lower", figures::number::significant(ratio, 2))
    } else if gain >= 0.0 {
        format!("{} % lower", pct(gain))
    } else {
        format!("{} % higher", pct(gain))
    };
    format!("{change} ({} % counts)", pct(needed))
}

/// The session's search over its recordings' setups.
pub struct Search<'s, 'a> {
    pub setups: Vec<&'s Setup<'a>>,
    pub tried: Vec<SessionCandidate>,
}

impl<'s, 'a> Search<'s, 'a> {
    /// `layout` fitted, starting from `from` (its effects at their values, new ones at their
    /// catalogue starts).
    pub fn fit(&self, layout: Layout, from: &Fitted) -> Fitted {
        self.fit_frozen(layout, from, BTreeMap::new())
    }

    /// As [`Self::fit`], with shared values `frozen` held.
    pub fn fit_frozen(
        &self,
        layout: Layout,
        from: &Fitted,
        frozen: BTreeMap<usize, f64>,
    ) -> Fitted {
        let joint = Joint::new(&self.setups, layout.clone(), &from.fit.full, frozen);
        let starts = joint.starts_from(&from.fit.full, &from.layout);
        Fitted {
            layout,
            fit: joint.fit(&starts, ITERATIONS),
        }
    }

    /// `layout` fitted from the recordings calibrated alone (`calibrated`; shared values at the
    /// recordings' medians, as [`Self::fit_first`]'s first start).
    fn fit_calibrated(&self, layout: Layout, from: &Fitted, calibrated: &Fitted) -> Fitted {
        let joint = Joint::new(
            &self.setups,
            layout.clone(),
            &from.fit.full,
            BTreeMap::new(),
        );
        let starts = vec![joint.starts_from(&calibrated.fit.full, &calibrated.layout)[0].clone()];
        Fitted {
            layout,
            fit: joint.fit(&starts, ITERATIONS),
        }
    }

    /// The session's first model, from each recording calibrated alone (`from`): started at
    /// the recordings' median and at each recording's own contact law and scales, with twice
    /// the iterations of a step.
    pub fn fit_first(&mut self, layout: Layout, from: &Fitted) -> Fitted {
        let joint = Joint::new(
            &self.setups,
            layout.clone(),
            &from.fit.full,
            BTreeMap::new(),
        );
        let carried = &joint.starts_from(&from.fit.full, &from.layout)[0];
        let f = Fitted {
            layout,
            fit: joint.fit(
                &joint.screened(joint.starts_each(carried), FIRST_STARTS),
                2 * ITERATIONS,
            ),
        };
        self.record(&f, true, "each recording with its own effects alone".into());
        f
    }

    pub(super) fn record(&mut self, f: &Fitted, accepted: bool, reason: String) {
        let names = |v: &[EffectKind]| v.iter().map(|k| k.name().to_string()).collect();
        let per_recording = distinct_kinds(
            f.layout
                .own
                .iter()
                .flatten()
                .copied()
                .filter(|k| !OWN_ALWAYS.contains(k)),
        );
        self.tried.push(SessionCandidate {
            shared: names(&f.layout.shared),
            per_recording: names(&per_recording),
            per_recording_scales: f
                .layout
                .own_scales
                .iter()
                .map(|&c| crate::data::CHANNELS[c + 1].to_string())
                .collect(),
            bic: f.fit.bic(),
            heldout_chi2: f.fit.heldout(),
            accepted,
            reason,
        });
    }

    /// Step 1: each output scale in `channels` (0 = Fz) made per recording where that passes
    /// both tests. One that passes is fitted again from the recordings calibrated alone
    /// (`calibrated`), the better optimum kept: a scale shared so far has bent the shared law
    /// (and taken effects in) to fit all recordings at once, and from there a scale per
    /// recording need not find its way back (an angle law of 1.13 came out 1.08, beside a
    /// bridge nonlinearity and moment scales per recording that nothing had hidden).
    pub fn scales(&mut self, mut cur: Fitted, channels: &[usize], calibrated: &Fitted) -> Fitted {
        for &c in channels {
            let mut layout = cur.layout.clone();
            layout.own_scales.push(c);
            let mut f = self.fit(layout.clone(), &cur);
            if Gain::of(&f, &cur).passes() {
                let again = self.fit_calibrated(layout, &cur, calibrated);
                if again.fit.sse < f.fit.sse {
                    f = again;
                }
            }
            let g = Gain::of(&f, &cur);
            let reason = g.words("one scale for the session");
            self.record(&f, g.passes(), reason);
            if g.passes() {
                cur = f;
            }
        }
        cur
    }

    /// Step 2: forward selection of shared effects among `candidates`.
    pub fn forward(&mut self, mut cur: Fitted, candidates: &[EffectKind]) -> Fitted {
        loop {
            let tries: Vec<(EffectKind, Fitted)> = candidates
                .par_iter()
                .filter(|&&k| may_add(&cur.layout.shared, k))
                .map(|&k| {
                    let mut layout = cur.layout.clone();
                    layout.shared.push(k);
                    (k, self.fit(layout, &cur))
                })
                .collect();
            // Each try's gain and words; the admissible one with the largest gain is taken.
            let scored: Vec<(Fitted, Gain, bool, String)> = tries
                .into_iter()
                .map(|(k, f)| {
                    let g = Gain::of(&f, &cur);
                    let mut words = g.words(&format!("without {}", k.name()));
                    let within = self.shape_within_calibration(&f, k);
                    if within {
                        words.push_str("; a static shape within what the calibration's map may bend (not a finding)");
                    }
                    let bound = self.at_bound(&f, k);
                    if bound {
                        words.push_str("; a parameter at a bound: unresolved");
                    }
                    (f, g, !within && !bound && g.bic > MIN_BIC_GAIN, words)
                })
                .collect();
            let best = (0..scored.len())
                .filter(|&i| scored[i].2)
                .max_by(|&a, &b| scored[a].1.bic.total_cmp(&scored[b].1.bic));
            for (i, (f, _, _, words)) in scored.iter().enumerate() {
                self.record(f, Some(i) == best, words.clone());
            }
            match best {
                Some(i) => cur = scored.into_iter().nth(i).expect("index of a try").0,
                None => return cur,
            }
        }
    }

    /// A static shape (`stiffening`, `bridge_nonlinearity`) whose strength, two standard
    /// errors towards none, bends no compared output of any recording beyond what the
    /// calibration's map from the load may bend it: the single diagnosis's documented threshold
    /// (`crate::static_shape`), on the session's shared strength.
    fn shape_within_calibration(&self, f: &Fitted, kind: EffectKind) -> bool {
        let neutral = match kind {
            EffectKind::Stiffening => 1.0,
            EffectKind::BridgeNonlinearity => 0.0,
            _ => return false,
        };
        let Some(at) = crate::fit::param_index(&f.layout.kinds(0), kind, 0) else {
            return false;
        };
        let value = f.fit.full[0][at];
        let se = f.fit.shared_stderr(at).unwrap_or(0.0);
        let z = crate::params::STRENGTH_Z;
        let sure = if (value - neutral).abs() <= z * se {
            neutral
        } else {
            value - (value - neutral).signum() * z * se
        };
        self.setups.iter().all(|s| {
            let span = Span::of(&s.drive, &s.fit_bounds);
            (0..3)
                .filter(|&k| s.used[k + 1])
                .all(|k| span.bend(kind, sure, k).is_none_or(|b| b <= span.span[k]))
        })
    }

    /// Whether a parameter of the shared effect `kind` last added sits on a bound (as a single
    /// recording's parameters are judged, `params::on_bound`): unresolved, as a single recording's selection rejects it (a
    /// relaxation of 0.8 % at the shortest time constant had been shared beside a hysteresis).
    fn at_bound(&self, f: &Fitted, kind: EffectKind) -> bool {
        let nth = f.layout.shared.iter().filter(|&&k| k == kind).count();
        let kinds = f.layout.kinds(0);
        let Some(at) = crate::fit::nth_param_index(&kinds, kind, nth.saturating_sub(1), 0) else {
            return false;
        };
        let model = f.model(self.setups[0]);
        // A relaxation or coupling slower than the record is a bound on its time, as alone;
        // not with the whole response relaxing (a relaxation of 0.99 at 12578 s had taken up
        // another model's force law).
        let slow_allowed = matches!(
            kind,
            EffectKind::ViscoelasticRelaxation | EffectKind::HighpassCoupling
        );
        (0..kind.param_names().len()).any(|j| {
            let (lower, upper) =
                crate::params::on_bound(&model.specs()[at + j], f.fit.full[0][at + j]);
            lower || (upper && !(slow_allowed && j == 0))
        })
    }

    /// Step 3: drop a shared effect whose held-out gain is within its noise. The kept ones
    /// come back with their gain over the session without them.
    ///
    /// A relaxation's second Prony term is tested first, alone; the first with it, as the whole
    /// effect.
    pub fn backward(&mut self, mut cur: Fitted) -> (Fitted, Vec<(EffectKind, Gain)>) {
        let mut kept = Vec::new();
        let order = cur.layout.shared.clone();
        for (i, k) in order.iter().copied().enumerate().rev() {
            let mut layout = cur.layout.clone();
            if order[i + 1..].contains(&k) {
                if kept.iter().any(|&(x, _)| x == k) {
                    continue;
                }
                layout.shared.retain(|&s| s != k);
            } else {
                let last = layout
                    .shared
                    .iter()
                    .rposition(|&s| s == k)
                    .expect("in the layout");
                layout.shared.remove(last);
            }
            let without = self.fit(layout, &cur);
            let mut g = Gain::of(&cur, &without);
            if g.untestable() {
                g = self.across(&cur, &without).unwrap_or(g);
            }
            if g.passes() {
                kept.push((k, g));
            } else {
                let reason = format!("{} dropped: {}", k.name(), g.words("without it"));
                self.record(&without, true, reason);
                cur = without;
            }
        }
        (cur, kept)
    }

    /// Step 4: each shared effect per recording instead, where that passes both tests.
    pub fn per_recording(&mut self, mut cur: Fitted) -> Fitted {
        if self.setups.len() < 2 {
            return cur;
        }
        for k in distinct_kinds(cur.layout.shared.clone()) {
            let f = self.fit(cur.layout.per_recording(k), &cur);
            let g = Gain::of(&f, &cur);
            let reason = format!("{} per recording: {}", k.name(), g.words("shared"));
            self.record(&f, g.passes(), reason);
            if g.passes() {
                cur = f;
            }
        }
        cur
    }
}

impl Search<'_, '_> {
    /// The session of recordings `keep` fitted from `from` (its layout and full vectors are
    /// theirs, in that order).
    pub fn fit_subset(&self, from: &Fitted, keep: &[usize]) -> Fitted {
        Search {
            setups: keep.iter().map(|&i| self.setups[i]).collect(),
            tried: Vec::new(),
        }
        .fit(from.layout.clone(), from)
    }

    /// Recording `r` alone under `layout`, its shared values `frozen` held: only its own
    /// calibration fitted, from where `f` left it.
    pub fn recording_alone(
        &self,
        f: &Fitted,
        r: usize,
        layout: Layout,
        frozen: BTreeMap<usize, f64>,
    ) -> Fitted {
        let from = Fitted {
            layout: layout.clone(),
            fit: JointFit::start(vec![f.fit.full[r].clone()]),
        };
        Search {
            setups: vec![self.setups[r]],
            tried: Vec::new(),
        }
        .fit_frozen(layout, &from, frozen)
    }
}

impl Fitted {
    /// The model of this fit's first recording on `setup` (its shared effects, and its own).
    pub fn model<'s, 'a>(&self, setup: &'s Setup<'a>) -> crate::fit::Model<'s, 'a> {
        crate::fit::Model::new(
            setup,
            &self.layout.kinds(0),
            &self.fit.full[0][..crate::fit::N_BASE],
        )
    }
}

/// Whether `kind` may join the session's `shared` effects: once, and a relaxation twice (a
/// second Prony term: a gel's spectrum spans decades).
fn may_add(shared: &[EffectKind], kind: EffectKind) -> bool {
    let n = shared.iter().filter(|&&k| k == kind).count();
    n == 0 || (n == 1 && kind == EffectKind::ViscoelasticRelaxation)
}

/// Effects that belong to one test whenever they are found: never shared.
pub const OWN_ALWAYS: [EffectKind; 3] = [
    EffectKind::ThermalDrift,
    EffectKind::AmplifierSaturation,
    EffectKind::MainsInterference,
];
