//! Candidate causes of the disagreements: each a physically argued change of the default
//! fingertip model, scored on all seven observations (`fingertip/OBSERVATIONS.md`, "Causes").

use crate::{Config, Drive, Material, PronyTerm, RodShape};

/// One candidate cause: a name, the argument for it, and the model change.
pub struct Cause {
    /// Short name (used on the command line and in the table).
    pub name: &'static str,
    /// Why it could matter, in one line.
    pub why: &'static str,
    /// The model with the cause applied to the default.
    pub apply: fn(&Config) -> Config,
}

/// Prony term of the gel's relaxation when the cause "viscoelastic gel" is on: the relaxation
/// the project's demo conceals (30 % with tau = 4 s), seconds slow like the paper's recovery.
pub const GEL_RELAXATION: PronyTerm = PronyTerm { g: 0.3, tau_s: 4.0 };

/// The FE causes, in the order of the table.
pub fn fe_causes() -> Vec<Cause> {
    let mut causes = contact_causes();
    causes.extend(body_causes());
    causes
}

/// The FE cause called `name` applied to `base`, or None for an unknown name.
pub fn apply_named(base: &Config, name: &str) -> Option<Config> {
    fe_causes()
        .into_iter()
        .find(|c| c.name == name)
        .map(|c| (c.apply)(base))
}

/// Causes at the rod: friction, the drive's axis, the end's shape.
fn contact_causes() -> Vec<Cause> {
    vec![
        Cause {
            name: "friction_0.3",
            why: "Coulomb friction at the rod (the toml's mu = 0.3): holds the gel under the rod",
            apply: |c| Config {
                friction_mu: 0.3,
                ..c.clone()
            },
        },
        Cause {
            name: "sticking_1.0",
            why: "near sticking at the rod (mu = 1): a dry gel on steel does not slide",
            apply: |c| Config {
                friction_mu: 1.0,
                ..c.clone()
            },
        },
        Cause {
            name: "drive_along_z",
            why: "the fingertip upright and the rod's end inclined, driven and measured along \
                  the fingertip axis (end face r = 30 mm so the rim stays off the gel)",
            apply: |c| Config {
                drive: Drive::FingertipAxis,
                rod_radius_mm: 30.0,
                ..c.clone()
            },
        },
        Cause {
            name: "wide_platen",
            why: "control for drive_along_z: the same 30 mm end driven along its own axis",
            apply: |c| Config {
                rod_radius_mm: 30.0,
                ..c.clone()
            },
        },
        Cause {
            name: "sphere_end",
            why: "a round-ended rod (sphere r = 40 mm): point contact, deeper indentation",
            apply: |c| Config {
                rod_shape: RodShape::SphereEnd,
                rod_radius_mm: 40.0,
                ..c.clone()
            },
        },
        Cause {
            name: "cylinder_across",
            why: "a rod lying across the fingertip (r = 20 mm), its contact line in the tilt \
                  plane at 60° from x as in the paper's Fig. 10",
            apply: |c| Config {
                rod_shape: RodShape::CylinderAcross,
                rod_radius_mm: 20.0,
                ..c.clone()
            },
        },
    ]
}

/// Causes in the fingertip's body: compressibility, the pillar, the gel's relaxation.
fn body_causes() -> Vec<Cause> {
    vec![
        Cause {
            name: "compressible_0.45",
            why: "a more compressible gel (nu = 0.45 against 0.49): less lateral bulging",
            apply: |c| Config {
                poisson: 0.45,
                ..c.clone()
            },
        },
        Cause {
            name: "tall_pillar",
            why: "package + pillar 4 mm tall (2 mm nominal): the pillar reaches into the gel",
            apply: |c| Config {
                inclusion_height_mm: 4.0,
                ..c.clone()
            },
        },
        Cause {
            name: "viscoelastic_gel",
            why: "the gel relaxes (Prony g = 0.3, tau = 4 s; E stays the relaxed modulus)",
            apply: |c| Config {
                material: Material::ViscoNeoHookean(vec![GEL_RELAXATION]),
                ..c.clone()
            },
        },
        Cause {
            name: "drive_along_z+viscoelastic_gel",
            why: "the two causes that fix rows, together: do they still fix them?",
            apply: |c| Config {
                material: Material::ViscoNeoHookean(vec![GEL_RELAXATION]),
                drive: Drive::FingertipAxis,
                rod_radius_mm: 30.0,
                ..c.clone()
            },
        },
    ]
}

/// The paper's sensor as the scorecard models it: the default fingertip with the gel's
/// relaxation of `hardware/paper-sensor.toml` (the `viscoelastic_gel` cause at the paper's
/// parameters; E stays the relaxed modulus). The offset cut's AC coupling, the file's other
/// adoption, is electronics: the caller adds it as the scorecard's `output_filter`.
pub fn paper_sensor(base: &Config, paper: &hardware::PaperSensor) -> Config {
    Config {
        material: Material::ViscoNeoHookean(vec![PronyTerm {
            g: paper.relaxation_fraction,
            tau_s: paper.relaxation_tau_s,
        }]),
        ..base.clone()
    }
}
