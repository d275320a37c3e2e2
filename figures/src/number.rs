//! Numbers a reader can take in at a glance: tick values with just the decimals their spacing
//! needs, units with an SI prefix instead of exponent form, and measurements as value ±
//! uncertainty rounded to the uncertainty.

/// Units that take no SI prefix (a "m°C" or "k%" would confuse more than it helps).
const NO_PREFIX: [&str; 6] = ["", "%", "°C", "degC", "deg", "°"];

/// A unit with an SI prefix chosen for the data's magnitude: shown value = value × `factor`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scale {
    pub factor: f64,
    /// The prefixed unit, e.g. `mV`; empty for a dimensionless quantity.
    pub unit: String,
}

impl Scale {
    /// `name [unit]`, or `name` alone when dimensionless.
    pub fn title(&self, name: &str) -> String {
        if self.unit.is_empty() {
            name.to_string()
        } else {
            format!("{name} [{}]", self.unit)
        }
    }
}

/// Whether `unit` already carries an SI prefix on a base unit (`µT`, `mm`, `mV`): shown as it
/// is, since a second prefix (`kµT`) would not be a unit.
fn prefixed(unit: &str) -> bool {
    const BASES: [&str; 9] = ["T", "V", "A", "N", "Pa", "m", "g", "s", "Hz"];
    let mut chars = unit.chars();
    let first = chars.next();
    let rest = chars.as_str();
    matches!(first, Some('p' | 'n' | 'µ' | 'u' | 'm' | 'k' | 'M' | 'G')) && BASES.contains(&rest)
}

/// The SI prefix that puts `max_abs` (in `unit`) between 1 and 1000: 0.005 V -> mV (×1000).
pub fn si_scale(max_abs: f64, unit: &str) -> Scale {
    let plain = Scale {
        factor: 1.0,
        unit: unit.to_string(),
    };
    if NO_PREFIX.contains(&unit) || prefixed(unit) || !(max_abs.is_finite() && max_abs > 0.0) {
        return plain;
    }
    let e = ((max_abs.log10() / 3.0).floor() as i32 * 3).clamp(-12, 12);
    let prefix = match e {
        -12 => "p",
        -9 => "n",
        -6 => "µ",
        -3 => "m",
        3 => "k",
        6 => "M",
        9 => "G",
        12 => "T",
        _ => return plain,
    };
    Scale {
        factor: 10f64.powi(-e),
        unit: format!("{prefix}{unit}"),
    }
}

/// Decimals needed to write multiples of `step` exactly (2.5 -> 1, 0.02 -> 2, 50 -> 0).
pub fn decimals_for(step: f64) -> usize {
    if !(step.is_finite() && step > 0.0) {
        return 0;
    }
    (0..=9)
        .find(|&d| {
            let s = step * 10f64.powi(d as i32);
            (s - s.round()).abs() < 1e-6 * s.max(1.0)
        })
        .unwrap_or(9)
}

/// `v` with `decimals` places, a true minus sign (U+2212), never "−0", and thin spaces between
/// groups of three digits from five integer digits on (`71 500 000`); "n/a" for a value that is
/// not a number (a model that was never fitted has no BIC).
pub fn fixed(v: f64, decimals: usize) -> String {
    if !v.is_finite() {
        return "n/a".to_string();
    }
    let s = format!("{v:.decimals$}");
    let digits = s.trim_start_matches('-');
    if digits.chars().all(|c| c == '0' || c == '.') {
        return digits.to_string();
    }
    let (int, frac) = digits.split_at(digits.find('.').unwrap_or(digits.len()));
    let mut grouped = String::new();
    for (i, c) in int.chars().enumerate() {
        if int.len() >= 5 && i > 0 && (int.len() - i) % 3 == 0 {
            grouped.push('\u{2009}');
        }
        grouped.push(c);
    }
    let sign = if s.starts_with('-') { "\u{2212}" } else { "" };
    format!("{sign}{grouped}{frac}")
}

/// A tick label: `v` with the decimals that the tick spacing `step` needs.
pub fn tick_label(v: f64, step: f64) -> String {
    fixed(v, decimals_for(step))
}

/// `v` to `digits` significant digits in fixed notation (no exponent): 0.0159, 50.9, 77970.
pub fn significant(v: f64, digits: u32) -> String {
    if !v.is_finite() {
        return "n/a".to_string();
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let mut mag = v.abs().log10().floor() as i32;
    // Rounded up to the next power of ten (9.996 to three digits), it has one digit fewer
    // after the point: "10.0", not "10.00".
    if (v.abs() / 10f64.powi(mag + 1 - digits as i32)).round() >= 10f64.powi(digits as i32) {
        mag += 1;
    }
    let decimals = (digits as i32 - 1 - mag).clamp(0, 12) as usize;
    let unit = 10f64.powi(mag + 1 - digits as i32);
    fixed((v / unit).round() * unit, decimals)
}

/// A measurement for a table: `6.08 ± 0.31 s`, `30.00 ± 0.02 mV`, `0.300` (no uncertainty,
/// three significant digits). The unit gets an SI prefix for the value's magnitude and the value
/// is rounded to the uncertainty's second significant digit.
pub fn measurement(value: f64, stderr: Option<f64>, unit: &str) -> String {
    let scale = si_scale(value.abs(), unit);
    let v = value * scale.factor;
    let body = match stderr.filter(|s| s.is_finite() && *s > 0.0) {
        Some(se) => {
            let se = se * scale.factor;
            let decimals = (1 - se.log10().floor() as i32).clamp(0, 9) as usize;
            format!("{} ± {}", fixed(v, decimals), fixed(se, decimals))
        }
        None => significant(v, 3),
    };
    if scale.unit.is_empty() {
        body
    } else {
        format!("{body} {}", scale.unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_put_values_between_one_and_a_thousand() {
        assert_eq!(si_scale(0.005, "V").unit, "mV");
        assert_eq!(si_scale(0.005, "V").factor, 1e3);
        assert_eq!(si_scale(50.9, "V").unit, "V");
        assert_eq!(si_scale(77_967.0, "Pa").unit, "kPa");
        assert_eq!(si_scale(3e-6, "V").unit, "µV");
        assert_eq!(si_scale(0.5, "%").unit, "%");
        assert_eq!(si_scale(5300.0, "µT").unit, "µT");
        assert_eq!(si_scale(0.05, "mm").unit, "mm");
        assert_eq!(si_scale(5.0, "Pa").unit, "Pa");
        assert_eq!(si_scale(0.0, "V").factor, 1.0);
    }

    #[test]
    fn ticks_and_values_read_without_exponents() {
        assert_eq!(tick_label(2.5, 2.5), "2.5");
        assert_eq!(tick_label(-0.02, 0.01), "\u{2212}0.02");
        assert_eq!(tick_label(-0.0, 0.5), "0.0");
        assert_eq!(tick_label(180.0, 20.0), "180");
        assert_eq!(significant(50.947, 3), "50.9");
        assert_eq!(significant(-0.015_93, 3), "\u{2212}0.0159");
        assert_eq!(significant(77_967.4, 3), "78\u{2009}000");
        // Rounded up to a power of ten: the digits asked for, no more.
        assert_eq!(significant(9.9996, 3), "10.0");
        assert_eq!(significant(9.999_999_999_999_998, 2), "10");
        assert_eq!(significant(-0.099_96, 2), "\u{2212}0.10");
        assert_eq!(fixed(-71_527_058.0, 0), "\u{2212}71\u{2009}527\u{2009}058");
        assert_eq!(fixed(2656.4, 0), "2656");
        assert_eq!(fixed(f64::NAN, 0), "n/a");
    }

    #[test]
    fn measurements_round_to_their_uncertainty() {
        assert_eq!(measurement(6.0803, Some(0.3138), "s"), "6.08 ± 0.31 s");
        assert_eq!(
            measurement(0.030_014, Some(1.73e-5), "V"),
            "30.014 ± 0.017 mV"
        );
        assert_eq!(measurement(77_967.4, Some(412.0), "Pa"), "77.97 ± 0.41 kPa");
        assert_eq!(measurement(0.299_95, None, ""), "0.300");
        assert_eq!(
            measurement(-1.2384, Some(0.05), "deg"),
            "\u{2212}1.238 ± 0.050 deg"
        );
    }
}
