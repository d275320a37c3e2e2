//! An amplifier output clipping at its rails, +-`limit_V`.

/// `limit_V`: the rail magnitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmplifierSaturation {
    pub limit_v: f64,
}

impl AmplifierSaturation {
    pub fn apply(&self, x: &mut [f64]) {
        let l = self.limit_v.abs();
        for y in x.iter_mut() {
            *y = y.clamp(-l, l);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: flat tops at a fixed voltage.
    #[test]
    fn flat_tops_at_the_rail() {
        let mut x = vec![0.5, 1.5, 2.0, -3.0];
        AmplifierSaturation { limit_v: 1.2 }.apply(&mut x);
        assert_eq!(x, vec![0.5, 1.2, 1.2, -1.2]);
    }
}
