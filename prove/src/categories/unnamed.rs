//! Physics nobody named (issue 40, item 6): a blind proof of the diagnosis's discovery step.
//! Each recording hides one kind of physics that no catalogue entry, library term, issue,
//! contract, doc or test of the project names, placed at one stage of the chain; a few
//! recordings hide nothing. The kinds, their truths and this scoring were written from the
//! physics, without reading the diagnosis's code: the diagnosis is read only through the
//! contract's JSON keys ([`crate::reported::ReportedEffect`]) and `fit.heldout`.
//!
//! The kinds ([`Kind`]), by stage:
//! - **material** (between the rod's travel and the load: on the load, and through the chain on
//!   the outputs): the gel's modulus following the temperature, the gel softening with the work
//!   done on it, the rig's zero moving as its frame warms, play (backlash) in the rod's drive, the
//!   load train ringing after a sudden change of the rod's speed;
//! - **transducer** (between the load and the outputs): a gap in the load path before the
//!   pillar takes load, the moments' axis turning with the load, the bridges' supply sagging as
//!   its battery discharges;
//! - **electronics** (one channel's chain): the rod motor's drive picked up by one channel, the
//!   load cell creeping, a reading that wraps round as an integer overflows, an amplifier whose
//!   gain droops as its output heats it.
//!
//! **Described right**: one reported effect with `"catalogue": false`
//! - at one of the truth's stages (two only where no recording of this test can tell them apart,
//!   the reason beside the truth),
//! - listing every channel the physics acts on and none outside the truth's (a material term may
//!   list the outputs that follow the load),
//! - whose `depends_on` holds at least one of the truth's defining quantities and nothing outside
//!   its allowed ones (the honest equivalents: on a test without memory the load and the rod's
//!   travel are functions of each other; a decay since a change is a function of
//!   `time_since_change`, `time` or a `load_history`),
//!
//! and the recording's held-out misfit falls (`fit.heldout.rmse_after < rmse_before`).
//! **Catalogue name claimed**: any reported effect without `"catalogue": false` on a recording
//! with physics (none of these recordings hides a catalogue effect). **False alarm**: any
//! reported effect on a null recording. The bar ([`Totals::passes`]): 80 % described
//! right, no name claimed, mean held-out after/before at most 0.6, no false alarm.

mod channels;
mod material;
mod record;
mod score;
mod signal;
mod truth;
mod variants;

pub use score::{judge, rows, table, totals, Judgement, KindRow, Totals};
pub use variants::specs;

use super::described::{ELECTRONICS, MATERIAL, OUTPUTS, TRANSDUCER};

/// One kind of physics nobody named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// The gel's modulus falls as it warms: F (1 - kappa (T - T_0)).
    ModulusFollowsTemperature,
    /// The gel's network is damaged by the work done on it: F (1 - c 2W / (W + W_1)), W the
    /// work of the loadings so far, W_1 the first loading's.
    WorkSoftening,
    /// The frame warms and its length changes: the gel sits at d + z (1 - e^(-t/tau)).
    RigZeroDrift,
    /// Play of width b in the rod's drive: the rod's tip follows the encoder through a dead
    /// band, b/2 behind it whichever way it moves.
    DriveBacklash,
    /// The load train rings after each sudden change of the rod's speed: a damped sinusoid
    /// whose size follows the speed's jump and the load at it.
    RigRinging,
    /// A gap in the load path: the pillar takes no load until the gel has pushed `F_g` through
    /// it, then the load beyond: outputs times max(0, 1 - F_g / F).
    PillarGap,
    /// The moments' axis turns with the load (the contact walks round the inclined hemisphere
    /// as it grows): (Mx, My) rotated by theta_max F / F_peak.
    MomentAxisTurning,
    /// The bridges' shared supply sags as its battery discharges: every output times
    /// 1 - s t / T.
    SupplySag,
    /// The rod motor's drive current picked up on one channel: a tanh(v / v_0).
    MotorPickup,
    /// The load cell creeps: F + c lag(F, tau).
    LoadCellCreep,
    /// A reading kept in an integer that overflows: it wraps round to the other end of its
    /// range, (x + L) mod 2L - L.
    CounterWrap,
    /// One amplifier's gain droops as its output heats it: x (1 - g lag((x / x_peak)^2, tau)).
    GainDroop,
}

impl Kind {
    pub const ALL: [Kind; 12] = [
        Kind::ModulusFollowsTemperature,
        Kind::WorkSoftening,
        Kind::RigZeroDrift,
        Kind::DriveBacklash,
        Kind::RigRinging,
        Kind::PillarGap,
        Kind::MomentAxisTurning,
        Kind::SupplySag,
        Kind::MotorPickup,
        Kind::LoadCellCreep,
        Kind::CounterWrap,
        Kind::GainDroop,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::ModulusFollowsTemperature => "modulus following the temperature",
            Kind::WorkSoftening => "softening with the work done",
            Kind::RigZeroDrift => "rig's zero drifting",
            Kind::DriveBacklash => "backlash in the rod's drive",
            Kind::RigRinging => "load train ringing",
            Kind::PillarGap => "gap before the pillar",
            Kind::MomentAxisTurning => "moments' axis turning with the load",
            Kind::SupplySag => "bridge supply sagging",
            Kind::MotorPickup => "motor drive pickup",
            Kind::LoadCellCreep => "load cell creeping",
            Kind::CounterWrap => "reading wrapping round",
            Kind::GainDroop => "amplifier gain drooping with its output",
        }
    }

    /// A material kind: its law is put into the gel's force, and the outputs follow it through
    /// the model's chain.
    pub fn is_material(self) -> bool {
        matches!(
            self,
            Kind::ModulusFollowsTemperature
                | Kind::WorkSoftening
                | Kind::RigZeroDrift
                | Kind::DriveBacklash
                | Kind::RigRinging
        )
    }
}

/// The channels a kind is put on, where it picks them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum On {
    Load,
    Fz,
    Mx,
    My,
    /// The two moments.
    Moments,
    /// The three outputs.
    Outputs,
}

impl On {
    pub fn columns(self) -> Vec<&'static str> {
        match self {
            On::Load => vec!["load_N"],
            On::Fz => vec![OUTPUTS[0]],
            On::Mx => vec![OUTPUTS[1]],
            On::My => vec![OUTPUTS[2]],
            On::Moments => OUTPUTS[1..].to_vec(),
            On::Outputs => OUTPUTS.to_vec(),
        }
    }
}

/// What one recording of the group hides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hidden {
    /// `None`: a null recording, no physics at all.
    pub kind: Option<Kind>,
    pub on: On,
    /// A test of the material alone: the outputs are not measured.
    pub material_alone: bool,
}

/// What one recording hides, and what a right answer says about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// `None`: a null recording (any reported effect is a false alarm).
    pub kind: Option<Kind>,
    /// The stages a right answer may give (the first is the generator's).
    pub stages: Vec<&'static str>,
    /// The channels the physics acts on: each must be in the answer.
    pub channels: Vec<&'static str>,
    /// Channels the answer may list besides (downstream of a material term: the outputs).
    pub channels_also: Vec<&'static str>,
    /// The quantities that define the term: `depends_on` must hold one.
    pub depends_any: Vec<&'static str>,
    /// Every quantity `depends_on` may hold.
    pub depends_allowed: Vec<&'static str>,
    /// The drawn parameters, for the table and the generator's tests.
    pub params: Vec<(&'static str, f64)>,
    pub material_alone: bool,
}

impl Truth {
    /// The drawn parameter `key`, if the kind has one.
    pub fn param(&self, key: &str) -> Option<f64> {
        self.params.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)
    }

    /// The truth in a table cell: stage, channels, dependence, parameters.
    pub fn describe(&self) -> String {
        if self.kind.is_none() {
            return "nothing".into();
        }
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(k, v)| format!("{k} = {}", short(*v)))
            .collect();
        format!(
            "{} [{}], depends on {}; {}",
            self.stages.join(" or "),
            self.channels.join(", "),
            self.depends_any.join(" or "),
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
