//! The diagnosis of one recording: the steps in the order they run, and nothing else. Each
//! step is a module of its own (`crate::steps`, `crate::select`) with one entry point; the
//! recording's data walks them in order, into each once and out again. With
//! `TACTILE_TRACE_STEPS=1` each step prints its name and what it found on standard error.
//!
//! One pass ([`diagnose_prepared`]): set up the calibration of the baseline (`calibration`,
//! `Prepared::setups`) -> read what the protocol allows (`steps::protocol`) -> fit the
//! catalogue's candidates and select (`select`) -> describe what the chosen model leaves
//! (`steps::described`) -> localise the baseline's residual and test the chosen model's
//! (`steps::residual`) -> evaluate at the full rate with its lines (`steps::full_rate`) -> the
//! effects (`steps::effects`) -> the verdict (`steps::verdict`) -> what is left undecided
//! (`steps::undecided`) -> the diagnosis (`steps::assemble`). Around it ([`diagnose`]): read
//! the recording (`prepared`) -> the other stretch held out (`steps::swap`) -> refits without a
//! frozen channel (`steps::freeze`) -> the discovery step's joint fit and gate
//! (`steps::discovery`).
use std::time::Instant;

use recording::Recording;

use crate::data::DataError;
use crate::options::{BaselineSource, Options};
use crate::outcome::Diagnosis;
use crate::prepared::{prepare, Prepared};
use crate::select::select;
use crate::steps::{self, trace, Pass};

/// Diagnose `rec`; `name` is what OUT.json calls the recording.
///
/// The catalogue and the library are fitted to the start of the recording and tested on its
/// end; where that leaves the end unexplained, the end is fitted and the start held out
/// (`steps::swap`). A channel found frozen is fitted again without what it read after it froze
/// (`steps::freeze`), the catalogue again without what the discovery step found, and the
/// discovery step dropped where the held-out stretch does not support it (`steps::discovery`).
pub fn diagnose(rec: &Recording, name: &str, opt: &Options) -> Result<Diagnosis, DataError> {
    let started = Instant::now();
    diagnose_from(prepare(rec, name, opt)?, name, opt, started)
}

/// [`diagnose`], with the recording dropped once it is prepared: the diagnosis reads its own
/// copy of the columns, and a caller that has no further use for the recording (`tactile
/// diagnose` of one file, a session's files) need not hold both. An hour at 1 kHz is 210 MB of
/// columns.
pub fn diagnose_owned(rec: Recording, name: &str, opt: &Options) -> Result<Diagnosis, DataError> {
    let started = Instant::now();
    let prepared = prepare(&rec, name, opt)?;
    drop(rec);
    diagnose_from(prepared, name, opt, started)
}

/// [`diagnose`], and `rec` as read, ready to fit (before the diagnosis's own refits moved its
/// stretches or freeze): a session's member is read once.
pub(crate) fn diagnose_kept(
    rec: &Recording,
    name: &str,
    opt: &Options,
) -> Result<(Diagnosis, Prepared), DataError> {
    let started = Instant::now();
    let prepared = prepare(rec, name, opt)?;
    let d = diagnose_from(prepared.clone(), name, opt, started)?;
    Ok((d, prepared))
}

/// The steps over `prepared`, begun at `started`, with the refits around them. A user's
/// simulation whose calibration had to absorb an implausible factor is refused
/// (`crate::scale_check`), unless the user accepted the factor.
fn diagnose_from(
    mut prepared: Prepared,
    name: &str,
    opt: &Options,
    started: Instant,
) -> Result<Diagnosis, DataError> {
    let once = |p: &Prepared| diagnose_prepared(p, name, opt);
    let first = once(&prepared);
    let (d, frozen) = steps::swap::run(&mut prepared, first, &once);
    trace("swap", || {
        format!("held out the start: {}", prepared.stretches.start_held_out)
    });
    let d = steps::freeze::refitted(&mut prepared, d, frozen, &once);
    trace("freeze", || {
        format!("fitted without frozen channels {:?}", prepared.frozen)
    });
    let d = steps::discovery::with_discovery_refitted(&mut prepared, d, &once);
    let mut d = steps::discovery::without_unsupported_discovery(&mut prepared, d, &once);
    trace("discovery", || {
        format!("discovery step dropped: {}", prepared.without_discovery)
    });
    d.report.seconds = started.elapsed().as_secs_f64();
    let judged = matches!(&opt.baseline, BaselineSource::Simulation(s) if !s.accepts_scale());
    crate::scale_check::check(&d.report, &prepared.meta, judged)?;
    Ok(d)
}

/// One pass of the steps over `prepared` with its stretches as they are: the diagnosis, and
/// the channels it found frozen with the time each froze.
fn diagnose_prepared(prepared: &Prepared, name: &str, opt: &Options) -> Pass {
    let fitted = prepared.fitted_data();
    let setups = prepared.setups(fitted.as_ref(), opt);
    let setup = &setups.whole;
    trace("calibration", || {
        format!(
            "channels compared {:?}, fitted on other data: {}",
            setup.used,
            fitted.is_some()
        )
    });
    let protocol = steps::protocol::run(prepared, setup);
    trace("protocol", || format!("forbidden {:?}", protocol.forbidden));
    let mut sel = select(
        setups.for_selection(),
        protocol.features,
        opt.progress.as_deref(),
    );
    trace("select", || format!("chose {:?}", sel.chosen().kinds));
    let drive = prepared.full_drive(setup);
    let mut model = steps::described::run(setup, &mut sel, &drive, &protocol.forbidden);
    trace("described", || {
        format!(
            "chose {:?}, {} terms",
            sel.chosen().kinds,
            model.described.found.terms.len()
        )
    });
    let (base, chosen) = (sel.base(), sel.chosen());
    let segments = &prepared.stretches.segments;
    let local = steps::residual::run(setup, (base, chosen), segments, &model.described);
    trace("residual", || format!("white after: {}", local.white_after));
    let (stretches, mains_allowed) = (&prepared.stretches, protocol.mains_allowed);
    let mut full = steps::full_rate::run(
        setup,
        (base, &drive),
        &model.chosen_full,
        stretches,
        mains_allowed,
    );
    trace("full_rate", || format!("{:?}", full.fit));
    let described = std::mem::take(&mut model.described.effects);
    let parts = std::mem::take(&mut model.described.parts);
    let found = steps::effects::run(&sel, &full, (described, parts), &drive);
    trace("effects", || format!("{} effects found", found.len()));
    let data = &prepared.data;
    let (effects, verdict, demoted) =
        steps::certified::run(data, &mut full, found, local.white_after);
    trace("certified", || {
        format!(
            "{} reported, {} undecided, {verdict:?}",
            effects.len(),
            demoted.len()
        )
    });
    let open = (prepared.stretches.heldout, protocol.moment_phi);
    let undecided = steps::undecided::run(setup, &sel, (&effects, demoted), verdict, open);
    trace("undecided", || format!("{} undecided", undecided.len()));
    let frozen = steps::freeze::frozen_channels(&model.described.found.terms);
    let found = steps::assemble::Found {
        sel: &sel,
        model,
        local,
        full,
        effects,
        verdict,
        undecided,
    };
    (
        steps::assemble::run(prepared, name, setup.used, found),
        frozen,
    )
}
