//! `tactile observations --session DIR`: the paper's observations stated as a session. One
//! recording of the paper's standard test (`hardware/fingertip.toml` `[test]`: 20 mm/min to 60 N,
//! hold, fast return) per inclination of the scorecard's sweep, at its azimuth, of *the paper's
//! sensor*: the project's one forward model (`baseline::standard_test`, the path of `tactile
//! simulate` and the session proof) whose Fz sensitivity at each angle is set so that the peak
//! Fz follows the paper's law across theta_p (`hardware/paper-sensor.toml` `[angle_law]`)
//! instead of the model's own. The model's law is measured from the forward model itself (a
//! noise-free recording per angle), so the recordings' Fz(theta)/Fz(0) is the paper's by
//! construction. The metadata are the true test's: `tactile diagnose --joint DIR` sees an
//! honest session, whose expected finding is `angle_dependence` on `fz_V` with the ratio
//! written to `DIR/paper-law.json`.

use std::path::{Path, PathBuf};

use anyhow::Context;
use baseline::standard_test::{simulate_standard_test_with, SimulateOptions};
use fingertip::observations::SWEEP_DEG;
use recording::Recording;

/// What the session's recordings are made with.
pub struct SessionOptions {
    pub dir: PathBuf,
    pub rate_hz: f64,
    pub seed: u64,
    pub noise_v: f64,
}

/// Load-cell noise of the session's recordings, N: the session proof's.
const NOISE_LOAD_N: f64 = 0.02;

/// One inclination of the session: the model's and the paper's Fz law there, and the Fz
/// sensitivity that turns the one into the other.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AngleLaw {
    pub theta_deg: f64,
    pub file: String,
    /// The forward model's peak Fz at this angle over that at 0°.
    pub model_fz_ratio: f64,
    /// The paper's.
    pub paper_fz_ratio: f64,
    /// The Fz sensitivity scale of the recording (1 at 0°).
    pub fz_scale: f64,
}

/// Write the session to `opt.dir`; the laws per angle, also written to `paper-law.json`.
pub fn write_session(opt: &SessionOptions) -> anyhow::Result<Vec<AngleLaw>> {
    let params = hardware::Params::load_default().context("loading hardware/")?;
    std::fs::create_dir_all(&opt.dir).with_context(|| format!("creating {}", opt.dir.display()))?;
    let model = model_fz_law(&params, opt.rate_hz)?;
    let mut laws = Vec::new();
    for (i, (&theta_deg, model_fz_ratio)) in SWEEP_DEG.iter().zip(model).enumerate() {
        let paper_fz_ratio = params.paper_sensor.fz_ratio(theta_deg);
        let fz_scale = paper_fz_ratio / model_fz_ratio;
        let noisy = SimulateOptions {
            noise_v: opt.noise_v,
            noise_load_n: NOISE_LOAD_N,
            seed: opt.seed.wrapping_add(i as u64),
            ..test_options(&params, theta_deg, opt.rate_hz)
        };
        let mut rec = simulate_standard_test_with(&noisy, &params, |b| b.scale[0] *= fz_scale)
            .with_context(|| format!("simulating the test at {theta_deg}°"))?;
        rec.meta.source = Some(format!(
            "tactile observations --session: the paper's sensor (Fz law of \
             hardware/paper-sensor.toml) at theta_p = {theta_deg}°"
        ));
        let file = format!("theta{theta_deg:02.0}.csv");
        write(&opt.dir.join(&file), &rec)?;
        laws.push(AngleLaw {
            theta_deg,
            file,
            model_fz_ratio,
            paper_fz_ratio,
            fz_scale,
        });
    }
    write_laws(&opt.dir, &laws)?;
    Ok(laws)
}

/// The paper's standard test at `theta_deg` and the sweep's azimuth, noise-free.
fn test_options(params: &hardware::Params, theta_deg: f64, rate_hz: f64) -> SimulateOptions {
    let test = &params.fingertip.test;
    SimulateOptions {
        rate_hz: Some(rate_hz),
        ..SimulateOptions::new(theta_deg, test.azimuth_deg, test.peak_load_n)
    }
}

/// The forward model's own law: its noise-free peak Fz at each angle of the sweep over that at
/// 0° (the sweep starts at 0°).
fn model_fz_law(params: &hardware::Params, rate_hz: f64) -> anyhow::Result<Vec<f64>> {
    let peaks = SWEEP_DEG
        .iter()
        .map(|&theta_deg| {
            let rec = simulate_standard_test_with(
                &test_options(params, theta_deg, rate_hz),
                params,
                |_| {},
            )
            .with_context(|| format!("simulating the model's test at {theta_deg}°"))?;
            Ok(peak_fz_v(&rec))
        })
        .collect::<anyhow::Result<Vec<f64>>>()?;
    anyhow::ensure!(
        peaks[0].abs() > 0.0,
        "the model's Fz at 0° does not move: no angle law to measure"
    );
    Ok(peaks.iter().map(|p| p / peaks[0]).collect())
}

/// The Fz output's largest excursion from its first sample, with its sign, V.
pub fn peak_fz_v(rec: &Recording) -> f64 {
    let fz = &rec.channels.fz_v;
    let first = fz.first().copied().unwrap_or(0.0);
    fz.iter()
        .map(|v| v - first)
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(0.0)
}

fn write(path: &Path, rec: &Recording) -> anyhow::Result<()> {
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    rec.write_to(file)
        .with_context(|| format!("writing {}", path.display()))
}

/// `paper-law.json`: the laws per angle and the ratio the joint diagnosis should find.
fn write_laws(dir: &Path, laws: &[AngleLaw]) -> anyhow::Result<()> {
    let (first, last) = (&laws[0], &laws[laws.len() - 1]);
    let doc = serde_json::json!({
        "angles": laws,
        "expected": {
            "name": "angle_dependence",
            "channel": "fz_V",
            "ratio": last.fz_scale / first.fz_scale,
        },
    });
    let path = dir.join("paper-law.json");
    std::fs::write(&path, serde_json::to_string_pretty(&doc)? + "\n")
        .with_context(|| format!("writing {}", path.display()))
}

/// The table the command prints.
pub fn print_laws(out: &mut impl std::io::Write, laws: &[AngleLaw]) -> std::io::Result<()> {
    writeln!(
        out,
        "theta_p  file         model Fz/Fz(0)  paper Fz/Fz(0)  Fz sensitivity"
    )?;
    for l in laws {
        writeln!(
            out,
            "{:5.0}°   {:<12} {:14.4}  {:14.4}  {:14.4}",
            l.theta_deg, l.file, l.model_fz_ratio, l.paper_fz_ratio, l.fz_scale
        )?;
    }
    if let (Some(first), Some(last)) = (laws.first(), laws.last()) {
        writeln!(
            out,
            "expected from `tactile diagnose --joint`: angle_dependence on fz_V, ratio {:.4}",
            last.fz_scale / first.fz_scale
        )?;
    }
    Ok(())
}
