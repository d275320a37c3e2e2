//! The public Mach-1 tests (real machines pressing a soft material; `shared/real-data/mach1/`
//! beside the checkout, read from their zip and never copied in), imported as `tactile import`
//! does and diagnosed blind. What a physicist expects (the data's README): stress relaxation in
//! Hayes' and the Static holds, a rate-dependent loss in the Dynamic sinusoids.
//! `cargo test -p prove --test mach1 -- --nocapture` (about a second each, in the test run)

#[path = "../../diagnosis/tests/support/mach1_zip.rs"]
mod mach1_zip;

use diagnosis::output::Report;
use mach1_zip::import;
use prove::real::{self, MACH1};
use recording::Recording;

fn diagnose(rec: &Recording, label: &str) -> Report {
    let hw = hardware::Params::load_default().expect("hardware");
    let opt = diagnosis::Options::from_hardware(&hw).expect("options");
    let d = diagnosis::diagnose(rec, label, &opt).unwrap_or_else(|e| panic!("{label}: {e}"));
    let r = d.report;
    // The material alone: no output's calibration is reported, every one of the contact law is.
    let shown: Vec<&str> = r
        .baseline
        .parameters
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    assert!(!shown.iter().any(|n| n.starts_with("scale_")), "{shown:?}");
    for n in [
        "force_exponent_shift",
        "force_warp_at_60pct",
        "force_warp_at_10pct",
    ] {
        assert!(shown.contains(&n), "{label}: {n} missing from {shown:?}");
    }
    let names: Vec<&str> = r.effects.iter().map(|e| e.name.as_str()).collect();
    println!(
        "{label}: {:?} {names:?}, held-out {:.4} -> {:.4}, {:.1} s",
        r.verdict, r.fit.heldout.rmse_before, r.fit.heldout.rmse_after, r.seconds
    );
    for e in &r.effects {
        println!("  {}: {:?}; {}", e.name, e.params.0, e.evidence);
    }
    r
}

/// The real test `i` of the proof's Mach-1 category, diagnosed and scored by the category's
/// own rule (`prove::real`): the expected effect set exactly; for the relaxation
/// tests no parameter at a bound and the held-out misfit at least halved, else falling.
fn answered_right(i: usize) {
    let test = &MACH1[i];
    let rec = import(test.file, test.pick);
    let r = diagnose(&rec, test.label);
    let s = real::score(test, &r);
    assert!(s.correct, "{}: {s:?}", test.label);
}

#[test]
fn hayes_first_site_relaxes() {
    answered_right(0);
}

#[test]
fn hayes_second_site_relaxes_and_is_not_frozen() {
    answered_right(1);
}

#[test]
fn hayes_third_site_relaxes() {
    answered_right(2);
}

#[test]
fn static_steps_relax() {
    answered_right(3);
}

#[test]
fn dynamic_sinusoids_lose_energy_with_rate() {
    answered_right(4);
}

/// Hayes' three sites as a session: one material, one protocol, three places. Each hold
/// relaxes over more than one time scale (two Prony terms, shared or each site's own as the
/// data decide), the session's fit of every site at least halves its held-out misfit, as the
/// site's own diagnosis does, and so does each site predicted with the others' shared physics.
#[test]
fn hayes_sites_relax_jointly_over_two_time_scales() {
    let hw = hardware::Params::load_default().expect("hardware");
    let opt = diagnosis::Options::from_hardware(&hw).expect("options");
    let inputs = real::HAYES_BLOCKS
        .iter()
        .map(|&i| {
            let rec = import("Hayes_data.txt", |b| b.index == i);
            (format!("site{i}.csv"), Ok(rec))
        })
        .collect();
    let r = diagnosis::joint::diagnose_recordings(inputs, &opt)
        .expect("the session is analysed")
        .report;
    let shared = r.shared.iter().map(|s| &s.effect);
    for row in &r.recordings {
        let effects: Vec<_> = row.effects.iter().flatten().chain(shared.clone()).collect();
        let names: Vec<&str> = effects.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["viscoelastic_relaxation"], "{}", row.file);
        assert!(
            effects[0].params.get("tau2_s").is_some(),
            "{}: {:?}",
            row.file,
            effects[0].params
        );
        let held = &row.fit.as_ref().expect("analysed").heldout;
        assert!(
            held.rmse_after <= 0.5 * held.rmse_before,
            "{}: {held:?}",
            row.file
        );
    }
    for v in &r.validation.leave_one_out {
        assert!(v.rmse_after <= 0.5 * v.rmse_before, "{v:?}");
    }
}

/// The Dynamic sinusoids as a session: one material at five rates, diagnosed jointly. Its
/// relaxation is the gel's, named once among the shared effects, and no recording names it
/// again with its own parameters.
#[test]
fn dynamic_sinusoids_share_one_relaxation() {
    let hw = hardware::Params::load_default().expect("hardware");
    let opt = diagnosis::Options::from_hardware(&hw).expect("options");
    let inputs = (1..=5)
        .map(|i| {
            let rec = import("Dynamic_data.txt", |b| b.index == i);
            (format!("sin{i}.csv"), Ok(rec))
        })
        .collect();
    let r = diagnosis::joint::diagnose_recordings(inputs, &opt)
        .expect("the session is analysed")
        .report;
    let shared: Vec<&str> = r.shared.iter().map(|s| s.effect.name.as_str()).collect();
    assert!(shared.contains(&"viscoelastic_relaxation"), "{shared:?}");
    for row in &r.recordings {
        let own: Vec<&str> = row
            .effects
            .iter()
            .flatten()
            .map(|e| e.name.as_str())
            .collect();
        assert!(
            !own.contains(&"viscoelastic_relaxation"),
            "{}: {own:?}",
            row.file
        );
    }
    assert_eq!(r.validation.leave_one_out.len(), 5);
}
