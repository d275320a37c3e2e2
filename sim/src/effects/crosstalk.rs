//! The chip rotated against its nominal axes by `angle_deg` about z: the measured moments are
//! the true ones rotated, Mx' = Mx cos a - My sin a, My' = Mx sin a + My cos a.

/// `angle_deg`: rotation of the chip axes, counter-clockwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crosstalk {
    pub angle_deg: f64,
}

impl Crosstalk {
    pub fn apply(&self, mx: &mut [f64], my: &mut [f64]) {
        let (s, c) = self.angle_deg.to_radians().sin_cos();
        for (x, y) in mx.iter_mut().zip(my.iter_mut()) {
            let (a, b) = (*x, *y);
            *x = a * c - b * s;
            *y = a * s + b * c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: one moment channel carries a load-proportional share of the other.
    #[test]
    fn moment_leaks_into_the_other_channel() {
        let mut mx = vec![0.0, 1.0, 2.0];
        let mut my = vec![0.0; 3];
        Crosstalk { angle_deg: 10.0 }.apply(&mut mx, &mut my);
        assert!((my[2] / mx[2] - 10f64.to_radians().tan()).abs() < 1e-12);
        assert!((my[1] * 2.0 - my[2]).abs() < 1e-12);
    }
}
