//! The session's page in a real browser (headless Chromium), checked as the single report is
//! (`report_browser.rs`, the same machinery): three short simulated recordings of one rotated
//! chip at three azimuths and a file that is not a recording are diagnosed jointly, the page
//! written, and a copy loaded with the checking scripts. It must load without console errors
//! and without fetching anything, every figure (the leave-one-out bars, one per recording) must
//! be drawn and laid out with a non-zero size, the verdict sentence must be in the first screen,
//! and every section must be there: the recordings with the bad file's error in red, the shared
//! effect, the validation's table and bars, the models tried collapsed. The verdict's box must
//! say, in red and first, that the bad file failed and why; each recording's figure must draw
//! the recording under the session's model and the baseline, a residual panel under each
//! channel and the held-out stretch. A screenshot is taken too. Chromium comes from `scripts/setup.sh`; without it this test fails (it never skips).

#[path = "support/browser.rs"]
mod browser;

use std::path::{Path, PathBuf};

use baseline::standard_test::{simulate_standard_test, SimulateOptions};
use browser::{
    check_findings, chromium, findings, findings_in, instrumented_with, run_chromium, screenshot,
};

/// The page's own sections, in order.
const SECTIONS: [&str; 8] = [
    "recordings",
    "shared",
    "sensitivities",
    "validation",
    "undecided",
    "candidates",
    "each",
    "verdict",
];

/// Writes the session page's findings into `<pre id=session-check>`: each section's height
/// (-1: missing), each table's class and rows, the bars of the first figure after the
/// validation heading with a visible size, the colour of error cells, and the candidates'
/// `<details>` (open or not, rows).
const SESSION_CHECKER: &str = "<script>{const out=[];\
['recordings','shared','sensitivities','validation','undecided','candidates','each','verdict'].forEach(id=>{\
const e=document.getElementById(id);out.push('section '+id+' '+(e?Math.round(e.getBoundingClientRect().height):-1))});\
document.querySelectorAll('table').forEach(t=>out.push('table '+t.className+' '+t.rows.length));\
const f=document.querySelector('h2#validation ~ figure svg');\
if(f){out.push('bars '+[...f.querySelectorAll('rect')].filter(r=>{const b=r.getBoundingClientRect();\
return b.width>4&&b.height>4}).length)}\
document.querySelectorAll('td.error').forEach(td=>out.push('error-cell '+getComputedStyle(td).color.replace(/ /g,'')));\
document.querySelectorAll('details').forEach(d=>out.push('details '+(d.open?1:0)+' '+d.querySelectorAll('tr').length));\
out.push('links '+document.querySelectorAll('a,link,img,iframe,object,embed').length);\
const v=document.getElementById('verdict'),fail=v&&v.querySelector('.failure');\
out.push('verdict-border '+getComputedStyle(v).borderLeftColor.replace(/ /g,''));\
if(fail){out.push('failure '+getComputedStyle(fail).color.replace(/ /g,'')+' '+fail.textContent)}\
document.querySelectorAll('h2#each ~ figure svg').forEach((s,i)=>{\
const t=[...s.querySelectorAll('text')].map(x=>x.textContent.trim());\
const has=l=>t.includes(l)?1:0;if(!has('recording'))return;\
const wide=[...s.querySelectorAll('polyline')].filter(p=>p.getAttribute('stroke-width')==='7').length;\
const held=[...s.querySelectorAll('rect')].filter(r=>r.getAttribute('fill')==='#969696'&&r.getBoundingClientRect().height>40).length;\
out.push(['each',i,has('recording'),has(\"session's model\"),has('baseline'),has('held out (never fitted)'),\
has('residual, baseline'),has(\"residual, session's model\"),t.filter(x=>x.startsWith('residual [')).length,wide,held].join(' '))});\
const pre=document.createElement('pre');pre.id='session-check';pre.textContent=out.join('\\n');\
document.body.appendChild(pre)}</script>";

/// Three recordings of a chip turned by 6° at azimuths 0, 45 and 90° (250 Hz, 20 s rest: short
/// enough for a debug-build suite), and a file that is not a recording.
fn session_files(dir: &Path) -> Vec<PathBuf> {
    let hw = hardware::Params::load_default().unwrap();
    let mut files = Vec::new();
    for azimuth in [0.0, 45.0, 90.0] {
        let opt = SimulateOptions {
            rate_hz: Some(250.0),
            recovery_s: Some(20.0),
            noise_v: 5e-4,
            noise_load_n: 2e-3,
            seed: azimuth as u64 + 1,
            effects: vec!["crosstalk:angle_deg=6".into()],
            ..SimulateOptions::new(20.0, azimuth, 2.0)
        };
        let rec = simulate_standard_test(&opt, &hw).unwrap();
        let path = dir.join(format!("az{azimuth}.csv"));
        rec.write_to(std::fs::File::create(&path).unwrap()).unwrap();
        files.push(path);
    }
    // Named as markup: the page must show the name, escaped, not interpret it.
    let bad = dir.join("bad<i>.csv");
    std::fs::write(&bad, "time_s,load_N\n0,1\n").unwrap();
    files.insert(1, bad);
    files
}

/// The session's findings: every section there, the error in red, the bars drawn, the
/// candidates collapsed, nothing linked.
fn check_session(lines: &[String], recordings: usize, analysed: usize) {
    let get = |key: &'static str| {
        lines
            .iter()
            .filter(move |l| l.split(' ').next() == Some(key))
    };
    for id in SECTIONS {
        let line = get("section")
            .find(|l| l.split(' ').nth(1) == Some(id))
            .unwrap_or_else(|| panic!("no section {id}: {lines:#?}"));
        let height: f64 = line.split(' ').nth(2).unwrap().parse().unwrap();
        assert!(height > 0.0, "section {id} missing or empty: {line}");
    }
    let rows = |class: &str| {
        get("table")
            .find(|l| l.split(' ').nth(1) == Some(class))
            .and_then(|l| l.split(' ').nth(2)?.parse::<usize>().ok())
    };
    assert_eq!(rows("recordings"), Some(recordings + 1), "{lines:#?}");
    assert_eq!(rows("validation"), Some(analysed + 1), "{lines:#?}");
    assert!(rows("shared").is_some_and(|n| n >= 2), "{lines:#?}");
    let errors: Vec<&String> = get("error-cell").collect();
    assert_eq!(errors.len(), recordings - analysed, "{lines:#?}");
    for e in errors {
        assert!(e.ends_with("rgb(187,0,0)"), "an error not in red: {e}");
    }
    let bars = get("bars")
        .next()
        .expect("no bar chart after the validation heading");
    let bars: usize = bars.split(' ').nth(1).unwrap().parse().unwrap();
    // Two bars per recording, the background, the legend's box and its two swatches.
    assert!(
        bars >= 2 * analysed + 4,
        "{bars} visible bars for {analysed} recordings"
    );
    let details: Vec<&String> = get("details").collect();
    assert_eq!(details.len(), 1, "{lines:#?}");
    assert!(
        details[0].starts_with("details 0 "),
        "candidates not collapsed: {details:?}"
    );
    assert_eq!(get("links").next().map(String::as_str), Some("links 0"));
    check_headline(lines, recordings - analysed);
    check_each(lines, analysed);
}

/// With a file that failed, the verdict's box is not green: its border is red and it leads
/// with the failure, in red, naming the file.
fn check_headline(lines: &[String], failed: usize) {
    let find = |key: &str| lines.iter().find(|l| l.split(' ').next() == Some(key));
    let border = find("verdict-border").expect("no verdict border");
    let failure = find("failure");
    if failed == 0 {
        assert!(failure.is_none(), "{failure:?}");
        return;
    }
    assert!(border.ends_with("rgb(214,39,40)"), "{border}");
    let failure = failure.expect("the headline does not say a file failed");
    assert!(
        failure.starts_with(&format!("failure rgb(187,0,0) {failed} of ")),
        "{failure}"
    );
    assert!(
        failure.contains("bad<i>.csv") && failure.contains("could not be analysed"),
        "{failure}"
    );
}

/// Each analysed recording's figure (of those under "Each recording", the ones that draw the
/// recording): the recording (wide, under the models), the session's model and the baseline
/// named in the legends, a residual panel under each signal panel, the held-out stretch
/// shaded.
fn check_each(lines: &[String], analysed: usize) {
    let each: Vec<Vec<usize>> = lines
        .iter()
        .filter(|l| l.split(' ').next() == Some("each"))
        .map(|l| l.split(' ').skip(1).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(each.len(), analysed, "{lines:#?}");
    for e in &each {
        let (named, residuals, wide, held) = (&e[1..7], e[7], e[8], e[9]);
        assert!(
            named.iter().all(|&n| n == 1),
            "a legend entry missing: {e:?}"
        );
        // One residual panel per signal panel, and the recording drawn wide in each (its
        // legend's swatches are wide too).
        assert!(residuals >= 2 && wide >= residuals, "{e:?}");
        assert!(held >= residuals, "the held-out stretch not shaded: {e:?}");
    }
}

#[test]
fn session_report_renders_in_headless_chromium() {
    chromium();
    let dir = std::env::temp_dir().join(format!("tactile-session-browser-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let files = session_files(&dir);
    let hw = hardware::Params::load_default().unwrap();
    let opt = diagnosis::Options::from_hardware(&hw).unwrap();
    let d = diagnosis::joint::diagnose_session(&files, &opt).unwrap();
    let analysed = d.singles.iter().filter(|(_, s)| s.is_ok()).count();
    assert_eq!(
        analysed, 3,
        "the simulated recordings were not all analysed"
    );
    assert!(
        d.report.shared.iter().any(|s| s.effect.name == "crosstalk"),
        "the turned chip was not found: {:?}",
        d.report.shared
    );
    let page = dir.join("session.html");
    diagnosis::joint::write_report(&page, &d).unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    let figures = html.matches("<svg").count();
    let left = d
        .report
        .recordings
        .iter()
        .filter(|r| r.remains.is_some())
        .count();
    assert_eq!(
        figures,
        1 + analysed + left,
        "the bars, one figure per recording and one of what remains in each not explained"
    );
    for banned in [
        "<script", "<a ", "href=", "src=", "<link", "@import", "url(",
    ] {
        assert!(!html.contains(banned), "the page holds {banned}");
    }
    assert!(
        html.contains("bad&lt;i&gt;.csv") && !html.contains("bad<i>"),
        "a file name not escaped"
    );

    let checked = dir.join("checked.html");
    std::fs::write(&checked, instrumented_with(&html, SESSION_CHECKER)).unwrap();
    let out = run_chromium(&checked, &dir.join("dom"), &["--dump-dom"]);
    let console: Vec<&str> = out
        .stderr
        .lines()
        .filter(|l| l.contains("CONSOLE") || l.contains("Uncaught"))
        .collect();
    assert!(console.is_empty(), "console messages: {console:#?}");
    check_findings(&findings(&out.stdout), figures);
    check_session(
        &findings_in(&out.stdout, "session-check"),
        files.len(),
        analysed,
    );

    screenshot(&page, &dir, "session.png");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The session's checks can fail: a missing section, an error not in red, missing bars, open
/// candidates or a link are each caught (the page-wide checks have their own test in
/// `report_browser.rs`).
#[test]
fn the_session_checks_catch_a_broken_page() {
    let good: Vec<String> = SECTIONS
        .iter()
        .map(|id| format!("section {id} 120"))
        .chain(
            [
                "table recordings 5",
                "table shared 2",
                "table validation 4",
                "table candidates 27",
                "bars 11",
                "error-cell rgb(187,0,0)",
                "details 0 27",
                "links 0",
                "verdict-border rgb(214,39,40)",
                "failure rgb(187,0,0) 1 of 4 files could not be analysed (bad<i>.csv: not a recording)",
                "each 0 1 1 1 1 1 1 3 3 6",
                "each 1 1 1 1 1 1 1 3 3 6",
                "each 2 1 1 1 1 1 1 3 3 6",
            ]
            .map(String::from),
        )
        .collect();
    check_session(&good, 4, 3);
    let broken = |from: &str, to: &str| -> Vec<String> {
        good.iter()
            .map(|l| if l == from { to.to_string() } else { l.clone() })
            .collect()
    };
    for (from, to) in [
        ("section shared 120", "section shared -1"),
        ("section each 120", "section each 0"),
        ("table recordings 5", "table recordings 4"),
        ("table shared 2", "table other 2"),
        ("error-cell rgb(187,0,0)", "error-cell rgb(34,34,34)"),
        ("bars 11", "bars 5"),
        ("details 0 27", "details 1 27"),
        ("links 0", "links 1"),
        ("verdict-border rgb(214,39,40)", "verdict-border rgb(44,160,44)"),
        (
            "failure rgb(187,0,0) 1 of 4 files could not be analysed (bad<i>.csv: not a recording)",
            "failure rgb(34,34,34) 1 of 4 files could not be analysed (bad<i>.csv: not a recording)",
        ),
        ("each 1 1 1 1 1 1 1 3 3 6", "each 1 1 1 0 1 1 1 3 3 6"),
        ("each 1 1 1 1 1 1 1 3 3 6", "each 1 1 1 1 1 1 1 3 0 6"),
        ("each 1 1 1 1 1 1 1 3 3 6", "each 1 1 1 1 1 1 1 3 3 0"),
        ("each 2 1 1 1 1 1 1 3 3 6", "each 2 1 1 1 1 1 1 0 0 6"),
    ] {
        let lines = broken(from, to);
        assert!(
            std::panic::catch_unwind(|| check_session(&lines, 4, 3)).is_err(),
            "{to} passed"
        );
    }
}
