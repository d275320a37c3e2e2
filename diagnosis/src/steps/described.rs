//! The described model: what the catalogue's chosen model leaves, described by the library's
//! terms (`crate::terms`) and the calibration's sanity findings, and a catalogue effect
//! replaced where terms are the other explanation of what it took up.
use baseline::{Drive, Outputs};
use sim::effects::EffectKind;

use crate::candidate::{heldout_needed, Candidate, MIN_BIC_GAIN};
use crate::fit::{Setup, OFFSET_AT, SCALE_AT};
use crate::misfit::white;
use crate::output::ParamDetail;
use crate::select::Selection;
use crate::steps::undecided::untestable;
use crate::{params, terms};

/// The chosen model with what it leaves described.
pub(crate) struct Model {
    /// The terms and sanity findings beyond the catalogue, and their contributions.
    pub described: terms::Described,
    /// The chosen model at the full rate, its described terms included.
    pub chosen_full: Outputs,
}

/// The chosen model of `sel` described ([`described_model`]; `sel`'s choice may change), on
/// the decimated series and at the full rate (`drive`); no term meets a `forbidden` catalogue
/// entry at another stage.
pub(crate) fn run(
    setup: &Setup,
    sel: &mut Selection,
    drive: &Drive,
    forbidden: &[EffectKind],
) -> Model {
    let (described, chosen_full) = described_model(setup, sel, drive, forbidden);
    let chosen_full = described.add_full(&chosen_full, &setup.data.full.t_s);
    Model {
        described,
        chosen_full,
    }
}

/// The chosen model with what it leaves described ([`describe`]), and the chosen model at the
/// full rate.
///
/// The library is searched on the model the catalogue chose when it named nothing, and, when
/// it named effects, on each model without one of them: a term is offered as the *other
/// explanation* of what a catalogue effect took up (a connector's offset step taken up by a
/// thermal drift, a power of the rod speed by a lag). Beside the whole catalogue model only
/// the terms no catalogue effect's misfit can mimic are offered
/// ([`terms::TermKind::beside_catalogue`]): on real rigs (the Mach-1 tests) the others take up
/// the effect's own misfit (a wander beside a relaxation spectrum that one Prony term does not
/// hold), which is not new physics. A catalogue effect is replaced where the model without
/// it, with its described terms, is at least as good by the criterion (within
/// [`MIN_BIC_GAIN`]) and no worse on the held-out stretch than the whole catalogue model with
/// the terms beside it: a freeze beside a relaxation is not the other explanation of the
/// relaxation, and the model without it had taken a lag and a relaxation at another stage
/// to make up the difference. Replacements go on, one effect at a time, against the model
/// last kept.
fn described_model(
    setup: &Setup,
    sel: &mut Selection,
    drive: &Drive,
    forbidden: &[EffectKind],
) -> (terms::Described, Outputs) {
    let on = On {
        setup,
        drive,
        forbidden,
    };
    if sel.chosen().kinds.is_empty() {
        return nothing_named(&on, sel);
    }
    // The chosen model with what may stand beside it is what a replacement must match.
    let (beside, beside_full) = on.candidate(sel, sel.chosen, true);
    let scores = if beside.found.terms.is_empty() {
        (sel.chosen().bic, sel.chosen().heldout_chi2)
    } else {
        (beside.found.bic, beside.found.heldout_chi2)
    };
    let mut current = (beside, beside_full, scores);
    // One effect at a time, while one is replaced: of two effects that each took up part of
    // one piece of physics, the second is weighed against the terms that replaced the first.
    loop {
        let Some((_, w, d_w, full_w, kind)) = best_replacement(&on, sel, current.2) else {
            return (current.0, current.1);
        };
        sel.replace_chosen(
            w,
            &format!(
                "the terms described without {} do as well by the criterion (within {MIN_BIC_GAIN}) and on the held-out stretch",
                kind.name()
            ),
        );
        let scores = (d_w.found.bic, d_w.found.heldout_chi2);
        current = (d_w, full_w, scores);
    }
}

/// What every candidate's description shares: the calibration's setup, the drive at the full
/// rate and the catalogue entries no term may meet at another stage.
struct On<'o, 'a> {
    setup: &'o Setup<'a>,
    drive: &'o Drive,
    forbidden: &'o [EffectKind],
}

impl On<'_, '_> {
    /// Candidate `i` described: its sanity findings, and where its residual stays structured
    /// the library's terms (with `beside`, those that may stand beside the whole catalogue).
    fn candidate(&self, sel: &Selection, i: usize, beside: bool) -> (terms::Described, Outputs) {
        let (setup, forbidden) = (self.setup, self.forbidden);
        let c = &sel.all[i];
        let full = c.outputs(self.drive);
        let dec: [Vec<f64>; 4] = std::array::from_fn(|k| c.outputs.channel(k).to_vec());
        let details = params::baseline(c, setup.data);
        let structured = !white(setup, &dec);
        let d = describe(setup, c, (&full, &details), structured, (beside, forbidden));
        (d, full)
    }
}

/// The chosen model described where the catalogue named nothing.
fn nothing_named(on: &On, sel: &Selection) -> (terms::Described, Outputs) {
    let (d, full) = on.candidate(sel, sel.chosen, false);
    // Terms that describe worse, by the criterion, what a catalogue effect the held-out
    // stretch cannot test describes are not the description either: that effect is left
    // undecided ([`untestable`]), and the terms go (a hysteresis on one press held out at
    // rest had been described as a power of the return's speed and a clip at the peak).
    let beaten = untestable(sel)
        .iter()
        .any(|&(i, _)| sel.all[i].bic < d.found.bic);
    if beaten && !d.found.terms.is_empty() {
        let c = &sel.all[sel.chosen];
        let details = params::baseline(c, on.setup.data);
        let plain = describe(on.setup, c, (&full, &details), false, (false, on.forbidden));
        return (plain, full);
    }
    (d, full)
}

/// A replacement of one of the chosen model's effects: the criterion of the model without it,
/// that model's index in the selection, its description and full-rate outputs, and the effect.
type Replacement = (f64, usize, terms::Described, Outputs, EffectKind);

/// The best replacement of one of the chosen model's effects by described terms, against the
/// current model's criterion and held-out chi-square (`bic`, `held`), if any does as well.
fn best_replacement(on: &On, sel: &Selection, (bic, held): (f64, f64)) -> Option<Replacement> {
    let mut best: Option<Replacement> = None;
    let kinds = sel.chosen().kinds.clone();
    for (i, &kind) in kinds.iter().enumerate() {
        let w = sel.without_index(i);
        if w == sel.chosen || sel.all[w].kinds.len() + 1 != kinds.len() {
            continue;
        }
        let (d_w, full_w) = on.candidate(sel, w, false);
        if d_w.found.terms.is_empty() {
            continue;
        }
        let bic_w = d_w.found.bic;
        // A discovered term can write the catalogue effect's own signature: it replaces the
        // effect only where it does better by the criterion and on the held-out stretch (by
        // half a percent of the misfit left: `heldout_needed`), not as well.
        let replaces = if d_w.found.terms.iter().any(|t| t.info.is_some()) {
            bic_w < bic - MIN_BIC_GAIN && held - d_w.found.heldout_chi2 > heldout_needed(0.0, held)
        } else {
            bic_w - bic <= MIN_BIC_GAIN && d_w.found.heldout_chi2 <= held
        };
        if replaces && best.as_ref().is_none_or(|b| bic_w < b.0) {
            best = Some((bic_w, w, d_w, full_w, kind));
        }
    }
    best
}

/// What the catalogue's model leaves, described: the calibration's sanity findings
/// (`terms::sanity`) always, and where the residual stays `structured` the library's terms
/// (`terms::search`; with `beside`, only those that may stand beside the whole catalogue;
/// none that meets a `forbidden` catalogue entry at another stage).
fn describe(
    setup: &Setup,
    chosen: &Candidate,
    (chosen_full, details): (&Outputs, &[ParamDetail]),
    structured: bool,
    (beside, forbidden): (bool, &[EffectKind]),
) -> terms::Described {
    let data = setup.data;
    let offset = std::array::from_fn(|c| chosen.fitted.full[OFFSET_AT + c]);
    // An output not compared was not calibrated: it is read at the metadata's gain (scale 1),
    // what a live channel would show.
    let mut nominal = chosen.fitted.full.clone();
    for c in (1..4).filter(|&c| !setup.used[c]) {
        nominal[SCALE_AT + c - 1] = 1.0;
    }
    let at_metadata = chosen.model.outputs(&nominal, &setup.drive);
    let model = std::array::from_fn(|c| {
        let m = if setup.used[c] {
            &chosen.outputs
        } else {
            &at_metadata
        };
        m.channel(c).to_vec()
    });
    let mut ctx = terms::Context::new(
        data,
        (&setup.fit_mask, &setup.heldout_mask),
        setup.used,
        model,
        std::array::from_fn(|c| chosen_full.channel(c)),
        offset,
    );
    ctx.discover = setup.discover;
    ctx.outputs_in_volts = setup.outputs_in_volts();
    ctx.loop_in_model = chosen.kinds.iter().any(|k| {
        matches!(
            k,
            EffectKind::Hysteresis | EffectKind::ViscoelasticRelaxation
        )
    });
    let nested = terms::Nested {
        n: chosen.fitted.solution.n,
        k: chosen.fitted.free.len(),
        fit_chi2: chosen.sse() + unweighed(setup, chosen, &setup.fit_mask),
        heldout_chi2: chosen.heldout_chi2 + unweighed(setup, chosen, &setup.heldout_mask),
    };
    ctx.beside_catalogue = beside;
    ctx.forbidden = forbidden.to_vec();
    // The directions cost a model evaluation per fitted parameter: only where terms are sought.
    if structured {
        let directions = chosen.directions();
        if beside {
            ctx.set_catalogue(directions);
        } else {
            ctx.set_directions(directions);
        }
    }
    terms::Described::new(&ctx, nested, details, structured)
}

/// The chi-square on `mask` that `chosen`'s own fit did not count: the samples it was fitted
/// without (a frozen channel's, [`Data::frozen_from`]) at `setup`'s weights, and the part of the
/// recording it was fitted without (a discovered term's, [`Prepared::discovered`]): the terms
/// are weighed against the misfit the whole recording shows.
fn unweighed(setup: &Setup, chosen: &Candidate, mask: &[bool]) -> f64 {
    let (all, fitted) = (setup.data, chosen.model.setup.data);
    if std::ptr::eq(all, fitted) {
        return 0.0;
    }
    (0..4)
        .filter(|&c| setup.used[c])
        .map(|c| {
            let (y, m) = (&all.fit.y[c], chosen.outputs.channel(c));
            (0..y.len())
                .filter(|&k| mask[k])
                .map(|k| {
                    let yf = fitted.fit.y[c][k];
                    (y[k] - m[k]).powi(2) * all.weight(c, k).powi(2)
                        - (yf - m[k]).powi(2) * fitted.weight(c, k).powi(2)
                })
                .sum::<f64>()
        })
        .sum()
}
