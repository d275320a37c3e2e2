//! Physics the catalogue lacks, described (`docs/diagnosis-format.md`, "Where the physics
//! acts"): when the chosen model's residual stays structured, a small library of terms, each a
//! function of recorded quantities (time, rod travel and speed, load and load rate,
//! temperature) located at a stage, is searched with the same forward–backward search and the
//! same two tests as the catalogue's effects: the BIC against the model without the term, and
//! the held-out stretch that no parameter saw ([`crate::candidate::heldout_needed`]).
//!
//! Every term adds to one channel's model a part linear in its amplitudes once its shape (a
//! time, a frequency, a time constant, a power) is chosen: contribution = fixed + X beta, with
//! beta by weighted least squares on the fitting stretch and the shape from a grid (each grid
//! dimension counted as a parameter in the BIC). The terms act on the chosen model's residual:
//! the catalogue's calibration stays as it was fitted, so a term can only be named for what the
//! calibrated model with its catalogue effects could not take up.
//!
//! Why each term is in the library, in its own file with its equation:
//! [`offset_step`] (a connector knock, a zero jump), [`stuck_channel`] (a channel that freezes),
//! [`line`] (a line at any frequency: a frame's vibration, a slow wander, mains on the load
//! cell), [`temperature_span`] (a span that follows the temperature), [`speed_power`] (a force
//! or output depending on a power of the rod speed), [`permanent_set`] (a set after the first
//! loading), [`output_relaxation`] (the sensing element creeps where the load does not),
//! [`output_set`] (the sensing element takes a set under load and recovers more slowly),
//! [`load_lag`] (the load cell's stream shifted in time), [`load_stiffening`] (the material
//! stiffening against the rod, on the load cell), [`load_saturation`] (the load cell's
//! amplifier clipping), [`material_recovery`] (a load that recovers with time: a tendon or a
//! hydrogel drying under the rod). Of these, [`output_relaxation`], [`load_lag`], [`load_stiffening`]
//! and [`load_saturation`] are catalogue entries met at a stage of their own. The
//! calibration's own checks, an inverted sign and a dead channel, are in [`sanity`].

pub(crate) mod discover;
mod fitting;
pub(crate) mod line;
pub(crate) mod load_lag;
pub(crate) mod load_saturation;
pub(crate) mod load_stiffening;
pub(crate) mod material_recovery;
pub(crate) mod offset_step;
pub(crate) mod output_relaxation;
pub(crate) mod output_set;
pub(crate) mod permanent_set;
pub(crate) mod report;
pub(crate) mod sanity;
mod score;
mod search;
pub(crate) mod speed_power;
pub(crate) mod stuck_channel;
pub(crate) mod temperature_span;
#[cfg(test)]
mod tests;
mod uncertainty;

pub(crate) use fitting::Context;
pub(crate) use score::Nested;
pub(crate) use search::{search, Found};

use crate::output::{EffectReport, ParamDetail};
use baseline::Outputs;
use sim::effects::Stage;

/// A line faster than the decimated series shows, found at the full rate on one channel
/// (`crate::mains::find_fast_line`), with its evidence against the model without it.
pub(crate) struct FastLine {
    pub channel: usize,
    pub line: crate::mains::Line,
    pub bic_gain: f64,
    pub heldout_ratio: f64,
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

/// What was described beyond the catalogue: the effects to report and the terms' contributions
/// to the model, on the decimated series and at the full rate.
pub(crate) struct Described {
    pub found: Found,
    pub effects: Vec<EffectReport>,
    /// Each of `effects`' part of the model at the full rate (`crate::certify`); `None` for a
    /// finding of the calibration's sanity, which is no term of the model.
    pub parts: Vec<Option<[Vec<f64>; 4]>>,
    decimated: [Vec<f64>; 4],
    full: [Vec<f64>; 4],
    /// The terms that are catalogue effects at a stage other than the catalogue's
    /// ([`TermKind::catalogue_kind`]), if any.
    pub at_stage: Option<AtStage>,
    /// The discovered terms ([`discover`]), if any.
    pub discovered: Option<AtStage>,
    /// Each discovered effect on its first channel, for the report's figure of it against
    /// what it depends on.
    pub curves: Vec<TermCurve>,
}

/// The contributions of the terms that are catalogue effects at a stage other than the
/// catalogue's (a sensing element's relaxation; the load cell's lag, stiffening or clip), on
/// the decimated series and at the full rate. A session searches each catalogue effect at its
/// own stage only, so it holds these as the recording's own diagnosis found them
/// ([`crate::prepared::Prepared::for_session`]).
#[derive(Debug, Clone)]
pub struct AtStage {
    pub decimated: [Vec<f64>; 4],
    pub full: [Vec<f64>; 4],
}

impl AtStage {
    /// Both parts together, where either is.
    fn sum(a: Option<AtStage>, b: Option<AtStage>) -> Option<AtStage> {
        match (a, b) {
            (Some(mut a), Some(b)) => {
                for c in 0..4 {
                    a.decimated[c]
                        .iter_mut()
                        .zip(&b.decimated[c])
                        .for_each(|(x, y)| *x += y);
                    a.full[c]
                        .iter_mut()
                        .zip(&b.full[c])
                        .for_each(|(x, y)| *x += y);
                }
                Some(a)
            }
            (a, b) => a.or(b),
        }
    }

    /// `data` less these parts (per channel, on the decimated series and at the full rate):
    /// what the recording shows without a term found in it, for a calibration that must not
    /// bend towards that term. Its noise, weights and regimes stay the recording's.
    pub(crate) fn taken_from(&self, data: &crate::data::Data) -> crate::data::Data {
        let mut d = data.clone();
        for c in 0..4 {
            let less = |y: &mut Vec<f64>, p: &[f64]| {
                y.iter_mut().zip(p).for_each(|(y, p)| *y -= p);
            };
            less(&mut d.fit.y[c], &self.decimated[c]);
            less(&mut d.full.y[c], &self.full[c]);
        }
        d
    }
}

impl Described {
    /// The calibration's sanity findings, and with `structured` (the chosen model's residual is
    /// not noise) the library's terms that pass both tests.
    pub fn new(ctx: &Context, nested: Nested, details: &[ParamDetail], structured: bool) -> Self {
        let found = if structured {
            search(ctx, nested)
        } else {
            Found::default()
        };
        // A channel found frozen was calibrated on what it read after it froze: its sign says
        // nothing of the wiring (a frozen My had read as inverted).
        let frozen = |f: &sanity::SanityFinding| {
            found
                .terms
                .iter()
                .any(|t| t.kind == TermKind::StuckChannel && f.channels.contains(&t.channel))
        };
        let inverted = sanity::inverted_signs(ctx, details, nested.n);
        let mut effects: Vec<EffectReport> = inverted
            .iter()
            .filter(|f| !frozen(f))
            .chain(&sanity::dead_channels(ctx, nested.n))
            .map(report::sanity_effect)
            .collect();
        let mut effect_parts: Vec<Option<[Vec<f64>; 4]>> = vec![None; effects.len()];
        for (mut e, group) in report::effects(&found) {
            uncertainty::fill_stderr(ctx, &found.terms, group[0], &mut e);
            effect_parts.push(Some(uncertainty::part(ctx, &found.terms, &group)));
            effects.push(e);
        }
        let full_t = &ctx.data.full.t_s;
        let decimated: [Vec<f64>; 4] =
            std::array::from_fn(|c| score::contribution(ctx, &found.terms, c));
        let full: [Vec<f64>; 4] = std::array::from_fn(|c| at_full(ctx, &found.terms, c, full_t));
        let parts = |terms: &[Term]| {
            (!terms.is_empty()).then(|| AtStage {
                decimated: std::array::from_fn(|c| score::contribution(ctx, terms, c)),
                full: std::array::from_fn(|c| at_full(ctx, terms, c, full_t)),
            })
        };
        let of_kind = |kind: fn(&Term) -> bool| -> Vec<Term> {
            found.terms.iter().filter(|t| kind(t)).cloned().collect()
        };
        let own = parts(&of_kind(|t| t.kind == TermKind::Discovered));
        // Held as found in a session: a catalogue effect at another stage than the catalogue's,
        // and a discovered term, which no session searches (sharing a catalogue effect in its
        // place would make up for one recording's own physics).
        let at_stage = AtStage::sum(
            parts(&of_kind(|t| t.kind.catalogue_kind().is_some())),
            own.clone(),
        );
        // A discovered term beyond what the channel's calibration could take up: the catalogue
        // refitted without it keeps its own share of the calibration.
        let discovered = own.map(|p| discover::beyond_calibration(ctx, p));
        let curves = discovered_curves(ctx, &found.terms);
        Self {
            found,
            effects,
            parts: effect_parts,
            decimated,
            full,
            at_stage,
            discovered,
            curves,
        }
    }

    /// The model `m` at the full rate with the terms.
    pub fn add_full(&self, m: &Outputs, _t_s: &[f64]) -> Outputs {
        let mut out = m.clone();
        add(&mut out.load_n, &self.full[0]);
        for c in 1..4 {
            add(&mut out.volts[c - 1], &self.full[c]);
        }
        out
    }

    /// The model's channels `m` on the decimated series with the terms.
    pub fn add_decimated(&self, m: &[Vec<f64>; 4]) -> [Vec<f64>; 4] {
        std::array::from_fn(|c| {
            let mut v = m[c].clone();
            add(&mut v, &self.decimated[c]);
            v
        })
    }
}

/// Each discovered effect's contribution on its first channel (decimated), named as it is
/// reported.
fn discovered_curves(ctx: &Context, terms: &[Term]) -> Vec<TermCurve> {
    let mut groups: Vec<usize> = terms
        .iter()
        .filter_map(|t| t.info.as_ref().map(|i| i.group))
        .collect();
    groups.dedup();
    groups
        .into_iter()
        .filter_map(|g| {
            let of: Vec<Term> = terms
                .iter()
                .filter(|t| t.info.as_ref().is_some_and(|i| i.group == g))
                .cloned()
                .collect();
            let lead = of.iter().min_by_key(|t| t.channel)?;
            Some(TermCurve {
                name: discover::describe(lead).name.into_owned(),
                channel: lead.channel,
                values: score::contribution(ctx, &of, lead.channel),
            })
        })
        .collect()
}

/// Channel `c`'s terms at the full rate's times `t_s`, each where the channel is live.
fn at_full(ctx: &Context, terms: &[Term], c: usize, t_s: &[f64]) -> Vec<f64> {
    let live = score::live(terms, c, None).map(|l| {
        t_s.iter()
            .map(|&t| sim::effects::interpolate(ctx.t_s(), &l, t))
            .collect::<Vec<f64>>()
    });
    let mut sum = vec![0.0; t_s.len()];
    for t in terms.iter().filter(|t| t.channel == c) {
        let part = t.at_full(ctx, t_s);
        match live.as_ref().filter(|_| t.kind != TermKind::StuckChannel) {
            Some(l) => sum
                .iter_mut()
                .zip(part.iter().zip(l))
                .for_each(|(s, (p, l))| *s += p * l),
            None => add(&mut sum, &part),
        }
    }
    sum
}

fn add(a: &mut [f64], b: &[f64]) {
    a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
}

/// A channel as a sentence names it.
pub(crate) fn channel_words(c: usize) -> &'static str {
    ["the load cell", "Fz", "Mx", "My"][c]
}

/// Which library term (or catalogue entry met at another stage through a term).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TermKind {
    OffsetStep,
    StuckChannel,
    Line,
    TemperatureSpan,
    SpeedPower,
    PermanentSet,
    OutputRelaxation,
    OutputSet,
    LoadLag,
    LoadStiffening,
    LoadSaturation,
    MaterialRecovery,
    /// A term found in the residual by the discovery step ([`discover`]): features of the
    /// dictionary, not a library entry.
    Discovered,
    /// Not a finding: the channel's offset and scale refitted with the terms on it, as the
    /// calibration would refit them jointly (no parameter the nested model does not have).
    Recalibration,
}

impl TermKind {
    pub const ALL: [TermKind; 12] = [
        TermKind::OffsetStep,
        TermKind::StuckChannel,
        TermKind::Line,
        TermKind::TemperatureSpan,
        TermKind::SpeedPower,
        TermKind::PermanentSet,
        TermKind::OutputRelaxation,
        TermKind::OutputSet,
        TermKind::LoadLag,
        TermKind::LoadStiffening,
        TermKind::LoadSaturation,
        TermKind::MaterialRecovery,
    ];

    /// Whether the term can act on channel `c` (0 the load cell, 1..4 the outputs).
    pub fn acts_on(self, c: usize) -> bool {
        match self {
            TermKind::OutputRelaxation | TermKind::OutputSet | TermKind::TemperatureSpan => c > 0,
            TermKind::LoadLag
            | TermKind::PermanentSet
            | TermKind::LoadStiffening
            | TermKind::LoadSaturation
            | TermKind::MaterialRecovery => c == 0,
            _ => true,
        }
    }

    /// The catalogue entry the term meets at another stage, if any (the sensing element's own
    /// relaxation, the load cell's lag), rather than a term of the library's own: it is
    /// reported under the entry's name and keeps its protocol preconditions
    /// ([`Context::forbidden`]).
    pub fn catalogue_kind(self) -> Option<sim::effects::EffectKind> {
        use sim::effects::EffectKind::*;
        match self {
            TermKind::LoadLag => Some(TimeOffset),
            TermKind::OutputRelaxation => Some(ViscoelasticRelaxation),
            TermKind::LoadStiffening => Some(Stiffening),
            TermKind::LoadSaturation => Some(AmplifierSaturation),
            _ => None,
        }
    }

    /// Whether `amplitude` (the term's first) is one its physics can have: positive for each
    /// term whose physics has a sign (a relaxation relaxes, a stiffening stiffens, a set adds
    /// to the response, a recovery adds load, a clip limits), and a relaxation no larger than
    /// the response it relaxes (the catalogue's `fraction`, 0-1). Fitted alone each is offered
    /// only so, and a model whose joint refit takes it out is not a model of that physics (a
    /// "relaxation" refitted to -26 % beside the channel's recalibration is an overshoot).
    pub fn admits(self, amplitude: f64) -> bool {
        match self {
            TermKind::OutputRelaxation => amplitude > 0.0 && amplitude <= 1.0,
            TermKind::OutputSet
            | TermKind::LoadStiffening
            | TermKind::LoadSaturation
            | TermKind::PermanentSet
            | TermKind::MaterialRecovery => amplitude > 0.0,
            _ => true,
        }
    }

    /// Whether the term may be offered beside the whole catalogue model: only where its
    /// signature is one no catalogue effect's misfit can take. A periodic line: a catalogue
    /// effect is a response to the rod's drive (its misfit sits at the drive's harmonics and
    /// the sidebands beside them, excluded from the line's search there, or at the protocol's
    /// slow time scales) or a slow function of time, so a line that repeats within seconds,
    /// off the drive, is something else. Every other term has a smooth signature that the
    /// misfit of a catalogue effect fitted with too few terms can take (a wander beside a
    /// relaxation spectrum on the Mach-1 tests), so beside the whole model it would describe
    /// the effect's own imperfection, not new physics. A load that recovers: a catalogue
    /// effect's misfit on the load under a hold is a further fall, never a rise
    /// ([`material_recovery`]). A channel that freezes while the model moves after it
    /// ([`stuck_channel`]): every catalogue effect is a response to the drive or a smooth
    /// function of time, and none stops a channel following the load; nor does any hold the
    /// load cell at a ceiling the recording never passes ([`load_saturation`]).
    pub fn beside_catalogue(self) -> bool {
        matches!(
            self,
            TermKind::Line
                | TermKind::MaterialRecovery
                | TermKind::StuckChannel
                | TermKind::LoadSaturation
        )
    }

    /// The channel's refitted offset and scale on channel `c` (see [`TermKind::Recalibration`]).
    /// Beside the whole catalogue model the refit is of every parameter the catalogue fitted,
    /// to first order ([`Context::catalogue`]).
    pub fn recalibration(ctx: &Context, c: usize) -> Term {
        let x = if ctx.catalogue[c].is_empty() {
            vec![vec![1.0; ctx.len()], ctx.signal(c)]
        } else {
            ctx.catalogue[c].clone()
        };
        Term {
            kind: TermKind::Recalibration,
            channel: c,
            shape: Vec::new(),
            beta: vec![0.0; x.len()],
            columns: fitting::Columns { x, fixed: None },
            n_params: 0,
            info: None,
        }
    }

    /// The best shape and amplitudes of the term on channel `c`, given the other terms'
    /// columns on that channel already in the model (`others`).
    pub fn fit(self, ctx: &Context, c: usize, others: &fitting::Columns) -> Option<Term> {
        match self {
            TermKind::OffsetStep => offset_step::fit(ctx, c, others),
            TermKind::StuckChannel => stuck_channel::fit(ctx, c, others),
            TermKind::Line => line::fit(ctx, c, others),
            TermKind::TemperatureSpan => temperature_span::fit(ctx, c, others),
            TermKind::SpeedPower => speed_power::fit(ctx, c, others),
            TermKind::PermanentSet => permanent_set::fit(ctx, c, others),
            TermKind::OutputRelaxation => output_relaxation::fit(ctx, c, others),
            TermKind::OutputSet => output_set::fit(ctx, c, others),
            TermKind::LoadLag => load_lag::fit(ctx, c, others),
            TermKind::LoadStiffening => load_stiffening::fit(ctx, c, others),
            TermKind::LoadSaturation => load_saturation::fit(ctx, c, others),
            TermKind::MaterialRecovery => material_recovery::fit(ctx, c, others),
            TermKind::Discovered | TermKind::Recalibration => None,
        }
    }
}

/// A fitted term in the contract's words: its name, parameters (primary first, with units),
/// the recorded quantities it is a function of, and its expression.
pub(crate) struct Description {
    pub name: std::borrow::Cow<'static, str>,
    pub params: Vec<(&'static str, f64, String)>,
    pub depends_on: Vec<&'static str>,
    pub form: String,
}

/// One term fitted on one channel.
#[derive(Debug, Clone)]
pub(crate) struct Term {
    pub kind: TermKind,
    pub channel: usize,
    /// The shape parameters chosen on their grid (a time, a frequency, ...).
    pub shape: Vec<f64>,
    /// Its columns and fixed part on the decimated series.
    pub columns: fitting::Columns,
    /// The amplitudes, in the order of the columns.
    pub beta: Vec<f64>,
    /// Parameters the criterion counts: the amplitudes plus the shape's grid dimensions.
    pub n_params: usize,
    /// What a discovered term is ([`discover::Info`]); `None` for the library's terms.
    pub info: Option<std::sync::Arc<discover::Info>>,
}

impl Term {
    /// Whether its amplitude is one its physics admits ([`TermKind::admits`]).
    pub fn admitted(&self) -> bool {
        self.beta.first().is_none_or(|&b| self.kind.admits(b))
    }

    /// Its contribution on the decimated series.
    pub fn contribution(&self) -> Vec<f64> {
        self.columns.contribution(&self.beta)
    }

    /// Its contribution at the full rate's times `t_s` (a line at its own instants; every other
    /// term, a function of slow recorded quantities, interpolated from the decimated series).
    pub fn at_full(&self, ctx: &Context, t_s: &[f64]) -> Vec<f64> {
        if self.kind == TermKind::Line {
            return line::at_times(self, t_s);
        }
        // The plain offset and scale (no shape) at the full rate; a refit along the calibration's
        // directions is interpolated as every other slow term is.
        if self.kind == TermKind::Recalibration
            && ctx.catalogue[self.channel].is_empty()
            && self.shape.is_empty()
        {
            let c = self.channel;
            let full = &ctx.data.full.y[c];
            return full
                .iter()
                .zip(&ctx.full_residual[c])
                .map(|(y, r)| self.beta[0] + self.beta[1] * (y - r - ctx.offset[c]))
                .collect();
        }
        let dec = self.contribution();
        t_s.iter()
            .map(|&t| sim::effects::interpolate(ctx.t_s(), &dec, t))
            .collect()
    }

    /// The term in the contract's words.
    pub fn describe(&self) -> Description {
        let unit = if self.channel == 0 { "N" } else { "V" };
        match self.kind {
            TermKind::OffsetStep => offset_step::describe(self, unit),
            TermKind::StuckChannel => stuck_channel::describe(self, unit),
            TermKind::Line => line::describe(self, unit),
            TermKind::TemperatureSpan => temperature_span::describe(self),
            TermKind::SpeedPower => speed_power::describe(self),
            TermKind::PermanentSet => permanent_set::describe(self),
            TermKind::OutputRelaxation => output_relaxation::describe(self),
            TermKind::OutputSet => output_set::describe(self, unit),
            TermKind::LoadLag => load_lag::describe(self),
            TermKind::LoadStiffening => load_stiffening::describe(self),
            TermKind::LoadSaturation => load_saturation::describe(self),
            TermKind::MaterialRecovery => material_recovery::describe(self),
            TermKind::Discovered => discover::describe(self),
            TermKind::Recalibration => Description {
                name: "recalibration".into(),
                params: Vec::new(),
                depends_on: Vec::new(),
                form: String::new(),
            },
        }
    }

    /// The stage where the term acts.
    pub fn stage(&self) -> Stage {
        match self.kind {
            TermKind::OffsetStep
            | TermKind::StuckChannel
            | TermKind::LoadLag
            | TermKind::LoadSaturation
            | TermKind::Recalibration => Stage::Electronics,
            TermKind::LoadStiffening | TermKind::MaterialRecovery => Stage::Material,
            TermKind::Line => line::stage(self),
            TermKind::TemperatureSpan => temperature_span::stage(self),
            TermKind::OutputRelaxation | TermKind::OutputSet => Stage::Transducer,
            TermKind::Discovered => self.info.as_ref().map_or(Stage::Electronics, |i| i.stage),
            TermKind::SpeedPower | TermKind::PermanentSet => {
                if self.channel == 0 {
                    Stage::Material
                } else {
                    Stage::Transducer
                }
            }
        }
    }
}
