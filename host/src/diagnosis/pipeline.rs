//! The diagnosis, start to end: read -> regimes -> calibrate the baseline -> localise -> fit each
//! catalogue effect singly and in pairs -> select by BIC and the held-out stretch together ->
//! mains at full rate -> verdict.

use std::time::Instant;

use rayon::prelude::*;
use sim::effects::EffectKind;

use super::baseline::{Drive, FrontEnd, Outputs};
use super::data::{Data, DataError, CHANNELS};
use super::fe_response::FeSource;
use super::fit::{initial_baseline, physical, stderr, Fitted, Model, Setup, N_BASE};
use super::localise::{self, ChannelLocalisation};
use super::mains::{self, Line};
use super::output::*;
use super::regimes::{self, Segment};
use crate::recording::Recording;

/// Knobs of a run and the project's model parameters the recording does not carry.
#[derive(Debug, Clone)]
pub struct Options {
    /// The fingertip FE and the chip behind the baseline's response tables.
    pub fe: FeSource,
    /// The chip's bridge output per volt of excitation per unit load (the `chip` crate).
    pub sensitivity_per_v: [[f64; 3]; 3],
    /// Show a progress bar.
    pub progress: bool,
}

impl Options {
    pub fn from_hardware(
        hw: &hardware::Params,
        progress: bool,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        let fe = super::baseline::FrontEnd::from_chip(hw, [1.0; 3], hw.chip.excitation_v)?;
        Ok(Self {
            fe: FeSource::from_hardware(hw)?,
            sensitivity_per_v: fe.sensitivity_per_v,
            progress,
        })
    }
}

/// Minimum BIC decrease for an effect to count (strong evidence, Kass & Raftery 1995).
const MIN_BIC_GAIN: f64 = 10.0;
/// Minimum held-out chi-square decrease: absolute (noise units) and relative.
const MIN_HELDOUT_GAIN: f64 = 25.0;
const MIN_HELDOUT_SHARE: f64 = 0.005;
/// Ljung–Box: lags and the p-value below which a residual is structured.
const LB_LAGS: usize = 20;
const LB_P: f64 = 1e-3;
/// Mains line: prominence in the residual spectrum to count as a line.
const MIN_LINE_PROMINENCE: f64 = 30.0;
/// LM iteration caps.
const BASE_ITERATIONS: usize = 80;
const EFFECT_ITERATIONS: usize = 40;

/// One fitted candidate.
pub struct Candidate<'s, 'a> {
    pub kinds: Vec<EffectKind>,
    pub model: Model<'s, 'a>,
    pub fitted: Fitted,
    pub bic: f64,
    pub aicc: f64,
    pub heldout_chi2: f64,
}

impl<'s, 'a> Candidate<'s, 'a> {
    fn new(model: Model<'s, 'a>, max_iterations: usize) -> Self {
        let fitted = model.fit(max_iterations);
        let n = fitted.solution.n as f64;
        let k = fitted.free.len() as f64;
        let fit_term = n * (fitted.solution.sse / n).max(1e-300).ln();
        let bic = fit_term + k * n.ln();
        let aicc = fit_term + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0).max(1.0);
        let mut r = Vec::new();
        model.weighted(&fitted.full, &model.setup.heldout_mask, &mut r);
        let heldout_chi2 = r.iter().map(|v| v * v).sum();
        Self {
            kinds: model.kinds.clone(),
            model,
            fitted,
            bic,
            aicc,
            heldout_chi2,
        }
    }

    /// Better than `other` (a sub-model) on both criteria.
    fn beats(&self, other: &Candidate) -> bool {
        let heldout_gain = other.heldout_chi2 - self.heldout_chi2;
        self.bic < other.bic - MIN_BIC_GAIN
            && heldout_gain > MIN_HELDOUT_GAIN.max(MIN_HELDOUT_SHARE * other.heldout_chi2)
    }
}

/// Everything the HTML report plots.
pub struct PlotData {
    pub t_s: Vec<f64>,
    pub recorded: [Vec<f64>; 4],
    pub baseline: [Vec<f64>; 4],
    pub improved: [Vec<f64>; 4],
    pub segments: Vec<Segment>,
    pub heldout: (f64, f64),
    pub used: [bool; 4],
}

pub struct Diagnosis {
    pub report: Report,
    pub plots: PlotData,
}

/// Diagnose `rec`; `name` is what OUT.json calls the recording.
pub fn diagnose(rec: &Recording, name: &str, opt: &Options) -> Result<Diagnosis, DataError> {
    let started = Instant::now();
    let data = Data::new(rec)?;
    let fit_t = &data.fit.t_s;
    let (_, segments) = regimes::detect(fit_t, &data.fit.rod_mm);
    let heldout = regimes::heldout_window(fit_t, &segments);
    let heldout_mask: Vec<bool> = fit_t.iter().map(|&t| t >= heldout.0).collect();
    let meta = &rec.meta;
    let fingertip = opt.fe.response(
        meta.fingertip_radius_mm,
        meta.contact_angle_deg,
        meta.azimuth_deg,
    )?;
    let used: [bool; 4] = std::array::from_fn(|c| data.range[c] > 10.0 * data.noise_full[c]);
    let thermal = match (&data.fit.temp_c, &data.full.temp_c) {
        (Some(fit), Some(full)) => super::temperature::fit(fit_t, fit, full),
        _ => None,
    };
    let temperature = |s: &super::data::Series| thermal.and(s.temp_c.clone());
    let setup = Setup {
        data: &data,
        drive: Drive::new(&fingertip, fit_t.clone(), &data.fit.rod_mm)
            .with_temperature(temperature(&data.fit)),
        front_end: FrontEnd {
            sensitivity_per_v: opt.sensitivity_per_v,
            gain: [meta.gain_fz, meta.gain_mx, meta.gain_my],
            excitation_v: meta.excitation_v,
            smoother_tau_s: meta
                .other
                .iter()
                .find(|(k, _)| k == super::baseline::SMOOTHER_KEY)
                .and_then(|(_, v)| v.trim().parse::<f64>().ok())
                .and_then(|alpha| super::baseline::smoother_tau_s(alpha, meta.sample_rate_hz)),
        },
        contact_angle_deg: meta.contact_angle_deg,
        fit_mask: heldout_mask.iter().map(|h| !h).collect(),
        heldout_mask,
        used,
        thermal,
    };

    let slow_kinds: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| *k != EffectKind::MainsInterference)
        .collect();
    let bar = progress_bar(opt.progress, 1 + slow_kinds.len() + 7);
    let init = initial_baseline(&setup);
    let base = Candidate::new(Model::new(&setup, &[], &init), BASE_ITERATIONS);
    bar.inc(1);
    let base_vec = base.fitted.full[..N_BASE].to_vec();
    let singles: Vec<Candidate> = slow_kinds
        .par_iter()
        .map(|&k| {
            let c = Candidate::new(Model::new(&setup, &[k], &base_vec), EFFECT_ITERATIONS);
            bar.inc(1);
            c
        })
        .collect();
    let pairs = fit_pairs(&setup, &singles, &bar);
    bar.finish_and_clear();

    // Selection: the lowest-BIC candidate each of whose effects beats the model without it.
    let single_of = |k: EffectKind| singles.iter().find(|c| c.kinds == [k]);
    let admissible = |c: &Candidate| -> bool {
        match c.kinds.as_slice() {
            [] => true,
            [_] => c.beats(&base),
            [a, b] => match (single_of(*a), single_of(*b)) {
                (Some(sa), Some(sb)) => c.beats(sa) && c.beats(sb),
                _ => false,
            },
            _ => false,
        }
    };
    let all: Vec<&Candidate> = std::iter::once(&base)
        .chain(&singles)
        .chain(&pairs)
        .collect();
    let chosen: &Candidate = all
        .iter()
        .copied()
        .filter(|c| admissible(c))
        .min_by(|a, b| a.bic.total_cmp(&b.bic))
        .unwrap_or(&base);
    let candidates = all
        .iter()
        .map(|c| CandidateReport {
            effects: c.kinds.iter().map(|k| k.name().to_string()).collect(),
            bic: c.bic,
            aicc: c.aicc,
            heldout_chi2: c.heldout_chi2,
            accepted: std::ptr::eq(*c, chosen),
        })
        .collect();

    // Full-rate evaluation: contract RMSEs and the mains line.
    let full_drive = Drive::new(&fingertip, data.full.t_s.clone(), &data.full.rod_mm)
        .with_temperature(temperature(&data.full));
    let base_full = base.model.outputs(&base.fitted.full, &full_drive);
    let chosen_full = chosen.model.outputs(&chosen.fitted.full, &full_drive);
    let full_heldout: Vec<bool> = data.full.t_s.iter().map(|&t| t >= heldout.0).collect();
    let full_fit: Vec<bool> = full_heldout.iter().map(|h| !h).collect();
    let base_line = line_in_residual(&data, &base_full, &full_fit);
    let mains = line_in_residual(&data, &chosen_full, &full_fit)
        .filter(|l| mains_helps(&data, &chosen_full, l, &full_fit, &full_heldout));
    let with_mains = |o: &Outputs| add_line(&data, o, mains.as_ref());
    let final_full = with_mains(&chosen_full);
    let all_rows = vec![true; data.full.len()];
    let rmse = |o: &Outputs, mask: &[bool]| contract_rmse(&data, o, mask);
    let fit = Fit {
        rmse_before: rmse(&base_full, &all_rows),
        rmse_after: rmse(&final_full, &all_rows),
        heldout: Heldout {
            t_start_s: heldout.0,
            t_end_s: heldout.1,
            rmse_before: rmse(&base_full, &full_heldout),
            rmse_after: rmse(&final_full, &full_heldout),
        },
    };

    // Localisation of the baseline's residual, on the decimated series.
    let base_dec = base.model.outputs(&base.fitted.full, &setup.drive);
    let residual: [Vec<f64>; 4] =
        std::array::from_fn(|c| diff(&data.fit.y[c], base_dec.channel(c)));
    let mismatches = localise::mismatches(fit_t, &segments, &residual, &data.range, &used, 0.02);
    let channels = channel_localisation(&data, &base_dec, &residual);
    let chosen_dec = chosen.model.outputs(&chosen.fitted.full, &setup.drive);
    let white_after = (0..4).filter(|&c| used[c]).all(|c| {
        let r = weighted(&data, c, &diff(&data.fit.y[c], chosen_dec.channel(c)));
        localise::ljung_box(&r, LB_LAGS).1 > LB_P
    });

    let mut effects = effect_reports(chosen, &base, &singles, &data);
    if let Some(line) = &mains {
        effects.push(mains_report(line, &data));
    }
    let verdict = match (effects.is_empty(), white_after) {
        (true, true) => Verdict::NoSignificantMismatch,
        (true, false) => Verdict::Unexplained,
        (false, true) => Verdict::Explained,
        (false, false) => Verdict::PartiallyExplained,
    };
    let report = Report {
        format: FORMAT,
        recording: name.to_string(),
        verdict,
        baseline: Baseline {
            params: baseline_params(&base),
            rmse: Numbers(
                (0..4)
                    .filter(|&c| used[c])
                    .map(|c| {
                        (
                            CHANNELS[c].to_string(),
                            channel_rmse(&data, &base_full, c, &all_rows),
                        )
                    })
                    .collect(),
            ),
        },
        mismatches,
        effects,
        fit,
        localisation: Localisation {
            channels,
            lines: base_line
                .iter()
                .filter(|l| l.prominence > MIN_LINE_PROMINENCE)
                .map(|l| (l.freq_hz, l.amplitude(), l.prominence))
                .collect(),
        },
        candidates,
        seconds: started.elapsed().as_secs_f64(),
    };
    // At the fitting rate a mains line averages out over whole periods, so the improved model
    // plotted there is the slow model alone.
    let improved_dec = chosen_dec;
    let plots = PlotData {
        t_s: fit_t.clone(),
        recorded: data.fit.y.clone(),
        baseline: std::array::from_fn(|c| base_dec.channel(c).to_vec()),
        improved: std::array::from_fn(|c| improved_dec.channel(c).to_vec()),
        segments,
        heldout,
        used,
    };
    Ok(Diagnosis { report, plots })
}

fn progress_bar(show: bool, n: usize) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(n as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "fitting candidate models {bar:30} {pos}/{len} {elapsed}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// Pairs among the four best singles by BIC, plus viscoelastic relaxation with AC coupling
/// (together they mimic the original observations), seeded from the singles' optima.
fn fit_pairs<'s, 'a>(
    setup: &'s Setup<'a>,
    singles: &[Candidate<'s, 'a>],
    bar: &indicatif::ProgressBar,
) -> Vec<Candidate<'s, 'a>> {
    let mut order: Vec<&Candidate> = singles.iter().collect();
    order.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    let top: Vec<EffectKind> = order.iter().take(4).map(|c| c.kinds[0]).collect();
    let mut pairs: Vec<(EffectKind, EffectKind)> = Vec::new();
    for i in 0..top.len() {
        for j in i + 1..top.len() {
            pairs.push((top[i].min(top[j]), top[i].max(top[j])));
        }
    }
    // Viscoelastic relaxation with AC coupling mimics the original observations; two Prony
    // terms cover a gel whose relaxation spans decades.
    let ve = EffectKind::ViscoelasticRelaxation;
    for pair in [(ve, EffectKind::HighpassCoupling), (ve, ve)] {
        if !pairs.contains(&pair) {
            pairs.push(pair);
        }
    }
    let out = pairs
        .par_iter()
        .map(|&(a, b)| {
            let sa = singles
                .iter()
                .find(|c| c.kinds == [a])
                .expect("every single is fitted");
            let sb = singles
                .iter()
                .find(|c| c.kinds == [b])
                .expect("every single is fitted");
            let better = if sa.bic < sb.bic { sa } else { sb };
            let mut model = Model::new(setup, &[a, b], &better.fitted.full[..N_BASE]);
            model.seed(0, &sa.fitted.full[N_BASE..]);
            if a == b {
                // Second Prony term: a decade apart on either side of the single term's tau.
                let ln_tau = sa.fitted.full[N_BASE];
                *model.starts_mut(0, 0) = vec![ln_tau];
                *model.starts_mut(1, 0) = vec![ln_tau + 10f64.ln(), ln_tau - 10f64.ln()];
                *model.starts_mut(1, 1) = vec![0.1];
            } else {
                model.seed(1, &sb.fitted.full[N_BASE..]);
            }
            let c = Candidate::new(model, EFFECT_ITERATIONS);
            bar.inc(1);
            c
        })
        .collect();
    out
}

/// Residual in noise units, re-binned to the coarse block length (fine blocks summed in
/// groups): whiteness is judged on the time scales the models describe, and noise coloured
/// on the scale of a few samples (smoother, anti-alias filter) does not count as structure.
fn weighted(data: &Data, c: usize, r: &[f64]) -> Vec<f64> {
    let target = data.fit.count.iter().copied().max().unwrap_or(1);
    let mut out = Vec::new();
    let (mut sum, mut m, mut count) = (0.0, 0usize, 0usize);
    for (k, v) in r.iter().enumerate() {
        sum += v * data.weight(c, k);
        m += 1;
        count += data.fit.count[k];
        if count >= target {
            out.push(sum / (m as f64).sqrt());
            (sum, m, count) = (0.0, 0, 0);
        }
    }
    out
}

fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// Mean over the compared channels of RMS residual / recorded peak-to-peak range.
fn contract_rmse(data: &Data, o: &Outputs, mask: &[bool]) -> f64 {
    let used: Vec<usize> = (0..4)
        .filter(|&c| data.range[c] > 10.0 * data.noise_full[c])
        .collect();
    used.iter()
        .map(|&c| channel_rmse(data, o, c, mask))
        .sum::<f64>()
        / used.len().max(1) as f64
}

fn channel_rmse(data: &Data, o: &Outputs, c: usize, mask: &[bool]) -> f64 {
    let y = &data.full.y[c];
    let m = o.channel(c);
    let (mut s, mut n) = (0.0, 0usize);
    for k in 0..y.len() {
        if mask[k] {
            s += (y[k] - m[k]).powi(2);
            n += 1;
        }
    }
    (s / n.max(1) as f64).sqrt() / data.range[c].max(1e-300)
}

fn line_in_residual(data: &Data, o: &Outputs, mask: &[bool]) -> Option<Line> {
    let res: Vec<Vec<f64>> = (1..4)
        .map(|c| diff(&data.full.y[c], o.channel(c)))
        .collect();
    let refs: Vec<&[f64]> = res.iter().map(|r| r.as_slice()).collect();
    let span = data.full.t_s[data.full.len() - 1] - data.full.t_s[0];
    let rate = (data.full.len() - 1) as f64 / span.max(1e-9);
    mains::find_line(&data.full.t_s, &refs, mask, rate)
}

/// Outputs plus the fitted line on the chip channels (full rate).
fn add_line(data: &Data, o: &Outputs, line: Option<&Line>) -> Outputs {
    let mut out = o.clone();
    if let Some(l) = line {
        let harmonic = l.coef[0][2] != 0.0 || l.coef[0][3] != 0.0;
        for b in 0..3 {
            for (v, &t) in out.volts[b].iter_mut().zip(&data.full.t_s) {
                *v += l.at(b, t, harmonic);
            }
        }
    }
    out
}

/// The line counts if it is prominent and removing it helps on the fitting stretch and on the
/// held-out stretch, both in noise units.
fn mains_helps(data: &Data, o: &Outputs, line: &Line, fit: &[bool], heldout: &[bool]) -> bool {
    if line.prominence < MIN_LINE_PROMINENCE {
        return false;
    }
    let with = add_line(data, o, Some(line));
    let chi2 = |m: &Outputs, mask: &[bool]| -> f64 {
        (1..4)
            .map(|c| {
                let w = 1.0 / data.noise_full[c];
                (0..data.full.len())
                    .filter(|&k| mask[k])
                    .map(|k| ((data.full.y[c][k] - m.channel(c)[k]) * w).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let (f0, f1) = (chi2(o, fit), chi2(&with, fit));
    let (h0, h1) = (chi2(o, heldout), chi2(&with, heldout));
    let n = fit.iter().filter(|&&b| b).count() as f64;
    let bic_gain = n * (f0 / f1).ln() - 13.0 * n.ln();
    bic_gain > MIN_BIC_GAIN && h0 - h1 > MIN_HELDOUT_GAIN.max(MIN_HELDOUT_SHARE * h0)
}

fn channel_localisation(
    data: &Data,
    base: &Outputs,
    residual: &[Vec<f64>; 4],
) -> Vec<ChannelLocalisation> {
    let d = &data.fit;
    let load = &d.y[0];
    let load2: Vec<f64> = load.iter().map(|v| v * v).collect();
    let dload: Vec<f64> = (0..d.len())
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(d.len() - 1));
            if d.t_s[b] > d.t_s[a] {
                (load[b] - load[a]) / (d.t_s[b] - d.t_s[a])
            } else {
                0.0
            }
        })
        .collect();
    (0..4)
        .filter(|&c| data.range[c] > 10.0 * data.noise_full[c])
        .map(|c| {
            let r = &residual[c];
            let (q, p) = localise::ljung_box(&weighted(data, c, r), LB_LAGS);
            ChannelLocalisation {
                channel: CHANNELS[c],
                ljung_box_q: q,
                ljung_box_p: p,
                white: p > LB_P,
                corr_load: localise::correlation(r, load),
                corr_load_squared: localise::correlation(r, &load2),
                corr_dload_dt: localise::correlation(r, &dload),
                corr_temperature: d.temp_c.as_ref().map(|t| localise::correlation(r, t)),
                corr_other_residuals: (0..4)
                    .filter(|&o| o != c)
                    .map(|o| {
                        (
                            CHANNELS[o].to_string(),
                            localise::correlation(r, &residual[o]),
                        )
                    })
                    .collect(),
                lag_estimate_s: localise::lag_estimate(&d.t_s, base.channel(c), r),
            }
        })
        .collect()
}

fn baseline_params(base: &Candidate) -> Numbers {
    let f = &base.fitted.full;
    let mut n = Numbers::default();
    n.push("youngs_modulus_Pa", f[0].exp());
    n.push("force_exponent_shift", f[1]);
    n.push("force_exponent_curvature", f[9]);
    n.push("scale_fz", f[2]);
    n.push("scale_moment", f[3]);
    n.push("azimuth_shift_deg", f[4]);
    for (i, ch) in CHANNELS.iter().enumerate() {
        n.push(&format!("offset_{ch}"), f[5 + i]);
    }
    n
}

/// The model without effect number `i` of `chosen`: the baseline or the other single.
fn without<'c, 's, 'a>(
    chosen: &'c Candidate<'s, 'a>,
    i: usize,
    base: &'c Candidate<'s, 'a>,
    singles: &'c [Candidate<'s, 'a>],
) -> &'c Candidate<'s, 'a> {
    let rest: Vec<EffectKind> = chosen
        .kinds
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != i)
        .map(|(_, k)| *k)
        .collect();
    singles.iter().find(|c| c.kinds == rest).unwrap_or(base)
}

fn effect_reports(
    chosen: &Candidate,
    base: &Candidate,
    singles: &[Candidate],
    data: &Data,
) -> Vec<EffectReport> {
    let model = &chosen.model;
    let full = &chosen.fitted.full;
    let mut r = Vec::new();
    model.weighted(full, &model.setup.fit_mask, &mut r);
    let rho = localise::lag1(&r);
    let mut i = N_BASE;
    let mut out: Vec<EffectReport> = Vec::new();
    for (index, &kind) in chosen.kinds.iter().enumerate() {
        let sub = without(chosen, index, base, singles);
        let bic_gain = sub.bic - chosen.bic;
        let heldout_gain = sub.heldout_chi2 / chosen.heldout_chi2.max(1e-300);
        let mut params = Numbers::default();
        let mut errs = Numbers::default();
        for name in kind.param_names() {
            params.push(name, physical(model, full, i));
            if let Some(se) = stderr(model, &chosen.fitted, i, rho) {
                errs.push(name, se);
            }
            i += 1;
        }
        // A second Prony term joins the first as `tau2_s`, `fraction2`; the larger share leads.
        if let Some(first) = out.iter_mut().find(|e| e.name == kind.name()) {
            let (mut a, mut b) = (
                (first.params.clone(), first.param_stderr.clone()),
                (params, errs),
            );
            if b.0.get("fraction") > a.0.get("fraction") {
                std::mem::swap(&mut a, &mut b);
            }
            for (src, dst) in [(&b.0, &mut a.0), (&b.1, &mut a.1)] {
                for (k, v) in src.0.clone() {
                    dst.push(
                        &format!(
                            "{}2{}",
                            k.trim_end_matches("_s"),
                            if k.ends_with("_s") { "_s" } else { "" }
                        ),
                        v,
                    );
                }
            }
            first.params = a.0;
            first.param_stderr = a.1;
            first.evidence = super::evidence::sentence(
                kind,
                &first.params,
                base.bic - chosen.bic,
                base.heldout_chi2 / chosen.heldout_chi2.max(1e-300),
                data,
            );
            let _ = (bic_gain, heldout_gain);
            continue;
        }
        out.push(EffectReport {
            name: kind.name().to_string(),
            channels: kind.channels().iter().map(|c| c.to_string()).collect(),
            evidence: super::evidence::sentence(kind, &params, bic_gain, heldout_gain, data),
            params,
            param_stderr: errs,
            catalogue: None,
        });
    }
    out
}

fn mains_report(line: &Line, data: &Data) -> EffectReport {
    let mut params = Numbers::default();
    params.push("freq_hz", line.freq_hz);
    params.push("amplitude_V", line.amplitude());
    // Cramér–Rao bounds for a sinusoid in white noise over N samples spanning T.
    let n = data.full.len() as f64;
    let sigma = (1..4).map(|c| data.noise_full[c]).sum::<f64>() / 3.0;
    let span = data.full.t_s[data.full.len() - 1] - data.full.t_s[0];
    let a = line.amplitude().max(1e-300);
    let mut errs = Numbers::default();
    errs.push(
        "freq_hz",
        (12.0f64).sqrt() * sigma / (std::f64::consts::TAU * a * span * (n / 3.0).sqrt()),
    );
    errs.push("amplitude_V", sigma * (2.0 / n).sqrt());
    let kind = EffectKind::MainsInterference;
    EffectReport {
        name: kind.name().to_string(),
        channels: kind.channels().iter().map(|c| c.to_string()).collect(),
        evidence: super::evidence::sentence(kind, &params, f64::NAN, f64::NAN, data),
        params,
        param_stderr: errs,
        catalogue: None,
    }
}
