//! The public Mach-1 tests (real machines pressing a soft material; `shared/real-data/mach1/`
//! beside the checkout, read from their zip and never copied in), imported as `tactile import`
//! does and diagnosed blind. What a physicist expects (the data's README): stress relaxation in
//! Hayes' and the Static holds, a rate-dependent loss in the Dynamic sinusoids.
//! `cargo test -p diagnosis --test mach1 -- --nocapture` (about a second each, in the test run)

#[path = "support/mach1_zip.rs"]
mod mach1_zip;

use diagnosis::output::Report;
use mach1_zip::import;
use recording::Recording;

fn diagnose(rec: &Recording, label: &str) -> Report {
    let hw = hardware::Params::load_default().expect("hardware");
    let opt = diagnosis::Options::from_hardware(&hw).expect("options");
    let d = diagnosis::diagnose(rec, label, &opt).unwrap_or_else(|e| panic!("{label}: {e}"));
    let r = d.report;
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

/// Relaxation named, alone, no parameter of it at a bound, held-out misfit at least halved.
fn relaxation_found(r: &Report, label: &str) {
    let names: Vec<&str> = r.effects.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["viscoelastic_relaxation"], "{label}");
    let at_bound: Vec<&str> = r.effects[0]
        .parameters
        .iter()
        .filter(|p| p.at_bound)
        .map(|p| p.name.as_str())
        .collect();
    assert!(at_bound.is_empty(), "{label}: at a bound: {at_bound:?}");
    assert!(
        r.fit.heldout.rmse_after <= 0.5 * r.fit.heldout.rmse_before,
        "{label}: held-out {} -> {}",
        r.fit.heldout.rmse_before,
        r.fit.heldout.rmse_after
    );
}

#[test]
fn hayes_first_site_relaxes() {
    let r = import("Hayes_data.txt", |b| b.kind == "Stress Relaxation");
    relaxation_found(&diagnose(&r, "Hayes site 1"), "Hayes site 1");
}

#[test]
fn static_steps_relax() {
    let r = import("Static_data.txt", |_| true);
    relaxation_found(&diagnose(&r, "Static"), "Static");
}

#[test]
fn dynamic_sinusoids_lose_energy_with_rate() {
    let r = import("Dynamic_data.txt", |b| b.index == 1);
    let report = diagnose(&r, "Dynamic block 1");
    let names: Vec<&str> = report.effects.iter().map(|e| e.name.as_str()).collect();
    assert!(
        names == ["viscoelastic_relaxation"] || names == ["hysteresis"],
        "a rate-dependent loss, and nothing else: {names:?}"
    );
    assert!(report.fit.heldout.rmse_after < report.fit.heldout.rmse_before);
}
