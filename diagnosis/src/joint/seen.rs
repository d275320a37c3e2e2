//! Each analysed recording as the session's model sees it, for its verdict and the page: the
//! session's model on the recording's fitting time base (the decimated series every fit uses),
//! in the recording's own frame, beside its recorded series and its baseline calibrated to it
//! alone; whether what the model leaves is noise; and, where it is not, where and how it still
//! misses.

use super::output::Remaining;
use super::search::Fitted;
use super::Members;
use crate::data::CHANNELS;
use crate::fit::{Model, N_BASE};
use crate::localise::mismatches;
use crate::outcome::PlotData;
use crate::report::{remains, words};

/// The windows of a residual named in `Remaining`: at most this many, each holding at least
/// [`MIN_SHARE`] of what the model leaves (the single diagnosis's `mismatches` keep 2 %).
const MAX_WINDOWS: usize = 3;
const MIN_SHARE: f64 = 0.02;

/// Recording `r` under the session's fit.
pub(crate) struct Seen {
    /// Its series: recorded, the baseline calibrated to it alone, and as `improved` the
    /// session's model, all in the recording's own frame, with the session's held-out stretch.
    pub plots: PlotData,
    /// Whether what the session's model leaves on every compared channel is noise (the single
    /// diagnosis's test, [`crate::misfit::white`]).
    pub white: bool,
}

/// Recording `r` under the session's fit `f`. On the channels in `own_terms` the recording
/// keeps terms of its own diagnosis beyond the catalogue, which the session's fit does not
/// carry: there its model is its own diagnosis's (catalogue and terms), as its row says.
pub(crate) fn seen(m: &Members, f: &Fitted, r: usize, own_terms: &[usize]) -> Seen {
    let setup = m.setups[r];
    let full = &f.fit.full[r];
    let outputs =
        Model::new(setup, &f.layout.kinds(r), &full[..N_BASE]).outputs(full, &setup.drive);
    let single = &m.diags[r].plots;
    let frame = Frame::of(m, r);
    let same_base = single.t_s.len() == setup.data.fit.t_s.len();
    // The model in the session's frame (what its fit saw), for the whiteness test.
    let session: [Vec<f64>; 4] = std::array::from_fn(|c| {
        if same_base && own_terms.contains(&c) {
            frame.to_session(c, &single.improved[c])
        } else {
            outputs.channel(c).to_vec()
        }
    });
    let white = crate::misfit::white(setup, &session);
    let plots = if same_base {
        PlotData {
            t_s: single.t_s.clone(),
            recorded: single.recorded.clone(),
            baseline: single.baseline.clone(),
            improved: std::array::from_fn(|c| frame.to_recorded(c, &session[c])),
            segments: single.segments.clone(),
            heldout: m.prepared[r].heldout(),
            used: setup.used,
            rod_mm: single.rod_mm.clone(),
            terms: Vec::new(),
        }
    } else {
        // Not expected: the session reads the recording as its own diagnosis did. Drawn in the
        // session's frame then, without the baseline.
        PlotData {
            t_s: setup.data.fit.t_s.clone(),
            recorded: setup.data.fit.y.clone(),
            baseline: std::array::from_fn(|c| vec![f64::NAN; setup.data.fit.y[c].len()]),
            improved: session,
            segments: Vec::new(),
            heldout: m.prepared[r].heldout(),
            used: setup.used,
            rod_mm: setup.data.fit.rod_mm.clone(),
            terms: Vec::new(),
        }
    };
    Seen { plots, white }
}

/// How the session's reading of a recording differs from the recording: a catalogue effect its
/// own diagnosis found at another stage taken out, then a sign turned back
/// ([`crate::prepared::Prepared::for_session`]).
pub(super) struct Frame<'d> {
    part: Option<&'d [Vec<f64>; 4]>,
    sign: [f64; 4],
}

impl<'d> Frame<'d> {
    pub(super) fn of(m: &'d Members, r: usize) -> Self {
        let flipped = m.flipped.get(r).map_or(&[][..], Vec::as_slice);
        Frame {
            part: m.diags[r].at_stage.as_ref().map(|a| &a.decimated),
            sign: std::array::from_fn(|c| if flipped.contains(&c) { -1.0 } else { 1.0 }),
        }
    }

    fn held(&self, c: usize, k: usize) -> f64 {
        self.part.and_then(|p| p[c].get(k)).copied().unwrap_or(0.0)
    }

    /// Channel `c` read as the session read it: `sign (v - part)`.
    pub(super) fn to_session(&self, c: usize, v: &[f64]) -> Vec<f64> {
        v.iter()
            .enumerate()
            .map(|(k, &x)| self.sign[c] * (x - self.held(c, k)))
            .collect()
    }

    /// Channel `c` of the session's reading in the recording's frame: `sign v + part`.
    fn to_recorded(&self, c: usize, v: &[f64]) -> Vec<f64> {
        v.iter()
            .enumerate()
            .map(|(k, &x)| self.sign[c] * x + self.held(c, k))
            .collect()
    }
}

/// Where and how the model in `p.improved` still misses: the regime windows holding the
/// largest shares of its residual, and each channel's residual in words where it shows a
/// trend, a period or a dependence on the load ([`remains`]).
pub(crate) fn remaining(p: &PlotData) -> Remaining {
    let residual: [Vec<f64>; 4] = std::array::from_fn(|c| {
        p.recorded[c]
            .iter()
            .zip(&p.improved[c])
            .map(|(a, b)| a - b)
            .collect()
    });
    let range: [f64; 4] = std::array::from_fn(|c| {
        let (lo, hi) = p.recorded[c]
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        (hi - lo).max(1e-300)
    });
    let mut windows = mismatches(&p.t_s, &p.segments, &residual, &range, &p.used, MIN_SHARE);
    windows.truncate(MAX_WINDOWS);
    let remains = remains::analyse(p);
    Remaining {
        windows,
        character: words::remainder_phrase(&remains),
        channels: remains.iter().filter_map(words::remains_sentence).collect(),
    }
}

/// The calibration's own findings (`terms::sanity`): a sign the session turns back itself, a
/// channel that reads nothing. Not terms a model carries.
const SANITY: [&str; 3] = ["inverted_sign", "dead_channel", "dead_sensor"];

/// The channel indices (of [`CHANNELS`]) that the terms beyond the catalogue among `effects`
/// (a recording's own diagnosis's) act on.
pub(crate) fn term_channels(effects: &[crate::output::EffectReport]) -> Vec<usize> {
    (0..4)
        .filter(|&c| {
            effects
                .iter()
                .filter(|e| !e.catalogue && !SANITY.contains(&e.name.as_str()))
                .any(|e| e.channels.iter().any(|n| n == CHANNELS[c]))
        })
        .collect()
}
