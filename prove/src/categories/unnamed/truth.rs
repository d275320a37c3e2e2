//! Each kind's truth, written from the physics before the diagnosis was run on it: the stages a
//! right answer may give, the channels, the quantities that define the term and those an honest
//! equivalent may use.

use super::{Hidden, Kind, Truth, ELECTRONICS, MATERIAL, OUTPUTS, TRANSDUCER};

/// The rod's and the load's quantities, functions of each other on a test without memory.
const TRAVEL: [&str; 2] = ["rod_mm", "load_N"];

/// A decay since a change: `time_since_change`, `time` (the changes' times fitted) or the load
/// through a first-order memory.
const MEMORY: [&str; 3] = ["load_history", "time_since_change", "time"];

/// The truth of `hidden` (its parameters follow as they are drawn).
pub(super) fn of(hidden: &Hidden) -> Truth {
    let Some(kind) = hidden.kind else {
        return Truth {
            kind: None,
            stages: Vec::new(),
            channels: Vec::new(),
            channels_also: Vec::new(),
            depends_any: Vec::new(),
            depends_allowed: Vec::new(),
            params: Vec::new(),
            material_alone: hidden.material_alone,
        };
    };
    let (stages, channels, any, mut allowed) = shape(kind, hidden);
    for q in &any {
        if !allowed.contains(q) {
            allowed.push(q);
        }
    }
    // A material term acts on the load; the outputs, which follow the load, may come with it.
    let also = if kind.is_material() && !hidden.material_alone {
        OUTPUTS.to_vec()
    } else {
        Vec::new()
    };
    Truth {
        kind: Some(kind),
        stages,
        channels,
        channels_also: also,
        depends_any: any,
        depends_allowed: allowed,
        params: Vec::new(),
        material_alone: hidden.material_alone,
    }
}

/// Stages, channels, defining and allowed quantities of `kind` put on `hidden.on`.
type Shape = (
    Vec<&'static str>,
    Vec<&'static str>,
    Vec<&'static str>,
    Vec<&'static str>,
);

fn shape(kind: Kind, hidden: &Hidden) -> Shape {
    use Kind::*;
    let on = hidden.on.columns();
    let load = vec!["load_N"];
    match kind {
        // The temperature is measured: a right answer names it. The term multiplies the load.
        ModulusFollowsTemperature => (vec![MATERIAL], load, vec!["temp_C"], TRAVEL.to_vec()),
        // The damage follows the work done so far: a memory of the load; on these tests,
        // whose loads rest at zero between presses, a function of time multiplies the load the
        // same way.
        WorkSoftening => (
            vec![MATERIAL],
            load,
            vec!["load_history", "time"],
            TRAVEL.to_vec(),
        ),
        // The gel's position moves with time; the load is the gel's force at the moved travel.
        RigZeroDrift => (vec![MATERIAL], load, vec!["time"], TRAVEL.to_vec()),
        // The tip's travel depends on the way the rod moves (the sign of its speed, or of the
        // load's rate on a press) and on the travel since it turned.
        DriveBacklash => {
            let mut allowed = TRAVEL.to_vec();
            allowed.push("time_since_change");
            (
                vec![MATERIAL],
                load,
                vec!["rod_speed", "load_rate"],
                allowed,
            )
        }
        // A force that really rings moves the outputs with the load; with the load cell alone
        // nothing tells it from the load cell's own underdamped filter ringing after a fast
        // change.
        RigRinging => rig_ringing(hidden.material_alone, load),
        // The outputs are a function of the transmitted load; each output is its own carrier.
        PillarGap => (
            vec![TRANSDUCER],
            OUTPUTS.to_vec(),
            TRAVEL.to_vec(),
            OUTPUTS.to_vec(),
        ),
        // The angle follows the load (Fz is proportional to it); each moment's term is the
        // other moment (and itself) times the angle.
        MomentAxisTurning => (
            vec![TRANSDUCER],
            OUTPUTS[1..].to_vec(),
            vec!["load_N", "rod_mm", "fz_V"],
            OUTPUTS.to_vec(),
        ),
        // The supply feeds the bridges: a sag of the supply and a sensitivity of the bridges
        // falling in time are the same output on every recording of this test.
        SupplySag => supply_sag(),
        // An additive pickup while the rod moves, out of contact too: the rod's speed only.
        MotorPickup => (vec![ELECTRONICS], on, vec!["rod_speed"], Vec::new()),
        // The load cell reads its load through a memory; it reads after the rod has left the
        // gel, which no material does.
        LoadCellCreep => (vec![ELECTRONICS], load, MEMORY.to_vec(), TRAVEL.to_vec()),
        // A function of the channel's own value, which follows the load.
        CounterWrap => {
            let mut any = TRAVEL.to_vec();
            any.extend(on.iter().filter(|c| !TRAVEL.contains(c)));
            (vec![ELECTRONICS], on, any, Vec::new())
        }
        // The gain follows a memory of the output's own power. A bridge's dissipation is set by
        // its supply, not by its output: a droop that follows the output is the amplifier's.
        GainDroop => {
            let mut allowed = TRAVEL.to_vec();
            allowed.extend(on.iter().copied());
            (vec![ELECTRONICS], on, MEMORY.to_vec(), allowed)
        }
    }
}

/// A ringing force (`RigRinging`) on the `load`; on the load cell alone (`material_alone`) the
/// load cell's own filter as well.
fn rig_ringing(material_alone: bool, load: Vec<&'static str>) -> Shape {
    let stages = if material_alone {
        vec![MATERIAL, ELECTRONICS]
    } else {
        vec![MATERIAL]
    };
    let mut allowed = TRAVEL.to_vec();
    allowed.extend(["rod_speed", "load_rate"]);
    (stages, load, vec!["time_since_change", "time"], allowed)
}

/// A sag of the bridges' supply (`SupplySag`) on every output, in time.
fn supply_sag() -> Shape {
    let mut allowed = TRAVEL.to_vec();
    allowed.extend(OUTPUTS);
    (
        vec![TRANSDUCER, ELECTRONICS],
        OUTPUTS.to_vec(),
        vec!["time"],
        allowed,
    )
}
