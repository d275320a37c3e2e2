//! `tactile prove`: generate recordings with concealed catalogue effects, diagnose them blind,
//! print and write the score table (markdown + CSV) and a summary plot.

use std::path::PathBuf;
use std::time::Instant;
use sysexit::ResultExt as _;

use anyhow::Context;

use baseline::Readout;
use diagnosis::Options;
use prove::lab::LabKind;
use prove::sessions::SessionKind;
use prove::{categories, csv, markdown, real, run as score, summary_svg, Plan, Summary};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder for score.md, score.csv and summary.svg.
    #[arg(long, default_value = "prove-out")]
    pub out: PathBuf,
    /// Seed of the generator.
    #[arg(long, default_value_t = 2026)]
    pub seed: u64,
    /// Sample rate of the generated recordings, Hz.
    #[arg(long, default_value_t = 1000.0)]
    pub rate: f64,
    /// Recordings with no effect.
    #[arg(long, default_value_t = 6)]
    pub no_effect: usize,
    /// Recordings per catalogue effect.
    #[arg(long, default_value_t = 3)]
    pub per_effect: usize,
    /// Also write the generated recordings (large) into the output folder.
    #[arg(long)]
    pub write_recordings: bool,
    /// Score the categories instead (protocols, another model's baseline, three effects,
    /// nuisances, then physics out of the catalogue, the catalogue at new stages and physics
    /// nobody named):
    /// categories.md in the output folder, one table row per category.
    #[arg(long)]
    pub categories: bool,
    /// With --categories, also score the real Mach-1 tests: the examples' zip or a folder holding
    /// Hayes_data.txt, Static_data.txt and Dynamic_data.txt (shared/real-data/mach1/).
    #[arg(long, requires = "categories")]
    pub mach1: Option<PathBuf>,
    /// With --categories, only the two groups of described physics (out of the catalogue, the
    /// catalogue at new stages): the quick run while the method is worked on.
    #[arg(long, requires = "categories")]
    pub described_only: bool,
    /// With --categories, only the group of physics nobody named (a row per kind, and null
    /// recordings): the quick run while the discovery step is worked on.
    #[arg(long, requires = "categories", conflicts_with = "described_only")]
    pub unnamed_only: bool,
    /// Score the session category instead: sessions of three recordings across azimuths, rod
    /// speeds and contact angles, diagnosed jointly (`tactile diagnose --joint`): sessions.md
    /// and each session's JSON in the output folder.
    #[arg(long, conflicts_with = "categories")]
    pub sessions: bool,
    /// Score the user's-simulation category instead: the lab's own model of the test (another
    /// contact law and other output laws) written as a simulation file (a static response or
    /// the test in time at its own rate), the recording that model with concealed effects;
    /// each diagnosed against the simulation and, for comparison, against our own baseline:
    /// simulation.md and the simulations (`simulations/`) in the output folder.
    #[arg(long, conflicts_with_all = ["categories", "sessions"])]
    pub simulation_category: bool,
    /// With --sessions, the category: `lab` (mixed sessions, null sessions on another model's
    /// fingertip, friction and hysteresis or relaxation across speeds, tests at their own rates
    /// and gains; sessions-lab.md and lab-NN.json in the output folder). Without it, the
    /// session category of issue 28.
    #[arg(long, requires = "sessions", value_name = "CATEGORY")]
    pub category: Option<SessionCategory>,
    /// With --sessions, sessions of each kind (default 2; with --category lab, rounds of its
    /// kinds, default 3: two mixed and two hysteresis-or-relaxation sessions a round).
    #[arg(long, requires = "sessions")]
    pub per_kind: Option<usize>,
    /// With --sessions, only the sessions of this kind (the same sessions as in the whole run);
    /// `one-press` is a study beyond the category, run only so. With --category lab, one of
    /// its kinds (mixed, null-other, friction-speeds, hysteresis-or-relaxation, rates-gains).
    #[arg(long, requires = "sessions", value_name = "KIND", value_parser = any_kind)]
    pub kind: Option<AnyKind>,
}

/// A session category other than the default one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SessionCategory {
    /// What a lab meets: prove::lab.
    Lab,
}

/// A kind of either session category, by its key (the keys are distinct).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnyKind {
    Session(SessionKind),
    Lab(LabKind),
}

/// A session kind by its key, for `--kind`.
fn any_kind(key: &str) -> Result<AnyKind, String> {
    if let Some(k) = SessionKind::from_key(key) {
        return Ok(AnyKind::Session(k));
    }
    if let Some(k) = LabKind::from_key(key) {
        return Ok(AnyKind::Lab(k));
    }
    let keys: Vec<&str> = SessionKind::ALL
        .iter()
        .chain(&SessionKind::EXTRA)
        .map(|k| k.key())
        .chain(LabKind::ALL.iter().map(|k| k.key()))
        .collect();
    Err(format!(
        "no session kind `{key}` (the kinds: {})",
        keys.join(", ")
    ))
}

/// Arguments that do not go together.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(String);

impl sysexit::ExitStatus for UsageError {
    fn exit_code(&self) -> u8 {
        sysexit::USAGE
    }
}

/// `--kind` of the default session category, or the error naming the category it belongs to.
fn standard_kind(kind: Option<AnyKind>) -> Result<Option<SessionKind>, UsageError> {
    match kind {
        None => Ok(None),
        Some(AnyKind::Session(k)) => Ok(Some(k)),
        Some(AnyKind::Lab(k)) => Err(UsageError(format!(
            "--kind {} is a kind of --category lab",
            k.key()
        ))),
    }
}

/// `--kind` of the lab category, or the error naming the category it belongs to.
fn lab_kind(kind: Option<AnyKind>) -> Result<Option<LabKind>, UsageError> {
    match kind {
        None => Ok(None),
        Some(AnyKind::Lab(k)) => Ok(Some(k)),
        Some(AnyKind::Session(k)) => Err(UsageError(format!(
            "--kind {} is not a kind of --category lab (its kinds: {})",
            k.key(),
            LabKind::ALL.map(|k| k.key()).join(", ")
        ))),
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let hw = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let plan = Plan {
        seed: args.seed,
        sample_rate_hz: args.rate,
        no_effect: args.no_effect,
        per_effect: args.per_effect,
        radius_mm: hw.fingertip.radius_mm,
        options: Options::from_hardware(&hw)?,
        readout: Readout::from_hardware(&hw)?,
    };
    if args.sessions {
        if args.category == Some(SessionCategory::Lab) {
            return run_lab(&plan, &args);
        }
        return run_sessions(&plan, &args);
    }
    if args.categories {
        return run_categories(&plan, &args);
    }
    if args.simulation_category {
        return run_simulation_category(&plan, &args);
    }
    let started = Instant::now();
    let cases = plan.generate()?;
    let generated = started.elapsed().as_secs_f64();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    if args.write_recordings {
        write_recordings(&cases, &args.out)?;
    }
    let scores = score(&cases, &plan.options);
    let summary = Summary::of(&scores);
    let table = markdown(&scores, &summary);
    println!("{table}");
    println!(
        "generated {} recordings in {generated:.1} s; total {:.1} s",
        cases.len(),
        started.elapsed().as_secs_f64()
    );
    std::fs::write(args.out.join("score.md"), &table)?;
    std::fs::write(args.out.join("score.csv"), csv(&scores))?;
    std::fs::write(args.out.join("summary.svg"), summary_svg(&scores))?;
    anyhow::ensure!(
        summary.passes(),
        "the proof's acceptance criteria are not met (see the table)"
    );
    Ok(())
}

/// Each generated recording as `prove-NN.csv` in `out`.
fn write_recordings(cases: &[prove::Case], out: &std::path::Path) -> anyhow::Result<()> {
    for c in cases {
        let path = out.join(format!("prove-{:02}.csv", c.id));
        let file =
            std::fs::File::create(&path).with_context(|| format!("creating {}", path.display()))?;
        c.recording
            .write_to(file)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// The session category: sessions.md (the table per kind, then one row per session) and
/// `session-NN.json`, each session's joint diagnosis, in the output folder.
fn run_sessions(plan: &Plan, args: &Args) -> anyhow::Result<()> {
    use prove::sessions;
    let started = Instant::now();
    let kind = standard_kind(args.kind).coded()?;
    let cases = plan.sessions(args.per_kind.unwrap_or(2), kind)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    if args.write_recordings {
        for c in &cases {
            for (name, rec) in &c.recordings {
                let path = args.out.join(name);
                let file = std::fs::File::create(&path)
                    .with_context(|| format!("creating {}", path.display()))?;
                rec.write_to(file)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
        }
    }
    let scores = sessions::run(&cases, &plan.options);
    for s in &scores {
        if let Some(r) = &s.report {
            let path = args.out.join(format!("session-{:02}.json", s.id));
            let text = serde_json::to_string_pretty(r)?;
            std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let text = format!(
        "{}\n{}\n{} sessions at {} Hz, seed {}, in {:.0} s\n",
        sessions::table(&scores),
        sessions::details(&scores, &cases),
        cases.len(),
        plan.sample_rate_hz,
        plan.seed,
        started.elapsed().as_secs_f64()
    );
    println!("{text}");
    let path = args.out.join("sessions.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

/// `--simulation-category`: each recording diagnosed against the lab's simulation and against
/// our own baseline; simulation.md and the simulations in the output folder.
fn run_simulation_category(plan: &Plan, args: &Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let cases = plan.simulation_cases(&args.out.join("simulations"))?;
    if args.write_recordings {
        for c in &cases {
            let path = args.out.join(format!("prove-{:04}.csv", c.case.id));
            let file = std::fs::File::create(&path)
                .with_context(|| format!("creating {}", path.display()))?;
            c.case
                .recording
                .write_to(file)
                .with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let scored = plan.run_simulation_cases(&cases);
    let (table, against_simulation, _) = prove::simulation::table(&cases, &scored);
    let text = format!(
        "# The user's simulation as the baseline, seed {}, {} Hz

{table}
{} recordings in {:.0} s
",
        plan.seed,
        plan.sample_rate_hz,
        cases.len(),
        started.elapsed().as_secs_f64()
    );
    println!("{text}");
    let path = args.out.join("simulation.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    anyhow::ensure!(
        against_simulation.passes(),
        "the user's-simulation category misses the acceptance bar (see the table)"
    );
    Ok(())
}

/// The lab category: sessions-lab.md (the table per kind and the bar, then one row per
/// session) and `lab-NN.json`, each session's joint diagnosis, in the output folder; printed
/// too. Fails (exit 1) when the bar is not met.
fn run_lab(plan: &Plan, args: &Args) -> anyhow::Result<()> {
    use prove::lab;
    let kind = lab_kind(args.kind).coded()?;
    let started = Instant::now();
    let cases = plan.lab_sessions(args.per_kind.unwrap_or(3), kind)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    if args.write_recordings {
        for (name, rec) in cases.iter().flat_map(|c| &c.recordings) {
            let path = args.out.join(name);
            let file = std::fs::File::create(&path)
                .with_context(|| format!("creating {}", path.display()))?;
            rec.write_to(file)
                .with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let scores = lab::run(&cases, &plan.options);
    for s in &scores {
        if let Some(r) = &s.report {
            let path = args.out.join(format!("lab-{:02}.json", s.id));
            let text = serde_json::to_string_pretty(r)?;
            std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let text = format!(
        "{}\n{}\n{} lab sessions at {} Hz, seed {}, in {:.0} s\n",
        lab::table(&scores),
        lab::details(&scores, &cases),
        cases.len(),
        plan.sample_rate_hz,
        plan.seed,
        started.elapsed().as_secs_f64()
    );
    println!("{text}");
    let path = args.out.join("sessions-lab.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    anyhow::ensure!(
        lab::Totals::of(&scores).passes(),
        "the lab sessions miss the bar (see {})",
        path.display()
    );
    Ok(())
}

/// `--categories`: every category's recordings diagnosed blind, a row per category.
fn run_categories(plan: &Plan, args: &Args) -> anyhow::Result<()> {
    if args.described_only || args.unnamed_only {
        std::fs::create_dir_all(&args.out)
            .with_context(|| format!("creating {}", args.out.display()))?;
        let mut text = String::new();
        let (pass, group) = if args.unnamed_only {
            (run_unnamed(plan, args, &mut text)?, "physics nobody named")
        } else {
            (run_described(plan, args, &mut text)?, "described physics")
        };
        let path = args.out.join("categories.md");
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        anyhow::ensure!(
            pass,
            "the {group} misses the acceptance bar (see the table)"
        );
        return Ok(());
    }
    let started = Instant::now();
    let (labelled, cases) = plan.generate_categories()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    if args.write_recordings {
        write_recordings(&cases, &args.out)?;
    }
    let scores = score(&cases, &plan.options);
    let table = categories::table(&labelled, &scores);
    let check = categories::described_on_effect_free(&labelled, &scores);
    let details = categories::details(&labelled, &scores);
    println!("{table}\n{check}\n{details}");
    println!(
        "{} recordings in {:.1} s",
        labelled.len(),
        started.elapsed().as_secs_f64()
    );
    let mut real_pass = true;
    let mut text = format!("{table}\n{check}\n{details}");
    if let Some(source) = &args.mach1 {
        let read = |name: &str| read_mach1(source, name).map_err(|e| format!("{e:#}"));
        let real = real::run_mach1(&read, plan).map_err(anyhow::Error::msg)?;
        let real_table = real::table(&real);
        println!("{real_table}");
        real_pass = real.iter().all(|s| s.correct);
        text.push_str(&format!("\n{real_table}"));
    }
    let described_pass = run_described(plan, args, &mut text)?;
    let unnamed_pass = run_unnamed(plan, args, &mut text)?;
    let path = args.out.join("categories.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    anyhow::ensure!(
        categories::all_pass(&labelled, &scores) && real_pass && described_pass && unnamed_pass,
        "some categories miss the acceptance bar (see the table)"
    );
    Ok(())
}

/// The described physics (out of the catalogue, the catalogue at new stages), diagnosed blind:
/// its tables appended to `text`; whether both groups pass.
fn run_described(plan: &Plan, args: &Args, text: &mut String) -> anyhow::Result<bool> {
    let started = Instant::now();
    let (labelled, cases) = plan.generate_described()?;
    if args.write_recordings {
        write_recordings(&cases, &args.out)?;
    }
    let scores = score(&cases, &plan.options);
    let table = categories::described::table(&labelled, &scores);
    println!("{table}");
    println!(
        "{} described recordings in {:.1} s",
        labelled.len(),
        started.elapsed().as_secs_f64()
    );
    text.push_str(&format!(
        "\n## Physics the catalogue lacks, and the catalogue at new stages\n\n{table}"
    ));
    Ok(categories::described::all_pass(&labelled, &scores))
}

/// Physics nobody named and the null recordings beside it, diagnosed blind: its table (a row per
/// kind, then every recording) appended to `text`; whether the group passes its bar.
fn run_unnamed(plan: &Plan, args: &Args, text: &mut String) -> anyhow::Result<bool> {
    let started = Instant::now();
    let (labelled, cases) = plan.generate_unnamed()?;
    if args.write_recordings {
        write_recordings(&cases, &args.out)?;
    }
    let scores = score(&cases, &plan.options);
    let table = categories::unnamed::table(&labelled, &scores);
    println!("{table}");
    println!(
        "{} recordings of physics nobody named in {:.1} s",
        labelled.len(),
        started.elapsed().as_secs_f64()
    );
    text.push_str(&format!(
        "\n## Physics nobody named (seed {}, blind)\n\n{table}",
        plan.seed
    ));
    Ok(categories::unnamed::totals(&labelled, &scores).passes())
}

/// The text of `name` from the Mach-1 examples at `source` (their zip, or a folder), each byte
/// one character (the exports are Latin-1).
fn read_mach1(source: &std::path::Path, name: &str) -> anyhow::Result<String> {
    use std::io::Read;
    let raw = if source.is_dir() {
        let path = source.join(name);
        std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?
    } else {
        let file =
            std::fs::File::open(source).with_context(|| format!("opening {}", source.display()))?;
        let mut zip = zip::ZipArchive::new(file)
            .with_context(|| format!("{}: not a zip archive", source.display()))?;
        let mut entry = zip
            .by_name(name)
            .with_context(|| format!("{}: no {name} inside", source.display()))?;
        let mut raw = Vec::new();
        entry
            .read_to_end(&mut raw)
            .with_context(|| format!("{}: reading {name}", source.display()))?;
        raw
    };
    Ok(raw.iter().map(|&b| char::from(b)).collect())
}
