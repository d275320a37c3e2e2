//! What the recording's protocol shows (`crate::preconditions`), read once the calibration is
//! set up: which catalogue effects may be fitted, which may not stand at another stage, and
//! whether a mains line may be looked for.
use sim::effects::EffectKind;

use crate::fit::Setup;
use crate::preconditions::{moment_direction, Features};
use crate::prepared::Prepared;
use crate::terms;

/// The protocol's findings a diagnosis carries through its steps.
pub(crate) struct Protocol {
    /// What the recording shows, for the selection's preconditions.
    pub features: Features,
    /// The baseline's moment direction: whether the moment scales can turn it (a precondition
    /// of crosstalk) and, after the search, what a turn they made would mean.
    pub moment_phi: Option<f64>,
    /// Whether the mains line is a candidate at all.
    pub mains_allowed: bool,
    /// The catalogue effects the protocol forbids, which no term may meet at another stage.
    pub forbidden: Vec<EffectKind>,
}

/// The protocol of `prepared` under its calibration `setup`.
pub(crate) fn run(prepared: &Prepared, setup: &Setup) -> Protocol {
    let moment_phi = moment_direction(&setup.drive);
    let features = Features::of(
        &prepared.data,
        &prepared.stretches.segments,
        setup.used,
        setup.thermal.is_some(),
    )
    .with_moment_direction(moment_phi, setup.fit_bounds.jig_azimuth_tolerance_deg);
    let mains_allowed = features.allows(EffectKind::MainsInterference).is_ok();
    let forbidden: Vec<EffectKind> = terms::TermKind::ALL
        .iter()
        .filter_map(|k| k.catalogue_kind())
        .filter(|&k| features.protocol_allows(k).is_err())
        .collect();
    Protocol {
        features,
        moment_phi,
        mains_allowed,
        forbidden,
    }
}
