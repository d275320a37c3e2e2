//! Which recordings each kind is tried in: channels, protocols (each with two presses or more,
//! or a staircase, so that the physics acts in the stretch the diagnosis holds out), our
//! fingertip or another model's, the material alone, sample rates from 200 Hz to 1 kHz; and the
//! null recordings on the same protocols and fingertips.

use super::{Hidden, Kind, On};
use crate::categories::TestShape;
use crate::CaseSpec;

/// One recording of the group.
struct Variant {
    kind: Option<Kind>,
    on: On,
    protocol: TestShape,
    /// Another model's fingertip: `Some(linear_outputs)`.
    other: Option<bool>,
    alone: bool,
    rate_hz: f64,
}

const fn v(kind: Kind, on: On, protocol: TestShape, rate_hz: f64) -> Variant {
    Variant {
        kind: Some(kind),
        on,
        protocol,
        other: None,
        alone: false,
        rate_hz,
    }
}

const fn null(protocol: TestShape, rate_hz: f64) -> Variant {
    Variant {
        kind: None,
        on: On::Outputs,
        protocol,
        other: None,
        alone: false,
        rate_hz,
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
}

use Kind::*;
use On::*;
use TestShape::{SpeedDecade, Staircase, Standard, StartInContact, Triangles};

/// Every kind in three recordings, then the null recordings.
const VARIANTS: [Variant; 42] = [
    v(ModulusFollowsTemperature, Load, Standard, 500.0),
    v(ModulusFollowsTemperature, Load, Staircase, 200.0)
        .alone()
        .other(false),
    v(ModulusFollowsTemperature, Load, Triangles, 1000.0).other(true),
    v(WorkSoftening, Load, Triangles, 500.0),
    v(WorkSoftening, Load, Standard, 200.0).alone(),
    v(WorkSoftening, Load, StartInContact, 500.0).other(false),
    v(RigZeroDrift, Load, Standard, 1000.0),
    v(RigZeroDrift, Load, SpeedDecade, 200.0)
        .alone()
        .other(true),
    v(RigZeroDrift, Load, Staircase, 500.0),
    v(DriveBacklash, Load, Triangles, 500.0),
    v(DriveBacklash, Load, Standard, 500.0).alone(),
    v(DriveBacklash, Load, StartInContact, 200.0).other(true),
    v(RigRinging, Load, Standard, 1000.0),
    v(RigRinging, Load, SpeedDecade, 500.0).other(false),
    v(RigRinging, Load, Standard, 500.0).alone(),
    v(PillarGap, Outputs, Standard, 500.0),
    v(PillarGap, Outputs, Staircase, 200.0).other(true),
    v(PillarGap, Outputs, Triangles, 1000.0),
    v(MomentAxisTurning, Moments, Standard, 500.0),
    v(MomentAxisTurning, Moments, Triangles, 200.0).other(true),
    v(MomentAxisTurning, Moments, StartInContact, 1000.0),
    v(SupplySag, Outputs, Standard, 200.0),
    v(SupplySag, Outputs, Staircase, 500.0).other(false),
    v(SupplySag, Outputs, Triangles, 1000.0),
    v(MotorPickup, Fz, Standard, 500.0),
    v(MotorPickup, My, Staircase, 1000.0).other(true),
    v(MotorPickup, Load, Triangles, 200.0).alone(),
    v(LoadCellCreep, Load, Standard, 500.0),
    v(LoadCellCreep, Load, Staircase, 200.0).other(false),
    v(LoadCellCreep, Load, Triangles, 1000.0).alone(),
    v(CounterWrap, Fz, Standard, 500.0),
    v(CounterWrap, Mx, Triangles, 200.0).other(true),
    v(CounterWrap, Load, Standard, 500.0).alone(),
    v(GainDroop, Fz, Standard, 500.0),
    v(GainDroop, Mx, Staircase, 200.0).other(false),
    v(GainDroop, My, Triangles, 1000.0),
    null(Standard, 500.0),
    null(Staircase, 200.0).other(true),
    null(Triangles, 1000.0),
    null(Standard, 500.0).alone(),
    null(StartInContact, 500.0).other(false),
    null(SpeedDecade, 200.0).alone(),
];

/// Each recording's label and case, in a fixed order.
pub fn specs() -> Vec<(String, CaseSpec)> {
    VARIANTS.iter().map(|x| (label(x), case(x))).collect()
}

fn label(x: &Variant) -> String {
    let mut label = match x.kind {
        Some(k) => format!("{} on {}", k.name(), x.on.columns().join(", ")),
        None => "null".to_string(),
    };
    label.push_str(&format!(", {}, {} Hz", x.protocol.name(), x.rate_hz));
    if x.alone {
        label.push_str(", material alone");
    }
    match x.other {
        Some(true) => label.push_str(", another model (linear outputs)"),
        Some(false) => label.push_str(", another model (FE load map)"),
        None => {}
    }
    label
}

fn case(x: &Variant) -> CaseSpec {
    CaseSpec {
        protocol: x.protocol,
        other_family: x.other,
        sample_rate_hz: Some(x.rate_hz),
        unnamed: Some(Hidden {
            kind: x.kind,
            on: x.on,
            material_alone: x.alone,
        }),
        ..CaseSpec::new(&[])
    }
}
