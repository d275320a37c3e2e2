//! Physics the catalogue lacks, and catalogue physics at a stage other than its usual one
//! (`docs/diagnosis-format.md`, "Where the physics acts, and physics the catalogue
//! lacks"). Each recording hides one [`Physics`], placed at its stage, on the fingertip of the
//! project's model or of another one ([`super::OtherFingertip`]), with or without sensor outputs
//! (a test of the material alone: load cell only), under several protocols, some with a
//! catalogue effect besides. The generators (`described/inject.rs`, `terms.rs`) are the proof's own physics: they do not
//! use the diagnosis's terms, nor the simulator's effects for what the recording is scored on.
//!
//! Two groups are scored (`described/score.rs`):
//! - **out of catalogue**: offset step, stuck or zero-reading channel, dead sensor, flipped
//!   sign, a load growing with a power of the rod speed, a span following the temperature, a
//!   frame vibration at a few hertz, a line at no mains frequency, a slow wander, a permanent set
//!   after the first loading, a sensing element that keeps a set after release and creeps back,
//!   a tendon that relaxes and then recovers load as it dries;
//! - **catalogue at a new stage**: mains and saturation on the load cell, stiffening and
//!   relaxation of the material alone, relaxation of the outputs that the load does not share
//!   (the sensing element creeps).
//!
//! **Described right** (out of catalogue): one reported effect with `"catalogue": false`
//! - at one of the truth's stages (two only where no recording of this test can tell them
//!   apart: a dead sensor is a dead chip or a cut cable, a span following the temperature is the
//!   bridges' or the amplifiers'),
//! - on every channel the physics acts on and on no channel outside the truth's (a term of the
//!   material acts on the load; the outputs, which follow the load, may be listed with it),
//! - whose `depends_on` holds at least one of the truth's defining quantities (`time` for a step,
//!   a line, a wander; `rod_speed` for a rate law; `temp_C` for a span; `rod_mm` for a set; the
//!   load or the channel itself for a flipped sign) and nothing outside the truth's allowed ones
//!   (the equivalent forms: a stuck channel is a step at a time of the model's output, so
//!   `load_N` or the channel may come with `time`; a dead sensor's term is the model's output
//!   removed, a constant or a function of the load).
//!
//! **Named right** (catalogue at a new stage): an effect with the catalogue name, at the truth's
//! stage, on the truth's channels by the same rule.
//!
//! **Catalogue name claimed**: any reported effect without `"catalogue": false` whose name is
//! neither the truth's catalogue name nor one of the catalogue effects hidden besides it.

mod inject;
mod score;
mod signal;
mod terms;
mod variants;

pub use score::{all_pass, judge, summary, table, GroupSummary, Judgement};
pub use variants::specs;

/// The stages of the contract.
pub const MATERIAL: &str = "material";
pub const TRANSDUCER: &str = "transducer";
pub const ELECTRONICS: &str = "electronics";

/// The sensor outputs, by their column names.
pub const OUTPUTS: [&str; 3] = ["fz_V", "mx_V", "my_V"];

/// The channel a kind acts on, where it picks one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Load,
    Fz,
    Mx,
    My,
    Outputs,
}

impl Target {
    pub fn columns(self) -> Vec<&'static str> {
        match self {
            Target::Load => vec!["load_N"],
            Target::Fz => vec![OUTPUTS[0]],
            Target::Mx => vec![OUTPUTS[1]],
            Target::My => vec![OUTPUTS[2]],
            Target::Outputs => OUTPUTS.to_vec(),
        }
    }
}

/// One kind of physics and how it is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Injection {
    pub physics: Physics,
    pub target: Target,
    /// The kind's second form: a stuck channel that repeats its last value instead of reading
    /// zero.
    pub alternate: bool,
    /// A test of the material alone: the outputs are not measured.
    pub material_alone: bool,
}

/// Which of the two groups a recording belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// Physics the catalogue lacks: to be described (`"catalogue": false`), never named.
    OutOfCatalogue,
    /// A catalogue entry at a stage or on a channel other than its usual one.
    NewStage,
}

impl Group {
    pub fn name(self) -> &'static str {
        match self {
            Group::OutOfCatalogue => "out of catalogue",
            Group::NewStage => "catalogue at a new stage",
        }
    }
}

/// One kind of physics hidden in a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Physics {
    /// A connector knock: one channel's offset steps at one instant.
    OffsetStep,
    /// One output reads zero (noise only), or repeats its last value, from mid-hold on.
    StuckChannel,
    /// Every output reads zero (noise only) while the rod and the load move.
    DeadSensor,
    /// One moment channel wired the wrong way round.
    SignFlip,
    /// The gel's load grows with a power of the rod speed: F (1 + a sgn(v) (|v| / v_ref)^m).
    RateDependentLoad,
    /// The outputs' span follows the temperature: V (1 + beta (T - T_0)).
    SpanFollowsTemperature,
    /// The frame vibrates at a few hertz: the load cell carries the rod's inertia.
    FrameVibration,
    /// A line on the outputs at no mains frequency (a switching supply, a display's refresh).
    LineNotMains,
    /// A slow wander, 0.03-0.07 Hz, on one channel.
    Wander,
    /// The gel keeps a set after the first loading: F(d - s) from the first release on.
    PermanentSet,
    /// The sensing element keeps a set under load and creeps back after release, where the
    /// load does not.
    SensingElementSet,
    /// A tendon relaxes under a held stretch, then recovers load as it dries.
    TendonRecovery,
    /// Mains pickup on the load cell's channel.
    MainsOnLoadCell,
    /// The load cell's amplifier clips.
    SaturationOnLoadCell,
    /// The material alone stiffens against the rod (load cell only).
    StiffeningAlone,
    /// The material alone relaxes (load cell only).
    RelaxationAlone,
    /// The outputs relax more than the load (the sensing element creeps), the load a little.
    SensingElementRelaxation,
}

impl Physics {
    pub fn name(self) -> &'static str {
        match self {
            Physics::OffsetStep => "offset step",
            Physics::StuckChannel => "stuck channel",
            Physics::DeadSensor => "dead sensor",
            Physics::SignFlip => "flipped sign",
            Physics::RateDependentLoad => "load with a power of the rod speed",
            Physics::SpanFollowsTemperature => "span following the temperature",
            Physics::FrameVibration => "frame vibration",
            Physics::LineNotMains => "line not at mains",
            Physics::Wander => "slow wander",
            Physics::PermanentSet => "permanent set",
            Physics::SensingElementSet => "sensing element's set",
            Physics::TendonRecovery => "tendon relaxing and recovering",
            Physics::MainsOnLoadCell => "mains on the load cell",
            Physics::SaturationOnLoadCell => "load cell saturating",
            Physics::StiffeningAlone => "stiffening, material alone",
            Physics::RelaxationAlone => "relaxation, material alone",
            Physics::SensingElementRelaxation => "sensing element relaxing",
        }
    }

    pub fn group(self) -> Group {
        match self {
            Physics::MainsOnLoadCell
            | Physics::SaturationOnLoadCell
            | Physics::StiffeningAlone
            | Physics::RelaxationAlone
            | Physics::SensingElementRelaxation => Group::NewStage,
            _ => Group::OutOfCatalogue,
        }
    }
}

/// What one recording hides, and what a right answer says about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    pub physics: Physics,
    /// The stages a right answer may give (the first is the generator's).
    pub stages: Vec<&'static str>,
    /// The channels the physics acts on: each must be in the answer.
    pub channels: Vec<&'static str>,
    /// Channels the answer may list besides (downstream of a material term: the outputs).
    pub channels_also: Vec<&'static str>,
    /// The quantities that define the term: `depends_on` must hold one (none: any or none).
    pub depends_any: Vec<&'static str>,
    /// Every quantity `depends_on` may hold.
    pub depends_allowed: Vec<&'static str>,
    /// The catalogue name a right answer gives (the new-stage group).
    pub catalogue_name: Option<&'static str>,
    /// Catalogue effects hidden besides it: naming them is no claim.
    pub hidden: Vec<String>,
    /// The drawn parameters, for the table and the generator's tests.
    pub params: Vec<(&'static str, f64)>,
    /// A test of the material alone: no sensor outputs.
    pub material_alone: bool,
}

impl Truth {
    /// The truth in a table cell: stage, channels, dependence or name, parameters.
    pub fn describe(&self) -> String {
        let what = match self.catalogue_name {
            Some(n) => format!("`{n}`"),
            None => format!("depends on {}", self.depends_any.join(" or ")),
        };
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(k, v)| format!("{k} = {}", short(*v)))
            .collect();
        format!(
            "{} [{}], {what}; {}",
            self.stages.join(" or "),
            self.channels.join(", "),
            params.join(", ")
        )
    }
}

/// A number in four significant digits.
fn short(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e4) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}
