//! Model selection: a forward–backward stepwise search over the catalogue effects, starting at
//! the calibrated baseline.
//!
//! Forward: every effect the protocol can show ([`Features::allows`]) is added to the current
//! model in turn (fitted in parallel, each from the current model's solution, see
//! [`Candidate::extend`]); of those that beat the current model and the baseline on the
//! criterion ([`Comparison::admits`](crate::candidate::Comparison::admits)) and whose primary
//! parameter is not pinned at a bound ([`crate::params::at_bounds`]), the one with the lowest
//! BIC is taken. Backward: each effect of the new model must still be admitted against the same
//! model without it; any that is not is pruned (the one whose removal costs least first). The search stops when no
//! addition is admitted. There is no limit on the number of effects, and a kind may enter twice
//! where the catalogue allows it (a second Prony term of the relaxation), so combinations are
//! found, not listed.
//!
//! The held-out test is confirmed at the end rather than at each step, because one missing
//! effect can hide another's held-out gain (a drift over an AC coupling's undershoot): from the
//! search's last model, the effect that least earns its place on both tests is dropped until
//! every remaining one passes both against the model without it
//! ([`Comparison::passes`](crate::candidate::Comparison::passes)), and a static shape that
//! bends no output beyond the calibration's span ([`crate::params::absorbed_static_shape`]) is
//! dropped too. The reported model is that one if it passes every test, else the last of the
//! search's path that does; the baseline when none does.

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use sim::effects::EffectKind;

use crate::candidate::{key_of, label_of, Candidate, Comparison};
use crate::fit::{Model, Setup, N_BASE};
use crate::output::CandidateReport;
use crate::params::{absorbed_static_shape, at_bounds, resolved};
use crate::preconditions::Features;

/// Told after each candidate model is fitted: (candidates fitted so far, candidates in all).
pub type Progress = dyn Fn(usize, usize) + Send + Sync;

/// LM iteration caps: the baseline from the linear start, an effect from the nested solution.
const BASE_ITERATIONS: usize = 80;
const EFFECT_ITERATIONS: usize = 40;

/// Counts fitted candidates for the progress report (the total grows as the search goes).
struct Tick<'p> {
    done: AtomicUsize,
    total: AtomicUsize,
    report: Option<&'p Progress>,
}

impl Tick<'_> {
    fn expect(&self, more: usize) {
        self.total.fetch_add(more, Ordering::Relaxed);
    }

    fn inc(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(report) = self.report {
            report(done, self.total.load(Ordering::Relaxed));
        }
    }
}

/// Every candidate fitted, why each was kept or rejected, and the one chosen.
pub struct Selection<'s, 'a> {
    /// Every fitted candidate; the calibrated baseline first.
    pub all: Vec<Candidate<'s, 'a>>,
    /// Index in `all` of the reported model.
    pub chosen: usize,
    /// Per candidate of `all`, why it was kept or rejected.
    reasons: Vec<String>,
    /// Per candidate of `all`, the index of the model it extends by one effect.
    parents: Vec<Option<usize>>,
    /// Effects never fitted because the recording cannot show them, with the reason.
    pub excluded: Vec<(EffectKind, String)>,
    protocol: Features,
}

/// Index in the full vector of the first parameter of the first `kind` among `kinds`.
fn first_param(kinds: &[EffectKind], kind: EffectKind) -> usize {
    N_BASE
        + kinds
            .iter()
            .take_while(|&&k| k != kind)
            .map(|k| k.param_names().len())
            .sum::<usize>()
}

/// Calibrate the baseline and run the search.
pub fn select<'s, 'a>(
    setup: &'s Setup<'a>,
    protocol: Features,
    progress: Option<&Progress>,
) -> Selection<'s, 'a> {
    let slow: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| *k != EffectKind::MainsInterference)
        .collect();
    let excluded: Vec<(EffectKind, String)> = EffectKind::ALL
        .into_iter()
        .filter_map(|k| protocol.allows(k).err().map(|why| (k, why)))
        .collect();
    let eligible: Vec<EffectKind> = slow
        .into_iter()
        .filter(|k| protocol.allows(*k).is_ok())
        .collect();
    let tick = Tick {
        done: AtomicUsize::new(0),
        total: AtomicUsize::new(1 + eligible.len()),
        report: progress,
    };
    let init = setup.initial_baseline();
    let base = Candidate::fit(Model::new(setup, &[], init), BASE_ITERATIONS);
    tick.inc();
    let mut s = Selection {
        all: vec![base],
        chosen: 0,
        reasons: vec![String::new()],
        parents: vec![None],
        excluded,
        protocol,
    };
    let mut path = vec![0];
    let mut current = 0;
    // Each round adds one effect; a model already on the path ends the search (a cycle).
    for step in 1..=2 * eligible.len() + 2 {
        let Some(next) = s.forward(setup, current, &eligible, step, &tick) else {
            break;
        };
        current = s.backward(setup, next, &tick);
        if path.iter().any(|&p| s.all[p].key() == s.all[current].key()) {
            break;
        }
        path.push(current);
    }
    let confirmed = s.confirm(setup, current, &tick);
    s.chosen = std::iter::once(confirmed)
        .chain(path.iter().rev().copied())
        .find(|&i| s.admissible(setup, i, &tick))
        .unwrap_or(0);
    s.describe_chosen(setup, &tick);
    s
}

impl<'s, 'a> Selection<'s, 'a> {
    /// The calibrated baseline.
    pub fn base(&self) -> &Candidate<'s, 'a> {
        &self.all[0]
    }

    /// The reported model.
    pub fn chosen(&self) -> &Candidate<'s, 'a> {
        &self.all[self.chosen]
    }

    /// The candidate of exactly `kinds`, if it was fitted.
    pub fn position_of(&self, kinds: &[EffectKind]) -> Option<usize> {
        self.find(kinds)
    }

    fn find(&self, kinds: &[EffectKind]) -> Option<usize> {
        let key = key_of(kinds);
        self.all.iter().position(|c| c.key() == key)
    }

    /// Fit `current` plus each eligible effect (in parallel); the index of the passing one with
    /// the lowest BIC, or `None` when none passes.
    fn forward(
        &mut self,
        setup: &'s Setup<'a>,
        current: usize,
        eligible: &[EffectKind],
        step: usize,
        tick: &Tick,
    ) -> Option<usize> {
        let kinds = &self.all[current].kinds;
        let ve = EffectKind::ViscoelasticRelaxation;
        // A relaxation may take a second Prony term: a gel's spectrum spans decades.
        let additions: Vec<EffectKind> = eligible
            .iter()
            .copied()
            .filter(|k| {
                !kinds.contains(k) || (*k == ve && kinds.iter().filter(|&&x| x == ve).count() == 1)
            })
            .collect();
        let indices = self.fit_additions(setup, current, &additions, tick);
        let mut best: Option<usize> = None;
        for &i in &indices {
            let verdict = self.addition_test(current, i);
            if let Err(why) = verdict {
                self.reasons[i] = format!("rejected at step {step}: {why}");
                continue;
            }
            if best.is_none_or(|b| self.all[i].bic < self.all[b].bic) {
                best = Some(i);
            }
        }
        let b = best?;
        for &i in &indices {
            if i != b && self.reasons[i].is_empty() {
                self.reasons[i] = format!(
                    "passed at step {step}, but {} lowered BIC more",
                    self.all[b].label()
                );
            }
        }
        let cmp = self.all[b].compare(&self.all[current]);
        self.reasons[b] = format!(
            "added at step {step}: {}",
            cmp.words(&self.all[current].label())
        );
        Some(b)
    }

    /// Fit the additions not fitted before; the indices of all of them in `all`.
    fn fit_additions(
        &mut self,
        setup: &'s Setup<'a>,
        current: usize,
        additions: &[EffectKind],
        tick: &Tick,
    ) -> Vec<usize> {
        let nested = &self.all[current];
        let todo: Vec<EffectKind> = additions
            .iter()
            .copied()
            .filter(|&k| {
                self.find(&[nested.kinds.as_slice(), &[k]].concat())
                    .is_none()
            })
            .collect();
        tick.expect(todo.len());
        // Each effect starts where it ended alone (if it was fitted alone), a second Prony term
        // a decade either side of the first; else from its catalogue starts.
        let seeds: Vec<Vec<Vec<f64>>> = todo
            .iter()
            .map(|&k| {
                if nested.kinds.contains(&k) {
                    return crate::specs::second_prony_seeds(
                        nested.fitted.full[first_param(&nested.kinds, k)],
                    );
                }
                self.find(&[k])
                    .map(|single| vec![self.all[single].fitted.full[N_BASE..].to_vec()])
                    .unwrap_or_default()
            })
            .collect();
        let fitted: Vec<Candidate<'s, 'a>> = todo
            .par_iter()
            .zip(&seeds)
            .map(|(&k, seeds)| {
                let c = Candidate::extend(setup, nested, k, seeds, EFFECT_ITERATIONS);
                tick.inc();
                c
            })
            .collect();
        for c in fitted {
            self.all.push(c);
            self.reasons.push(String::new());
            self.parents.push(Some(current));
        }
        additions
            .iter()
            .filter_map(|&k| self.find(&[self.all[current].kinds.as_slice(), &[k]].concat()))
            .collect()
    }

    /// Whether candidate `i`, `current` plus one effect, may be taken: it beats `current` and
    /// the baseline on both tests, and its primary parameters are resolved.
    /// Whether candidate `i` passes the tests an effect must pass to be added to the baseline,
    /// the held-out stretch's aside (the criterion, its parameters off their bounds).
    pub fn admissible_alone(&self, i: usize) -> bool {
        self.addition_test(0, i).is_ok()
    }

    fn addition_test(&self, current: usize, i: usize) -> Result<(), String> {
        let c = &self.all[i];
        if c.at_neutral {
            return Err("the fit could not improve on the model it extends; the effect stays at its neutral values".into());
        }
        let vs_current = c.compare(&self.all[current]);
        if !vs_current.admits() {
            return Err(vs_current.words(&self.all[current].label()));
        }
        let vs_base = c.compare(self.base());
        if !vs_base.admits() {
            return Err(vs_base.words("the baseline"));
        }
        at_bounds(c, &self.protocol)
    }

    /// From candidate `i`, drop the effect that least earns its place on both tests until
    /// every effect passes both against the same model without it; the index of what is left.
    /// Then, while a static shape bends the outputs no further than the calibration may
    /// ([`absorbed_static_shape`]), drop it and prune again.
    fn confirm(&mut self, setup: &'s Setup<'a>, mut i: usize, tick: &Tick) -> usize {
        let why = ("not reported", "does not earn its place on both tests");
        loop {
            i = self.prune(setup, i, 0, Comparison::passes, why, tick);
            let Some((drop, weak)) = absorbed_static_shape(&self.all[i]) else {
                return i;
            };
            self.reasons[i] = format!("not reported: {weak}");
            i = self.without(setup, i, drop, tick);
        }
    }

    /// The model `from` without effect number `drop`, its index. Fitted from `from`'s solution
    /// with that effect taken out, unless fitted before; a model fitted before is refitted from
    /// there too when that start alone already fits better than its own fit did.
    ///
    /// Why: a smaller model fitted earlier on the search's path may sit in a worse local
    /// minimum than the larger model shows it has. Left so, the effect in hand would be credited
    /// with the difference (a `stiffening` of exponent 1.00, the identity, once gained 1357 in
    /// BIC that way), though without it the model fits as well.
    fn without(&mut self, setup: &'s Setup<'a>, from: usize, drop: usize, tick: &Tick) -> usize {
        let c = &self.all[from];
        let (mut kinds, mut start) = (Vec::new(), c.fitted.full[..N_BASE].to_vec());
        let mut at = N_BASE;
        for (j, k) in c.kinds.iter().enumerate() {
            let n = k.param_names().len();
            if j != drop {
                kinds.push(*k);
                start.extend_from_slice(&c.fitted.full[at..at + n]);
            }
            at += n;
        }
        let mut model = Model::new(setup, &kinds, &start[..N_BASE]);
        let before = self.find(&kinds);
        if let Some(i) = before {
            if model.sse_at(&start) >= self.all[i].sse() {
                return i;
            }
        }
        tick.expect(1);
        let mut at = N_BASE;
        for (e, k) in kinds.iter().enumerate() {
            let n = k.param_names().len();
            model.pin_starts(e, &start[at..at + n]);
            at += n;
        }
        let fitted = Candidate::fit(model, EFFECT_ITERATIONS);
        tick.inc();
        let what = format!(
            "{} without {}",
            self.all[from].label(),
            self.all[from].kinds[drop].name()
        );
        match before {
            Some(i) => {
                self.all[i] = fitted;
                self.refit_extensions(setup, i, tick);
                let refit = format!("refitted from {what}, a better start than its first fit");
                self.reasons[i] = match self.reasons[i].as_str() {
                    "" => refit,
                    first => format!("{first}; {refit}"),
                };
                i
            }
            None => {
                self.all.push(fitted);
                self.reasons.push(format!(
                    "{what}, fitted to test whether that effect earns its place"
                ));
                self.parents.push(None);
                self.all.len() - 1
            }
        }
    }

    /// After candidate `i` was refitted to a lower cost, refit each model that extends it and
    /// now costs more than it, from its new solution (and theirs in turn): every candidate
    /// keeps a cost no higher than the model it nests.
    fn refit_extensions(&mut self, setup: &'s Setup<'a>, i: usize, tick: &Tick) {
        let children: Vec<usize> = (0..self.all.len())
            .filter(|&j| self.parents[j] == Some(i) && self.all[j].sse() > self.all[i].sse())
            .collect();
        for j in children {
            let Some(&kind) = self.all[j].kinds.last() else {
                continue;
            };
            tick.expect(1);
            let own = self.all[j].fitted.full[self.all[i].fitted.full.len()..].to_vec();
            self.all[j] = Candidate::extend(setup, &self.all[i], kind, &[own], EFFECT_ITERATIONS);
            tick.inc();
            self.refit_extensions(setup, j, tick);
        }
    }

    /// Prune the effects of candidate `i` that the model without them no longer admits, the one
    /// whose removal costs least first; the index of what is left.
    fn backward(&mut self, setup: &'s Setup<'a>, i: usize, tick: &Tick) -> usize {
        let why = ("pruned", "stopped earning its place");
        self.prune(setup, i, 1, Comparison::admits, why, tick)
    }

    /// While candidate `i` has more than `keep` effects, drop the one that fails `test` against
    /// the same model without it and whose removal leaves the lowest BIC; the index left. The
    /// dropped model's reason reads "`why.0`: `<effect>` `why.1` (`<scores>`)".
    fn prune(
        &mut self,
        setup: &'s Setup<'a>,
        mut i: usize,
        keep: usize,
        test: fn(&Comparison) -> bool,
        why: (&str, &str),
        tick: &Tick,
    ) -> usize {
        while self.all[i].kinds.len() > keep {
            let mut worst: Option<(usize, usize)> = None;
            for drop in 0..self.all[i].kinds.len() {
                let w = self.without(setup, i, drop, tick);
                let passes = test(&self.all[i].compare(&self.all[w]));
                if !passes && worst.is_none_or(|(_, b)| self.all[w].bic < self.all[b].bic) {
                    worst = Some((drop, w));
                }
            }
            let Some((drop, w)) = worst else {
                return i;
            };
            let cmp = self.all[i].compare(&self.all[w]);
            self.reasons[i] = format!(
                "{}: {} {} ({})",
                why.0,
                self.all[i].kinds[drop].name(),
                why.1,
                cmp.words(&format!("the model without it, {}", self.all[w].label()))
            );
            i = w;
        }
        i
    }

    /// Whether candidate `i` passes every test: against the baseline, each effect against the
    /// same model without it, primary parameters resolved.
    fn admissible(&mut self, setup: &'s Setup<'a>, i: usize, tick: &Tick) -> bool {
        if i == 0 {
            return true;
        }
        let vs_base = self.all[i].compare(self.base());
        if self.all[i].at_neutral || !vs_base.passes() {
            self.reasons[i] = format!("not reported: {}", vs_base.words("the baseline"));
            return false;
        }
        if let Err(why) = resolved(&self.all[i], &self.protocol) {
            self.reasons[i] = format!("not reported: {why}");
            return false;
        }
        for drop in 0..self.all[i].kinds.len() {
            let w = self.without(setup, i, drop, tick);
            let cmp = self.all[i].compare(&self.all[w]);
            if !cmp.passes() {
                self.reasons[i] = format!(
                    "not reported: {} does not earn its place ({})",
                    self.all[i].kinds[drop].name(),
                    cmp.words(&self.all[w].label())
                );
                return false;
            }
        }
        true
    }

    /// The chosen candidate's reason: its evidence against the baseline and per effect.
    fn describe_chosen(&mut self, setup: &'s Setup<'a>, tick: &Tick) {
        let i = self.chosen;
        if i == 0 {
            self.reasons[0] = "accepted: no effect passed both tests against the baseline and the model without it".into();
            return;
        }
        let mut parts = vec![self.all[i].compare(self.base()).words("the baseline")];
        for drop in 0..self.all[i].kinds.len() {
            let w = self.without(setup, i, drop, tick);
            let kind = self.all[i].kinds[drop];
            let again = self.all[i].kinds[..drop].contains(&kind);
            parts.push(format!(
                "{}{}: {}",
                kind.name(),
                if again { " (second term)" } else { "" },
                self.all[i]
                    .compare(&self.all[w])
                    .words("the model without it")
            ));
        }
        self.reasons[i] = format!("accepted: {}", parts.join("; "));
        if self.reasons[0].is_empty() {
            self.reasons[0] = "the calibrated baseline every candidate nests".into();
        }
    }

    /// Report candidate `i` instead of the chosen one, for `why` (a described term took up what
    /// the chosen model's extra effect had).
    pub fn replace_chosen(&mut self, i: usize, why: &str) {
        let old = self.chosen;
        self.reasons[old] = format!("rejected: {why}");
        self.reasons[i] = format!("accepted: {why}");
        self.chosen = i;
    }

    /// The index in `all` of the model `chosen` without effect number `i`.
    pub fn without_index(&self, i: usize) -> usize {
        let kinds: Vec<EffectKind> = self
            .chosen()
            .kinds
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, k)| *k)
            .collect();
        self.find(&kinds).unwrap_or(0)
    }

    /// Each candidate's scores and reason for OUT.json, the effects never fitted last.
    pub fn reports(&self) -> Vec<CandidateReport> {
        let fitted = self.all.iter().enumerate().map(|(i, c)| CandidateReport {
            effects: c.kinds.iter().map(|k| k.name().to_string()).collect(),
            bic: c.bic,
            aicc: c.aicc,
            heldout_chi2: c.heldout_chi2,
            fit_chi2: c.sse(),
            extends: self.parents[i].map(|p| {
                self.all[p]
                    .kinds
                    .iter()
                    .map(|k| k.name().to_string())
                    .collect()
            }),
            accepted: i == self.chosen,
            reason: if self.reasons[i].is_empty() {
                format!("fitted while checking {}", label_of(&c.kinds))
            } else {
                self.reasons[i].clone()
            },
        });
        let excluded = self.excluded.iter().map(|(k, why)| CandidateReport {
            effects: vec![k.name().to_string()],
            bic: f64::NAN,
            aicc: f64::NAN,
            heldout_chi2: f64::NAN,
            fit_chi2: f64::NAN,
            extends: None,
            accepted: false,
            reason: why.clone(),
        });
        fitted.chain(excluded).collect()
    }
}
