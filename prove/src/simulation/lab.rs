//! The lab's own model of the test, and its simulation written as a lab would write it: another
//! contact law and other output laws than ours, run at the lab's guess of the gel's modulus
//! and at its own front end, into a file of either form of `docs/simulation-format.md`.

use std::fmt::Write as _;
use std::path::Path;

use baseline::{evaluate, BaselineParams, Drive, FingertipResponse, Readout, UnitResponse};
use recording::{Channels, Meta, Recording};
use sim::compression::RodHistory;
use sim::effects::EffectSet;

use crate::categories::OtherFingertip;

/// A lumped model of the fingertip: a contact force linear plus cubic in the travel (a spring
/// and a stiffening one, F = F_ref [a u + (1 - a) u^3], u = d / d_ref), an Fz share of the load
/// that falls as the contact spreads (Fz ~ F^0.9) and moments whose arm grows with the travel
/// (M ~ F (1 + b u) / (1 + b)), equal to our FE's chip loads at `d_ref`, per pascal.
pub struct Lumped {
    pub reference: UnitResponse,
    pub d_ref_mm: f64,
    /// The linear share a of the force at `d_ref`.
    pub linear_share: f64,
    /// How fast the moments' arm grows, b.
    pub arm_growth: f64,
}

/// Fz's power of the load in the lumped model.
const FZ_POWER: f64 = 0.9;

impl FingertipResponse for Lumped {
    fn unit_response(&self, rod_mm: f64) -> UnitResponse {
        if rod_mm <= 0.0 {
            return UnitResponse::default();
        }
        let u = rod_mm / self.d_ref_mm;
        let a = self.linear_share;
        let r = a * u + (1.0 - a) * u.powi(3);
        let arm = (1.0 + self.arm_growth * u) / (1.0 + self.arm_growth);
        let c = self.reference.chip;
        UnitResponse {
            force_n: self.reference.force_n * r,
            chip: [c[0] * r.powf(FZ_POWER), c[1] * r * arm, c[2] * r * arm],
        }
    }
}

/// The lab's model: one of two families, neither ours.
pub enum LabModel<'a> {
    PowerLaw(OtherFingertip<'a>),
    Lumped(Lumped),
}

impl LabModel<'_> {
    pub fn response(&self) -> &dyn FingertipResponse {
        match self {
            Self::PowerLaw(m) => m,
            Self::Lumped(m) => m,
        }
    }

    /// In words, for the table.
    pub fn name(&self) -> String {
        match self {
            Self::PowerLaw(m) => format!(
                "power law n = {:.2}, outputs {}",
                m.exponent,
                if m.linear_outputs {
                    "linear in the load"
                } else {
                    "on the FE's map"
                }
            ),
            Self::Lumped(m) => format!(
                "lumped: linear share {:.2} + cubic, Fz ~ F^0.9, arm growth {:.2}",
                m.linear_share, m.arm_growth
            ),
        }
    }
}

/// How the lab writes its simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Form {
    /// A static response table, a row every `step_mm`.
    Table { step_mm: f64 },
    /// The test in time at `rate_hz`: from first contact on (its own t = 0 there) or the whole
    /// test on a time base `shift_s` later than the recording's.
    Series {
        rate_hz: f64,
        from_contact: bool,
        shift_s: f64,
    },
}

impl Form {
    pub fn name(&self) -> String {
        match *self {
            Form::Table { step_mm } => format!("table, {step_mm} mm rows"),
            Form::Series {
                rate_hz,
                from_contact: true,
                ..
            } => format!("test at {rate_hz} Hz from contact"),
            Form::Series {
                rate_hz, shift_s, ..
            } => format!("test at {rate_hz} Hz, t + {shift_s:.2} s"),
        }
    }
}

/// What the lab simulates and at which front end.
pub struct Written<'m> {
    pub model: &'m dyn FingertipResponse,
    /// The lab's guess of the gel (its modulus) with nothing else calibrated.
    pub nominal: BaselineParams,
    /// The front end its outputs are given at (its own gains: bridge volts, say).
    pub readout: Readout,
    /// Channels left empty: load_N, fz_V, mx_V, my_V.
    pub lacks: [bool; 4],
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    pub radius_mm: f64,
    pub source: String,
}

impl Written<'_> {
    /// The simulation of the rod path `history` (the recording's path at the recording's rate;
    /// the lab's rate is the form's) in `form`, written to `path`.
    pub fn write(&self, form: Form, history: &RodPath, path: &Path) -> std::io::Result<()> {
        let text = match form {
            Form::Table { step_mm } => self.table(step_mm, history.largest_mm()),
            Form::Series {
                rate_hz,
                from_contact,
                shift_s,
            } => self.series(&history.at_rate(rate_hz), from_contact, shift_s)?,
        };
        std::fs::write(path, text)
    }

    /// The load and outputs along `rod_mm` (noise-free, no effect), at times `t_s`.
    fn outputs(&self, t_s: Vec<f64>, rod_mm: &[f64]) -> [Vec<f64>; 4] {
        let drive = Drive::new(self.model, t_s, rod_mm);
        let o = evaluate(
            &drive,
            &self.readout,
            &self.nominal,
            &EffectSet::default(),
            self.contact_angle_deg,
            None,
        );
        let [fz, mx, my] = o.volts;
        let mut out = [o.load_n, fz, mx, my];
        for (c, column) in out.iter_mut().enumerate() {
            if self.lacks[c] {
                column.iter_mut().for_each(|v| *v = f64::NAN);
            }
        }
        out
    }

    /// A static response from 0 to past the largest travel, a row every `step_mm`.
    fn table(&self, step_mm: f64, largest_mm: f64) -> String {
        let rows = (1.02 * largest_mm / step_mm).ceil() as usize + 1;
        let rod: Vec<f64> = (0..rows).map(|k| k as f64 * step_mm).collect();
        let out = self.outputs(rod.clone(), &rod);
        let g = self.readout.signal.gain;
        let mut text = format!(
            "# format = tactile-response/1\n# source = {}\n# contact_angle_deg = {}\n\
             # azimuth_deg = {}\n# fingertip_radius_mm = {}\n# gain_fz = {}\n# gain_mx = {}\n\
             # gain_my = {}\n# excitation_V = {}\n",
            self.source,
            self.contact_angle_deg,
            self.azimuth_deg,
            self.radius_mm,
            g[0],
            g[1],
            g[2],
            self.readout.signal.excitation_v
        );
        // A lab leaves out the columns it does not model.
        let names = ["load_N", "fz_V", "mx_V", "my_V"];
        let kept: Vec<usize> = (0..4).filter(|&c| !self.lacks[c]).collect();
        let header: Vec<&str> = kept.iter().map(|&c| names[c]).collect();
        let _ = writeln!(text, "rod_mm,{}", header.join(","));
        for (k, d) in rod.iter().enumerate() {
            let values: Vec<String> = kept.iter().map(|&c| format!("{}", out[c][k])).collect();
            let _ = writeln!(text, "{d},{}", values.join(","));
        }
        text
    }

    /// The simulated test along `h`, on its own time base.
    fn series(&self, h: &RodHistory, from_contact: bool, shift_s: f64) -> std::io::Result<String> {
        let out = self.outputs(h.t_s.clone(), &h.rod_mm);
        // From the last sample before the rod touches, with its own t = 0 at contact.
        let first = if from_contact {
            h.rod_mm
                .iter()
                .position(|&d| d > 0.0)
                .unwrap_or(0)
                .saturating_sub(1)
        } else {
            0
        };
        let t0 = if from_contact { h.t_s[first] } else { -shift_s };
        let [load_n, fz_v, mx_v, my_v] = out.map(|c| c[first..].to_vec());
        let g = self.readout.signal.gain;
        let rec = Recording {
            meta: Meta {
                sample_rate_hz: 1.0 / (h.t_s[1] - h.t_s[0]),
                contact_angle_deg: self.contact_angle_deg,
                azimuth_deg: self.azimuth_deg,
                fingertip_radius_mm: self.radius_mm,
                gain_fz: g[0],
                gain_mx: g[1],
                gain_my: g[2],
                excitation_v: self.readout.signal.excitation_v,
                rod_speed_mm_per_min: None,
                source: Some(self.source.clone()),
                other: Vec::new(),
            },
            channels: Channels {
                t_s: h.t_s[first..].iter().map(|t| t - t0).collect(),
                rod_mm: h.rod_mm[first..].to_vec(),
                load_n,
                fz_v,
                mx_v,
                my_v,
            },
            temp_c: None,
            extra: Vec::new(),
        };
        let mut bytes = Vec::new();
        rec.write_to(&mut bytes)?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }
}

/// The recording's rod path: its schedule and turns, to be sampled at any rate.
pub struct RodPath {
    pub schedule: sim::compression::RodSchedule,
    pub turns_mm: Vec<f64>,
}

impl RodPath {
    pub fn at_rate(&self, rate_hz: f64) -> RodHistory {
        sim::compression::RodSchedule {
            sample_rate_hz: rate_hz,
            ..self.schedule.clone()
        }
        .rod_history(&self.turns_mm)
    }

    pub fn largest_mm(&self) -> f64 {
        self.turns_mm.iter().cloned().fold(0.0, f64::max)
    }
}
