//! The chip's parameters as the model uses them: plain `f64` in SI units, no allocation, so the
//! firmware's emulator can hold them. Built from `hardware/chip.toml` by [`crate::from_hardware`].

/// The four beams. A and B lie along x (A at +x), C and D along y (C at +y).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Beam {
    /// Along +x.
    A,
    /// Along -x.
    B,
    /// Along +y.
    C,
    /// Along -y.
    D,
}

impl Beam {
    /// All beams, in order.
    pub const ALL: [Beam; 4] = [Beam::A, Beam::B, Beam::C, Beam::D];

    /// Outward unit vector (from the block towards the frame), (e_x, e_y).
    pub fn direction(self) -> (f64, f64) {
        match self {
            Beam::A => (1.0, 0.0),
            Beam::B => (-1.0, 0.0),
            Beam::C => (0.0, 1.0),
            Beam::D => (0.0, -1.0),
        }
    }
}

/// A resistor's current direction relative to its beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orientation {
    /// Along the beam: senses the beam's bending stress through pi_l.
    Longitudinal,
    /// Across the beam: senses the beam's bending stress through pi_t.
    Transverse,
}

/// The arms of a Wheatstone bridge; the output is V(left node) - V(right node).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arm {
    /// From the supply to the left node.
    UpperLeft,
    /// From the left node to ground.
    LowerLeft,
    /// From the supply to the right node.
    UpperRight,
    /// From the right node to ground.
    LowerRight,
}

impl Arm {
    /// Arms in the order of [`Bridge::fixed_ohm`].
    pub const ALL: [Arm; 4] = [
        Arm::UpperLeft,
        Arm::LowerLeft,
        Arm::UpperRight,
        Arm::LowerRight,
    ];

    /// Index into [`Bridge::fixed_ohm`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Cross-beam geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Beam length L, frame to block.
    pub beam_length_m: f64,
    /// Beam width b (in the wafer plane).
    pub beam_width_m: f64,
    /// Beam thickness h (along z).
    pub beam_thickness_m: f64,
    /// Half-width c of the central block.
    pub block_half_width_m: f64,
    /// Pillar height above the top surface.
    pub pillar_height_m: f64,
    /// Thickness of the block (the wafer); only the frame-FE check uses it.
    pub block_thickness_m: f64,
}

/// Silicon constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Silicon {
    /// Young's modulus E_X along the beams.
    pub youngs_modulus_pa: f64,
    /// Shear modulus G for torsion.
    pub shear_modulus_pa: f64,
    /// Longitudinal piezoresistive coefficient pi_l.
    pub pi_l_per_pa: f64,
    /// Transverse piezoresistive coefficient pi_t.
    pub pi_t_per_pa: f64,
    /// Fracture strength that defines the chip's strength.
    pub fracture_strength_pa: f64,
}

/// One piezoresistor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resistor {
    /// The beam it lies on.
    pub beam: Beam,
    /// Centre distance from the beam's frame end (0 at the frame, L at the block).
    pub x_m: f64,
    /// Its direction relative to the beam.
    pub orientation: Orientation,
    /// The bridge arm it sits in.
    pub arm: Arm,
}

/// One Wheatstone bridge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    /// Four piezoresistors.
    pub resistors: [Resistor; 4],
    /// Stress-free resistance added to each arm, indexed by [`Arm::index`].
    pub fixed_ohm: [f64; 4],
}

/// Everything the chip model needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChipParams {
    /// Cross-beam geometry.
    pub geometry: Geometry,
    /// Silicon constants.
    pub silicon: Silicon,
    /// Nominal resistance of every piezoresistor at zero stress.
    pub resistance_ohm: f64,
    /// Bridge supply voltage.
    pub excitation_v: f64,
    /// The Fz, Mx and My bridges, in that order.
    pub bridges: [Bridge; 3],
}

/// A load on the block through the pillar. Fz presses into the chip (along -z) when positive;
/// Mx, My are right-handed about +x, +y.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    /// Pressing force.
    pub fz_n: f64,
    /// Moment about +x.
    pub mx_nm: f64,
    /// Moment about +y.
    pub my_nm: f64,
}

impl Load {
    /// A load from its three components.
    pub const fn new(fz_n: f64, mx_nm: f64, my_nm: f64) -> Self {
        Self { fz_n, mx_nm, my_nm }
    }

    /// As an array (Fz, Mx, My).
    pub fn to_array(self) -> [f64; 3] {
        [self.fz_n, self.mx_nm, self.my_nm]
    }
}
