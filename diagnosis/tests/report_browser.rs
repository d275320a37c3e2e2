//! The HTML report in a real browser (headless Chromium): a recording with concealed effects is
//! diagnosed, its report written, and a copy of the page with a small checking script loaded.
//! The page must load without console errors and without fetching anything, every figure must
//! be drawn and laid out with a non-zero size, and the verdict sentence must be visible in the
//! first screen. A screenshot is taken too. Chromium comes from `scripts/setup.sh`; without it
//! this test fails (it never skips).

use std::fs::File;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use baseline::synth::{simulate, Noise, SimSpec};
use baseline::{BaselineParams, Readout};
use sim::effects::Effect;

const CHROMIUM: &str = "/usr/bin/chromium";
const WINDOW: &str = "--window-size=1280,900";

/// Catches errors from the first byte on, including resources that fail to load.
const CATCHER: &str = "<script>window.__errors=[];\
addEventListener('error',e=>__errors.push(e.message||('failed to load '+(e.target&&(e.target.src||e.target.href)))),true);\
addEventListener('unhandledrejection',e=>__errors.push('unhandled rejection '+e.reason));\
{const ce=console.error;console.error=(...a)=>{__errors.push(a.join(' '));ce(...a)}}</script>";

/// Writes its findings into the DOM as lines `key values...`, which `--dump-dom` returns.
const CHECKER: &str = "<script>{const out=[];\
out.push('errors '+__errors.length);__errors.forEach(e=>out.push('error '+e));\
out.push('resources '+performance.getEntriesByType('resource').length);\
out.push('viewport '+innerWidth+' '+innerHeight);\
document.querySelectorAll('svg').forEach((s,i)=>{const b=s.getBoundingClientRect();\
out.push(['svg',i,s.querySelectorAll('polyline,path,line,rect,circle,text').length,\
s.querySelectorAll('polyline').length,Math.round(b.width),Math.round(b.height)].join(' '))});\
const v=document.getElementById('verdict');\
if(v){const b=v.getBoundingClientRect(),st=getComputedStyle(v);\
const shown=st.display!=='none'&&st.visibility==='visible'&&parseFloat(st.opacity)>0;\
out.push(['verdict',Math.round(b.top),Math.round(b.bottom),Math.round(b.width),shown?1:0,v.innerText.trim().length].join(' '))}\
const pre=document.createElement('pre');pre.id='report-check';pre.textContent=out.join('\\n');\
document.body.appendChild(pre)}</script>";

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

fn chromium() -> PathBuf {
    let path = PathBuf::from(CHROMIUM);
    assert!(
        path.exists(),
        "{CHROMIUM} not found: the report's browser test needs Chromium; scripts/setup.sh installs it"
    );
    path
}

/// What a Chromium run printed.
struct Printed {
    stdout: String,
    stderr: String,
}

/// Chromium headless on `page` with `args` and a fresh profile in `dir`. Output goes to files
/// (a DOM dump overfills a pipe nobody reads until the end); the whole process group is killed
/// after two minutes.
fn run_chromium(page: &Path, dir: &Path, args: &[&str]) -> Printed {
    std::fs::create_dir_all(dir).unwrap();
    let (out, err) = (dir.join("stdout"), dir.join("stderr"));
    let mut child = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
        ])
        .args(["--no-first-run", "--disable-background-networking"])
        .args(["--disable-component-update", "--disable-sync", WINDOW])
        .arg(format!("--user-data-dir={}", dir.join("profile").display()))
        .args(["--enable-logging=stderr", "--v=0"])
        .args(args)
        .arg(format!("file://{}", page.display()))
        .stdout(File::create(&out).unwrap())
        .stderr(File::create(&err).unwrap())
        .process_group(0)
        .spawn()
        .expect("starting chromium");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > Duration::from_secs(120) {
            let group = format!("-{}", child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
            panic!(
                "chromium did not finish within two minutes on {}",
                page.display()
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let printed = Printed {
        stdout: std::fs::read_to_string(out).unwrap(),
        stderr: std::fs::read_to_string(err).unwrap(),
    };
    assert!(status.success(), "chromium failed: {}", printed.stderr);
    printed
}

/// The report with the error catcher first and the checker last.
fn instrumented(html: &str) -> String {
    let head = "<meta charset=utf-8>";
    assert!(
        html.contains(head) && html.contains("</body>"),
        "unexpected page shape"
    );
    html.replacen(head, &format!("{head}{CATCHER}"), 1)
        .replacen("</body>", &format!("{CHECKER}</body>"), 1)
}

/// The checker's lines out of the dumped DOM.
fn findings(dom: &str) -> Vec<String> {
    let start = dom
        .find("<pre id=\"report-check\">")
        .expect("the checking script did not run");
    let body = &dom[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</pre>").unwrap()];
    let text = body
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    text.lines().map(str::to_string).collect()
}

fn numbers(line: &str) -> Vec<f64> {
    line.split(' ')
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect()
}

/// The page's own findings: no errors, nothing fetched, every figure drawn, verdict in view.
fn check_findings(lines: &[String], figures: usize) {
    let get = |key: &'static str| {
        lines
            .iter()
            .filter(move |l| l.split(' ').next() == Some(key))
    };
    assert_eq!(
        get("errors").next().map(|l| numbers(l)),
        Some(vec![0.0]),
        "{lines:#?}"
    );
    assert_eq!(
        get("resources").next().map(|l| numbers(l)),
        Some(vec![0.0]),
        "fetched: {lines:#?}"
    );
    let svgs: Vec<Vec<f64>> = get("svg").map(|l| numbers(l)).collect();
    assert_eq!(svgs.len(), figures, "{lines:#?}");
    for s in &svgs {
        let (drawn, polylines, w, h) = (s[1], s[2], s[3], s[4]);
        assert!(
            drawn > 20.0 && polylines >= 2.0,
            "figure {} nearly empty: {s:?}",
            s[0]
        );
        assert!(
            w > 300.0 && h > 100.0,
            "figure {} laid out at {w} x {h}",
            s[0]
        );
    }
    let viewport = numbers(get("viewport").next().expect("viewport"));
    let v = numbers(get("verdict").next().expect("no #verdict on the page"));
    let (top, bottom, width, shown, chars) = (v[0], v[1], v[2], v[3], v[4]);
    assert!(
        shown == 1.0 && width > 0.0 && chars > 40.0,
        "verdict hidden: {v:?}"
    );
    assert!(
        top >= 0.0 && bottom <= viewport[1],
        "verdict outside the first screen: {v:?}"
    );
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

    let shot = dir.join("report.png");
    run_chromium(
        &report,
        &dir.join("profile-shot"),
        &[&format!("--screenshot={}", shot.display())],
    );
    let png = std::fs::read(&shot).expect("no screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 10_000,
        "screenshot of {} bytes",
        png.len()
    );
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
