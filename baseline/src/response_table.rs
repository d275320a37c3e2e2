//! A tabulated fingertip response (from the FE model or any other source): force and chip
//! loads per unit modulus at a rising list of rod travels, interpolated between them.

use crate::response::{FingertipResponse, UnitResponse};

/// A tabulated response (from the FE model or any other source), zero at and before the first
/// point (no contact). Between points the force is interpolated as ln F against ln(travel), and
/// each chip load as its ratio to the force, both monotone cubic (PCHIP, [`super::interp`]).
/// A contact force grows like a power of the travel whose exponent changes slowly, so it is
/// nearly straight in those coordinates: interpolated in F against d, the FE's 0.8 mm steps put
/// ripples of ~0.5 % on the load (its local exponent wandering by +-0.05 between nodes), a
/// hundred times a load cell's noise, which another model's smooth law exposed as a structured
/// misfit. The chip loads' ratios to the force (the maps of the outputs) change slowly too.
/// Before the first point in contact the force follows the first interval's power; past the
/// last, the last interval's; the ratios stay at their end values.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseTable {
    rod_mm: Vec<f64>,
    /// ln rod travel at the nodes in contact (positive travel and force).
    ln_rod: Vec<f64>,
    /// ln force per Pa, then the three chip loads over the force, at those nodes.
    values: [Vec<f64>; 4],
    slopes: [Vec<f64>; 4],
}

impl ResponseTable {
    /// `rod_mm` increasing, one point each.
    pub fn new(rod_mm: Vec<f64>, points: Vec<UnitResponse>) -> Self {
        assert_eq!(rod_mm.len(), points.len(), "one response per rod travel");
        assert!(
            rod_mm.windows(2).all(|w| w[1] > w[0]),
            "rod travel must increase"
        );
        let contact: Vec<(f64, &UnitResponse)> = rod_mm
            .iter()
            .zip(&points)
            .filter(|(d, p)| **d > 0.0 && p.force_n > 0.0)
            .map(|(d, p)| (d.ln(), p))
            .collect();
        let ln_rod: Vec<f64> = contact.iter().map(|(l, _)| *l).collect();
        let values: [Vec<f64>; 4] = std::array::from_fn(|k| {
            contact
                .iter()
                .map(|(_, p)| {
                    if k == 0 {
                        p.force_n.ln()
                    } else {
                        p.chip[k - 1] / p.force_n
                    }
                })
                .collect()
        });
        let slopes = std::array::from_fn(|k| crate::interp::slopes(&ln_rod, &values[k]));
        Self {
            rod_mm,
            ln_rod,
            values,
            slopes,
        }
    }

    /// From a quasi-static curve computed at modulus `youngs_modulus_pa` (rod_mm, force_n,
    /// chip loads), divided by that modulus: the neo-Hookean response scales linearly with E at
    /// fixed geometry (`fingertip`'s `response_scales_linearly_with_youngs_modulus`). Points
    /// must have increasing rod travel; repeated travels (a hold) keep the first.
    pub fn from_curve(
        points: impl IntoIterator<Item = (f64, f64, [f64; 3])>,
        youngs_modulus_pa: f64,
    ) -> Self {
        let mut rod = Vec::new();
        let mut out = Vec::new();
        for (rod_mm, force_n, chip) in points {
            if rod.last().is_some_and(|&r: &f64| rod_mm <= r) {
                continue;
            }
            rod.push(rod_mm);
            out.push(UnitResponse {
                force_n: force_n / youngs_modulus_pa,
                chip: chip.map(|c| c / youngs_modulus_pa),
            });
        }
        Self::new(rod, out)
    }

    /// Tabulate any response on `n` even steps of `0..=max_rod_mm`.
    pub fn sample(model: &dyn FingertipResponse, max_rod_mm: f64, n: usize) -> Self {
        let rod: Vec<f64> = (0..n)
            .map(|i| max_rod_mm * i as f64 / (n - 1) as f64)
            .collect();
        let points = rod.iter().map(|&d| model.unit_response(d)).collect();
        Self::new(rod, points)
    }

    /// The largest tabulated rod travel.
    pub fn max_rod_mm(&self) -> f64 {
        self.rod_mm.last().copied().unwrap_or(0.0)
    }

    /// Component `k` (ln F, or a chip load's ratio to F) at ln travel `l`: the cubic inside the
    /// nodes, the end interval's straight line (ln F) or the end value (ratios) outside.
    fn component(&self, k: usize, l: f64) -> f64 {
        let (x, y, d) = (&self.ln_rod, &self.values[k], &self.slopes[k]);
        let last = x.len() - 1;
        let end = |i: usize, j: usize| {
            if k == 0 && last > 0 {
                y[i] + (y[j] - y[i]) / (x[j] - x[i]) * (l - x[i])
            } else {
                y[i]
            }
        };
        if l < x[0] {
            end(0, 1.min(last))
        } else if l > x[last] {
            end(last, last.saturating_sub(1))
        } else {
            crate::interp::eval(x, y, d, l)
        }
    }
}

impl FingertipResponse for ResponseTable {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        if self.ln_rod.is_empty() || rod_mm <= 0.0 || rod_mm <= self.rod_mm[0] {
            return UnitResponse::default();
        }
        let l = rod_mm.ln();
        let force_n = self.component(0, l).exp();
        UnitResponse {
            force_n,
            chip: std::array::from_fn(|k| force_n * self.component(k + 1, l)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::Linear;

    #[test]
    fn table_interpolates_and_is_zero_before_contact() {
        let t = ResponseTable::sample(&Linear, 10.0, 11);
        assert_eq!(t.unit_response(-1.0), UnitResponse::default());
        assert!((t.unit_response(3.5).force_n - 3.5).abs() < 1e-12);
        assert!((t.unit_response(12.0).chip[2] - 6.0).abs() < 1e-12);
    }

    #[test]
    fn table_from_a_curve_is_per_unit_modulus() {
        let pts = [
            (0.0, 0.0, [0.0; 3]),
            (1.0, 2e4, [1e4, 0.0, 5e3]),
            (1.0, 2e4, [1e4, 0.0, 5e3]),
            (2.0, 6e4, [3e4, -1e3, 1e4]),
        ];
        let t = ResponseTable::from_curve(pts, 1e4);
        let u = t.unit_response(1.0);
        assert!((u.force_n - 2.0).abs() < 1e-12 && (u.chip[0] - 1.0).abs() < 1e-12);
        let mid = t.unit_response(1.5).force_n;
        assert!(mid > 2.0 && mid < 6.0, "{mid}");
    }

    /// A power law tabulated at the FE's 0.8 mm steps comes back exactly between the points
    /// (within rounding), and so does a chip load that is a fixed share of it: interpolated in F
    /// against d, the same table was 0.5 % off mid-interval near contact.
    #[test]
    fn a_power_law_is_exact_between_the_points() {
        let rod: Vec<f64> = (0..12).map(|k| 0.8 * k as f64).collect();
        let points = rod
            .iter()
            .map(|&d: &f64| UnitResponse {
                force_n: d.powf(1.7),
                chip: [0.3 * d.powf(1.7), 0.0, -0.1 * d.powf(1.7)],
            })
            .collect();
        let t = ResponseTable::new(rod, points);
        for d in [0.3, 1.2, 2.0, 4.4, 8.5, 9.5] {
            let u = t.unit_response(d);
            let exact = d.powf(1.7);
            assert!(
                (u.force_n / exact - 1.0).abs() < 1e-12,
                "{d}: {}",
                u.force_n
            );
            assert!((u.chip[2] / exact + 0.1).abs() < 1e-12, "{d}: {:?}", u.chip);
        }
    }
}
