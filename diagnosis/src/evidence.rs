//! What OUT.json says of each effect found: its parameters in full and one plain sentence of
//! what physics the baseline left out, how it shows, and how strong the evidence is.

use sim::effects::EffectKind;

use super::data::Data;
use super::mains::Line;
use super::output::{EffectReport, EvidenceValues, Numbers, ParamDetail};
use super::select::Selection;

/// The sentence for `kind` with its fitted `params`; `bic_gain` and `heldout_gain` (held-out
/// chi-square without the effect over with it) quantify the evidence where known.
pub fn sentence(
    kind: EffectKind,
    params: &Numbers,
    bic_gain: f64,
    heldout_gain: f64,
    _data: &Data,
) -> String {
    let p = |k: &str| params.get(k).unwrap_or(f64::NAN);
    use EffectKind::*;
    let what = match kind {
        ViscoelasticRelaxation => format!(
            "The gel is viscoelastic: {:.0} % of its instantaneous response relaxes with tau = {:.2} s, so the force decays under the hold and the outputs creep back after the fast release, which a quasi-static model cannot show.",
            100.0 * p("fraction"), p("tau_s")),
        Hysteresis => format!(
            "The gel loses energy independently of rate: the unloading path runs {:.1} % of full scale below the loading path.",
            100.0 * p("width")),
        HighpassCoupling => format!(
            "The offset cut acts as AC coupling with tau = {:.1} s: outputs sag under constant load and undershoot their initial value after release before creeping back.",
            p("tau_s")),
        ThermalDrift => format!(
            "The bridge offsets drift with warm-up by {:.4} V with tau = {:.0} s, visible at rest and unrelated to the load.",
            p("amplitude_V"), p("tau_s")),
        Stiffening => format!(
            "The load path stiffens: the outputs grow as the {:.2} power of the elastic response, the same on loading and unloading.",
            p("exponent")),
        Crosstalk => format!(
            "The chip is rotated {:.1} deg against its nominal axes: each moment channel carries a load-proportional share of the other.",
            p("angle_deg")),
        AmplifierSaturation => format!(
            "An amplifier clips at +-{:.3} V: the outputs have flat tops at that voltage.",
            p("limit_V")),
        TimeOffset => format!(
            "The sensor stream lags the load reference by {:.1} ms: the residual follows the signals' derivative, largest during the fast release.",
            1e3 * p("lag_s")),
        MainsInterference => format!(
            "Mains pickup at {:.2} Hz with {:.4} V amplitude (and its third harmonic) shows as a narrow spectral line in the outputs.",
            p("freq_hz"), p("amplitude_V")),
        BridgeNonlinearity => format!(
            "The bridges respond to the square of the stress: a quadratic term of {:.1} % of full scale at full load.",
            100.0 * p("quadratic")),
        ContactFriction => format!(
            "Coulomb friction (mu = {:.2}) at the inclined contact makes the moments stick at the reversal and lag the load while Fz stays smooth.",
            p("mu")),
    };
    let what = match params.get("tau2_s") {
        Some(tau2) => format!("{what} A second relaxation term of {:.0} % with tau = {:.2} s shows that the relaxation spans more than one time scale.", 100.0 * p("fraction2"), tau2),
        None => what,
    };
    if bic_gain.is_finite() && heldout_gain.is_finite() {
        format!(
            "{what} (Against the model without it: BIC lower by {:.0}, held-out misfit {:.1} times smaller.)",
            bic_gain, heldout_gain
        )
    } else {
        what
    }
}

/// The sentence's closing note on parameters the data did not resolve.
fn bound_note(parameters: &[ParamDetail]) -> String {
    let pinned: Vec<String> = parameters
        .iter()
        .filter(|p| p.at_bound)
        .map(|p| {
            format!(
                "{} = {:.3e} {} ({})",
                p.name,
                p.value,
                p.unit,
                p.note.as_deref().unwrap_or("at its bound")
            )
        })
        .collect();
    if pinned.is_empty() {
        String::new()
    } else {
        format!(" Not resolved, reported as bounds: {}.", pinned.join("; "))
    }
}

/// The channels `kind` acts on that the recording measured: the gel's relaxation in a test of
/// the material alone acts on its load cell only.
fn measured_channels(kind: EffectKind, data: &Data) -> Vec<String> {
    const COLUMNS: [&str; 4] = ["load_N", "fz_V", "mx_V", "my_V"];
    kind.channels()
        .iter()
        .filter(|name| {
            COLUMNS
                .iter()
                .position(|c| c == *name)
                .is_none_or(|c| data.compared(c))
        })
        .map(|c| c.to_string())
        .collect()
}

/// Each effect of the chosen model: parameters with standard errors and bounds, and the
/// evidence against the model without it. A second relaxation term joins the first as
/// `tau2_s`, `fraction2` (one effect, two time scales).
pub fn effect_reports(sel: &Selection, data: &Data) -> Vec<EffectReport> {
    let chosen = sel.chosen();
    let details = crate::params::effects(chosen, data);
    let mut out: Vec<EffectReport> = Vec::new();
    for (index, (kind, parameters)) in details.into_iter().enumerate() {
        let without = &sel.all[sel.without_index(index)];
        let cmp = chosen.compare(without);
        if let Some(first) = out.iter_mut().find(|e| e.name == kind.name()) {
            join_second_term(first, parameters);
            let vs_base = chosen.compare(sel.base());
            first.evidence = sentence(
                kind,
                &first.params,
                vs_base.bic_gain,
                vs_base.heldout_ratio,
                data,
            ) + &bound_note(&first.parameters);
            continue;
        }
        let mut params = Numbers::default();
        let mut errs = Numbers::default();
        for p in &parameters {
            params.push(&p.name, p.value);
            if let Some(se) = p.stderr {
                errs.push(&p.name, se);
            }
        }
        out.push(EffectReport {
            name: kind.name().to_string(),
            stage: kind.stage(),
            channels: measured_channels(kind, data),
            evidence: sentence(kind, &params, cmp.bic_gain, cmp.heldout_ratio, data)
                + &bound_note(&parameters),
            params,
            param_stderr: errs,
            catalogue: true,
            depends_on: None,
            form: None,
            inclusion: None,
            parameters,
            evidence_values: Some(EvidenceValues::with_bic_gain(cmp.bic_gain)),
        });
    }
    out
}

/// A second Prony term joins the first as `tau2_s`, `fraction2`; the larger share leads.
fn join_second_term(first: &mut EffectReport, second: Vec<ParamDetail>) {
    let mut a = first.parameters.clone();
    let mut b = second;
    let fraction = |ps: &[ParamDetail]| {
        ps.iter()
            .find(|p| p.name == "fraction")
            .map_or(0.0, |p| p.value)
    };
    if fraction(&b) > fraction(&a) {
        std::mem::swap(&mut a, &mut b);
    }
    for p in &mut b {
        p.name = second_term_name(&p.name);
    }
    a.extend(b);
    first.params = Numbers(a.iter().map(|p| (p.name.clone(), p.value)).collect());
    first.param_stderr = Numbers(
        a.iter()
            .filter_map(|p| Some((p.name.clone(), p.stderr?)))
            .collect(),
    );
    first.parameters = a;
}

/// A second Prony term's name for its parameter `name`: `tau2_s`, `fraction2`.
pub(crate) fn second_term_name(name: &str) -> String {
    match name.strip_suffix("_s") {
        Some(stem) => format!("{stem}2_s"),
        None => format!("{name}2"),
    }
}

/// The mains line as an effect, with Cramér–Rao standard errors for a sinusoid in white noise
/// over N samples spanning T.
pub fn mains_report(line: &Line, data: &Data) -> EffectReport {
    mains_on(line, data, &[1, 2, 3])
}

/// The mains line on the load cell: the same catalogue entry at the load cell's electronics.
pub fn load_mains_report(line: &Line, data: &Data) -> EffectReport {
    let mut e = mains_on(line, data, &[0]);
    e.channels = vec!["load_N".into()];
    e.evidence = format!(
        "Mains pickup at {:.2} Hz with {:.4} N amplitude on the load cell's own electronics: a narrow spectral line in the load.",
        line.freq_hz,
        line.amplitude()
    );
    e.params = Numbers(vec![
        ("freq_hz".into(), line.freq_hz),
        ("amplitude_N".into(), line.amplitude()),
    ]);
    e
}

fn mains_on(line: &Line, data: &Data, chans: &[usize]) -> EffectReport {
    let n = data.full.len() as f64;
    let sigma = chans.iter().map(|&c| data.noise[c].sd()).sum::<f64>() / chans.len().max(1) as f64;
    let span = data.full.t_s[data.full.len() - 1] - data.full.t_s[0];
    let a = line.amplitude().max(1e-300);
    let detail =
        |name: &str, value: f64, se: f64, unit: &str, (lower, upper): (f64, f64)| ParamDetail {
            name: name.into(),
            value,
            stderr: Some(se),
            ci_low: None,
            ci_high: None,
            unit: unit.into(),
            lower,
            upper,
            at_bound: false,
            note: None,
        };
    let parameters = vec![
        detail(
            "freq_hz",
            line.freq_hz,
            (12.0f64).sqrt() * sigma / (std::f64::consts::TAU * a * span * (n / 3.0).sqrt()),
            "Hz",
            crate::mains::BAND_HZ,
        ),
        detail(
            "amplitude_V",
            line.amplitude(),
            sigma * (2.0 / n).sqrt(),
            "V",
            (0.0, f64::INFINITY),
        ),
    ];
    let params = Numbers(
        parameters
            .iter()
            .map(|p| (p.name.clone(), p.value))
            .collect(),
    );
    let errs = Numbers(
        parameters
            .iter()
            .filter_map(|p| Some((p.name.clone(), p.stderr?)))
            .collect(),
    );
    let kind = EffectKind::MainsInterference;
    EffectReport {
        name: kind.name().to_string(),
        stage: kind.stage(),
        channels: kind.channels().iter().map(|c| c.to_string()).collect(),
        evidence: sentence(kind, &params, f64::NAN, f64::NAN, data),
        params,
        param_stderr: errs,
        catalogue: true,
        depends_on: None,
        form: None,
        inclusion: None,
        parameters,
        evidence_values: None,
    }
}

/// Each catalogue effect of `reports` (as [`effect_reports`] gives them)'s part of the model at
/// the full rate: the chosen model minus the chosen model refitted without it (without both
/// Prony terms of a relaxation with two).
pub fn catalogue_parts(
    sel: &Selection,
    drive: &baseline::Drive,
    reports: &[EffectReport],
) -> Vec<crate::certify::Part> {
    let chosen = sel.chosen();
    let with = chosen.outputs(drive);
    reports
        .iter()
        .map(|e| {
            let first = chosen.kinds.iter().position(|k| k.name() == e.name);
            let others: Vec<EffectKind> = chosen
                .kinds
                .iter()
                .copied()
                .filter(|k| k.name() != e.name)
                .collect();
            let without = sel
                .position_of(&others)
                .or_else(|| first.map(|i| sel.without_index(i)))
                .unwrap_or(sel.chosen);
            let less = sel.all[without].outputs(drive);
            std::array::from_fn(|c| {
                let (a, b) = (with.channel(c), less.channel(c));
                a.iter().zip(b).map(|(x, y)| x - y).collect()
            })
        })
        .collect()
}
