//! Axis ranges with ticks at round numbers (1, 2, 2.5 or 5 times a power of ten).

use crate::number::tick_label;

/// An axis range and the spacing of its ticks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ticks {
    pub lo: f64,
    pub hi: f64,
    pub step: f64,
}

impl Ticks {
    /// Round ticks for `lo..hi`, about `target` of them. With `expand` the range grows to the
    /// enclosing ticks (value axes: the frame ends on a labelled number); without, it stays
    /// the data's (time axes: no empty stretch after the last sample).
    pub fn new(lo: f64, hi: f64, target: usize, expand: bool) -> Ticks {
        let (lo, hi) = sane_range(lo, hi);
        let step = nice_step((hi - lo) / target.max(1) as f64);
        if expand {
            Ticks {
                lo: (lo / step + 1e-9).floor() * step,
                hi: (hi / step - 1e-9).ceil() * step,
                step,
            }
        } else {
            // An end within 2 % of the span inside a tick moves out onto it (never in, which
            // would clip data): a time axis starting at 0.1 s starts at a labelled 0.
            let near = |v: f64, t: f64| {
                if (v - t).abs() <= 0.02 * (hi - lo) {
                    t
                } else {
                    v
                }
            };
            Ticks {
                lo: near(lo, (lo / step).floor() * step),
                hi: near(hi, (hi / step).ceil() * step),
                step,
            }
        }
    }

    /// The tick values: the multiples of the step inside the range.
    pub fn values(&self) -> Vec<f64> {
        let first = (self.lo / self.step - 1e-9).ceil() as i64;
        let last = (self.hi / self.step + 1e-9).floor() as i64;
        (first..=last)
            .map(|k| {
                let v = k as f64 * self.step;
                if v.abs() < 1e-12 * self.step {
                    0.0
                } else {
                    v
                }
            })
            .collect()
    }

    /// The label of tick `v`: as many decimals as the spacing needs, a true minus sign.
    pub fn label(&self, v: f64) -> String {
        tick_label(v, self.step)
    }
}

/// A finite range with room in it: a flat or missing series still gets a readable axis.
fn sane_range(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    if hi - lo > 1e-12 * lo.abs().max(hi.abs()) && hi > lo {
        return (lo, hi);
    }
    let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
    (lo - half, hi + half)
}

/// The round step at or just above `raw`.
fn nice_step(raw: f64) -> f64 {
    let mag = 10f64.powf(raw.log10().floor());
    let n = raw / mag;
    let m = [1.0, 2.0, 2.5, 5.0]
        .into_iter()
        .find(|&m| m >= n - 1e-9)
        .unwrap_or(10.0);
    m * mag
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_axes_end_on_round_ticks() {
        let t = Ticks::new(-0.0131, 0.0468, 5, true);
        assert_eq!(t.step, 0.02);
        assert!(
            (t.lo + 0.02).abs() < 1e-12 && (t.hi - 0.06).abs() < 1e-12,
            "{t:?}"
        );
        let labels: Vec<String> = t.values().iter().map(|&v| t.label(v)).collect();
        assert_eq!(labels, ["\u{2212}0.02", "0.00", "0.02", "0.04", "0.06"]);
    }

    #[test]
    fn time_axes_keep_the_data_range_and_tick_inside_it() {
        let t = Ticks::new(0.0, 179.5, 8, false);
        assert_eq!((t.lo, t.hi, t.step), (0.0, 179.5, 25.0));
        assert_eq!(t.values().last(), Some(&175.0));
        assert_eq!(t.values().len(), 8);
        let t = Ticks::new(0.1, 172.0, 8, false);
        assert_eq!((t.lo, t.hi), (0.0, 175.0), "ends near a tick move onto it");
    }

    #[test]
    fn flat_or_empty_series_still_get_an_axis() {
        let t = Ticks::new(5.0, 5.0, 4, true);
        assert!(t.lo < 5.0 && t.hi > 5.0 && t.values().len() >= 2, "{t:?}");
        let t = Ticks::new(f64::INFINITY, f64::NEG_INFINITY, 4, true);
        assert_eq!((t.lo, t.hi), (0.0, 1.0));
    }
}
