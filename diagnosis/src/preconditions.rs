//! What a recording's protocol and channels can show, and so which catalogue effects may even be
//! fitted. An effect whose signature the recording cannot contain is not a candidate: fitted
//! anyway, its operator would only bend the model towards whatever else is missing (a lag on a
//! single ramp is a modulus change; a loop without unloading is a curvature).

use baseline::Drive;
use sim::effects::EffectKind;

use crate::data::Data;
use crate::regimes::{Regime, Segment};

/// Lowest mains frequency the line search looks for (`mains::BAND_HZ`).
const LOWEST_MAINS_HZ: f64 = 45.0;

/// Whether a recording sampled at `sample_rate_hz` can show a mains line: its Nyquist
/// frequency must lie above the lowest mains frequency. Below it a line aliases to whatever
/// slow wave the sampling makes of it, which no line search can attribute.
pub fn mains_visible(sample_rate_hz: f64) -> bool {
    sample_rate_hz > 2.0 * LOWEST_MAINS_HZ
}

/// The features of a recording that catalogue signatures need.
#[derive(Debug, Clone, PartialEq)]
pub struct Features {
    /// A stretch where the rod stays still in contact (a relaxation decays there).
    pub hold: bool,
    /// An unloading path covering a real share of the loading path (a loop needs both).
    pub unloading: bool,
    /// The rod's speed in contact changes (start, stop, reversal, a different rate): a lag or a
    /// rate-dependent response shows only where the speed changes.
    pub rate_change: bool,
    /// A stretch out of contact (rest or recovery), where a drift shows unrelated to load.
    pub rest: bool,
    /// A measured temperature that moves beyond its noise.
    pub temperature: bool,
    /// Which of load_N, fz_V, mx_V, my_V are compared (measured, range above noise).
    pub used: [bool; 4],
    /// Full sample rate, Hz.
    pub sample_rate_hz: f64,
    /// The baseline's moment vector lies off both moment axes (beyond the jig's mounting
    /// accuracy), so the two calibrated moment scales can turn it as a rotated chip would.
    pub moment_scales_turn: bool,
}

impl Features {
    /// Read the protocol from the regimes detected on the fitting series.
    pub fn of(data: &Data, segments: &[Segment], used: [bool; 4], temperature: bool) -> Self {
        let t = &data.fit.t_s;
        let rod = &data.fit.rod_mm;
        let peak = rod.iter().cloned().fold(0.0, f64::max);
        let span = |s: &Segment| t[s.end - 1] - t[s.start];
        let travel = |s: &Segment| (rod[s.start] - rod[s.end - 1]).abs();
        let has = |r: Regime| {
            segments
                .iter()
                .any(|s| s.regime == r && s.end > s.start + 1)
        };
        // Unloading must cover a quarter of the peak travel: a loop's two branches have to be
        // compared over a load range, not at an overshoot's tip.
        let unloading_travel: f64 = segments
            .iter()
            .filter(|s| s.regime == Regime::Release)
            .map(travel)
            .sum();
        // A hold of half a second or more: shorter stops are a ramp's turn-round, which counts
        // as a change of speed below but shows no decay under a held rod.
        let hold = segments
            .iter()
            .any(|s| s.regime == Regime::Hold && rod[s.start] > 0.0 && span(s) >= 0.5);
        let unloading = peak > 0.0 && unloading_travel > 0.25 * peak;
        let full = &data.full.t_s;
        let sample_rate_hz = if full.len() > 1 {
            (full.len() - 1) as f64 / (full[full.len() - 1] - full[0]).max(1e-9)
        } else {
            0.0
        };
        Self {
            hold,
            unloading,
            rate_change: hold || unloading || loading_speeds_differ(t, rod, segments),
            rest: has(Regime::Rest) || has(Regime::Recovery),
            temperature,
            used,
            sample_rate_hz,
            moment_scales_turn: false,
        }
    }

    /// The same protocol with the baseline's moment direction `phi_rad` (atan2(My, Mx)); a
    /// direction within `tolerance_deg` of an axis leaves one moment channel near zero, which no
    /// scale turns.
    pub fn with_moment_direction(self, phi_rad: Option<f64>, tolerance_deg: f64) -> Self {
        let off_axis = phi_rad.is_some_and(|phi| {
            let (s, c) = phi.sin_cos();
            s.abs().min(c.abs()) > tolerance_deg.to_radians().sin()
        });
        Self {
            moment_scales_turn: off_axis,
            ..self
        }
    }

    /// `Ok` when the recording can show `kind`'s signature, else the reason in words.
    pub fn allows(&self, kind: EffectKind) -> Result<(), String> {
        use EffectKind::*;
        let outputs = self.used[1] || self.used[2] || self.used[3];
        // Only the gel's effects act on the load; the rest change the sensor's outputs alone,
        // so without a measured output they have nothing to act on.
        if !matches!(kind, ViscoelasticRelaxation | Hysteresis) && !outputs {
            return Err(
                "precondition: no sensor output measured (it acts on the outputs only)".into(),
            );
        }
        self.protocol_allows(kind)
    }

    /// Whether the protocol can show `kind` wherever it acts (the load cell's channel
    /// included): [`Self::allows`] without its demand for a sensor output, for the library's
    /// terms that meet a catalogue entry at another stage.
    pub fn protocol_allows(&self, kind: EffectKind) -> Result<(), String> {
        use EffectKind::*;
        let moments = self.used[2] && self.used[3];
        match kind {
            Hysteresis if !self.unloading => Err("precondition: no unloading path (a loop needs loading and unloading over a quarter of the travel)".into()),
            ViscoelasticRelaxation if !self.rate_change => Err("precondition: no hold and no change of rod speed (relaxation shows only as decay under a held rod or as rate dependence)".into()),
            HighpassCoupling if !(self.hold || self.unloading) => Err("precondition: no hold and no unloading (AC coupling shows as sag under constant load or undershoot after release)".into()),
            TimeOffset if !self.rate_change => Err("precondition: the rod speed never changes (a lag on a constant-speed ramp is a shift of the contact point, which calibration absorbs)".into()),
            ThermalDrift if !(self.rest || self.temperature) => Err("precondition: no stretch out of contact and no measured temperature (drift shows at rest, unrelated to load)".into()),
            Crosstalk | ContactFriction if !moments => Err("precondition: the two moment channels are not both measured".into()),
            Crosstalk if self.moment_scales_turn => Err("precondition: one direction of load with the moment off both axes: a rotated chip is the two moment scales' ratio, which calibration absorbs (see `undecided`)".into()),
            MainsInterference if !mains_visible(self.sample_rate_hz) => Err(format!(
                "precondition: sample rate {:.0} Hz cannot show a 45-65 Hz line (Nyquist {:.0} Hz)",
                self.sample_rate_hz,
                self.sample_rate_hz / 2.0
            )),
            _ => Ok(()),
        }
    }
}

/// Whether the loading speeds in contact differ by more than a factor two between loading
/// segments (a staircase of rates), which makes a rate-dependent response visible.
fn loading_speeds_differ(t: &[f64], rod: &[f64], segments: &[Segment]) -> bool {
    let speeds: Vec<f64> = segments
        .iter()
        .filter(|s| s.regime == Regime::Loading && s.end > s.start + 1)
        .filter_map(|s| {
            let dt = t[s.end - 1] - t[s.start];
            (dt > 0.0).then(|| (rod[s.end - 1] - rod[s.start]) / dt)
        })
        .collect();
    let max = speeds.iter().cloned().fold(0.0, f64::max);
    let min = speeds.iter().cloned().fold(f64::INFINITY, f64::min);
    speeds.len() > 1 && max > 2.0 * min
}

/// The direction atan2(My, Mx) of the baseline's chip moment at the drive's largest moment.
pub(crate) fn moment_direction(drive: &Drive) -> Option<f64> {
    let m = drive.units().max_by(|a, b| {
        a.chip[1]
            .hypot(a.chip[2])
            .total_cmp(&b.chip[1].hypot(b.chip[2]))
    })?;
    (m.chip[1] != 0.0 || m.chip[2] != 0.0).then(|| m.chip[2].atan2(m.chip[1]))
}
