//! Which recordings each kind is tried in: channels, protocols, the fingertip of another model,
//! the material alone, a catalogue effect besides.

use sim::effects::EffectKind;

use super::{Injection, Physics, Target};
use crate::categories::TestShape;
use crate::CaseSpec;

/// One recording of a kind: where it acts and what else varies.
struct Variant {
    physics: Physics,
    target: Target,
    protocol: TestShape,
    /// Another model's fingertip: `Some(linear_outputs)`.
    other: Option<bool>,
    alone: bool,
    alternate: bool,
    with: &'static [EffectKind],
}

const fn v(physics: Physics, target: Target, protocol: TestShape) -> Variant {
    Variant {
        physics,
        target,
        protocol,
        other: None,
        alone: false,
        alternate: false,
        with: &[],
    }
}

impl Variant {
    const fn other(mut self, linear_outputs: bool) -> Self {
        self.other = Some(linear_outputs);
        self
    }
    const fn alone(mut self) -> Self {
        self.alone = true;
        self
    }
    const fn alternate(mut self) -> Self {
        self.alternate = true;
        self
    }
    const fn with(mut self, kinds: &'static [EffectKind]) -> Self {
        self.with = kinds;
        self
    }
}

use EffectKind::{Hysteresis, ThermalDrift, ViscoelasticRelaxation};
use Physics::*;
use Target::*;
use TestShape::{LongHold, SpeedDecade, Staircase, Standard, Triangles};

/// Every kind in three or four recordings; the catalogue at new stages in two or three.
const VARIANTS: [Variant; 52] = [
    v(OffsetStep, Fz, Standard),
    v(OffsetStep, Mx, Standard).with(&[ViscoelasticRelaxation]),
    v(OffsetStep, Load, Standard).other(true),
    v(OffsetStep, My, Staircase),
    v(StuckChannel, Mx, LongHold),
    v(StuckChannel, My, Standard).alternate(),
    v(StuckChannel, Fz, Standard).with(&[ViscoelasticRelaxation]),
    v(DeadSensor, Outputs, Standard),
    v(DeadSensor, Outputs, Standard)
        .other(false)
        .with(&[ViscoelasticRelaxation]),
    v(DeadSensor, Outputs, Triangles),
    v(SignFlip, Mx, Standard),
    v(SignFlip, My, Standard).other(true),
    v(SignFlip, Mx, Staircase).with(&[ViscoelasticRelaxation]),
    v(RateDependentLoad, Load, SpeedDecade),
    v(RateDependentLoad, Load, SpeedDecade).alone(),
    v(RateDependentLoad, Load, SpeedDecade).other(true),
    v(RateDependentLoad, Load, Standard).alone().other(false),
    v(SpanFollowsTemperature, Outputs, Standard),
    v(SpanFollowsTemperature, Outputs, LongHold),
    v(SpanFollowsTemperature, Outputs, Standard).other(false),
    v(FrameVibration, Load, Standard),
    v(FrameVibration, Load, Standard).alone(),
    v(FrameVibration, Load, Staircase).with(&[ViscoelasticRelaxation]),
    v(LineNotMains, Fz, Standard),
    v(LineNotMains, Outputs, Standard).other(true),
    v(LineNotMains, My, Staircase).with(&[ThermalDrift]),
    v(Wander, My, Standard),
    v(Wander, Load, Standard).alone(),
    v(Wander, Fz, LongHold),
    v(PermanentSet, Load, Standard),
    v(PermanentSet, Load, Standard).alone(),
    v(PermanentSet, Load, SpeedDecade).other(false),
    v(PermanentSet, Load, Triangles).with(&[Hysteresis]),
    v(SensingElementSet, Outputs, LongHold),
    v(SensingElementSet, Outputs, Standard),
    v(SensingElementSet, Outputs, Staircase).other(true),
    v(TendonRecovery, Load, LongHold).alone(),
    v(TendonRecovery, Load, TestShape::HoldToEnd).alone(),
    v(TendonRecovery, Load, LongHold).alone().other(false),
    v(MainsOnLoadCell, Load, Standard),
    v(MainsOnLoadCell, Load, Standard).alone(),
    v(MainsOnLoadCell, Load, Staircase).other(true),
    v(SaturationOnLoadCell, Load, Standard),
    v(SaturationOnLoadCell, Load, Standard).alone(),
    v(StiffeningAlone, Load, Standard).alone(),
    v(StiffeningAlone, Load, Staircase).alone(),
    v(StiffeningAlone, Load, Standard).alone().other(false),
    v(RelaxationAlone, Load, LongHold).alone(),
    v(RelaxationAlone, Load, Staircase).alone(),
    v(SensingElementRelaxation, Outputs, LongHold),
    v(SensingElementRelaxation, Outputs, Staircase),
    v(SensingElementRelaxation, Outputs, LongHold).other(false),
];

/// Each recording's label and case, in a fixed order.
pub fn specs() -> Vec<(String, CaseSpec)> {
    VARIANTS
        .iter()
        .map(|x| {
            let mut label = format!(
                "{} on {}, {}",
                x.physics.name(),
                x.target.columns().join(", "),
                x.protocol.name()
            );
            if x.alone {
                label.push_str(", material alone");
            }
            if let Some(linear) = x.other {
                label.push_str(if linear {
                    ", another model (linear outputs)"
                } else {
                    ", another model (FE load map)"
                });
            }
            if x.alternate {
                label.push_str(", repeats its last value");
            }
            for k in x.with {
                label.push_str(&format!(" + {}", k.name()));
            }
            let spec = CaseSpec {
                protocol: x.protocol,
                other_family: x.other,
                injection: Some(Injection {
                    physics: x.physics,
                    target: x.target,
                    alternate: x.alternate,
                    material_alone: x.alone,
                }),
                ..CaseSpec::new(x.with)
            };
            (label, spec)
        })
        .collect()
}
