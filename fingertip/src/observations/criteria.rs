//! Thresholds of agreement, each argued from the uncertainty of the paper's measurement in
//! `fingertip/OBSERVATIONS.md` ("Criteria").

/// "Larger": a ratio of two separate tests above this (run-to-run repeatability ~2 %).
pub const LARGER_RATIO: f64 = 1.02;
/// "Hardly changes": a ratio within this of 1.
pub const HARDLY_CHANGES: f64 = 0.05;
/// "Nonlinear, a power law": a fitted exponent at least this...
pub const NONLINEAR_EXPONENT: f64 = 1.10;
/// The fit starts at this fraction of the final travel: below it (n ~ 2) the outputs are under
/// a tenth of their peak, in the trace's noise on the paper's linear plots.
pub const POWER_LAW_FROM: f64 = 0.3;
/// ...with an rms log residual of the fit at most this (a power law describes it).
pub const POWER_LAW_RMS: f64 = 0.05;
/// The smallest level a plotted output resolves, as a fraction of its peak.
pub const VISIBLE_FRACTION: f64 = 0.02;
/// "Drop at once": at least this fraction of the peak is gone when the rod is back.
pub const DROP_AT_ONCE: f64 = 0.5;
/// "Slowly over seconds": the time to settle within VISIBLE_FRACTION lies in this range, s.
pub const SLOW_RECOVERY_S: (f64, f64) = (1.0, 60.0);
/// "Crosstalk small": the moment about the tilt direction at most this of the tilt moment.
pub const SMALL_CROSSTALK: f64 = 0.10;
/// "Slight S": the weaker lobe of the S at least VISIBLE_FRACTION and at most this.
pub const SLIGHT_S_MAX: f64 = 0.10;
