//! The diagnosis, start to end, one function per step: read the recording (`Data`) -> find its
//! regimes and the held-out stretch (`Stretches`) -> set up the calibration of the baseline
//! (`calibration_setup`) and read what the protocol allows (`Features`) -> fit the candidates
//! and select by BIC and the held-out stretch together (`select::select`) -> evaluate at the
//! full rate with the mains line (`full_rate`) -> localise the baseline's residual and test the
//! chosen model's for whiteness (`localise_residual`) -> the effects' evidence
//! (`evidence::effect_reports`) -> verdict (`verdict`) -> the report's data ([`Report`],
//! [`PlotData`]).
use std::sync::Arc;
use std::time::Instant;

use recording::{Meta, Recording};
use sim::effects::EffectKind;
use sim::forward::SignalPath;

use crate::candidate::{heldout_needed, Candidate, MIN_BIC_GAIN};
use crate::certify::{channel_rmse, contract_rmse};
use crate::data::{Data, DataError, CHANNELS};
use crate::fit::Setup;
use crate::localise::{self, ChannelLocalisation, Mismatch};
use crate::mains::{self, Line};
use crate::output::*;
use crate::preconditions::Features;
use crate::regimes::{self, Segment};
use crate::select::select;
use crate::simulation::{self, Samples, SimulationError, SimulationReport, Simulations};
use crate::{evidence, noise, params, stats, terms, undecided};
use baseline::fe_response::{AngleBlend, FeSource};
use baseline::{Drive, Outputs, Readout, UnitResponse};

pub use crate::select::Progress;

/// Where the baseline model comes from: the one place it is chosen.
#[derive(Debug, Clone, Default)]
pub enum BaselineSource {
    /// Our fingertip's FE tables and our chip ([`Options::fe`]).
    #[default]
    Fe,
    /// The user's own simulation of each recording (`docs/simulation-format.md`), calibrated
    /// with a load scale, the three output scales and four offsets.
    Simulation(Simulations),
}

/// Knobs of a run and the project's model parameters the recording does not carry.
#[derive(Clone)]
pub struct Options {
    /// Our FE model or the user's simulation.
    pub baseline: BaselineSource,
    /// The fingertip FE and the chip behind the baseline's response tables.
    pub fe: FeSource,
    /// The chip's bridge output per volt of excitation per unit load (the `chip` crate).
    pub sensitivity_per_v: [[f64; 3]; 3],
    /// How far the baseline may be calibrated (`hardware/fit-bounds.toml`).
    pub fit_bounds: hardware::FitBounds,
    /// Called as the candidate models are fitted (a progress bar, say).
    pub progress: Option<Arc<Progress>>,
}

impl std::fmt::Debug for Options {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Options")
            .field("baseline", &self.baseline)
            .field("fe", &self.fe)
            .field("sensitivity_per_v", &self.sensitivity_per_v)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl Options {
    /// The project's fingertip, chip and pillar from `hardware/`, no progress reports.
    pub fn from_hardware(
        hw: &hardware::Params,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        let fe = Readout::from_chip(hw, [1.0; 3], hw.chip.excitation_v)?;
        Ok(Self {
            baseline: BaselineSource::Fe,
            fe: FeSource::from_hardware(hw)?,
            sensitivity_per_v: fe.signal.sensitivity_per_v,
            fit_bounds: hw.fit_bounds.clone(),
            progress: None,
        })
    }
}

/// Lags of the whiteness tests (Ljung–Box for the baseline's residual, the verdict's
/// autoregression), and the Ljung–Box p-value below which a residual is structured.
const LB_LAGS: usize = 20;
const LB_P: f64 = 1e-3;

/// Everything the HTML report plots.
pub struct PlotData {
    /// Time of the decimated series, s.
    pub t_s: Vec<f64>,
    /// The recording's load_N, fz_V, mx_V, my_V, decimated.
    pub recorded: [Vec<f64>; 4],
    /// The calibrated baseline on the same time base.
    pub baseline: [Vec<f64>; 4],
    /// The chosen model on the same time base.
    pub improved: [Vec<f64>; 4],
    /// The regimes of the test.
    pub segments: Vec<Segment>,
    /// Start and end of the held-out stretch, s.
    pub heldout: (f64, f64),
    /// Channels compared (a range above the noise).
    pub used: [bool; 4],
    /// The rod's travel on the same time base, mm.
    pub rod_mm: Vec<f64>,
    /// Each discovered effect on its first channel.
    pub terms: Vec<TermCurve>,
}

impl PlotData {
    /// The recording `data` and its `baseline` on the fitting series, with `stretches`; the
    /// improved model the baseline until set.
    fn of(data: &Data, baseline: [Vec<f64>; 4], stretches: &Stretches, used: [bool; 4]) -> Self {
        PlotData {
            t_s: data.fit.t_s.clone(),
            recorded: data.fit.y.clone(),
            improved: baseline.clone(),
            baseline,
            segments: stretches.segments.clone(),
            heldout: stretches.heldout,
            used,
            rod_mm: data.fit.rod_mm.clone(),
            terms: Vec::new(),
        }
    }
}

/// A discovered effect's contribution to one channel's model, on the decimated time base.
#[derive(Debug, Clone)]
pub struct TermCurve {
    /// As the effect is reported (`name`).
    pub name: String,
    /// Its channel (index of `data::CHANNELS`).
    pub channel: usize,
    pub values: Vec<f64>,
}

/// The diagnosis of one recording: OUT.json's content and the report's plots.
pub struct Diagnosis {
    /// What OUT.json holds (`docs/diagnosis-format.md`).
    pub report: Report,
    /// What the HTML report plots.
    pub plots: PlotData,
    /// The catalogue effects found at a stage other than the catalogue's, which a session
    /// holds as this diagnosis found them.
    pub(crate) at_stage: Option<crate::terms::AtStage>,
    /// What the discovery step found ([`crate::terms::discover`]), on both series.
    pub(crate) discovered: Option<crate::terms::AtStage>,
}

/// Diagnose `rec`; `name` is what OUT.json calls the recording.
///
/// The catalogue and the library are fitted to the start of the recording and tested on its
/// end. When nothing fitted there explains what the end shows (`unexplained`), the physics may
/// act only in the end (a connector knocked late, a channel that freezes in the last cycle):
/// the stretches are swapped, the end fitted and the start held out, and that diagnosis is
/// kept when it finds what acts. It passed the same two tests, on the other stretch.
///
/// A channel found frozen (`stuck_channel`) reads nothing of the sensor from then on: the
/// catalogue is fitted again without those samples (`Data::frozen_from`), so that its
/// effects are chosen on what the sensor did, and that diagnosis is kept when it finds the
/// freeze it was fitted without (a frozen Fz had the catalogue bend a lag, a power of the rod
/// speed and a relaxation at the transducer to follow it).
pub fn diagnose(rec: &Recording, name: &str, opt: &Options) -> Result<Diagnosis, DataError> {
    let started = Instant::now();
    let mut prepared = prepare(rec, name, opt)?;
    let (mut d, mut frozen) = diagnose_prepared(&prepared, name, opt);
    if d.report.verdict == Verdict::Unexplained {
        prepared.stretches.swap(&prepared.data.fit.t_s);
        let swapped = diagnose_prepared(&prepared, name, opt);
        if !swapped.0.report.effects.is_empty() {
            (d, frozen) = swapped;
        }
    }
    // Fitted without the frozen samples the model follows the channel's own calibration, and
    // the freeze may show where it began: refitted until the freeze it finds is the one it was
    // fitted without (a fixed point), or kept as first found.
    for _ in 0..MAX_FREEZE_REFITS {
        if frozen.is_empty() {
            break;
        }
        prepared.frozen.clone_from(&frozen);
        let (again, still) = diagnose_prepared(&prepared, name, opt);
        if same_freeze(&prepared.data, &frozen, &still) {
            d = again;
            break;
        }
        frozen = still;
    }
    let d = with_discovery_refitted(&mut prepared, d, name, opt);
    let mut d = without_unsupported_discovery(&mut prepared, d, name, opt);
    d.report.seconds = started.elapsed().as_secs_f64();
    Ok(d)
}

/// `d`, or where its discovered terms leave the held-out stretch predicted worse than by the
/// baseline (the contract's RMSE, at the full rate: the terms passed their test on the fitting
/// series' blocks), the diagnosis without the discovery step. Only what the held-out stretch
/// supports is reported.
fn without_unsupported_discovery(
    prepared: &mut Prepared,
    d: Diagnosis,
    name: &str,
    opt: &Options,
) -> Diagnosis {
    let held = &d.report.fit.heldout;
    let discovered = d.report.effects.iter().any(|e| e.is_discovered());
    if !discovered || held.rmse_after <= held.rmse_before {
        return d;
    }
    prepared.discovered = None;
    prepared.without_discovery = true;
    diagnose_prepared(prepared, name, opt).0
}

/// Refits of the catalogue without what the discovery step found before it is taken as found.
const MAX_DISCOVERY_REFITS: usize = 2;

/// `d` again with the catalogue fitted without its discovered terms, until the terms found
/// again are the ones it was fitted without (the same channels and features), or as first
/// found when the refit loses them. The calibration fitted to the whole recording had bent
/// towards what the model lacked: a discovered term fitted beside it takes up the bend too
/// (a softening in time came with a function of the travel), and the refit removes it. It
/// is the universal differential equation's joint fit, done by alternation: the model with
/// the unknown block fitted, then the block on what the model leaves.
fn with_discovery_refitted(
    prepared: &mut Prepared,
    mut d: Diagnosis,
    name: &str,
    opt: &Options,
) -> Diagnosis {
    for _ in 0..MAX_DISCOVERY_REFITS {
        let Some(parts) = d.discovered.clone() else {
            break;
        };
        let before = discovered_names(&d.report.effects);
        prepared.discovered = Some(parts);
        let (again, _) = diagnose_prepared(prepared, name, opt);
        let after = discovered_names(&again.report.effects);
        // The refit is kept only where it still discovers and predicts the held-out stretch
        // no worse: an alternation that wandered (a calibration bent around a wrong term) is
        // not a better joint fit.
        let held = |d: &Diagnosis| d.report.fit.heldout.rmse_after;
        if after.is_empty() || held(&again) > held(&d) {
            break;
        }
        d = with_baseline_of(again, &d);
        if after == before {
            break;
        }
    }
    prepared.discovered = None;
    d
}

/// `again` with the baseline of `first`: the baseline is the one calibrated to the recording
/// itself (the contract's `rmse_before`, where it misses and its page), not the one fitted
/// without the discovered terms.
fn with_baseline_of(mut again: Diagnosis, first: &Diagnosis) -> Diagnosis {
    let (r, f) = (&mut again.report, &first.report);
    r.baseline = f.baseline.clone();
    r.mismatches = f.mismatches.clone();
    r.localisation = f.localisation.clone();
    r.fit.rmse_before = f.fit.rmse_before;
    r.fit.heldout.rmse_before = f.fit.heldout.rmse_before;
    again.plots.baseline = first.plots.baseline.clone();
    again
}

/// The names and channels of the discovered effects of a report, sorted.
fn discovered_names(effects: &[EffectReport]) -> Vec<(String, Vec<String>)> {
    let mut v: Vec<(String, Vec<String>)> = effects
        .iter()
        .filter(|e| e.inclusion.is_some())
        .map(|e| (e.name.clone(), e.channels.clone()))
        .collect();
    v.sort();
    v
}

/// Refits without a frozen channel's samples before the freeze found is taken as it was first
/// found: each moves the freeze towards where the channel's own calibration puts it.
const MAX_FREEZE_REFITS: usize = 3;

/// Whether `b` finds the freezes `a` found: the same channels, each from the same time to
/// within two samples of the fitting series (a freeze found elsewhere once the catalogue no
/// longer follows it is not the one the refit was for).
fn same_freeze(data: &Data, a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
    let t = &data.fit.t_s;
    let step_s = (t[t.len() - 1] - t[0]) / (t.len().max(2) - 1) as f64;
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 2.0 * step_s)
}

/// One diagnosis of `prepared` with its stretches as they are, and the channels it found
/// frozen with the time each froze.
fn diagnose_prepared(
    prepared: &Prepared,
    name: &str,
    opt: &Options,
) -> (Diagnosis, Vec<(usize, f64)>) {
    let (data, stretches) = (&prepared.data, &prepared.stretches);
    let setup = prepared.setup(opt);
    let fitted = prepared.fitted_data();
    let frozen_setup = fitted.as_ref().map(|d| prepared.setup_on(d, opt));
    let sel_setup = frozen_setup.as_ref().unwrap_or(&setup);
    // The baseline's moment direction: whether the moment scales can turn it (a precondition
    // of crosstalk) and, after the search, what a turn they made would mean.
    let moment_phi = moment_direction(&setup.drive);
    let protocol = Features::of(
        data,
        &stretches.segments,
        setup.used,
        setup.thermal.is_some(),
    )
    .with_moment_direction(moment_phi, setup.fit_bounds.jig_azimuth_tolerance_deg);
    let mains_allowed = protocol.allows(EffectKind::MainsInterference).is_ok();
    let forbidden: Vec<EffectKind> = terms::TermKind::ALL
        .iter()
        .filter_map(|k| k.catalogue_kind())
        .filter(|&k| protocol.protocol_allows(k).is_err())
        .collect();
    let mut sel = select(sel_setup, protocol, opt.progress.as_deref());
    let drive = prepared.full_drive(&setup);
    let (described, chosen_full) = described_model(&setup, &mut sel, &drive, &forbidden);
    let (base, chosen) = (sel.base(), sel.chosen());
    let base_full = base.outputs(&drive);
    let details = params::baseline(chosen, data);
    let chosen_full = described.add_full(&chosen_full, &data.full.t_s);
    let mut local = localise_residual(&setup, base, chosen, &stretches.segments);
    if !described.found.terms.is_empty() {
        local.chosen = described.add_decimated(&local.chosen);
        local.white_after = white(&setup, &local.chosen);
    }
    let full = full_rate(&setup, &base_full, &chosen_full, stretches, mains_allowed);
    let mut full = full;
    let found = all_effects(&sel, &full, (described.effects, described.parts), &drive);
    // Below the resolution floor the baseline's residual is arithmetic, not a mismatch.
    let white = local.white_after || full.fit.rmse_before < RESOLUTION_FLOOR;
    let (effects, verdict, demoted) = certified(data, &mut full, found, white);
    let mut undecided = undecided_findings(&setup, &effects, &details, moment_phi);
    undecided.extend(demoted);
    // A structured residual that nothing named explains, and an effect the held-out stretch
    // cannot test would: said, not guessed.
    if effects.is_empty() && verdict != Verdict::NoSignificantMismatch {
        undecided.extend(untestable_findings(&sel, stretches.heldout));
    }
    let report = Report {
        format: FORMAT,
        recording: name.to_string(),
        verdict,
        baseline: Baseline {
            params: baseline_params(base),
            rmse: full.baseline_rmse,
            parameters: params::baseline(base, data),
            simulation: prepared.simulation.clone(),
        },
        mismatches: local.mismatches,
        effects,
        undecided,
        fit: full.fit,
        localisation: Localisation {
            channels: local.channels,
            lines: prominent_lines(full.baseline_line.as_ref()),
        },
        candidates: sel.reports(),
        seconds: 0.0,
    };
    let plots = PlotData {
        // At the fitting rate a mains line averages out over whole periods, so the improved
        // model plotted there is the slow model alone.
        improved: local.chosen,
        terms: described.curves.clone(),
        ..PlotData::of(data, local.baseline, stretches, setup.used)
    };
    let frozen = frozen_channels(&described.found.terms);
    let d = Diagnosis {
        report,
        plots,
        at_stage: described.at_stage,
        discovered: described.discovered,
    };
    (d, frozen)
}

/// The channels `terms` found frozen, each with the time it froze.
fn frozen_channels(terms: &[terms::Term]) -> Vec<(usize, f64)> {
    terms
        .iter()
        .filter(|t| t.kind == terms::TermKind::StuckChannel)
        .map(|t| (t.channel, t.shape[0]))
        .collect()
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
    sel: &mut crate::select::Selection,
    drive: &Drive,
    forbidden: &[EffectKind],
) -> (terms::Described, Outputs) {
    // Candidate `i` described: its sanity findings, and where its residual stays structured
    // the library's terms (with `beside`, those that may stand beside the whole catalogue).
    let of = |sel: &crate::select::Selection, i: usize, beside: bool| {
        let c = &sel.all[i];
        let full = c.outputs(drive);
        let dec: [Vec<f64>; 4] = std::array::from_fn(|k| c.outputs.channel(k).to_vec());
        let details = params::baseline(c, setup.data);
        let structured = !white(setup, &dec);
        let d = describe(setup, c, (&full, &details), structured, (beside, forbidden));
        (d, full)
    };
    if sel.chosen().kinds.is_empty() {
        let (d, full) = of(sel, sel.chosen, false);
        // Terms that describe worse, by the criterion, what a catalogue effect the held-out
        // stretch cannot test describes are not the description either: that effect is left
        // undecided ([`untestable`]), and the terms go (a hysteresis on one press held out at
        // rest had been described as a power of the return's speed and a clip at the peak).
        let beaten = untestable(sel)
            .iter()
            .any(|&(i, _)| sel.all[i].bic < d.found.bic);
        if beaten && !d.found.terms.is_empty() {
            let c = &sel.all[sel.chosen];
            let details = params::baseline(c, setup.data);
            let plain = describe(setup, c, (&full, &details), false, (false, forbidden));
            return (plain, full);
        }
        return (d, full);
    }
    // The chosen model with what may stand beside it is what a replacement must match.
    let (beside, beside_full) = of(sel, sel.chosen, true);
    let scores = if beside.found.terms.is_empty() {
        (sel.chosen().bic, sel.chosen().heldout_chi2)
    } else {
        (beside.found.bic, beside.found.heldout_chi2)
    };
    let mut current = (beside, beside_full, scores);
    // One effect at a time, while one is replaced: of two effects that each took up part of
    // one piece of physics, the second is weighed against the terms that replaced the first.
    loop {
        let (bic, held) = current.2;
        let mut best: Option<(f64, usize, terms::Described, Outputs, EffectKind)> = None;
        let kinds = sel.chosen().kinds.clone();
        for (i, &kind) in kinds.iter().enumerate() {
            let w = sel.without_index(i);
            if w == sel.chosen || sel.all[w].kinds.len() + 1 != kinds.len() {
                continue;
            }
            let (d_w, full_w) = of(sel, w, false);
            if d_w.found.terms.is_empty() {
                continue;
            }
            let bic_w = d_w.found.bic;
            // A discovered term can write the catalogue effect's own signature: it replaces
            // the effect only where it does better by the criterion and on the held-out
            // stretch (by half a percent of the misfit left: `heldout_needed`), not as well.
            let replaces = if d_w.found.terms.iter().any(|t| t.info.is_some()) {
                bic_w < bic - MIN_BIC_GAIN
                    && held - d_w.found.heldout_chi2 > crate::candidate::heldout_needed(0.0, held)
            } else {
                bic_w - bic <= MIN_BIC_GAIN && d_w.found.heldout_chi2 <= held
            };
            if replaces && best.as_ref().is_none_or(|b| bic_w < b.0) {
                best = Some((bic_w, w, d_w, full_w, kind));
            }
        }
        let Some((_, w, d_w, full_w, kind)) = best else {
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
    let offset = std::array::from_fn(|c| chosen.fitted.full[crate::fit::OFFSET_AT + c]);
    // An output not compared was not calibrated: it is read at the metadata's gain (scale 1),
    // what a live channel would show.
    let mut nominal = chosen.fitted.full.clone();
    for c in (1..4).filter(|&c| !setup.used[c]) {
        nominal[crate::fit::SCALE_AT + c - 1] = 1.0;
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

/// The effects that pass the certification (`crate::certify`), the verdict, and what went to
/// `undecided`. Where an effect went, the fit is the model's without it, and the verdict is no
/// `explained` by an effect the answer no longer reports.
fn certified(
    data: &Data,
    full: &mut FullRate,
    found: Vec<(EffectReport, Option<crate::certify::Part>)>,
    white_after: bool,
) -> (Vec<EffectReport>, Verdict, Vec<Undecided>) {
    let certified = crate::certify::certify(data, full.masks(), &full.model, found);
    let effects = certified.effects;
    let mut verdict = verdict(!effects.is_empty(), white_after);
    if certified.demoted {
        full.refit(data, &certified.model);
        if verdict == Verdict::Explained {
            verdict = Verdict::PartiallyExplained;
        }
        if effects.is_empty() {
            verdict = Verdict::Unexplained;
        }
    }
    (effects, verdict, certified.undecided)
}

/// The effects to report: the chosen catalogue effects, the mains lines on the outputs and on
/// the load cell, and what was described beyond the catalogue; each with its part of the
/// model at the full rate (`certify::Part`), which the certification tests.
fn all_effects(
    sel: &crate::select::Selection,
    full: &FullRate,
    (described, parts): (Vec<EffectReport>, Vec<Option<crate::certify::Part>>),
    drive: &Drive,
) -> Vec<(EffectReport, Option<crate::certify::Part>)> {
    let data = sel.base().model.setup.data;
    let catalogue = evidence::effect_reports(sel, data);
    let catalogue_parts = evidence::catalogue_parts(sel, drive, &catalogue);
    let mut effects: Vec<(EffectReport, Option<crate::certify::Part>)> = catalogue
        .into_iter()
        .zip(catalogue_parts.into_iter().map(Some))
        .collect();
    let outputs: Vec<usize> = OUTPUTS.into_iter().filter(|&c| data.modelled(c)).collect();
    let line_part = |line: &Line, chans: &[usize]| line_part(data, line, chans);
    if let Some(line) = &full.mains {
        effects.push((
            evidence::mains_report(line, data),
            Some(line_part(line, &outputs)),
        ));
    }
    if let Some(line) = &full.load_mains {
        let part = line_part(line, &LOAD_CELL);
        effects.push((evidence::load_mains_report(line, data), Some(part)));
    }
    for e in terms::report::fast_lines(&full.fast) {
        let f = e.params.get("freq_hz").unwrap_or(f64::NAN);
        let mut part: crate::certify::Part = std::array::from_fn(|_| Vec::new());
        for l in full
            .fast
            .iter()
            .filter(|l| (l.line.freq_hz - f).abs() < 0.01)
        {
            let one = line_part(&l.line, &[l.channel]);
            part[l.channel].clone_from(&one[l.channel]);
        }
        effects.push((e, Some(part)));
    }
    effects.extend(described.into_iter().zip(parts));
    effects
}

/// A line on `chans` at the full rate, alone: its part of the model (no part elsewhere).
fn line_part(data: &Data, line: &Line, chans: &[usize]) -> crate::certify::Part {
    let n = data.full.len();
    let zero = Outputs {
        load_n: vec![0.0; n],
        volts: std::array::from_fn(|_| vec![0.0; n]),
    };
    let with = add_line(data, &zero, Some(line), chans);
    std::array::from_fn(|c| {
        if chans.contains(&c) {
            with.channel(c).to_vec()
        } else {
            Vec::new()
        }
    })
}

/// What the data leaves open: a turn of the moment scales that crosstalk or the gains would
/// explain alike, and gains far off the metadata.
fn undecided_findings(
    setup: &Setup,
    effects: &[EffectReport],
    details: &[ParamDetail],
    moment_phi: Option<f64>,
) -> Vec<Undecided> {
    // A moment read with its sign inverted turns the calibrated moment vector as a rotated
    // chip would; it is found as such, so the turn is not also left undecided.
    let inverted = effects.iter().any(|e| e.name == "inverted_sign");
    let ambiguous = moment_phi
        .filter(|_| setup.used[2] && setup.used[3] && !named(effects, EffectKind::Crosstalk))
        .filter(|_| !inverted)
        .and_then(|phi| undecided::crosstalk_or_gains(details, phi, &setup.fit_bounds));
    // Against a user's simulation an output's scale calibrates the simulation's outputs, which
    // may be off by any factor (its own gains, a sensitivity it assumed): no finding of gains.
    let gains = terms::sanity::gains_off(details).filter(|_| !setup.user_simulation);
    ambiguous.into_iter().chain(gains).collect()
}

/// The catalogue effects that the criterion keeps on the fitting stretch, alone against the
/// baseline, but that the held-out stretch cannot test (`Comparison::untestable`): were one
/// the truth, its held-out gain would not count. Each with its candidate's index and that
/// comparison; the chosen model's own effects are not among them.
fn untestable(sel: &crate::select::Selection) -> Vec<(usize, crate::candidate::Comparison)> {
    let chosen = &sel.chosen().kinds;
    (0..sel.all.len())
        .filter(|&i| sel.all[i].kinds.len() == 1 && !chosen.contains(&sel.all[i].kinds[0]))
        .filter(|&i| sel.admissible_alone(i))
        .map(|i| (i, sel.all[i].compare(sel.base())))
        .filter(|(_, cmp)| cmp.untestable())
        .collect()
}

/// Each [`untestable`] effect, undecided: what the fitting stretch says of it and why the
/// held-out stretch cannot, and which recording would decide.
///
/// Only the effects the criterion cannot tell from the best of them (within `MIN_BIC_GAIN`):
/// the fitting stretch decides between them, though not whether the best is there.
fn untestable_findings(sel: &crate::select::Selection, heldout: (f64, f64)) -> Vec<Undecided> {
    let all = untestable(sel);
    let best = all
        .iter()
        .map(|&(i, _)| sel.all[i].bic)
        .fold(f64::INFINITY, f64::min);
    all.into_iter()
        .filter(|&(i, _)| sel.all[i].bic <= best + MIN_BIC_GAIN)
        .map(|(i, cmp)| {
            let c = &sel.all[i];
            let kind = c.kinds[0];
            let mut params = crate::output::Numbers::default();
            for (_, details) in params::effects(c, sel.base().model.setup.data) {
                for p in details {
                    params.push(&p.name, p.value);
                }
            }
            Undecided {
                effects: vec![kind.name().into()],
                calibration: Vec::new(),
                params,
                reason: format!(
                    "{} fits the fitting stretch (BIC {:.0} below the baseline's), but the held-out stretch ({:.1}-{:.1} s) cannot test it: were it the truth, it would lower the held-out misfit there by {:.1} (noise units), and the test needs more than {:.1}. A recording that shows its signature again after the stretch it is fitted on (another press and release) would decide",
                    kind.name(),
                    cmp.bic_gain,
                    heldout.0,
                    heldout.1,
                    cmp.heldout_reach,
                    cmp.heldout_needed
                ),
            }
        })
        .collect()
}

fn named(effects: &[EffectReport], kind: EffectKind) -> bool {
    effects.iter().any(|e| e.name == kind.name())
}

/// The direction atan2(My, Mx) of the baseline's chip moment at the drive's largest moment.
fn moment_direction(drive: &Drive) -> Option<f64> {
    let m = drive.unit.iter().max_by(|a, b| {
        a.chip[1]
            .hypot(a.chip[2])
            .total_cmp(&b.chip[1].hypot(b.chip[2]))
    })?;
    (m.chip[1] != 0.0 || m.chip[2] != 0.0).then(|| m.chip[2].atan2(m.chip[1]))
}

/// The baseline's response to the recorded rod path.
enum Fingertip {
    /// Our FE tables at the recording's contact angle and azimuth.
    Fe(Box<AngleBlend>),
    /// The user's simulation at each full-rate sample of the recording (load scale 1).
    Simulated(Arc<Vec<UnitResponse>>),
}

/// One recording read and ready to fit: its data, stretches and fingertip. A single diagnosis
/// and each member of a joint one (`crate::joint`) set up their fits from it alike.
pub(crate) struct Prepared {
    pub data: Data,
    stretches: Stretches,
    fingertip: Fingertip,
    /// The user's simulation behind the baseline, where it is one (OUT.json's
    /// `baseline.simulation`).
    simulation: Option<SimulationReport>,
    pub meta: Meta,
    /// The data without its readings held (`Data::without_held`), if it has any: worked out
    /// once, for every diagnosis of the recording.
    held: Option<Data>,
    /// Channels found frozen, each with the time it froze, s.
    frozen: Vec<(usize, f64)>,
    /// What an earlier diagnosis discovered, which the catalogue is fitted without.
    discovered: Option<crate::terms::AtStage>,
    /// No discovery step ([`Setup::discover`]).
    without_discovery: bool,
}

/// Read `rec` and look up its fingertip's response at its contact angle and azimuth.
/// The contract's held-out RMSE of `prediction`'s channels as the model of `rec` (the same
/// samples). With `prediction` the recording without its noise it is the least any model can
/// reach on that stretch: the floor under a held-out ratio. `None` when the two differ in
/// length.
pub fn heldout_rmse_of(
    rec: &Recording,
    prediction: &Recording,
    opt: &Options,
) -> Result<Option<f64>, DataError> {
    let p = prepare(rec, "", opt)?;
    let c = &prediction.channels;
    if c.len() != p.data.full.t_s.len() {
        return Ok(None);
    }
    let o = Outputs {
        load_n: c.load_n.clone(),
        volts: [c.fz_v.clone(), c.mx_v.clone(), c.my_v.clone()],
    };
    Ok(Some(p.rmse(&o).1))
}

/// Read `rec` (called `name` in the outputs) and look up its baseline's response: the FE's at
/// its contact angle and azimuth, or its simulation's (`opt.baseline`).
pub(crate) fn prepare(rec: &Recording, name: &str, opt: &Options) -> Result<Prepared, DataError> {
    let mut data = Data::new(rec)?;
    let meta = rec.meta.clone();
    let (fingertip, simulation) = match &opt.baseline {
        BaselineSource::Fe => {
            let fe = opt.fe.response(
                meta.fingertip_radius_mm,
                meta.contact_angle_deg,
                meta.azimuth_deg,
            )?;
            (Fingertip::Fe(Box::new(fe)), None)
        }
        BaselineSource::Simulation(sims) => {
            let path = sims
                .for_recording(name)
                .ok_or_else(|| SimulationError::Unpaired(name.to_string()))?;
            let at = Samples {
                t_s: &data.full.t_s,
                rod_mm: &data.full.rod_mm,
            };
            let loaded = simulation::load(path, rec, at, opt.sensitivity_per_v)?;
            data = data.unmodelled(loaded.lacks);
            (
                Fingertip::Simulated(Arc::new(loaded.units)),
                Some(loaded.report),
            )
        }
    };
    let stretches = Stretches::detect(&data);
    Ok(Prepared {
        held: data.without_held(),
        data,
        stretches,
        fingertip,
        simulation,
        meta,
        frozen: Vec::new(),
        discovered: None,
        without_discovery: false,
    })
}

impl Prepared {
    /// The recording as a session's member: without the catalogue effects its own diagnosis
    /// found at a stage other than the catalogue's (`at`), which a session's model, with each
    /// effect at its own stage only, is not fitted to; and with the channels `flips` read with
    /// their sign turned back (`inverted_sign`: a wire). The range, the stretches and the free
    /// offsets stay the recording's.
    pub fn for_session(&mut self, at: Option<&crate::terms::AtStage>, flips: &[usize]) {
        let parts = at.map(|a| [&a.full, &a.decimated]);
        for (k, series) in [&mut self.data.full, &mut self.data.fit]
            .into_iter()
            .enumerate()
        {
            for c in 0..4 {
                if let Some(parts) = parts {
                    let part = &parts[k][c];
                    series.y[c].iter_mut().zip(part).for_each(|(y, p)| *y -= p);
                }
                if flips.contains(&c) {
                    series.y[c].iter_mut().for_each(|y| *y = -*y);
                }
            }
        }
        self.held = self.data.without_held();
    }

    /// The calibration setup of this recording's fits.
    pub fn setup(&self, opt: &Options) -> Setup<'_> {
        self.setup_on(&self.data, opt)
    }

    /// The calibration setup on `data` (this recording's, or it without a frozen channel).
    fn setup_on<'a>(&self, data: &'a Data, opt: &Options) -> Setup<'a> {
        Setup {
            discover: !self.without_discovery,
            ..calibration_setup(data, &self.meta, &self.fingertip, &self.stretches, opt)
        }
    }

    /// The data the catalogue is fitted on where it is not the recording as read: without the
    /// readings held and what a frozen channel read after it froze, and without what the
    /// discovery step found (held as found, so that the calibration is not bent towards it; the
    /// terms are then found again on the whole recording).
    fn fitted_data(&self) -> Option<Data> {
        let base = self.without_frozen().or_else(|| self.held.clone());
        match &self.discovered {
            Some(parts) => Some(parts.taken_from(base.as_ref().unwrap_or(&self.data))),
            None => base,
        }
    }

    /// The data without the readings held (`Data::without_held`) and without what the frozen
    /// channels read after they froze; `None` where none froze.
    fn without_frozen(&self) -> Option<Data> {
        if self.frozen.is_empty() {
            return None;
        }
        let start = self.held.as_ref().unwrap_or(&self.data).clone();
        Some(
            self.frozen
                .iter()
                .fold(start, |d, &(c, t)| d.frozen_from(c, t)),
        )
    }

    /// The drive at the full rate, for the contract's RMSEs.
    pub fn full_drive(&self, setup: &Setup) -> Drive {
        let data = &self.data;
        let (t, rod) = (data.full.t_s.clone(), &data.full.rod_mm);
        let drive = match &self.fingertip {
            Fingertip::Fe(fe) => Drive::new(fe.as_ref(), t, rod),
            Fingertip::Simulated(units) => Drive::of_samples(t, rod, units.to_vec()),
        };
        drive.with_temperature(setup.thermal.and(data.full.temp_c.clone()))
    }

    /// What the recording's protocol shows, for the effects' preconditions.
    pub fn features(&self, setup: &Setup) -> Features {
        let phi = moment_direction(&setup.drive);
        Features::of(
            &self.data,
            &self.stretches.segments,
            setup.used,
            setup.thermal.is_some(),
        )
        .with_moment_direction(phi, setup.fit_bounds.jig_azimuth_tolerance_deg)
    }

    /// The held-out stretch (start, end), s.
    pub fn heldout(&self) -> (f64, f64) {
        self.stretches.heldout
    }

    /// The contract's RMSEs of `o` (full rate): the whole recording, the held-out stretch.
    pub fn rmse(&self, o: &Outputs) -> (f64, f64) {
        let mask = self.stretches.mask(&self.data.full.t_s);
        let all = vec![true; mask.len()];
        (
            contract_rmse(&self.data, o, &all),
            contract_rmse(&self.data, o, &mask),
        )
    }
}

/// The regimes of the test (found at the full rate with the load, carried onto the decimated
/// series) and the stretch held out of the fits.
struct Stretches {
    segments: Vec<Segment>,
    /// Start and end of the held-out stretch, s.
    heldout: (f64, f64),
    /// The time that parts the fitted stretch from the held-out one, s.
    boundary_s: f64,
    /// Whether the start of the recording is held out (the end fitted) rather than its end.
    start_held_out: bool,
}

impl Stretches {
    fn detect(data: &Data) -> Self {
        let segments = data.segments.clone();
        let heldout = regimes::heldout_window(&data.fit.t_s, &segments);
        Self {
            segments,
            heldout,
            boundary_s: heldout.0,
            start_held_out: false,
        }
    }

    /// Hold out the start of the recording (up to the boundary) and fit its end instead.
    fn swap(&mut self, t_s: &[f64]) {
        let t0 = t_s.first().copied().unwrap_or(self.boundary_s);
        self.start_held_out = true;
        self.heldout = (t0, self.boundary_s);
    }

    /// Whether each time of `t_s` lies in the held-out stretch.
    fn mask(&self, t_s: &[f64]) -> Vec<bool> {
        t_s.iter()
            .map(|&t| (t >= self.boundary_s) != self.start_held_out)
            .collect()
    }
}

/// Everything the fits of one recording share: the drive on the decimated series, the front end
/// of the recording's metadata, the stretches and the channels worth comparing.
fn calibration_setup<'a>(
    data: &'a Data,
    meta: &Meta,
    fingertip: &Fingertip,
    stretches: &Stretches,
    opt: &Options,
) -> Setup<'a> {
    let fit_t = &data.fit.t_s;
    let heldout_mask = stretches.mask(fit_t);
    let thermal = match (&data.fit.temp_c, &data.full.temp_c) {
        (Some(fit), Some(full)) => crate::temperature::fit(fit_t, fit, full),
        _ => None,
    };
    let (t, rod) = (fit_t.clone(), &data.fit.rod_mm);
    let (drive, fit_bounds) = match fingertip {
        Fingertip::Fe(fe) => (
            Drive::over_blocks(fe.as_ref(), t, rod, &data.full.rod_mm, &data.bounds),
            opt.fit_bounds.clone(),
        ),
        Fingertip::Simulated(units) => (
            Drive::over_blocks_of_samples(t, rod, units, &data.bounds),
            simulation::calibration_bounds(&opt.fit_bounds, data.compared(0)),
        ),
    };
    Setup {
        data,
        drive: drive.with_temperature(thermal.and(data.fit.temp_c.clone())),
        user_simulation: matches!(fingertip, Fingertip::Simulated(_)),
        readout: readout(meta, opt),
        contact_angle_deg: meta.contact_angle_deg,
        fit_mask: heldout_mask.iter().map(|h| !h).collect(),
        heldout_mask,
        used: std::array::from_fn(|c| data.compared(c)),
        discover: true,
        thermal,
        fit_bounds,
        initial: Default::default(),
    }
}

/// The front end the recording describes: the chip's sensitivities with the metadata's gains,
/// excitation and firmware smoother.
fn readout(meta: &Meta, opt: &Options) -> Readout {
    Readout {
        signal: SignalPath {
            sensitivity_per_v: opt.sensitivity_per_v,
            gain: [meta.gain_fz, meta.gain_mx, meta.gain_my],
            excitation_v: meta.excitation_v,
        },
        smoother_tau_s: meta
            .other
            .iter()
            .find(|(k, _)| k == recording::SMOOTHER_KEY)
            .and_then(|(_, v)| v.trim().parse::<f64>().ok())
            .and_then(|alpha| baseline::smoother_tau_s(alpha, meta.sample_rate_hz)),
    }
}

/// The full-rate evaluation: the contract's RMSEs and the mains line.
struct FullRate {
    /// The line in the baseline's residual (prominent or not).
    baseline_line: Option<Line>,
    /// The mains line the final model includes, if it passed both tests.
    mains: Option<Line>,
    /// The mains line on the load cell, if it passed both tests.
    load_mains: Option<Line>,
    /// Lines faster than the decimated series shows, each on its channel.
    fast: Vec<terms::FastLine>,
    /// RMSE of the baseline per compared channel.
    baseline_rmse: Numbers,
    /// RMSEs before and after, whole recording and held-out stretch.
    fit: Fit,
    /// The final model at the full rate, the lines included.
    model: Outputs,
    /// The fitting and the held-out stretch at the full rate.
    fitting: Vec<bool>,
    heldout: Vec<bool>,
}

impl FullRate {
    /// The fitting and the held-out stretch at the full rate.
    fn masks(&self) -> (&[bool], &[bool]) {
        (&self.fitting, &self.heldout)
    }

    /// The fit's `rmse_after` numbers of `model` instead.
    fn refit(&mut self, data: &Data, model: &Outputs) {
        self.fit.rmse_after = contract_rmse(data, model, &vec![true; data.full.len()]);
        self.fit.heldout.rmse_after = contract_rmse(data, model, &self.heldout);
        self.model = model.clone();
    }
}

/// The baseline and the chosen model at the full rate; the mains line searched in the chosen
/// model's residual joins it if it helps on both stretches.
fn full_rate(
    setup: &Setup,
    base_full: &Outputs,
    chosen_full: &Outputs,
    stretches: &Stretches,
    mains_allowed: bool,
) -> FullRate {
    let data = setup.data;
    let heldout = stretches.heldout;
    let full_heldout = stretches.mask(&data.full.t_s);
    let full_fit: Vec<bool> = full_heldout.iter().map(|h| !h).collect();
    // An output the baseline does not model (a user's simulation without moments) leaves the
    // recorded output itself as its residual: no line is looked for there.
    let outputs: Vec<usize> = OUTPUTS.into_iter().filter(|&c| data.modelled(c)).collect();
    let baseline_line = line_in_residual(data, base_full, &full_fit, &outputs);
    let mains = line_in_residual(data, chosen_full, &full_fit, &outputs)
        .filter(|_| mains_allowed)
        .filter(|l| mains_helps(data, chosen_full, l, (&full_fit, &full_heldout), &outputs));
    let with_mains = add_line(data, chosen_full, mains.as_ref(), &outputs);
    // The load cell picks up the mains as well: its line is looked for on its own (it need
    // not share the outputs' phase or even their presence: a test of the material alone has
    // only the rate's precondition, the mains' own).
    let load_mains = line_in_residual(data, &with_mains, &full_fit, &LOAD_CELL)
        .filter(|_| crate::preconditions::mains_visible(data.rate_hz) && setup.used[0])
        .filter(|l| mains_helps(data, &with_mains, l, (&full_fit, &full_heldout), &LOAD_CELL));
    let with_load_mains = add_line(data, &with_mains, load_mains.as_ref(), &LOAD_CELL);
    let fast = fast_lines(setup, &with_load_mains, (&full_fit, &full_heldout));
    let final_full = fast.iter().fold(with_load_mains, |o, f| {
        add_line(data, &o, Some(&f.line), &[f.channel])
    });
    let all_rows = vec![true; data.full.len()];
    let rmse = |o: &Outputs, mask: &[bool]| contract_rmse(data, o, mask);
    let baseline_rmse = Numbers(
        (0..4)
            .filter(|&c| setup.used[c])
            .map(|c| {
                let r = channel_rmse(data, base_full, c, &all_rows);
                (CHANNELS[c].to_string(), r)
            })
            .collect(),
    );
    let fit = Fit {
        rmse_before: rmse(base_full, &all_rows),
        rmse_after: rmse(&final_full, &all_rows),
        heldout: Heldout {
            t_start_s: heldout.0,
            t_end_s: heldout.1,
            rmse_before: rmse(base_full, &full_heldout),
            rmse_after: rmse(&final_full, &full_heldout),
        },
    };
    FullRate {
        baseline_line,
        mains,
        load_mains,
        fast,
        baseline_rmse,
        fit,
        model: final_full,
        fitting: full_fit,
        heldout: full_heldout,
    }
}

/// Where the baseline misses, on the decimated series.
struct Localised {
    mismatches: Vec<Mismatch>,
    channels: Vec<ChannelLocalisation>,
    /// The baseline's and the chosen model's channels on the decimated series.
    baseline: [Vec<f64>; 4],
    chosen: [Vec<f64>; 4],
    /// Whether the chosen model leaves a white residual on every compared channel.
    white_after: bool,
}

/// Localise the calibrated baseline's residual in time and channel, and test the chosen
/// model's residual for whiteness.
fn localise_residual(
    setup: &Setup,
    base: &Candidate,
    chosen: &Candidate,
    segments: &[Segment],
) -> Localised {
    let data = setup.data;
    // Both models were evaluated on the decimated series when they were scored.
    let base_dec = &base.outputs;
    let residual: [Vec<f64>; 4] =
        std::array::from_fn(|c| diff(&data.fit.y[c], base_dec.channel(c)));
    let mismatches = localise::mismatches(
        &data.fit.t_s,
        segments,
        &residual,
        &data.range,
        &setup.used,
        0.02,
    );
    let channels = channel_localisation(data, base_dec, &residual);
    let chosen_dec = &chosen.outputs;
    // Whether the chosen model leaves noise ([`white`]).
    let white_after = white(
        setup,
        &std::array::from_fn(|c| chosen_dec.channel(c).to_vec()),
    );
    Localised {
        mismatches,
        channels,
        baseline: std::array::from_fn(|c| base_dec.channel(c).to_vec()),
        chosen: std::array::from_fn(|c| chosen_dec.channel(c).to_vec()),
        white_after,
    }
}

/// Whether the model `m` (its channels on the decimated series) leaves a white residual on
/// every compared channel.
///
/// Each compared channel's residual, with the noise's own colour taken out (coloured noise is
/// not a mismatch), is structured where it fails both of two tests: a portmanteau test at a
/// family-wise LB_P over the channels (Bonferroni), and the evidence an effect needs for an
/// autoregression of it (`stats::ar_evidence`). The first alone took a model's
/// approximations at a ten-thousandth of the range, spread over many lags, for a mismatch; the
/// second alone, a lag-1 correlation that whitening with a slightly wrong slow noise leaves.
/// And it must fail them under every noise the free stretch allows (`Noise::plausible`):
/// a slow part read from a few seconds is known to a third, and whitening with its middle
/// left bins correlated by +-0.25 in both directions on coloured noise alone. A channel read
/// to a quantum coarser than its noise first has its rounding bias taken out (`quantisation`):
/// a held value keeps its own bias, which no amount of averaging removes. Isolated outlying
/// bins (a spike is one bin at 10 Hz) are not structure in time and are set aside. A residual
/// whose RMS stays below [`RESOLUTION_FLOOR`] of the channel's range (a noiseless channel the
/// model reproduces: a simulation's load cell) is white: no measurement could show it.
pub(crate) fn white(setup: &Setup, m: &[Vec<f64>; 4]) -> bool {
    let data = setup.data;
    let compared = setup.used.iter().filter(|u| **u).count().max(1);
    let bin = data.fit.count.iter().copied().max().unwrap_or(1);
    (0..4).filter(|&c| setup.used[c]).all(|c| {
        let r = data.residual_without_rounding_bias(c, &m[c]);
        let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len().max(1) as f64).sqrt();
        if rms < RESOLUTION_FLOOR * data.range[c] || (data.noiseless[c] && rms < data.noise[c].sd())
        {
            return true;
        }
        let r = localise::without_isolated_outliers(&weighted(data, c, &r), LB_P);
        !data.noise[c].plausible().iter().all(|noise| {
            let e = noise::prewhitened(&r, noise, bin, LB_LAGS);
            let significant = stats::ljung_box(&e, LB_LAGS).1 <= LB_P / compared as f64;
            significant && stats::ar_evidence(&e, LB_LAGS).0 > crate::candidate::MIN_BIC_GAIN
        })
    })
}

/// The verdict from whether any effect was found and whether the final residual is white.
/// One part in 2^24 of a channel's recorded range: a 24-bit converter's resolution, finer than
/// anything this chain records. A baseline whose residual stays below it (the baseline's own
/// recording from `tactile simulate` without noise) leaves nothing a measurement could show;
/// its whitened residual is then the arithmetic's error, structured but not physics.
const RESOLUTION_FLOOR: f64 = 1.0 / 16_777_216.0;

fn verdict(found: bool, white_after: bool) -> Verdict {
    match (found, white_after) {
        (false, true) => Verdict::NoSignificantMismatch,
        (false, false) => Verdict::Unexplained,
        (true, true) => Verdict::Explained,
        (true, false) => Verdict::PartiallyExplained,
    }
}

/// The lines in the baseline's residual prominent enough to report.
fn prominent_lines(line: Option<&Line>) -> Vec<(f64, f64, f64)> {
    line.iter()
        .filter(|l| l.prominence > mains::MIN_LINE_PROMINENCE)
        .map(|l| (l.freq_hz, l.amplitude(), l.prominence))
        .collect()
}

/// Residual re-binned to the coarse block length (fine blocks summed in groups), each bin the
/// sum over its samples divided by the noise model's deviation of such a sum: whiteness is
/// judged on the time scales the models describe, and noise coloured on the scale of a few
/// samples (smoother, anti-alias filter) does not count as structure. Normalised by the whole
/// bin's noise, not block by block: under slow noise, fine blocks' weights would make a bin in
/// a move several times as variable as one at rest, and a whiteness test over bins of unequal
/// variance rejects too often.
fn weighted(data: &Data, c: usize, r: &[f64]) -> Vec<f64> {
    let target = data.fit.count.iter().copied().max().unwrap_or(1);
    let mut out = Vec::new();
    let (mut sum, mut count) = (0.0, 0usize);
    for (v, &n) in r.iter().zip(&data.fit.count) {
        sum += v * n as f64;
        count += n;
        if count >= target {
            out.push(sum / data.noise[c].sum_covariance(count, 0).sqrt());
            (sum, count) = (0.0, 0);
        }
    }
    out
}

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// The outputs' channels, where the mains line was first looked for, and the load cell's.
const OUTPUTS: [usize; 3] = [1, 2, 3];
const LOAD_CELL: [usize; 1] = [0];

fn line_in_residual(data: &Data, o: &Outputs, mask: &[bool], chans: &[usize]) -> Option<Line> {
    if chans.is_empty() {
        return None;
    }
    let res: Vec<Vec<f64>> = chans
        .iter()
        .map(|&c| diff(&data.full.y[c], o.channel(c)))
        .collect();
    let refs: Vec<&[f64]> = res.iter().map(|r| r.as_slice()).collect();
    mains::find_line(&data.full.t_s, &refs, mask, data.rate_hz)
}

/// Outputs plus the fitted line on the channels `chans` it was fitted on (full rate).
fn add_line(data: &Data, o: &Outputs, line: Option<&Line>, chans: &[usize]) -> Outputs {
    let mut out = o.clone();
    if let Some(l) = line {
        let harmonic = l.coef[0][2] != 0.0 || l.coef[0][3] != 0.0;
        for (b, &c) in chans.iter().enumerate() {
            let values = if c == 0 {
                &mut out.load_n
            } else {
                &mut out.volts[c - 1]
            };
            for (v, &t) in values.iter_mut().zip(&data.full.t_s) {
                *v += l.at(b, t, harmonic);
            }
        }
    }
    out
}

/// The line counts if it is prominent and removing it helps on the fitting stretch and on the
/// held-out stretch, both in noise units.
fn mains_helps(
    data: &Data,
    o: &Outputs,
    line: &Line,
    masks: (&[bool], &[bool]),
    chans: &[usize],
) -> bool {
    line_evidence(data, o, line, masks, chans).is_some()
}

/// The line's BIC gain and held-out chi-square ratio against the model without it, where it
/// is prominent and passes both tests.
fn line_evidence(
    data: &Data,
    o: &Outputs,
    line: &Line,
    (fit, heldout): (&[bool], &[bool]),
    chans: &[usize],
) -> Option<(f64, f64)> {
    if line.prominence < mains::MIN_LINE_PROMINENCE {
        return None;
    }
    let with = add_line(data, o, Some(line), chans);
    let chi2 = |m: &Outputs, mask: &[bool]| -> f64 {
        chans
            .iter()
            .map(|&c| {
                let w = 1.0 / data.noise[c].sd();
                (0..data.full.len())
                    .filter(|&k| mask[k])
                    .map(|k| ((data.full.y[c][k] - m.channel(c)[k]) * w).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let (f0, f1) = (chi2(o, fit), chi2(&with, fit));
    let (h0, h1) = (chi2(o, heldout), chi2(&with, heldout));
    // The two models differ by the line itself: its norm on the held-out stretch.
    let diff = chans
        .iter()
        .map(|&c| {
            let w = 1.0 / data.noise[c].sd();
            (0..data.full.len())
                .filter(|&k| heldout[k])
                .map(|k| ((with.channel(c)[k] - o.channel(c)[k]) * w).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        .sqrt();
    let n = fit.iter().filter(|&&b| b).count() as f64;
    // The frequency, and per channel sine and cosine at f and 3f.
    let k = 1.0 + 4.0 * chans.len() as f64;
    let bic_gain = n * (f0 / f1).ln() - k * n.ln();
    (bic_gain > MIN_BIC_GAIN && h0 - h1 > heldout_needed(diff, h0))
        .then(|| (bic_gain, h0 / h1.max(1e-300)))
}

/// Lines faster than the decimated series shows ([`terms::line::MAX_FREQ_HZ`]), outside the
/// mains band, searched channel by channel in the residual of `o`: each with its channel and
/// evidence, where it passes both tests.
fn fast_lines(setup: &Setup, o: &Outputs, masks: (&[bool], &[bool])) -> Vec<terms::FastLine> {
    let data = setup.data;
    (0..4)
        .filter(|&c| setup.used[c])
        .filter_map(|c| {
            let r = diff(&data.full.y[c], o.channel(c));
            let line = mains::find_fast_line(
                &data.full.t_s,
                &[&r],
                masks.0,
                data.rate_hz,
                terms::line::MAX_FREQ_HZ,
            )?;
            let (bic_gain, ratio) = line_evidence(data, o, &line, masks, &[c])?;
            Some(terms::FastLine {
                channel: c,
                line,
                bic_gain,
                heldout_ratio: ratio,
            })
        })
        .collect()
}

fn channel_localisation(
    data: &Data,
    base: &Outputs,
    residual: &[Vec<f64>; 4],
) -> Vec<ChannelLocalisation> {
    let d = &data.fit;
    let load = &d.y[0];
    let load2: Vec<f64> = load.iter().map(|v| v * v).collect();
    let dload: Vec<f64> = (0..d.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(d.len() - 1));
            if d.t_s[b] > d.t_s[a] {
                (load[b] - load[a]) / (d.t_s[b] - d.t_s[a])
            } else {
                0.0
            }
        })
        .collect();
    (0..4)
        .filter(|&c| data.compared(c))
        .map(|c| {
            let r = &residual[c];
            let (q, p) = stats::ljung_box(&weighted(data, c, r), LB_LAGS);
            ChannelLocalisation {
                channel: CHANNELS[c],
                ljung_box_q: q,
                ljung_box_p: p,
                white: p > LB_P,
                corr_load: stats::pearson(r, load),
                corr_load_squared: stats::pearson(r, &load2),
                corr_dload_dt: stats::pearson(r, &dload),
                corr_temperature: d.temp_c.as_ref().map(|t| stats::pearson(r, t)),
                corr_other_residuals: (0..4)
                    .filter(|&o| o != c)
                    .map(|o| (CHANNELS[o].to_string(), stats::pearson(r, &residual[o])))
                    .collect(),
                lag_estimate_s: localise::lag_estimate(&d.t_s, base.channel(c), r),
            }
        })
        .collect()
}

fn baseline_params(base: &Candidate) -> Numbers {
    let mut n = Numbers::default();
    for (name, value) in params::baseline_values(base) {
        n.push(name, value);
    }
    n
}
