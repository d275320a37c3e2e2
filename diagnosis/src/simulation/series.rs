//! The simulated test (`tactile-recording/1`): the lab's run of the same rod path on its own
//! time base and rate, shifted onto the recording's by the rod's travel and interpolated at the
//! recording's samples.
//!
//! The shift: the rod first reaching half the recorded largest travel on the way in, in both,
//! gives a first guess; the RMS distance between the two rod paths over the recording's contact
//! is then minimised around it (golden section). A shift that leaves the paths further apart
//! than [`MAX_RMS_SHARE`] of the largest travel (RMS) or [`MAX_GAP_SHARE`] anywhere is another
//! protocol, and refused.

use std::path::Path;

use recording::Recording;

use super::curve::{usable_rows, Curve};
use super::{Aligned, Named, Samples, SimulationError};

/// Two rod paths this far apart (RMS over the contact, share of the largest recorded travel)
/// are not one: a slower ramp, another peak, another protocol. An FE run of the nominal path
/// beside a machine's recorded one stays well inside it (a 1 % speed error over one ramp).
pub(crate) const MAX_RMS_SHARE: f64 = 0.02;
/// ... nor paths this far apart at any one recorded sample in contact (another peak).
pub(crate) const MAX_GAP_SHARE: f64 = 0.05;
/// Recorded samples in contact the rod paths are compared on at most (evenly picked).
const COMPARED_SAMPLES: usize = 20_000;
/// Golden-section steps of the shift: the bracket shrinks by 0.618 each.
const SHIFT_STEPS: usize = 60;

/// The simulation `sim` aligned onto `data`'s full-rate times.
pub(crate) fn align(path: &Path, sim: &Recording, at: Samples) -> Result<Aligned, SimulationError> {
    let c = &sim.channels;
    let signals = c.signals();
    let simulated: [bool; 4] = std::array::from_fn(|k| signals[k].1.iter().any(|v| !v.is_nan()));
    let mut needed: Vec<&[f64]> = vec![&c.rod_mm];
    needed.extend((0..4).filter(|&k| simulated[k]).map(|k| signals[k].1));
    let rows = usable_rows(&c.t_s, &needed);
    if rows.len() < 2 {
        return Err(SimulationError::TooShort {
            path: path.to_path_buf(),
            rows: rows.len(),
        });
    }
    let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let t_sim = pick(&c.t_s);
    let rod = Curve::new(t_sim.clone(), pick(&c.rod_mm));
    let rod_sim = pick(&c.rod_mm);
    let (t, d) = (at.t_s, at.rod_mm);
    let shift = Shift::find(path, (&t_sim, &rod_sim, &rod), (t, d))?;
    shift.covers(path, &t_sim, (t, d))?;
    let columns = std::array::from_fn(|k| {
        simulated[k].then(|| {
            let curve = Curve::new(t_sim.clone(), pick(signals[k].1));
            t.iter().map(|&ti| curve.at(ti + shift.s)).collect()
        })
    });
    let (n, span) = (t_sim.len(), t_sim[t_sim.len() - 1] - t_sim[0]);
    let rate = if span > 0.0 {
        (n - 1) as f64 / span
    } else {
        0.0
    };
    // Less than a recorded sample is no stretch held.
    let dt = (t[t.len() - 1] - t[0]) / (t.len().max(2) - 1) as f64;
    let beyond = |s: f64| if s > dt { s } else { 0.0 };
    let held = (
        beyond(t_sim[0] - shift.s - t[0]),
        beyond(t[t.len() - 1] - (t_sim[n - 1] - shift.s)),
    );
    Ok(Aligned {
        columns,
        aligned: shift.words(n, rate, t.len(), held),
        alignment: shift.numbers(rate, held),
    })
}

/// The time shift found: the simulation's `t_s` = the recording's + `s`.
struct Shift {
    s: f64,
    rms_mm: f64,
    gap_mm: f64,
    largest_mm: f64,
    contact_s: f64,
}

impl Shift {
    /// The shift that puts the simulated rod path `(t_sim, rod_sim, rod)` on the recorded
    /// `(t, d)`, or why there is none.
    fn find(
        path: &Path,
        (t_sim, rod_sim, rod): (&[f64], &[f64], &Curve),
        (t, d): (&[f64], &[f64]),
    ) -> Result<Self, SimulationError> {
        let largest = d.iter().cloned().fold(0.0, f64::max);
        let half = 0.5 * largest;
        let covers = || SimulationError::Travel {
            path: path.to_path_buf(),
            covers_mm: (
                rod_sim.iter().cloned().fold(f64::INFINITY, f64::min),
                rod_sim.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            ),
            needs_mm: (0.0, largest),
        };
        let guess = rising(t_sim, rod_sim, half).ok_or_else(covers)?
            - rising(t, d, half).expect("the recording reaches its own half");
        let contact: Vec<usize> = (0..d.len()).filter(|&i| d[i] > 0.0).collect();
        let step = (contact.len() / COMPARED_SAMPLES).max(1);
        let compared: Vec<(f64, f64)> = contact
            .iter()
            .step_by(step)
            .map(|&i| (t[i], d[i]))
            .collect();
        let rms = |s: f64| {
            let sum: f64 = compared
                .iter()
                .map(|&(ti, di)| (rod.at(ti + s) - di).powi(2))
                .sum();
            (sum / compared.len().max(1) as f64).sqrt()
        };
        let dt = |x: &[f64]| (x[x.len() - 1] - x[0]) / (x.len().max(2) - 1) as f64;
        let reach = (5.0 * dt(t_sim)).max(5.0 * dt(t)).max(0.5);
        let s = golden(&rms, guess - reach, guess + reach);
        let s = if rms(guess) < rms(s) { guess } else { s };
        let gap = compared
            .iter()
            .map(|&(ti, di)| (rod.at(ti + s) - di).abs())
            .fold(0.0, f64::max);
        let shift = Self {
            s,
            rms_mm: rms(s),
            gap_mm: gap,
            largest_mm: largest,
            contact_s: contact.last().map_or(0.0, |&j| t[j] - t[contact[0]]),
        };
        if shift.rms_mm > MAX_RMS_SHARE * largest || shift.gap_mm > MAX_GAP_SHARE * largest {
            return Err(SimulationError::Protocol {
                path: path.to_path_buf(),
                shift_s: s,
                rms_mm: shift.rms_mm,
                gap_mm: shift.gap_mm,
                share_pct: 100.0 * shift.rms_mm / largest,
                limit_pct: 100.0 * MAX_RMS_SHARE,
            });
        }
        Ok(shift)
    }

    /// Refuse a simulation whose time, once shifted, stops short of the recording's contact
    /// (by more than one of its samples): out of contact its first or last values are held.
    fn covers(
        &self,
        path: &Path,
        t_sim: &[f64],
        (t, d): (&[f64], &[f64]),
    ) -> Result<(), SimulationError> {
        let first = d.iter().position(|&x| x > 0.0).unwrap_or(0);
        let last = d.iter().rposition(|&x| x > 0.0).unwrap_or(0);
        let n = t_sim.len();
        let slack = (t_sim[n - 1] - t_sim[0]) / (n - 1) as f64;
        let (from, to) = (t_sim[0] - self.s, t_sim[n - 1] - self.s);
        if from > t[first] + slack || to < t[last] - slack {
            return Err(SimulationError::Time {
                path: path.to_path_buf(),
                from_s: from,
                to_s: to,
                contact_from_s: t[first],
                contact_to_s: t[last],
            });
        }
        Ok(())
    }

    fn words(&self, samples: usize, rate_hz: f64, recorded: usize, held: (f64, f64)) -> String {
        let mut held_words = Vec::new();
        if held.0 > 0.0 {
            held_words.push(format!(
                "its first values held over the recording's first {:.3} s",
                held.0
            ));
        }
        if held.1 > 0.0 {
            held_words.push(format!(
                "its last values over the recording's last {:.3} s",
                held.1
            ));
        }
        let held_words = if held_words.is_empty() {
            String::new()
        } else {
            format!("; {} (the rod out of contact there)", held_words.join(", "))
        };
        format!(
            "shifted in time by {:+.4} s (the simulation's t_s = the recording's {} {:.4} s), found by the rod's travel: the two rod paths {:.4} mm apart RMS ({:.2} % of the largest travel, {:.3} mm at most) over the {:.1} s in contact; its {samples} samples ({rate_hz:.4} Hz) interpolated (monotone cubic in time) at the recording's {recorded}{held_words}",
            self.s,
            if self.s < 0.0 { '-' } else { '+' },
            self.s.abs(),
            self.rms_mm,
            100.0 * self.rms_mm / self.largest_mm.max(f64::MIN_POSITIVE),
            self.gap_mm,
            self.contact_s,
        )
    }

    fn numbers(&self, rate_hz: f64, held: (f64, f64)) -> Named<f64> {
        [
            ("time_shift_s", self.s),
            ("rod_rms_mm", self.rms_mm),
            ("rod_max_gap_mm", self.gap_mm),
            ("sample_rate_hz", rate_hz),
            ("held_before_s", held.0),
            ("held_after_s", held.1),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect()
    }
}

/// The first time `y` rises through `level` (linear between samples), if it does.
fn rising(t: &[f64], y: &[f64], level: f64) -> Option<f64> {
    let i = (1..y.len()).find(|&i| y[i - 1] < level && y[i] >= level)?;
    let f = (level - y[i - 1]) / (y[i] - y[i - 1]);
    Some(t[i - 1] + f * (t[i] - t[i - 1]))
}

/// The minimum of `f` on `[a, b]` by golden-section search (`f` unimodal there).
fn golden(f: &dyn Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..SHIFT_STEPS {
        if f1 <= f2 {
            (b, x2, f2) = (x2, x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        } else {
            (a, x1, f1) = (x1, x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        x1
    } else {
        x2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_finds_a_parabola_minimum() {
        let x = golden(&|x| (x - 0.37).powi(2), -2.0, 3.0);
        assert!((x - 0.37).abs() < 1e-9, "{x}");
    }

    #[test]
    fn rising_interpolates_the_crossing() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let y = [0.0, 1.0, 3.0, 1.0];
        assert_eq!(rising(&t, &y, 2.0), Some(1.5));
        assert_eq!(rising(&t, &y, 4.0), None);
    }
}
