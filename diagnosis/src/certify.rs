//! The certification step (diagnosis-v1's amendment of 2026-11-28): every effect the answer
//! reports carries its evidence as numbers (`evidence_values`) and passes, in code, a test with
//! a stated error rate on the held-out stretch, which no parameter saw; the false-discovery
//! rate is controlled over everything the answer tests. An effect that fails goes to
//! `undecided` with the reason and the test that would decide it, and the fit and verdict are
//! those of the model without it.
//!
//! The held-out test is the sample-split test of a fixed direction. Fitted on the fitting
//! stretch, the effect adds `d` to the model; on the held-out stretch the model without it
//! leaves `r0`, with it `r1 = r0 - d`. Were the effect absent (`r0` noise), `S = sum w^2 d r0`
//! would have mean zero; with it `S` gains `sum w^2 d^2`. `S` is divided by the deviation the
//! residual left *with* the effect gives it, read from contiguous batches of the held-out
//! stretch (`BATCHES`; the residual's correlation within a batch is kept, as in a batch-means
//! estimate): `T = S / sqrt(sum_j (sum_{k in j} w^2 d r1)^2)`, referred to Student's t with
//! Satterthwaite's degrees of freedom (one batch that holds the whole effect leaves one degree).
//! One-sided p-values, then Benjamini–Hochberg at [`FDR_Q`] over the answer's effects.

use baseline::Outputs;

use crate::data::Data;
use crate::misfit::contract_rmse;
use crate::output::{EffectReport, EvidenceValues, Undecided};
use crate::stats::student_t_survival;

/// The false-discovery rate controlled over one answer's effects (Benjamini–Hochberg).
pub(crate) const FDR_Q: f64 = 0.05;

/// Contiguous batches of the held-out stretch in the test's deviation.
const BATCHES: usize = 10;

/// The least share of the bootstrap resamples that must keep a discovered feature.
const MIN_INCLUSION: f64 = 0.5;

/// An effect's part of the model at the full rate: the model with it minus the model without
/// it, per channel (`load_N`, `fz_V`, `mx_V`, `my_V`; an empty vector where it has none).
pub(crate) type Part = [Vec<f64>; 4];

/// What the step leaves: the effects certified, what goes to `undecided`, and the model at the
/// full rate without the effects that went.
pub(crate) struct Certified {
    pub effects: Vec<EffectReport>,
    pub undecided: Vec<Undecided>,
    pub model: Outputs,
    /// Whether any effect went.
    pub demoted: bool,
}

/// Certify `effects` (each with its `part`, `None` for a finding of the calibration's sanity,
/// which is not a term of the model) against the recording `data` and the `model` at the full
/// rate that holds them all; `heldout` and `fitting` mark the two stretches at the full rate.
pub(crate) fn certify(
    data: &Data,
    (fitting, heldout): (&[bool], &[bool]),
    model: &Outputs,
    effects: Vec<(EffectReport, Option<Part>)>,
) -> Certified {
    let mut effects = effects;
    for (e, part) in &mut effects {
        if let Some(p) = part.as_ref() {
            e.evidence_values = Some(values(data, (fitting, heldout), model, e, p));
        }
    }
    control_fdr(&mut effects);
    let mut out = Certified {
        effects: Vec::new(),
        undecided: Vec::new(),
        model: model.clone(),
        demoted: false,
    };
    for (mut e, part) in effects {
        explain_missing_uncertainty(&mut e);
        let failed = failures(&e);
        match part.filter(|_| !failed.is_empty()) {
            Some(p) => {
                subtract(&mut out.model, &p);
                out.undecided.push(demoted(&e, &failed));
                out.demoted = true;
            }
            None => out.effects.push(e),
        }
    }
    out
}

/// The numbers of `e`'s evidence: the criterion's gain as the search found it (or, for a line
/// found at the full rate, from the fitting stretch's chi-square there), the contract's RMSE
/// on the held-out stretch without and with it, and the held-out test's p-value.
fn values(
    data: &Data,
    (fitting, heldout): (&[bool], &[bool]),
    model: &Outputs,
    e: &EffectReport,
    part: &Part,
) -> EvidenceValues {
    let mut without = model.clone();
    subtract(&mut without, part);
    let bic_gain = e
        .evidence_values
        .map(|v| v.bic_gain)
        .filter(|b| b.is_finite())
        .unwrap_or_else(|| full_rate_bic_gain(data, fitting, (&without, model), e.params.0.len()));
    EvidenceValues {
        bic_gain,
        heldout_rmse_without: contract_rmse(data, &without, heldout),
        heldout_rmse_with: contract_rmse(data, model, heldout),
        p_value: Some(heldout_p_value(data, heldout, model, part)),
        q_value: None,
    }
}

/// The one-sided p-value of the held-out test (the module's head).
fn heldout_p_value(data: &Data, heldout: &[bool], model: &Outputs, part: &Part) -> f64 {
    let rows: Vec<usize> = (0..heldout.len()).filter(|&k| heldout[k]).collect();
    let channels: Vec<usize> = (0..4)
        .filter(|&c| data.compared(c) && !part[c].is_empty())
        .collect();
    // Per sample: w^2 d r1 and w^2 d r0 summed over the channels.
    let (mut s0, mut batch) = (0.0, vec![0.0; BATCHES]);
    for (i, &k) in rows.iter().enumerate() {
        for &c in &channels {
            let w2 = data.noise[c].sd().powi(-2);
            let d = part[c][k];
            let r1 = data.full.y[c][k] - model.channel(c)[k];
            s0 += w2 * d * (r1 + d);
            batch[i * BATCHES / rows.len().max(1)] += w2 * d * r1;
        }
    }
    let v: f64 = batch.iter().map(|b| b * b).sum();
    if v <= 0.0 || !v.is_finite() {
        // The effect does not reach the held-out stretch: nothing there can test it.
        return 1.0;
    }
    let df = (v * v / batch.iter().map(|b| b.powi(4)).sum::<f64>()).max(1.0);
    student_t_survival(s0 / v.sqrt(), df)
}

/// BIC gain of a term fitted at the full rate (a line), with `k` parameters, from the
/// chi-square of the fitting stretch without and with it (white weights, as it was found).
fn full_rate_bic_gain(
    data: &Data,
    fitting: &[bool],
    (without, with): (&Outputs, &Outputs),
    k: usize,
) -> f64 {
    let chi2 = |m: &Outputs| -> f64 {
        (0..4)
            .filter(|&c| data.compared(c))
            .map(|c| {
                let w2 = data.noise[c].sd().powi(-2);
                (0..fitting.len())
                    .filter(|&i| fitting[i])
                    .map(|i| w2 * (data.full.y[c][i] - m.channel(c)[i]).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let n = fitting.iter().filter(|&&b| b).count() as f64;
    n * (chi2(without) / chi2(with).max(1e-300)).ln() - k as f64 * n.ln()
}

/// Benjamini–Hochberg over the effects that were tested: each one's adjusted p-value.
fn control_fdr(effects: &mut [(EffectReport, Option<Part>)]) {
    let mut tested: Vec<(usize, f64)> = effects
        .iter()
        .enumerate()
        .filter_map(|(i, (e, _))| Some((i, e.evidence_values?.p_value?)))
        .collect();
    tested.sort_by(|a, b| a.1.total_cmp(&b.1));
    let m = tested.len() as f64;
    let mut running = 1.0f64;
    for (rank, &(i, p)) in tested.iter().enumerate().rev() {
        running = running.min(p * m / (rank + 1) as f64);
        if let Some(v) = effects[i].0.evidence_values.as_mut() {
            v.q_value = Some(running.min(1.0));
        }
    }
}

/// Says in `e`'s evidence why a parameter carries no uncertainty, where its own sentence does
/// not (the contract: `null` only where none can be computed, and then the evidence says why).
fn explain_missing_uncertainty(e: &mut EffectReport) {
    let missing: Vec<String> = e
        .parameters
        .iter()
        .filter(|p| p.stderr.is_none() && (p.ci_low.is_none() || p.ci_high.is_none()))
        .filter(|p| {
            !e.evidence
                .contains(&format!("No standard error for {}", p.name))
        })
        .map(|p| {
            let why = p
                .note
                .as_deref()
                .unwrap_or("the fit's covariance does not resolve it");
            format!("{} ({why})", p.name)
        })
        .collect();
    if !missing.is_empty() {
        e.evidence
            .push_str(&format!(" No uncertainty for {}.", missing.join("; ")));
    }
}

/// Why `e` may not be reported, each in words with what would decide it; empty when it passes.
fn failures(e: &EffectReport) -> Vec<(String, &'static str)> {
    let mut why = Vec::new();
    const AGAIN: &str = "a recording that shows its signature again beyond the stretch it is fitted on (another press and release, a longer hold)";
    if let Some(v) = e.evidence_values {
        if !above(v.bic_gain, 0.0) {
            why.push((
                format!(
                    "the criterion does not fall with it (BIC gain {:.1})",
                    v.bic_gain
                ),
                "a longer recording of the same test",
            ));
        }
        if !above(v.heldout_rmse_without, v.heldout_rmse_with) {
            why.push((
                format!(
                    "the held-out misfit does not fall with it ({} without, {} with)",
                    sig(v.heldout_rmse_without),
                    sig(v.heldout_rmse_with)
                ),
                AGAIN,
            ));
        }
        if let Some(q) = v.q_value.filter(|&q| above(q, FDR_Q) || q.is_nan()) {
            why.push((format!("the held-out test does not support it (p = {}, {} after controlling the false-discovery rate at {FDR_Q})", sig(v.p_value.unwrap_or(f64::NAN)), sig(q)), AGAIN));
        }
    }
    for (feature, share) in e.inclusion.iter().flat_map(|n| &n.0) {
        if *share < MIN_INCLUSION {
            why.push((format!("its feature {feature} was kept in only {:.0} % of the bootstrap resamples", 100.0 * share), "a recording whose protocol moves this feature apart from the others (a hold, an unloading, a second speed)"));
        }
    }
    for p in &e.parameters {
        if within_error(p) {
            why.push((
                format!(
                    "{} = {} lies within its own uncertainty of zero",
                    p.name,
                    sig(p.value)
                ),
                "a longer or quieter recording that resolves it",
            ));
        }
    }
    why
}

/// `a > b`, false where either is not a number (a test not made is not passed).
fn above(a: f64, b: f64) -> bool {
    a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater)
}

/// Whether a parameter's interval holds zero: |value| below its standard error, or zero
/// inside its 95 % interval. A value at a bound is a bound, not an estimate.
fn within_error(p: &crate::output::ParamDetail) -> bool {
    if p.at_bound {
        return false;
    }
    let by_se = p.stderr.is_some_and(|se| p.value.abs() < se);
    let by_ci = matches!((p.ci_low, p.ci_high), (Some(lo), Some(hi)) if lo <= 0.0 && hi >= 0.0);
    by_se || by_ci
}

/// `e` as a finding the answer cannot report: its parameters, why, and what would decide.
fn demoted(e: &EffectReport, failed: &[(String, &'static str)]) -> Undecided {
    let why: Vec<&str> = failed.iter().map(|f| f.0.as_str()).collect();
    let mut decide: Vec<&str> = failed.iter().map(|f| f.1).collect();
    decide.dedup();
    Undecided {
        effects: vec![e.name.clone()],
        calibration: Vec::new(),
        params: e.params.clone(),
        reason: format!(
            "{} on {} fits the fitting stretch but is not certified: {}. What would decide: {}",
            e.name,
            e.channels.join(", "),
            why.join("; "),
            decide.join("; or ")
        ),
    }
}

/// A number to three significant figures.
fn sig(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let decimals = 2 - x.abs().log10().floor() as i32;
    if (0..=6).contains(&decimals) {
        format!("{x:.*}", decimals as usize)
    } else {
        format!("{x:.2e}")
    }
}

fn subtract(o: &mut Outputs, part: &Part) {
    for (c, p) in part.iter().enumerate() {
        let m = if c == 0 {
            &mut o.load_n
        } else {
            &mut o.volts[c - 1]
        };
        m.iter_mut().zip(p).for_each(|(a, b)| *a -= b);
    }
}

#[cfg(test)]
mod tests;
