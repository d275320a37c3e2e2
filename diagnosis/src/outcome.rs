//! What a diagnosis of one recording gives: OUT.json's content ([`Report`]) and what the HTML
//! report plots ([`PlotData`]). The last step (`steps::assemble`) builds it; the report, a
//! session and a joint diagnosis read it.
use crate::data::Data;
use crate::output::Report;
use crate::regimes::Segment;
use crate::stretches::Stretches;
use crate::terms::TermCurve;

/// Everything the HTML report plots.
pub struct PlotData {
    /// Time of the decimated series, s.
    pub t_s: Vec<f64>,
    /// The recording's load_N, fz_V, mx_V, my_V, decimated.
    pub recorded: [Vec<f64>; 4],
    /// The calibrated baseline on the same time base.
    pub baseline: [Vec<f64>; 4],
    /// The chosen model on the same time base.
    pub improved: [Vec<f64>; 4],
    /// The regimes of the test.
    pub segments: Vec<Segment>,
    /// Start and end of the held-out stretch, s.
    pub heldout: (f64, f64),
    /// Channels compared (a range above the noise).
    pub used: [bool; 4],
    /// The rod's travel on the same time base, mm.
    pub rod_mm: Vec<f64>,
    /// Each discovered effect on its first channel.
    pub terms: Vec<TermCurve>,
}

impl PlotData {
    /// The recording `data` and its `baseline` on the fitting series, with `stretches`; the
    /// improved model the baseline until set.
    pub(crate) fn of(
        data: &Data,
        baseline: [Vec<f64>; 4],
        stretches: &Stretches,
        used: [bool; 4],
    ) -> Self {
        PlotData {
            t_s: data.fit.t_s.clone(),
            recorded: data.fit.y.clone(),
            improved: baseline.clone(),
            baseline,
            segments: stretches.segments.clone(),
            heldout: stretches.heldout,
            used,
            rod_mm: data.fit.rod_mm.clone(),
            terms: Vec::new(),
        }
    }
}

/// The diagnosis of one recording: OUT.json's content and the report's plots.
pub struct Diagnosis {
    /// What OUT.json holds (`docs/diagnosis-format.md`).
    pub report: Report,
    /// What the HTML report plots.
    pub plots: PlotData,
    /// The catalogue effects found at a stage other than the catalogue's, which a session
    /// holds as this diagnosis found them.
    pub(crate) at_stage: Option<crate::terms::AtStage>,
    /// What the discovery step found ([`crate::terms::discover`]), on both series.
    pub(crate) discovered: Option<crate::terms::AtStage>,
}
