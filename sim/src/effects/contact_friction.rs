//! Coulomb friction at the inclined contact. The tangential part of the contact load (which
//! makes the moments) sticks until the elastic demand moves past the friction band mu N, then
//! slides with it: a play operator of half-width b = mu N. With N = F cos theta and the demand
//! d = F sin theta (in moment units), b = mu cot(theta) |d|: on loading the moments lag the
//! demand, at a reversal they stick (flat) while Fz moves, then jump onto the unloading path.

/// Largest share of the demand the band may take (mu cot theta >= 1 would lock the contact).
pub const MAX_BAND: f64 = 0.9;

/// `mu`: Coulomb friction coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFriction {
    pub mu: f64,
}

impl ContactFriction {
    /// Band as a share of the demand at contact angle theta.
    pub fn band_share(&self, contact_angle_deg: f64) -> f64 {
        let tan = contact_angle_deg.to_radians().tan().abs();
        if tan < 1e-9 {
            return MAX_BAND;
        }
        (self.mu.abs() / tan).min(MAX_BAND)
    }

    /// Apply to one moment channel (the demand, in place).
    pub fn apply(&self, contact_angle_deg: f64, moment: &mut [f64]) {
        let share = self.band_share(contact_angle_deg);
        let mut m = moment.first().copied().unwrap_or(0.0);
        for d in moment.iter_mut() {
            let b = share * d.abs();
            m = m.clamp(*d - b, *d + b);
            *d = m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: the moment lags on loading, sticks flat at the reversal while the
    /// load is already falling, then follows the load down.
    #[test]
    fn moment_sticks_at_reversal() {
        let up: Vec<f64> = (0..=100).map(|k| k as f64 / 100.0).collect();
        let mut m: Vec<f64> = up.iter().chain(up.iter().rev()).copied().collect();
        let f = ContactFriction { mu: 0.1 };
        let share = f.band_share(20.0);
        f.apply(20.0, &mut m);
        assert!((m[100] - (1.0 - share)).abs() < 1e-12, "lags on loading");
        assert_eq!(m[103], m[100], "sticks after the reversal");
        assert!(
            (m[101 + 80] - 0.2 * (1.0 + share)).abs() < 1e-12,
            "slides above the demand"
        );
        assert_eq!(m[201], 0.0);
    }
}
