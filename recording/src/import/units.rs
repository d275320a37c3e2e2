//! The units an imported log may be in, each with its factor to the recording's unit (s, mm or
//! N): one table per quantity, shared by every importer and by the command line's checks.

/// Standard gravity, N per kgf: a gram- or kilogram-force (a scale's reading) in N.
pub const N_PER_KGF: f64 = 9.80665;

/// A unit: its name and the factor to the recording's unit (s, mm or N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// The unit's name, e.g. `gf`.
    pub name: &'static str,
    /// Recording units per one of this unit.
    pub factor: f64,
}

const fn u(name: &'static str, factor: f64) -> Unit {
    Unit { name, factor }
}

/// Time units, to s. A Unix time is a count of one of them since 1970 (an epoch in s, ms, µs
/// or ns): the importer subtracts the first time, so only the unit matters.
pub const TIME_UNITS: [Unit; 6] = [
    u("s", 1.0),
    u("ms", 1e-3),
    u("us", 1e-6),
    u("µs", 1e-6),
    u("ns", 1e-9),
    u("min", 60.0),
];

/// Length units, to mm.
pub const LENGTH_UNITS: [Unit; 4] = [u("mm", 1.0), u("um", 1e-3), u("µm", 1e-3), u("m", 1e3)];

/// Force units, to N. A scale's `g` and `kg` are its reading of a mass, read here as the force
/// of that mass under standard gravity (gram- and kilogram-force).
pub const FORCE_UNITS: [Unit; 8] = [
    u("N", 1.0),
    u("mN", 1e-3),
    u("kN", 1e3),
    u("gf", N_PER_KGF * 1e-3),
    u("g", N_PER_KGF * 1e-3),
    u("kgf", N_PER_KGF),
    u("kg", N_PER_KGF),
    u("lbf", 4.448_221_615_260_5),
];

/// The unit called `name` among `units`, if any.
pub fn unit(units: &[Unit], name: &str) -> Option<Unit> {
    units.iter().copied().find(|u| u.name == name.trim())
}

/// The unit called `name` among `units`, or an error listing the known ones (for a command
/// line's value parser).
pub fn parse(units: &[Unit], name: &str) -> Result<Unit, String> {
    unit(units, name).ok_or_else(|| {
        let known: Vec<&str> = units.iter().map(|u| u.name).collect();
        format!("unknown unit {name:?} (known: {})", known.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scale_reading_in_grams_is_a_gram_force() {
        let g = unit(&FORCE_UNITS, "g").unwrap();
        assert!((g.factor * 1000.0 - 9.80665).abs() < 1e-12);
        assert_eq!(unit(&TIME_UNITS, "µs").unwrap().factor, 1e-6);
        assert!(parse(&FORCE_UNITS, "stone")
            .unwrap_err()
            .contains("known: N, mN"));
    }
}
