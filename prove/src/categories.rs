//! The proof's categories: what a user varies, each scored on its own (`tactile prove
//! --categories`). The standard proof draws one protocol from one model; these recordings keep
//! the catalogue's effects but change what the diagnosis must survive:
//!
//! - **protocols**: staircases of ramps and holds, triangles without holds, rod speeds a decade
//!   apart, long holds (released or not), a start already in contact, 20 Hz to 2 kHz;
//! - **independent baseline**: the fingertip of another model of the same test (a power-law
//!   contact, outputs linear in the load or following the FE's load-to-output map), within the
//!   calibration's bounds ([`OtherFingertip`]);
//! - **three effects** at once;
//! - **nuisances** that are not missing physics and must not be named: wrong gains in the
//!   metadata, a load-cell offset, coarse quantisation, isolated spikes, missing rows, coloured
//!   noise, a temperature column the outputs ignore ([`nuisances::Nuisance`]);
//! - the **real Mach-1 tests**, with the physics each must show: [`super::real`];
//! - **described physics**: physics the catalogue lacks, and catalogue entries at another
//!   stage, scored on stage, channels and dependence or name ([`described`]);
//! - **unnamed physics**: kinds no catalogue, library, issue, contract or doc names, written
//!   blind to the diagnosis and scored per kind on stage, channels and dependence
//!   ([`unnamed`]).

pub mod described;
mod family;
mod nuisances;
mod protocols;
pub mod unnamed;

use std::fmt::Write as _;

use sim::effects::EffectKind;

pub use family::OtherFingertip;
pub use nuisances::Nuisance;
pub use protocols::TestShape;

use crate::{Case, CaseSpec, Plan, Score, Summary};
use baseline::fe_response::FeResponseError;
use recording::Recording;

/// A group of recordings scored together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    Protocols,
    IndependentBaseline,
    ThreeEffects,
    Nuisances,
    /// Scored on their own terms ([`described::table`]), not in [`table`].
    Described(described::Group),
    /// Scored per kind ([`unnamed::table`]), not in [`table`].
    Unnamed,
}

impl Category {
    pub const ALL: [Category; 4] = [
        Category::Protocols,
        Category::IndependentBaseline,
        Category::ThreeEffects,
        Category::Nuisances,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::Protocols => "protocols",
            Category::IndependentBaseline => "independent baseline",
            Category::ThreeEffects => "three effects",
            Category::Nuisances => "nuisances",
            Category::Described(g) => g.name(),
            Category::Unnamed => "unnamed physics",
        }
    }
}

/// A generated recording's category and a short label of what was varied.
#[derive(Debug, Clone)]
pub struct Labelled {
    pub category: Category,
    pub label: String,
    /// What a described recording hides ([`Category::Described`]).
    pub truth: Option<described::Truth>,
    /// What a recording of unnamed physics hides ([`Category::Unnamed`]).
    pub unnamed: Option<unnamed::Truth>,
}

use EffectKind::*;

/// Effect sets every protocol is tried with: none, and the time-domain effects a protocol
/// changes the look of. Hysteresis is added where the protocol unloads slowly.
const PROTOCOL_TRUTHS: [&[EffectKind]; 4] = [
    &[],
    &[ViscoelasticRelaxation],
    &[HighpassCoupling],
    &[ThermalDrift],
];

/// Effects of the independent-baseline category: every effect that is not a static shape (a
/// static-shape effect is what another model's shape looks like, within the calibration's
/// bounds it must not be named; beyond them it is a finding, tested in the standard proof).
const INDEPENDENT_TRUTHS: [&[EffectKind]; 11] = [
    &[],
    &[],
    &[],
    &[ViscoelasticRelaxation],
    &[HighpassCoupling],
    &[ThermalDrift],
    &[Hysteresis],
    &[Crosstalk],
    &[MainsInterference],
    &[TimeOffset],
    &[ViscoelasticRelaxation, HighpassCoupling],
];

/// Three effects at once, each pair of signatures distinct (a loop, a decay, a drift, a line).
const TRIPLES: [[EffectKind; 3]; 8] = [
    [ViscoelasticRelaxation, HighpassCoupling, ThermalDrift],
    [ViscoelasticRelaxation, Hysteresis, MainsInterference],
    [HighpassCoupling, Crosstalk, ThermalDrift],
    [ViscoelasticRelaxation, TimeOffset, MainsInterference],
    [Hysteresis, ThermalDrift, Crosstalk],
    [ViscoelasticRelaxation, HighpassCoupling, MainsInterference],
    [ContactFriction, ViscoelasticRelaxation, ThermalDrift],
    [Stiffening, ViscoelasticRelaxation, ThermalDrift],
];

/// Effect sets each nuisance is tried with.
const NUISANCE_TRUTHS: [&[EffectKind]; 3] = [&[], &[], &[ViscoelasticRelaxation]];

impl Plan {
    /// Every category's recordings (in parallel, each from its own seed), with their labels;
    /// the described physics apart ([`Plan::generate_described`]).
    pub fn generate_categories(&self) -> Result<(Vec<Labelled>, Vec<Case>), FeResponseError> {
        self.generate_from(category_specs(), 1000)
    }

    /// The described physics' recordings: out of the catalogue, and the catalogue at new stages.
    pub fn generate_described(&self) -> Result<(Vec<Labelled>, Vec<Case>), FeResponseError> {
        let specs = described::specs()
            .into_iter()
            .map(|(label, spec)| {
                let group = spec
                    .injection
                    .map_or(described::Group::OutOfCatalogue, |i| i.physics.group());
                (Category::Described(group), label, spec)
            })
            .collect();
        self.generate_from(specs, 2000)
    }

    /// The recordings of physics nobody named, and the null recordings beside them.
    pub fn generate_unnamed(&self) -> Result<(Vec<Labelled>, Vec<Case>), FeResponseError> {
        let specs = unnamed::specs()
            .into_iter()
            .map(|(label, spec)| (Category::Unnamed, label, spec))
            .collect();
        self.generate_from(specs, 3000)
    }

    fn generate_from(
        &self,
        specs: Vec<(Category, String, CaseSpec)>,
        first_id: usize,
    ) -> Result<(Vec<Labelled>, Vec<Case>), FeResponseError> {
        use rayon::prelude::*;
        specs
            .into_par_iter()
            .enumerate()
            .map(|(id, (category, label, spec))| {
                let case = self.build(id + first_id, &spec)?;
                let truth = case.described.clone();
                let unnamed = case.unnamed.clone();
                Ok((
                    Labelled {
                        category,
                        label,
                        truth,
                        unnamed,
                    },
                    case,
                ))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(|v| v.into_iter().unzip())
    }
}

/// What each category's recordings hide and vary, in a fixed order.
fn category_specs() -> Vec<(Category, String, CaseSpec)> {
    let mut out = Vec::new();
    for protocol in TestShape::ALL {
        let mut truths: Vec<&[EffectKind]> = PROTOCOL_TRUTHS.to_vec();
        if protocol.unloads_slowly() {
            truths.push(&[Hysteresis]);
        }
        for kinds in truths {
            let spec = CaseSpec {
                protocol,
                ..CaseSpec::new(kinds)
            };
            out.push((Category::Protocols, protocol.name().to_string(), spec));
        }
    }
    for (i, kinds) in INDEPENDENT_TRUTHS.iter().enumerate() {
        let spec = CaseSpec {
            other_family: Some(i % 2 == 0),
            ..CaseSpec::new(kinds)
        };
        let label = if i % 2 == 0 {
            "linear outputs"
        } else {
            "FE load map"
        };
        out.push((Category::IndependentBaseline, label.to_string(), spec));
    }
    for (i, kinds) in TRIPLES.iter().chain(TRIPLES.iter()).enumerate() {
        let label = if i < TRIPLES.len() { "set 1" } else { "set 2" };
        out.push((
            Category::ThreeEffects,
            label.to_string(),
            CaseSpec::new(kinds),
        ));
    }
    for nuisance in Nuisance::ALL {
        for kinds in NUISANCE_TRUTHS {
            let spec = CaseSpec {
                nuisance: Some(nuisance),
                ..CaseSpec::new(kinds)
            };
            out.push((Category::Nuisances, nuisance.name().to_string(), spec));
        }
    }
    out
}

/// One row per category: the acceptance figures of its recordings.
pub fn table(labelled: &[Labelled], scores: &[Score]) -> String {
    let mut out = String::from(
        "| category | recordings | effect set right | false alarms | effect-free not `no_significant_mismatch` | held-out after/before (with an effect) | passes |\n|---|---|---|---|---|---|---|\n",
    );
    for (category, s) in summaries(labelled, scores) {
        let _ = writeln!(
            out,
            "| {} | {} | {:.0} % | {} of {} | {} of {} | {:.3} | {} |",
            category.name(),
            s.cases,
            100.0 * s.correct_share,
            s.false_alarms,
            s.no_effect_cases,
            s.not_quiet,
            s.no_effect_cases,
            s.heldout_ratio_mean,
            if category_passes(&s) { "yes" } else { "no" },
        );
    }
    out
}

/// Every category passes [`category_passes`] (a described term on an effect-free recording
/// counts among its false alarms).
pub fn all_pass(labelled: &[Labelled], scores: &[Score]) -> bool {
    summaries(labelled, scores)
        .iter()
        .all(|(_, s)| category_passes(s))
}

/// The effect-free recordings of the categories of [`table`] that got a described term
/// (`"catalogue": false`), in one line: a description must not be a new false alarm.
pub fn described_on_effect_free(labelled: &[Labelled], scores: &[Score]) -> String {
    let free: Vec<&Score> = labelled
        .iter()
        .zip(scores)
        .filter(|(l, s)| Category::ALL.contains(&l.category) && s.effect_free())
        .map(|(_, s)| s)
        .collect();
    let with: Vec<String> = free
        .iter()
        .filter(|s| !s.described().is_empty())
        .map(|s| format!("{:02} ({})", s.id, s.described().join(", ")))
        .collect();
    format!(
        "Effect-free recordings with a described term (`\"catalogue\": false`, counted among the false alarms): {} of {}{}{}.\n",
        with.len(),
        free.len(),
        if with.is_empty() { "" } else { ": " },
        with.join(", ")
    )
}

/// The acceptance figures of each category's recordings.
fn summaries(labelled: &[Labelled], scores: &[Score]) -> Vec<(Category, Summary)> {
    Category::ALL
        .iter()
        .map(|&category| {
            let of: Vec<Score> = labelled
                .iter()
                .zip(scores)
                .filter(|(l, _)| l.category == category)
                .map(|(_, s)| s.clone())
                .collect();
            (category, Summary::of(&of))
        })
        .collect()
}

/// The bar for a category: 90 % of effect sets right, no false alarm and the verdict
/// `no_significant_mismatch` on every effect-free recording, held-out misfit at least halved on
/// average where an effect is present.
pub fn category_passes(s: &Summary) -> bool {
    s.correct_share >= 0.9 && s.false_alarms == 0 && s.not_quiet == 0 && s.heldout_ratio_mean <= 0.5
}

/// Every recording with its case number (`prove-NN.csv` with `--write-recordings`), category,
/// label, truth, what was found ("?": undecided against a calibration) and, for an effect-free
/// recording, whether its verdict was `no_significant_mismatch`.
pub fn details(labelled: &[Labelled], scores: &[Score]) -> String {
    let mut out = String::from(
        "| case | category | varied | hidden | found | right | effect-free, `no_significant_mismatch` |\n|---|---|---|---|---|---|---|\n",
    );
    for (l, s) in labelled.iter().zip(scores) {
        let _ = writeln!(
            out,
            "| {:02} | {} | {} | {} | {} | {} | {} |",
            s.id,
            l.category.name(),
            l.label,
            s.truth
                .iter()
                .cloned()
                .chain(
                    s.unseen
                        .iter()
                        .map(|e| format!("({e}, unseen at this rate)"))
                )
                .collect::<Vec<_>>()
                .join(" + "),
            s.answer(" + "),
            if s.correct { "yes" } else { "**no**" },
            match (s.effect_free(), s.quiet) {
                (false, _) => "",
                (true, true) => "yes",
                (true, false) => "**no**",
            },
        );
    }
    out
}

/// The recorded channel called `column` (`load_N` or an output), mutable: where the groups'
/// generators put their physics in.
pub(crate) fn column_mut<'a>(rec: &'a mut Recording, column: &str) -> &'a mut Vec<f64> {
    let c = &mut rec.channels;
    match column {
        "load_N" => &mut c.load_n,
        "fz_V" => &mut c.fz_v,
        "mx_V" => &mut c.mx_v,
        _ => &mut c.my_v,
    }
}

/// The same column, read-only.
pub(crate) fn column<'a>(rec: &'a Recording, column: &str) -> &'a [f64] {
    let c = &rec.channels;
    match column {
        "load_N" => &c.load_n,
        "fz_V" => &c.fz_v,
        "mx_V" => &c.mx_v,
        _ => &c.my_v,
    }
}
