//! `tactile observations`: the paper's seven observations against the fingertip model, one row
//! each (statement, quantity, model value, agree or not, the physics responsible); `--causes`
//! scores every candidate cause of the disagreements, `--lmee` the elastic energy along the
//! inclination. The computation is `fingertip::observations`; the AC coupling of the offset
//! cut, an electronics effect, is the `sim` catalogue's operator.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use fingertip::observations::{self, causes, energy, Scorecard, Setup};
use fingertip::Config;
use sim::effects::HighpassCoupling;

use super::paper_session::{self, SessionOptions};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Nominal element size, mm.
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub mesh_size: f64,
    /// Apply one candidate cause to the default model (see `--causes` for the names).
    #[arg(long, value_name = "NAME")]
    pub cause: Option<String>,
    /// AC coupling of the offset cut on every output, time constant in s.
    #[arg(long, value_name = "S")]
    pub highpass_tau: Option<f64>,
    /// Score the default and every candidate cause; print what each does to each observation.
    #[arg(long)]
    pub causes: bool,
    /// Also compute the elastic potential energy along the inclination (LMEE).
    #[arg(long)]
    pub lmee: bool,
    /// Score the paper's sensor: the default fingertip with the gel's relaxation and the offset
    /// cut's AC coupling of `hardware/paper-sensor.toml` (`--highpass-tau` overrides the latter).
    #[arg(long, conflicts_with_all = ["cause", "causes"])]
    pub paper_sensor: bool,
    /// Write the paper's session to DIR instead of scoring: one recording of the paper's sensor
    /// per inclination of the sweep (0, 10, 20, 30°), for `tactile diagnose --joint DIR`.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["cause", "causes", "lmee", "paper_sensor", "highpass_tau"])]
    pub session: Option<PathBuf>,
    /// Sample rate of the session's recordings, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 200.0, requires = "session")]
    pub rate: f64,
    /// Noise seed of the session's recordings (the recording at the i-th angle uses seed + i).
    #[arg(long, default_value_t = 1, requires = "session")]
    pub seed: u64,
    /// White noise on each output of the session's recordings, V (standard deviation).
    #[arg(long, value_name = "V", default_value_t = 0.002, requires = "session")]
    pub noise_v: f64,
}

/// AC coupling of the demo's concealed effect (`scripts/demo-chain.sh`), for `--causes`.
const AC_COUPLING_TAU_S: f64 = 25.0;
/// Inclinations of the LMEE sweep, degrees.
const LMEE_THETAS_DEG: [f64; 7] = [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0];

/// The default fingertip of `hardware/fingertip.toml` at its standard test.
pub fn default_config(hw: &hardware::Fingertip, mesh_size_mm: f64) -> Config {
    Config::from_hardware(hw, mesh_size_mm)
}

fn print_card(out: &mut impl Write, card: &Scorecard) -> std::io::Result<()> {
    writeln!(out, "model: {}", card.label)?;
    for r in &card.rows {
        let status = if r.agree { "agree" } else { "DISAGREE" };
        writeln!(out, "{}. [{status}] {}", r.number, r.statement)?;
        for c in &r.checks {
            let mark = if c.agree { "ok" } else { "no" };
            writeln!(
                out,
                "     {mark}  {} = {:.4}  (paper: {})",
                c.quantity, c.value, c.criterion
            )?;
        }
        writeln!(out, "     physics: {}", r.physics)?;
    }
    Ok(())
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(dir) = &args.session {
        return run_session(&args, dir);
    }
    let params = hardware::Params::load_default().context("loading hardware/")?;
    let hw = params.fingertip;
    let base = default_config(&hw, args.mesh_size);
    let hp_tau = args.highpass_tau.or(args
        .paper_sensor
        .then_some(params.paper_sensor.ac_coupling_tau_s));
    let highpass = move |t: &[f64], y: &mut [f64]| {
        if let Some(tau_s) = hp_tau {
            HighpassCoupling { tau_s }.apply(t, y)
        }
    };
    let mut out = std::io::stdout().lock();
    if args.causes {
        return run_causes(&mut out, &base, &hw, args.json);
    }
    let (config, label) = match &args.cause {
        None if args.paper_sensor => (
            causes::paper_sensor(&base, &params.paper_sensor),
            paper_sensor_label(&params.paper_sensor),
        ),
        None => (base.clone(), "default".to_string()),
        Some(name) => {
            let config = causes::apply_named(&base, name)
                .with_context(|| format!("--cause {name}: not a known cause (see --causes)"))?;
            (config, name.clone())
        }
    };
    let label = match hp_tau {
        Some(t) => format!("{label} + AC coupling tau {t} s"),
        None => label,
    };
    let card = observations::score(&Setup::from_hardware(config, &hw, &label, Some(&highpass)))
        .context("running the fingertip model")?;
    let lmee = if args.lmee { Some(lmee(&base)?) } else { None };
    if args.json {
        let doc = serde_json::json!({"scorecard": card, "lmee": lmee});
        writeln!(out, "{}", serde_json::to_string_pretty(&doc)?)?;
        return Ok(());
    }
    print_card(&mut out, &card)?;
    if let Some(points) = lmee {
        print_lmee(&mut out, &points)?;
    }
    Ok(())
}

/// The paper's sensor's name in the scorecard, with its relaxation (the AC coupling is added
/// to the label with the other filters).
fn paper_sensor_label(p: &hardware::PaperSensor) -> String {
    format!(
        "paper's sensor: relaxation g {} tau {} s",
        p.relaxation_fraction, p.relaxation_tau_s
    )
}

/// `--session DIR`: write the paper's session and print its laws.
fn run_session(args: &Args, dir: &std::path::Path) -> anyhow::Result<()> {
    anyhow::ensure!(
        args.rate.is_finite() && args.rate > 0.0,
        "--rate must be a positive number of Hz"
    );
    anyhow::ensure!(
        args.noise_v.is_finite() && args.noise_v >= 0.0,
        "--noise-v must be zero or positive"
    );
    let laws = paper_session::write_session(&SessionOptions {
        dir: dir.to_path_buf(),
        rate_hz: args.rate,
        seed: args.seed,
        noise_v: args.noise_v,
    })?;
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&laws)?)?;
    } else {
        paper_session::print_laws(&mut out, &laws)?;
    }
    Ok(())
}

/// Rod travel of the LMEE sweep, mm: just under the default's travel at 60 N and 0° (8.46 mm),
/// so that every angle reaches it.
const LMEE_TRAVEL_MM: f64 = 8.0;
const LMEE_STEPS: usize = 10;

/// Energy along the inclination for the default drive and for the rod driven along z.
fn lmee(base: &Config) -> anyhow::Result<Vec<(String, Vec<energy::EnergyPoint>)>> {
    let along_z = causes::apply_named(base, "drive_along_z").context("cause drive_along_z")?;
    [
        ("jig (drive along the rod)", base.clone()),
        ("upright (drive along z)", along_z),
    ]
    .into_iter()
    .map(|(name, c)| {
        let pts =
            energy::energy_along_inclination(&c, &LMEE_THETAS_DEG, LMEE_TRAVEL_MM, LMEE_STEPS)
                .with_context(|| format!("energy sweep, {name}"))?;
        Ok((name.to_string(), pts))
    })
    .collect()
}

fn print_lmee(
    out: &mut impl Write,
    sweeps: &[(String, Vec<energy::EnergyPoint>)],
) -> std::io::Result<()> {
    writeln!(
        out,
        "\nelastic potential energy along the inclination at {LMEE_TRAVEL_MM} mm of travel:"
    )?;
    for (name, pts) in sweeps {
        writeln!(out, "  {name}:")?;
        for p in pts {
            writeln!(
                out,
                "    theta {:4.1}  U {:.5} J  load {:6.2} N  Fz {:.4} N",
                p.theta_deg, p.energy_j, p.force_n, p.fz_n
            )?;
        }
        let minima = energy::interior_minima(pts, 1e-4);
        writeln!(out, "    interior local minima of U: {minima:?}")?;
    }
    Ok(())
}

/// The causes table: one line per model, the status of each observation and the key values.
fn run_causes(
    out: &mut impl Write,
    base: &Config,
    hw: &hardware::Fingertip,
    json: bool,
) -> anyhow::Result<()> {
    let ac = |t: &[f64], y: &mut [f64]| {
        HighpassCoupling {
            tau_s: AC_COUPLING_TAU_S,
        }
        .apply(t, y)
    };
    let visco = causes::fe_causes()
        .into_iter()
        .find(|c| c.name == "viscoelastic_gel")
        .map(|c| (c.apply)(base));
    let mut models: Vec<(String, Config, bool)> = vec![("default".into(), base.clone(), false)];
    for c in causes::fe_causes() {
        models.push((c.name.into(), (c.apply)(base), false));
    }
    models.push(("ac_coupling_25s".into(), base.clone(), true));
    if let Some(v) = visco {
        models.push(("viscoelastic_gel+ac_coupling_25s".into(), v, true));
    }
    let mut cards = Vec::new();
    if !json {
        writeln!(out, "| model | 1 | 2 | 3 | 4 | 5 | 6 | 7 | Fz20/Fz0 | Fz30/Fz0 | recovery s | crossing | S lobe |")?;
        writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    }
    for (name, config, with_ac) in models {
        let filter: Option<&observations::OutputFilter> = if with_ac { Some(&ac) } else { None };
        match observations::score(&Setup::from_hardware(config, hw, &name, filter)) {
            Ok(card) => {
                if !json {
                    writeln!(out, "{}", table_line(&card))?;
                }
                cards.push(serde_json::to_value(&card)?);
            }
            Err(e) => {
                if !json {
                    writeln!(out, "| {name} | FE failed: {e} |")?;
                }
                cards.push(serde_json::json!({"label": name, "error": e.to_string()}));
            }
        }
    }
    if json {
        writeln!(out, "{}", serde_json::to_string_pretty(&cards)?)?;
    }
    Ok(())
}

fn table_line(card: &Scorecard) -> String {
    let status: Vec<&str> = card
        .rows
        .iter()
        .map(|r| if r.agree { "✓" } else { "✗" })
        .collect();
    let v = |row: usize, check: usize| card.rows[row].checks[check].value;
    format!(
        "| {} | {} | {:.3} | {:.3} | {:.1} | {:.3} | {:.4} |",
        card.label,
        status.join(" | "),
        v(1, 0),
        v(5, 0),
        v(2, 1),
        v(4, 0),
        v(6, 0)
    )
}
