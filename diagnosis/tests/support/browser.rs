//! The headless-Chromium machinery of the HTML reports' browser tests (`report_browser.rs`,
//! `session_report_browser.rs`; `#[path]`-included, not a test target of its own): a page
//! loaded with an error catcher first and a checking script last, which writes its findings
//! into the DOM that `--dump-dom` returns, and the checks every report passes. Chromium comes
//! from `scripts/setup.sh`; without it the tests fail (they never skip).
// Each test target uses part of it.
#![allow(dead_code)]

use std::fs::File;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

pub const CHROMIUM: &str = "/usr/bin/chromium";
const WINDOW: &str = "--window-size=1280,900";

/// Catches errors from the first byte on, including resources that fail to load.
pub const CATCHER: &str = "<script>window.__errors=[];\
addEventListener('error',e=>__errors.push(e.message||('failed to load '+(e.target&&(e.target.src||e.target.href)))),true);\
addEventListener('unhandledrejection',e=>__errors.push('unhandled rejection '+e.reason));\
{const ce=console.error;console.error=(...a)=>{__errors.push(a.join(' '));ce(...a)}}</script>";

/// Writes its findings into the DOM as lines `key values...`, which `--dump-dom` returns.
pub const CHECKER: &str = "<script>{const out=[];\
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

pub fn chromium() -> PathBuf {
    let path = PathBuf::from(CHROMIUM);
    assert!(
        path.exists(),
        "{CHROMIUM} not found: the report's browser test needs Chromium; scripts/setup.sh installs it"
    );
    path
}

/// What a Chromium run printed.
pub struct Printed {
    pub stdout: String,
    pub stderr: String,
}

/// Chromium headless on `page` with `args` and a fresh profile in `dir`. Output goes to files
/// (a DOM dump overfills a pipe nobody reads until the end); the whole process group is killed
/// after two minutes.
pub fn run_chromium(page: &Path, dir: &Path, args: &[&str]) -> Printed {
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
pub fn instrumented(html: &str) -> String {
    instrumented_with(html, "")
}

/// The report with the error catcher first, then the checker and `extra` (a page's own
/// checking script) last.
pub fn instrumented_with(html: &str, extra: &str) -> String {
    let head = "<meta charset=utf-8>";
    assert!(
        html.contains(head) && html.contains("</body>"),
        "unexpected page shape"
    );
    html.replacen(head, &format!("{head}{CATCHER}"), 1)
        .replacen("</body>", &format!("{CHECKER}{extra}</body>"), 1)
}

/// The checker's lines out of the dumped DOM.
pub fn findings(dom: &str) -> Vec<String> {
    findings_in(dom, "report-check")
}

/// The lines a checking script wrote into `<pre id=ID>` of the dumped DOM.
pub fn findings_in(dom: &str, id: &str) -> Vec<String> {
    let start = dom
        .find(&format!("<pre id=\"{id}\">"))
        .expect("the checking script did not run");
    let body = &dom[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</pre>").unwrap()];
    let text = body
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    text.lines().map(str::to_string).collect()
}

pub fn numbers(line: &str) -> Vec<f64> {
    line.split(' ')
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect()
}

/// The page's own findings: no errors, nothing fetched, every figure drawn, verdict in view.
pub fn check_findings(lines: &[String], figures: usize) {
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

/// A screenshot of `page` into `dir/name`: it must be a PNG of some substance.
pub fn screenshot(page: &Path, dir: &Path, name: &str) {
    let shot = dir.join(name);
    run_chromium(
        page,
        &dir.join("profile-shot"),
        &[&format!("--screenshot={}", shot.display())],
    );
    let png = std::fs::read(&shot).expect("no screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 10_000,
        "screenshot of {} bytes",
        png.len()
    );
}
