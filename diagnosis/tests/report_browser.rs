//! The HTML report in a real browser (headless Chromium): a recording with concealed effects is
//! diagnosed, its report written, and a copy of the page with a small checking script loaded.
//! The page must load without console errors and without fetching anything, every figure must
//! be drawn and laid out with a non-zero size, and the verdict sentence must be visible in the
//! first screen. A screenshot is taken too. Chromium comes from `scripts/setup.sh`; without it
//! this test fails (it never skips).

#[path = "support/browser.rs"]
mod browser;

use baseline::synth::{simulate, Noise, SimSpec};
use baseline::{BaselineParams, Readout};
use browser::{check_findings, chromium, findings, instrumented, run_chromium, screenshot};
use sim::effects::Effect;

/// Two cycles at 100 Hz with relaxation, AC coupling and a warm-up drift: short enough for a
/// debug-build suite, rich enough for zooms and a partial explanation.
fn diagnosed() -> diagnosis::Diagnosis {
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let fingertip = opt.fe.response(20.0, 20.0, 60.0).unwrap();
    let effects = [
        "viscoelastic_relaxation:tau_s=4,fraction=0.3",
        "highpass_coupling:tau_s=40",
        "thermal_drift:amplitude_V=0.03,tau_s=60",
    ];
    let spec = SimSpec {
        fingertip: &fingertip,
        readout: Readout::from_hardware(&hw).unwrap(),
        baseline: BaselineParams::nominal(1.1e5),
        contact_angle_deg: 20.0,
        azimuth_deg: 60.0,
        radius_mm: 20.0,
        test: sim::compression::RodSchedule {
            sample_rate_hz: 100.0,
            ..Default::default()
        },
        peak_loads_n: vec![60.0, 40.0],
        effects: effects.map(|e| Effect::from_spec(e).unwrap()).to_vec(),
        noise: Noise {
            load_n: 0.02,
            volts: [2e-3; 3],
            temp_c: 0.0,
        },
        seed: 3,
        ambient_c: 24.0,
        warm_up_rise_c: 0.0,
        ambient_swing: None,
        source: "report browser test".into(),
    };
    diagnosis::diagnose(&simulate(&spec), "browser-test.csv", &opt).unwrap()
}

#[test]
fn report_renders_in_headless_chromium() {
    chromium();
    let dir = std::env::temp_dir().join(format!("tactile-report-browser-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let d = diagnosed();
    let report = dir.join("report.html");
    diagnosis::report::write(&report, &d).unwrap();
    let html = std::fs::read_to_string(&report).unwrap();
    let figures = html.matches("<svg").count();
    let used = d.plots.used.iter().filter(|u| **u).count();
    assert!(
        figures >= used + d.report.effects.len(),
        "{figures} figures for {used} channels"
    );
    assert!(
        !d.report.effects.is_empty(),
        "the concealed effects were not found"
    );

    let checked = dir.join("checked.html");
    std::fs::write(&checked, instrumented(&html)).unwrap();
    let out = run_chromium(&checked, &dir.join("dom"), &["--dump-dom"]);
    let console: Vec<&str> = out
        .stderr
        .lines()
        .filter(|l| l.contains("CONSOLE") || l.contains("Uncaught"))
        .collect();
    assert!(console.is_empty(), "console messages: {console:#?}");
    check_findings(&findings(&out.stdout), figures);

    screenshot(&report, &dir, "report.png");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The checks can fail: a page with a script error, an empty figure and a hidden verdict is
/// caught on each count.
#[test]
fn the_checks_catch_a_broken_page() {
    let dir = std::env::temp_dir().join(format!("tactile-report-broken-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let broken = "<!doctype html><meta charset=utf-8><body>\
                  <p id=verdict style='visibility:hidden'>hidden</p><svg></svg>\
                  <script>no_such_function()</script></body>";
    let page = dir.join("broken.html");
    std::fs::write(&page, instrumented(broken)).unwrap();
    let out = run_chromium(&page, &dir.join("dom"), &["--dump-dom"]);
    let lines = findings(&out.stdout);
    assert!(
        lines.iter().any(|l| l.contains("no_such_function")),
        "{lines:#?}"
    );
    assert!(
        out.stderr.contains("Uncaught"),
        "the console log shows the error too"
    );
    let caught = std::panic::catch_unwind(|| check_findings(&lines, 1));
    assert!(caught.is_err(), "a broken page passed: {lines:#?}");
    // Each failure on its own, the others repaired.
    let repaired = |from: &str, to: &str| -> Vec<String> {
        let good = [
            "errors 0",
            "resources 0",
            "viewport 1280 800",
            "svg 0 50 3 900 500",
        ];
        let mut v: Vec<String> = good.iter().map(|s| s.to_string()).collect();
        v.push("verdict 60 160 900 1 200".into());
        v.iter()
            .map(|l| if l == from { to.to_string() } else { l.clone() })
            .collect()
    };
    assert!(std::panic::catch_unwind(|| check_findings(&repaired("", ""), 1)).is_ok());
    for (from, to) in [
        ("errors 0", "errors 1"),
        ("resources 0", "resources 2"),
        ("svg 0 50 3 900 500", "svg 0 3 0 900 500"),
        ("svg 0 50 3 900 500", "svg 0 50 3 0 0"),
        ("verdict 60 160 900 1 200", "verdict 60 160 900 0 200"),
        ("verdict 60 160 900 1 200", "verdict 1200 1300 900 1 200"),
    ] {
        let lines = repaired(from, to);
        assert!(
            std::panic::catch_unwind(|| check_findings(&lines, 1)).is_err(),
            "{to} passed"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
