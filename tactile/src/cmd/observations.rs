//! `tactile observations`: the paper's seven observations against the fingertip model, one row
//! each (statement, quantity, model value, agree or not, the physics responsible); `--causes`
//! scores every candidate cause of the disagreements, `--lmee` the elastic energy along the
//! inclination. The computation is `fingertip::observations`; the AC coupling of the offset
//! cut, an electronics effect, is the `sim` catalogue's operator.

use std::io::Write;

use anyhow::Context;
use fingertip::observations::{self, causes, energy, Scorecard, Setup};
use fingertip::Config;
use sim::effects::HighpassCoupling;

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
    let hw = hardware::Params::load_default()
        .context("loading hardware/")?
        .fingertip;
    let base = default_config(&hw, args.mesh_size);
    let hp_tau = args.highpass_tau;
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
