//! The observation scorecard against what `fingertip/OBSERVATIONS.md` claims, row by row.
//! The default model runs in the test run (four FE curves and a 32-step recovery on 7,080
//! tetrahedra: 66-84 s measured on 2 cores shared with three other builds, load average 7-10;
//! a few seconds of FE when idle); the causes that fix rows are `--ignored`:
//! `cargo test -p fingertip --release --test observations -- --ignored`.

use fingertip::observations::{self, causes, Scorecard, Setup};
use fingertip::Config;
use sim::effects::HighpassCoupling;

/// The mesh of the scorecard (7,080 tetrahedra; 8 mm does not reach 60 N).
const MESH_MM: f64 = 5.0;
/// Load steps to the peak: half the CLI's 40, to halve the test's time; every status is far
/// enough from its threshold not to move (checked against the CLI's 40-step run).
const LOAD_STEPS: usize = 20;

fn setup<'a>(
    config: Config,
    hw: &hardware::Fingertip,
    f: Option<&'a observations::OutputFilter>,
) -> Setup<'a> {
    let config = Config {
        load_steps: LOAD_STEPS,
        ..config
    };
    Setup::from_hardware(config, hw, "test", f)
}

/// The status column of the table under `heading` in OBSERVATIONS.md: observation -> agree.
fn claimed(heading: &str) -> Vec<(u8, bool)> {
    let md = include_str!("../OBSERVATIONS.md");
    let start = md
        .find(heading)
        .unwrap_or_else(|| panic!("OBSERVATIONS.md has no {heading:?}"));
    md[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .filter_map(|l| {
            let cells: Vec<&str> = l
                .split('|')
                .map(str::trim)
                .filter(|c| !c.is_empty())
                .collect();
            let number = cells.first()?.parse::<u8>().ok()?;
            Some((number, cells.last()?.starts_with("agree")))
        })
        .collect()
}

fn assert_matches(card: &Scorecard, heading: &str) {
    let claims = claimed(heading);
    assert_eq!(claims.len(), 7, "seven rows under {heading:?}");
    for (number, agree) in claims {
        let row = &card.rows[usize::from(number) - 1];
        assert_eq!(row.number, number);
        assert_eq!(
            row.agree, agree,
            "observation {number}: model {:?}, OBSERVATIONS.md claims agree = {agree}",
            row.checks
        );
    }
}

#[test]
fn default_model_scores_as_observations_md_claims() {
    let hw = hardware::Params::load_default()
        .expect("hardware")
        .fingertip;
    let card = observations::score(&setup(Config::from_hardware(&hw, MESH_MM), &hw, None))
        .expect("scorecard");
    assert_eq!(card.rows.len(), 7);
    assert_matches(&card, "## Scorecard of the default model");
}

fn cause(hw: &hardware::Fingertip, name: &str) -> Config {
    causes::apply_named(&Config::from_hardware(hw, MESH_MM), name).expect("known cause")
}

#[test]
#[ignore = "three more scorecards, ~2 min"]
fn causes_score_as_observations_md_claims() {
    let hw = hardware::Params::load_default()
        .expect("hardware")
        .fingertip;
    let card =
        observations::score(&setup(cause(&hw, "drive_along_z"), &hw, None)).expect("scorecard");
    assert_matches(&card, "## Scorecard with the rod driven along z");
    let card =
        observations::score(&setup(cause(&hw, "viscoelastic_gel"), &hw, None)).expect("scorecard");
    assert_matches(&card, "## Scorecard with a viscoelastic gel");
    let ac = |t: &[f64], y: &mut [f64]| HighpassCoupling { tau_s: 25.0 }.apply(t, y);
    let base = Config::from_hardware(&hw, MESH_MM);
    let card = observations::score(&setup(base, &hw, Some(&ac))).expect("scorecard");
    assert_matches(&card, "## Scorecard with AC coupling");
}

/// The paper's sensor (`hardware/paper-sensor.toml`): the default fingertip with the gel's
/// relaxation, every output through the offset cut's AC coupling; what the CLI's
/// `--paper-sensor` scores.
#[test]
#[ignore = "one more scorecard, ~30 s"]
fn papers_sensor_scores_as_observations_md_claims() {
    let params = hardware::Params::load_default().expect("hardware");
    let (hw, paper) = (&params.fingertip, &params.paper_sensor);
    let config = causes::paper_sensor(&Config::from_hardware(hw, MESH_MM), paper);
    let tau_s = paper.ac_coupling_tau_s;
    let ac = move |t: &[f64], y: &mut [f64]| HighpassCoupling { tau_s }.apply(t, y);
    let card = observations::score(&setup(config, hw, Some(&ac))).expect("scorecard");
    assert_matches(&card, "## Scorecard of the paper's sensor");
}
