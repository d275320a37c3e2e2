//! Physical sanity of the calibration, before it is taken as a fit: the calibration may give an
//! output any sensitivity scale (`hardware/fit-bounds.toml`), so a channel wired with its sign
//! inverted, or a gain tens of percent off the metadata, would otherwise be absorbed silently.
//!
//! - An inverted sign: an output's calibrated scale is negative, so it reads minus the model's
//!   output. It is a finding when it passes the catalogue's two tests against the best model
//!   that keeps the model's sign, which for a scale that wants to be negative is the scale at
//!   zero, the channel a constant (its weighted mean over the fitting stretch):
//!
//!   ```text
//!   y = offset - |s| m(t)   against   y = c
//!   ```
//!
//! - A dead channel: an output whose recorded range stays within ten noise deviations (so it is
//!   not compared) while the model, at the metadata's gains, swings well beyond them. It must
//!   pass the same tests: the constant it reads against the model's swing.
//! - A gain off the metadata by more than [`GAIN_TOLERANCE`] beyond two standard errors: the
//!   metadata's gain or the transducer's sensitivity, which one a single recording cannot say,
//!   so it is reported as undecided.

use super::fitting::Context;
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};
use crate::data::CHANNELS;
use crate::output::{Numbers, ParamDetail, Undecided};
use sim::effects::Stage;

/// A calibrated gain further than this from the metadata's (as a factor) is a finding: the
/// amplifiers' gain resistors hold 1 %, and a chip's sensitivity that is tens of percent from
/// its data sheet is a chip to question, not to calibrate silently.
pub(crate) const GAIN_TOLERANCE: f64 = 0.2;

/// A finding of the calibration's sanity, as an effect of the contract.
pub(crate) struct SanityFinding {
    pub name: &'static str,
    pub stage: Stage,
    pub channels: Vec<usize>,
    pub params: Vec<(&'static str, f64, String)>,
    pub depends_on: Vec<&'static str>,
    pub form: String,
    pub evidence: String,
    /// The channel's model to plot and to score at the full rate is unchanged.
    pub bic_gain: f64,
    pub heldout_ratio: f64,
}

/// The outputs read with their sign inverted, each as a finding.
pub(crate) fn inverted_signs(
    ctx: &Context,
    details: &[ParamDetail],
    nested_n: usize,
) -> Vec<SanityFinding> {
    (1..4)
        .filter(|&c| ctx.used[c])
        .filter_map(|c| {
            let scale = details
                .iter()
                .find(|p| p.name == format!("scale_{}", &CHANNELS[c][..2]))?;
            if scale.value >= 0.0 {
                return None;
            }
            let (bic_gain, ratio) = against_constant(ctx, c, nested_n, false)?;
            let name = super::channel_words(c);
            Some(SanityFinding {
                name: "inverted_sign",
                stage: Stage::Electronics,
                channels: vec![c],
                params: vec![("gain_factor", scale.value, "1".into())],
                depends_on: vec!["load_N"],
                form: format!(
                    "{name} reads {:.3} x the model's output: its sign is inverted",
                    scale.value
                ),
                evidence: format!(
                    "{name} moves against the load where the model says it moves with it: its calibration needs a negative sensitivity ({:.3} x the metadata's gain), which no transducer has; its wiring or sign convention is inverted.",
                    scale.value
                ),
                bic_gain,
                heldout_ratio: ratio,
            })
        })
        .collect()
}

/// Outputs that read a constant while the model, at the metadata's gains, swings: dead or
/// disconnected; all three at once are one dead sensor.
pub(crate) fn dead_channels(ctx: &Context, nested_n: usize) -> Vec<SanityFinding> {
    let dead: Vec<(usize, f64, f64, f64)> = (1..4)
        .filter(|&c| !ctx.used[c] && ctx.outputs_in_volts)
        .filter_map(|c| {
            let noise = ctx.data.noise[c].sd();
            let swing = crate::data::peak_to_peak(ctx.model[c].iter().copied());
            if swing <= 10.0 * noise.max(ctx.data.range[c] / 10.0) {
                return None;
            }
            let (bic_gain, ratio) = against_constant(ctx, c, nested_n, true)?;
            (bic_gain > MIN_BIC_GAIN).then_some((c, swing, bic_gain, ratio))
        })
        .collect();
    if dead.is_empty() {
        return Vec::new();
    }
    let level = |c: usize| {
        let y = &ctx.data.fit.y[c];
        y.iter().sum::<f64>() / y.len().max(1) as f64
    };
    let channels: Vec<usize> = dead.iter().map(|d| d.0).collect();
    let names: Vec<&str> = channels.iter().map(|&c| super::channel_words(c)).collect();
    let all = channels.len() == 3;
    let (bic_gain, ratio) = (dead[0].2, dead[0].3);
    let mut params = Vec::new();
    for &(c, swing, _, _) in &dead {
        params.push((level_name(c), level(c), "V".into()));
        params.push((swing_name(c), swing, "V".into()));
    }
    let what = if all {
        "The sensor is dead or disconnected: all its outputs".to_string()
    } else {
        format!("Dead or disconnected: {}", names.join(" and "))
    };
    Vec::from([SanityFinding {
        name: if all { "dead_sensor" } else { "dead_channel" },
        stage: Stage::Electronics,
        channels,
        params,
        depends_on: Vec::new(),
        form: format!(
            "{} read a constant (within their noise) while the rod and the load move",
            names.join(", ")
        ),
        evidence: format!(
            "{what} read a constant within their noise while the rod moves and the load cell swings by {:.3} N; at the metadata's gains the model expects a swing of {:.3} V. Nothing from the bridges reaches the recording: check the cable, the supply and the converter.",
            ctx.data.range[0], dead[0].1
        ),
        bic_gain,
        heldout_ratio: ratio,
    }])
}

fn level_name(c: usize) -> &'static str {
    ["load_level", "fz_level_V", "mx_level_V", "my_level_V"][c]
}

fn swing_name(c: usize) -> &'static str {
    [
        "load_swing",
        "fz_expected_swing_V",
        "mx_expected_swing_V",
        "my_expected_swing_V",
    ][c]
}

/// The model's channel `c` against a constant (its weighted mean over the fitting stretch):
/// the BIC gain and held-out chi-square ratio of whichever the finding says is right (the
/// constant for a dead channel, the model for an inverted one), None where it fails either
/// test.
fn against_constant(ctx: &Context, c: usize, n: usize, constant_wins: bool) -> Option<(f64, f64)> {
    let (mut sw, mut swy) = (0.0, 0.0);
    for k in (0..ctx.len()).filter(|&k| ctx.fit_mask[k]) {
        let w2 = ctx.data.weight(c, k).powi(2);
        sw += w2;
        swy += w2 * ctx.data.fit.y[c][k];
    }
    let level = swy / sw.max(1e-300);
    let constant: Vec<f64> = ctx.model[c].iter().map(|m| level - m).collect();
    let chi2 = |part: Option<&[f64]>, mask: &[bool]| ctx.chi2(c, part, mask);
    let (model_fit, const_fit) = (
        chi2(None, ctx.fit_mask),
        chi2(Some(&constant), ctx.fit_mask),
    );
    let (model_held, const_held) = (
        chi2(None, ctx.heldout_mask),
        chi2(Some(&constant), ctx.heldout_mask),
    );
    let ((small_fit, large_fit), (small_held, large_held)) = if constant_wins {
        ((model_fit, const_fit), (model_held, const_held))
    } else {
        ((const_fit, model_fit), (const_held, model_held))
    };
    let n = n as f64;
    // The two differ by the channel's scale: one parameter.
    let bic_gain = n * (small_fit / large_fit.max(1e-300)).ln() - n.ln();
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.heldout_mask[k]).collect();
    let blocks: Vec<(usize, usize)> = rows.iter().map(|&k| ctx.data.bounds[k]).collect();
    let coefficients: Vec<f64> = rows
        .iter()
        .map(|&k| constant[k] * ctx.data.weight(c, k).powi(2))
        .collect();
    let diff = ctx.data.noise[c]
        .block_means_variance(&blocks, &coefficients)
        .max(0.0)
        .sqrt();
    let passes =
        bic_gain > MIN_BIC_GAIN && small_held - large_held > heldout_needed(diff, small_held);
    passes.then_some((bic_gain, small_held / large_held.max(1e-300)))
}

/// Calibrated output gains off the metadata's by more than [`GAIN_TOLERANCE`] (two standard
/// errors beyond it), as undecided between the metadata and the transducer.
pub(crate) fn gains_off(details: &[ParamDetail]) -> Option<Undecided> {
    let off: Vec<&ParamDetail> = details
        .iter()
        .filter(|p| p.name.starts_with("scale_") && p.value > 0.0)
        .filter(|p| {
            let ln_off = p.value.ln().abs() - (1.0 + GAIN_TOLERANCE).ln();
            ln_off > 2.0 * p.stderr.unwrap_or(0.0) / p.value
        })
        .collect();
    if off.is_empty() {
        return None;
    }
    let mut params = Numbers::default();
    for p in &off {
        params.push(
            &format!("{}_factor", p.name.trim_start_matches("scale_")),
            p.value,
        );
    }
    let words: Vec<String> = off
        .iter()
        .map(|p| {
            format!(
                "{} {:+.0} %",
                p.name.trim_start_matches("scale_").to_uppercase(),
                100.0 * (p.value - 1.0)
            )
        })
        .collect();
    Some(Undecided {
        effects: Vec::new(),
        calibration: off.iter().map(|p| p.name.clone()).collect(),
        params,
        reason: format!(
            "the outputs need gains off the metadata's ({}), beyond the {:.0} % that the amplifiers and a chip's spread allow: either the gains in the metadata are wrong (electronics) or the chip's sensitivity or the load's share to it is (transducer); one recording cannot tell them apart (a check with a known load on the sensor alone would)",
            words.join(", "),
            100.0 * GAIN_TOLERANCE
        ),
    })
}
