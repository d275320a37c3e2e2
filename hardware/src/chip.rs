//! `chip.toml`: the silicon cross-beam chip (geometry, silicon constants, piezoresistors, bridge
//! wiring and excitation). The `chip` crate turns this into its plain no_std parameter struct.

use std::path::Path;

use crate::{ParamError, Reader};

/// The chip as written in `chip.toml`, in the file's units.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Chip {
    /// Square outline side of the die.
    pub footprint_um: f64,
    /// Beam length L from the frame to the block.
    pub beam_length_um: f64,
    /// Beam width b, in the wafer plane.
    pub beam_width_um: f64,
    /// Beam thickness h, along z.
    pub beam_thickness_um: f64,
    /// Half-width c of the central block.
    pub block_half_width_um: f64,
    /// Pillar height above the chip's top surface.
    pub pillar_height_um: f64,
    /// Block (wafer) thickness.
    pub block_thickness_um: f64,
    /// Mask overlay tolerance of the resistors against the beams.
    pub mask_misalignment_um: f64,
    /// Young's modulus along the beams.
    pub youngs_modulus_pa: f64,
    /// Shear modulus used for torsion.
    pub shear_modulus_pa: f64,
    /// Longitudinal piezoresistive coefficient.
    pub pi_l_per_pa: f64,
    /// Transverse piezoresistive coefficient.
    pub pi_t_per_pa: f64,
    /// Fracture strength that defines the chip's strength.
    pub fracture_strength_pa: f64,
    /// Bridge supply voltage.
    pub excitation_v: f64,
    /// Nominal resistance of every piezoresistor.
    pub resistance_ohm: f64,
    /// Length of each piezoresistor.
    pub resistor_length_um: f64,
    /// The Fz, Mx and My bridges, in that order.
    pub bridges: [Bridge; 3],
}

/// One Wheatstone bridge: four piezoresistors and a fixed resistance per arm.
#[derive(Debug, Clone, PartialEq)]
pub struct Bridge {
    /// Fixed resistance added to [upper_left, lower_left, upper_right, lower_right].
    pub fixed_ohm: [f64; 4],
    /// The four piezoresistors r1..r4.
    pub resistors: [Resistor; 4],
}

/// One piezoresistor on a beam.
#[derive(Debug, Clone, PartialEq)]
pub struct Resistor {
    /// Beam name: "A", "B", "C" or "D".
    pub beam: &'static str,
    /// Centre position from the beam's frame end.
    pub x_um: f64,
    /// "longitudinal" or "transverse" to the beam.
    pub orientation: &'static str,
    /// "upper_left", "lower_left", "upper_right" or "lower_right".
    pub arm: &'static str,
}

/// Bridge names as keys in the file, in the order of [`Chip::bridges`].
pub const BRIDGE_NAMES: [&str; 3] = ["fz", "mx", "my"];
/// Arm names, in the order of [`Bridge::fixed_ohm`].
pub const ARM_NAMES: [&str; 4] = ["upper_left", "lower_left", "upper_right", "lower_right"];

impl Chip {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let chip = Self::read(&mut r);
        chip.check(&mut r);
        r.finish()?;
        Ok(chip)
    }

    fn read(r: &mut Reader) -> Self {
        Self {
            footprint_um: r.f64("geometry.footprint_um", 100.0..=20_000.0),
            beam_length_um: r.f64("geometry.beam_length_um", 10.0..=5000.0),
            beam_width_um: r.f64("geometry.beam_width_um", 1.0..=2000.0),
            beam_thickness_um: r.f64("geometry.beam_thickness_um", 1.0..=1000.0),
            block_half_width_um: r.f64("geometry.block_half_width_um", 1.0..=5000.0),
            pillar_height_um: r.f64("geometry.pillar_height_um", 0.0..=10_000.0),
            block_thickness_um: r.f64("geometry.block_thickness_um", 1.0..=2000.0),
            mask_misalignment_um: r.f64("tolerance.mask_misalignment_um", 0.0..=50.0),
            youngs_modulus_pa: r.f64("silicon.youngs_modulus_pa", 100.0e9..=200.0e9),
            shear_modulus_pa: r.f64("silicon.shear_modulus_pa", 40.0e9..=90.0e9),
            pi_l_per_pa: r.f64("silicon.pi_l_per_pa", -200.0e-11..=200.0e-11),
            pi_t_per_pa: r.f64("silicon.pi_t_per_pa", -200.0e-11..=200.0e-11),
            fracture_strength_pa: r.f64("silicon.fracture_strength_pa", 0.1e9..=10.0e9),
            excitation_v: r.f64("bridge.excitation_v", 0.1..=15.0),
            resistance_ohm: r.f64("bridge.resistance_ohm", 10.0..=1.0e6),
            resistor_length_um: r.f64("bridge.resistor_length_um", 1.0..=1000.0),
            bridges: BRIDGE_NAMES.map(|name| read_bridge(r, name)),
        }
    }

    /// The rules that span several keys.
    fn check(&self, r: &mut Reader) {
        let span_um = 2.0 * (self.block_half_width_um + self.beam_length_um);
        if span_um >= self.footprint_um {
            r.reject(
                "geometry.beam_length_um",
                format!(
                    "block and beams span 2(c + L) = {span_um} um, which leaves no frame inside \
                     the {} um footprint",
                    self.footprint_um
                ),
            );
        }
        let half = self.resistor_length_um / 2.0;
        for (name, bridge) in BRIDGE_NAMES.iter().zip(&self.bridges) {
            for (i, res) in bridge.resistors.iter().enumerate() {
                if res.x_um - half < 0.0 || res.x_um + half > self.beam_length_um {
                    r.reject(
                        &format!("bridge.{name}.r{}.x_um", i + 1),
                        format!(
                            "a {} um resistor centred at {} um does not fit on a {} um beam",
                            self.resistor_length_um, res.x_um, self.beam_length_um
                        ),
                    );
                }
            }
            self.check_balance(r, name, bridge);
        }
    }

    /// Every arm needs a resistance and the bridge must be balanced at zero stress.
    fn check_balance(&self, r: &mut Reader, name: &str, bridge: &Bridge) {
        let mut arm_ohm = bridge.fixed_ohm;
        for res in &bridge.resistors {
            if let Some(i) = ARM_NAMES.iter().position(|a| *a == res.arm) {
                arm_ohm[i] += self.resistance_ohm;
            }
        }
        if arm_ohm.iter().any(|&ohm| ohm <= 0.0) {
            r.reject(
                &format!("bridge.{name}"),
                "every arm needs a resistor or a fixed resistance",
            );
            return;
        }
        let (left, right) = (arm_ohm[0] / arm_ohm[1], arm_ohm[2] / arm_ohm[3]);
        if (left - right).abs() > 1e-9 * left {
            r.reject(
                &format!("bridge.{name}.fixed_ohm"),
                format!(
                    "the bridge is not balanced at zero stress: upper/lower is {left} on the \
                     left and {right} on the right"
                ),
            );
        }
    }
}

fn read_bridge(r: &mut Reader, name: &str) -> Bridge {
    let fixed_ohm = r.f64_array::<4>(&format!("bridge.{name}.fixed_ohm"), 0.0..=1.0e7);
    let resistors = [1, 2, 3, 4].map(|i| {
        let key = format!("bridge.{name}.r{i}");
        Resistor {
            beam: r.choice(&format!("{key}.beam"), &["A", "B", "C", "D"]),
            x_um: r.f64(&format!("{key}.x_um"), 0.0..=5000.0),
            orientation: r.choice(
                &format!("{key}.orientation"),
                &["longitudinal", "transverse"],
            ),
            arm: r.choice(&format!("{key}.arm"), &ARM_NAMES),
        }
    });
    Bridge {
        fixed_ohm,
        resistors,
    }
}
