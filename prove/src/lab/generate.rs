//! The lab sessions' recordings: each test of a design simulated on the session's sensor, with
//! the shared effects and its own, at its own rate, gains and excitation.

use rayon::prelude::*;
use sim::compression::RodSchedule;
use sim::effects::{AmplifierSaturation, Effect};

use super::design::{self, Family, LabKind, Own, SessionDesign, TestDesign};
use crate::categories::OtherFingertip;
use crate::{peak_output_v, Plan};
use baseline::fe_response::{AngleBlend, FeResponseError};
use baseline::synth::{simulate, SimSpec};
use baseline::FingertipResponse;
use recording::Recording;

/// A generated lab session: its design (the truth) and its recordings.
pub struct LabCase {
    pub design: SessionDesign,
    /// Each test's file name and recording, in the design's order.
    pub recordings: Vec<(String, Recording)>,
    /// Each test's own effects as simulated (a clip's rail in volts), in the design's order.
    pub own: Vec<Vec<Effect>>,
}

impl LabCase {
    /// The file name of test `i` of session `id`.
    pub fn file_name(id: usize, i: usize) -> String {
        format!("lab{id:02}-{i}.csv")
    }
}

impl Plan {
    /// Every lab session's design: `per_kind` rounds of every kind (of `only`, when given),
    /// numbered round by round, so a session's id, and so its recordings, depend neither on
    /// `only` nor on later rounds.
    pub fn lab_designs(&self, per_kind: usize, only: Option<LabKind>) -> Vec<SessionDesign> {
        let mut designs = Vec::new();
        let mut id = 0;
        for round in 0..per_kind {
            for kind in LabKind::ALL {
                let n = kind.sessions_per_round();
                for k in 0..n {
                    if only.is_none_or(|o| o == kind) {
                        let j = round * n + k;
                        designs.push(design::draw(self.seed, self.sample_rate_hz, id, kind, j));
                    }
                    id += 1;
                }
            }
        }
        designs
    }

    /// The designs' sessions simulated (in parallel, each test from its own seed).
    pub fn lab_sessions(
        &self,
        per_kind: usize,
        only: Option<LabKind>,
    ) -> Result<Vec<LabCase>, FeResponseError> {
        self.lab_designs(per_kind, only)
            .into_par_iter()
            .map(|d| self.lab_case(d))
            .collect()
    }

    /// One design's recordings.
    pub fn lab_case(&self, design: SessionDesign) -> Result<LabCase, FeResponseError> {
        let mut recordings = Vec::new();
        let mut own = Vec::new();
        for (i, t) in design.tests.iter().enumerate() {
            let (rec, effects) = self.lab_test(&design, t)?;
            recordings.push((LabCase::file_name(design.id, i), rec));
            own.push(effects);
        }
        Ok(LabCase {
            design,
            recordings,
            own,
        })
    }

    /// One test of a session: the sensor's truth with this test's jig, rate, gains and
    /// excitation, the shared effects and its own.
    fn lab_test(
        &self,
        d: &SessionDesign,
        t: &TestDesign,
    ) -> Result<(Recording, Vec<Effect>), FeResponseError> {
        let fe = self
            .options
            .fe
            .response(self.radius_mm, t.contact_angle_deg, t.azimuth_deg)?;
        let mut base = d.base;
        base.azimuth_shift_deg = t.azimuth_shift_deg;
        let mut readout = self.readout;
        for (g, f) in readout.signal.gain.iter_mut().zip(t.gain_factor) {
            *g *= f;
        }
        readout.signal.excitation_v *= t.excitation_factor;
        let other = other_fingertip(d, &fe, base.youngs_modulus_pa);
        let fingertip: &dyn FingertipResponse = match &other {
            Some(o) => o,
            None => &fe,
        };
        let own: Vec<Effect> = t
            .own
            .map(|o| match o {
                Own::Drift(e) => Effect::ThermalDrift(e),
                Own::Mains(e) => Effect::MainsInterference(e),
                Own::Clip { share } => Effect::AmplifierSaturation(AmplifierSaturation {
                    limit_v: share * peak_output_v(fingertip, &readout, &base, t.peaks_n[1]),
                }),
            })
            .into_iter()
            .collect();
        let spec = SimSpec {
            fingertip,
            readout,
            baseline: base,
            contact_angle_deg: t.contact_angle_deg,
            azimuth_deg: t.azimuth_deg,
            radius_mm: self.radius_mm,
            test: RodSchedule {
                sample_rate_hz: t.sample_rate_hz,
                recovery_s: 45.0,
                speed_mm_per_min: t.speed_mm_per_min,
                ..Default::default()
            },
            peak_loads_n: t.peaks_n.to_vec(),
            effects: [d.shared.clone(), own.clone()].concat(),
            noise: d.noise,
            seed: t.seed,
            ambient_c: 24.0,
            // Only a test whose chip warms up (its own drift) sees its temperature rise.
            warm_up_rise_c: 6.0,
            ambient_swing: None,
            source: "tactile prove (lab session)".into(),
        };
        Ok((simulate(&spec), own))
    }
}

/// Another model's fingertip where the session is pressed on one: its force law meets the FE's
/// at the session's peak load.
fn other_fingertip<'a>(
    d: &SessionDesign,
    fe: &'a AngleBlend,
    modulus_pa: f64,
) -> Option<OtherFingertip<'a>> {
    let Family::Other {
        exponent,
        linear_outputs,
    } = d.family
    else {
        return None;
    };
    Some(OtherFingertip {
        fe,
        exponent,
        d_ref_mm: sim::compression::rod_at_load(
            |r| fe.unit_response(r).force_n * modulus_pa,
            d.reference_n,
            60.0,
        ),
        linear_outputs,
    })
}
