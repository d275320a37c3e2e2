//! Building [`ChipParams`] from `hardware/chip.toml` (std side): micrometres to metres, names to
//! enums. The loader has already validated ranges and cross-key rules.

use core::fmt;

use crate::params::{Arm, Beam, Bridge, ChipParams, Geometry, Orientation, Resistor, Silicon};

/// A value in the hardware description that the model cannot represent.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum FromHardwareError {
    /// A beam name other than A, B, C, D.
    UnknownBeam(String),
    /// An orientation other than longitudinal or transverse.
    UnknownOrientation(String),
    /// An arm name other than the four of a Wheatstone bridge.
    UnknownArm(String),
}

impl fmt::Display for FromHardwareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownBeam(s) => write!(f, "unknown beam `{s}` in chip.toml"),
            Self::UnknownOrientation(s) => {
                write!(f, "unknown resistor orientation `{s}` in chip.toml")
            }
            Self::UnknownArm(s) => write!(f, "unknown bridge arm `{s}` in chip.toml"),
        }
    }
}

impl std::error::Error for FromHardwareError {}

const UM: f64 = 1e-6;

impl TryFrom<&hardware::Chip> for ChipParams {
    type Error = FromHardwareError;

    fn try_from(c: &hardware::Chip) -> Result<Self, Self::Error> {
        let geometry = Geometry {
            beam_length_m: c.beam_length_um * UM,
            beam_width_m: c.beam_width_um * UM,
            beam_thickness_m: c.beam_thickness_um * UM,
            block_half_width_m: c.block_half_width_um * UM,
            pillar_height_m: c.pillar_height_um * UM,
            block_thickness_m: c.block_thickness_um * UM,
        };
        let silicon = Silicon {
            youngs_modulus_pa: c.youngs_modulus_pa,
            shear_modulus_pa: c.shear_modulus_pa,
            pi_l_per_pa: c.pi_l_per_pa,
            pi_t_per_pa: c.pi_t_per_pa,
            fracture_strength_pa: c.fracture_strength_pa,
        };
        let bridges = [
            bridge(&c.bridges[0])?,
            bridge(&c.bridges[1])?,
            bridge(&c.bridges[2])?,
        ];
        Ok(Self {
            geometry,
            silicon,
            resistance_ohm: c.resistance_ohm,
            excitation_v: c.excitation_v,
            bridges,
        })
    }
}

impl ChipParams {
    /// Load `hardware/` (see [`hardware::Params::load_default`]) and build the chip's parameters.
    pub fn load_default() -> Result<Self, Box<dyn std::error::Error + Send + Sync>> {
        let hw = hardware::Params::load_default()?;
        Ok(Self::try_from(&hw.chip)?)
    }
}

fn bridge(b: &hardware::ChipBridge) -> Result<Bridge, FromHardwareError> {
    let r = |i: usize| resistor(&b.resistors[i]);
    Ok(Bridge {
        resistors: [r(0)?, r(1)?, r(2)?, r(3)?],
        fixed_ohm: b.fixed_ohm,
    })
}

fn resistor(r: &hardware::ChipResistor) -> Result<Resistor, FromHardwareError> {
    let beam = match r.beam {
        "A" => Beam::A,
        "B" => Beam::B,
        "C" => Beam::C,
        "D" => Beam::D,
        other => return Err(FromHardwareError::UnknownBeam(other.into())),
    };
    let orientation = match r.orientation {
        "longitudinal" => Orientation::Longitudinal,
        "transverse" => Orientation::Transverse,
        other => return Err(FromHardwareError::UnknownOrientation(other.into())),
    };
    let arm = match r.arm {
        "upper_left" => Arm::UpperLeft,
        "lower_left" => Arm::LowerLeft,
        "upper_right" => Arm::UpperRight,
        "lower_right" => Arm::LowerRight,
        other => return Err(FromHardwareError::UnknownArm(other.into())),
    };
    Ok(Resistor {
        beam,
        x_m: r.x_um * UM,
        orientation,
        arm,
    })
}

/// A chip description the model cannot represent is bad data.
impl sysexit::ExitStatus for FromHardwareError {
    fn exit_code(&self) -> u8 {
        sysexit::DATA
    }
}
