//! `tactile diagnose --simulation` through the binary (`docs/simulation-format.md`): one
//! recording, a batch with a folder of simulations, a joint session with one simulation per
//! recording; and the one-line refusals with their exit codes.

mod common;

use std::path::{Path, PathBuf};

use common::{fails, tactile};

fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-simcli-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The lab's law: F = k d^1.8 N, Fz = 0.015 V/N.
fn law(k: f64, d: f64) -> (f64, f64) {
    let f = k * d.max(0.0).powf(1.8);
    (f, 0.015 * f)
}

/// The rod's path at time `t`: 2 s at -0.5 mm, in at 20 mm/min to `peak_mm`, 2 s hold, out at
/// 600 mm/min, 30 s of rest.
fn rod(t: f64, peak_mm: f64) -> f64 {
    let t_in = (peak_mm + 0.5) / (20.0 / 60.0);
    let t_out = (peak_mm + 0.5) / (600.0 / 60.0);
    match t {
        t if t < 2.0 => -0.5,
        t if t < 2.0 + t_in => -0.5 + (t - 2.0) * 20.0 / 60.0,
        t if t < 4.0 + t_in => peak_mm,
        t if t < 4.0 + t_in + t_out => peak_mm - (t - 4.0 - t_in) * 600.0 / 60.0,
        _ => -0.5,
    }
}

const META: &str = "# contact_angle_deg = 20\n# azimuth_deg = 60\n# fingertip_radius_mm = 20\n\
                    # gain_fz = 1100\n# gain_mx = 110\n# gain_my = 110\n# excitation_V = 3.3\n";

/// A recording at 100 Hz of the law with a gel `k`, deterministic noise, no moments measured.
fn write_recording(path: &Path, k: f64, peak_mm: f64) {
    let mut text = format!("# format = tactile-recording/1\n# sample_rate_hz = 100\n{META}t_s,rod_mm,load_N,fz_V,mx_V,my_V\n");
    let mut state = 12345u64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2.0 * 3f64.sqrt()
    };
    let t_end = 2.0 + (peak_mm + 0.5) * 3.0 + 2.0 + 0.1 * (peak_mm + 0.5) + 30.0;
    for i in 0..(t_end * 100.0) as usize {
        let t = i as f64 / 100.0;
        let d = rod(t, peak_mm);
        let (f, fz) = law(k, d);
        text.push_str(&format!(
            "{t:.2},{d:.5},{:.6},{:.6},,\n",
            f + 0.02 * noise(),
            fz + 0.002 * noise()
        ));
    }
    std::fs::write(path, text).unwrap();
}

/// The lab's static response of the law with its guess `k` of the gel, to `to_mm`.
fn write_table(path: &Path, k: f64, to_mm: f64) {
    let mut text = format!(
        "# format = tactile-response/1\n# source = the lab's law\n{META}rod_mm,load_N,fz_V\n"
    );
    for i in 0..=(to_mm / 0.1).ceil() as usize {
        let d = i as f64 * 0.1;
        let (f, fz) = law(k, d);
        text.push_str(&format!("{d},{f},{fz}\n"));
    }
    std::fs::write(path, text).unwrap();
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn one_recording_against_its_simulation_says_whose_and_how_aligned() {
    let d = dir("one");
    let (rec, sim, out) = (d.join("rec.csv"), d.join("sim.csv"), d.join("out.json"));
    write_recording(&rec, 1.1, 6.0);
    write_table(&sim, 1.0, 6.2);
    let o = tactile(&[
        "diagnose",
        s(&rec),
        "--simulation",
        s(&sim),
        "--json",
        s(&out),
        "--report",
        s(&d.join("r.html")),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = json(&out);
    assert_eq!(v["verdict"], "no_significant_mismatch", "{v}");
    let scale = v["baseline"]["params"]["load_scale"].as_f64().unwrap();
    assert!((scale - 1.1).abs() < 0.01, "{scale}");
    let sim_out = &v["baseline"]["simulation"];
    assert_eq!(sim_out["file"], s(&sim));
    assert_eq!(sim_out["form"], "static_response");
    assert_eq!(sim_out["metadata"]["source"], "the lab's law");
    assert!(sim_out["not_compared"]["mx_V"].is_string());
    let page = std::fs::read_to_string(d.join("r.html")).unwrap();
    assert!(page.contains("id=simulation") && page.contains("the lab's law"));
}

#[test]
fn a_batch_pairs_by_folder_and_a_session_in_order() {
    let d = dir("batch");
    let (recs, sims) = (d.join("recs"), d.join("sims"));
    std::fs::create_dir_all(&recs).unwrap();
    std::fs::create_dir_all(&sims).unwrap();
    for (name, k) in [("a.csv", 1.0), ("b.csv", 1.2)] {
        write_recording(&recs.join(name), k, 6.0);
        write_table(&sims.join(name), 1.0, 6.2);
    }
    let out = d.join("out");
    let o = tactile(&[
        "diagnose",
        s(&recs),
        "--simulation",
        s(&sims),
        "--out-dir",
        s(&out),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = json(&out.join("b.json"));
    assert_eq!(b["baseline"]["simulation"]["file"], s(&sims.join("b.csv")));
    let scale = b["baseline"]["params"]["load_scale"].as_f64().unwrap();
    assert!((scale - 1.2).abs() < 0.015, "{scale}");
    let joint = d.join("joint.json");
    let (a, b) = (recs.join("a.csv"), recs.join("b.csv"));
    let (sa, sb) = (sims.join("a.csv"), sims.join("b.csv"));
    let o = tactile(&[
        "diagnose",
        "--joint",
        s(&a),
        s(&b),
        "--simulation",
        s(&sa),
        "--simulation",
        s(&sb),
        "--json",
        s(&joint),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(json(&joint)["recordings"].as_array().unwrap().len() == 2);
}

#[test]
fn refusals_name_the_file_and_the_field() {
    let d = dir("refused");
    let (rec, out) = (d.join("rec.csv"), d.join("out.json"));
    write_recording(&rec, 1.0, 6.0);
    let gone = d.join("gone.csv");
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--simulation",
            s(&gone),
            "--json",
            s(&out),
        ]),
        66,
        &["gone.csv"],
    );
    let short = d.join("short.csv");
    write_table(&short, 1.0, 4.0);
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--simulation",
            s(&short),
            "--json",
            s(&out),
        ]),
        65,
        &[
            "short.csv",
            "`rod_mm`",
            "does not cover the recorded travel",
        ],
    );
    let other = d.join("other.csv");
    write_recording(&other, 1.0, 4.0);
    // Another test of the same protocol (a stiffer gel): a byte-identical copy is refused as
    // the same recording given twice before any pairing.
    let rec2 = d.join("rec2.csv");
    write_recording(&rec2, 1.1, 6.0);
    fails(
        &tactile(&[
            "diagnose",
            s(&rec2),
            "--simulation",
            s(&other),
            "--json",
            s(&out),
        ]),
        65,
        &["other.csv", "`rod_mm`", "another protocol"],
    );
    let bad = d.join("bad.csv");
    std::fs::write(
        &bad,
        "# format = tactile-response/1\nrod_mm,load_N,Fz_V\n0,0,0\n",
    )
    .unwrap();
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--simulation",
            s(&bad),
            "--json",
            s(&out),
        ]),
        65,
        &["bad.csv: line 2", "`Fz_V`"],
    );
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            s(&rec2),
            "--simulation",
            s(&short),
            "--simulation",
            s(&bad),
            "--simulation",
            s(&bad),
            "--out-dir",
            s(&d.join("o")),
        ]),
        64,
        &["3 simulations for 2 recordings"],
    );
    assert!(!out.exists(), "nothing written on a refusal");
}

/// A simulation in another unit is refused naming the factor and the unit it looks like, exit
/// 65, nothing written; `--accept-scale` takes it on purpose.
#[test]
fn a_simulation_in_another_unit_is_refused_unless_accepted() {
    let d = dir("unit");
    let (rec, out) = (d.join("rec.csv"), d.join("out.json"));
    write_recording(&rec, 1.1, 6.0);
    // The lab's law in mN labelled N: loads and outputs a thousand times the recording's.
    let milli = d.join("milli.csv");
    write_table(&milli, 1100.0, 6.2);
    let run = |sim: &Path, extra: &[&str]| {
        let mut args = vec![
            "diagnose",
            s(&rec),
            "--simulation",
            s(sim),
            "--json",
            s(&out),
        ];
        args.extend_from_slice(extra);
        tactile(&args)
    };
    fails(
        &run(&milli, &[]),
        65,
        &[
            "milli.csv",
            "load is 1000x the recording's",
            "mN labelled N?",
        ],
    );
    assert!(!out.exists(), "a refused diagnosis wrote its JSON");
    let o = run(&milli, &["--accept-scale"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let scale = json(&out)["baseline"]["params"]["load_scale"]
        .as_f64()
        .unwrap();
    assert!((scale - 1e-3).abs() < 1e-5, "{scale}");
    // The rod's travel in µm labelled mm.
    let micro = d.join("micro.csv");
    let text = std::fs::read_to_string(&milli).unwrap();
    let mut lines = Vec::new();
    for line in text.lines() {
        match line.split_once(',') {
            Some((rod, rest)) if rod.parse::<f64>().is_ok() => {
                lines.push(format!("{},{rest}", rod.parse::<f64>().unwrap() * 1000.0));
            }
            _ => lines.push(line.to_string()),
        }
    }
    std::fs::write(&micro, lines.join("\n") + "\n").unwrap();
    fails(
        &run(&micro, &[]),
        65,
        &[
            "micro.csv",
            "rod travel",
            "1033x the recording's",
            "µm labelled mm?",
        ],
    );
}

/// A binary simulation or recording is bad data (65) naming the file and the line, not an
/// I/O failure (74).
#[test]
fn a_binary_simulation_or_recording_is_bad_data_naming_the_line() {
    let d = dir("binary");
    let (rec, out) = (d.join("rec.csv"), d.join("out.json"));
    write_recording(&rec, 1.0, 6.0);
    let blob = d.join("blob.csv");
    std::fs::write(
        &blob,
        [0x89u8, b'P', b'N', b'G', 0, 0xff, 0xfe, b'\n', 1, 2],
    )
    .unwrap();
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--simulation",
            s(&blob),
            "--json",
            s(&out),
        ]),
        65,
        &["blob.csv", "line 1", "not UTF-8"],
    );
    let table = d.join("latin.csv");
    write_table(&table, 1.0, 6.2);
    let mut bytes = std::fs::read(&table).unwrap();
    bytes.splice(0..0, b"# note = 20\xb0C\n".iter().copied());
    std::fs::write(&table, bytes).unwrap();
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--simulation",
            s(&table),
            "--json",
            s(&out),
        ]),
        65,
        &["latin.csv", "line 1", "not UTF-8"],
    );
    fails(
        &tactile(&["diagnose", s(&blob), "--json", s(&out)]),
        65,
        &["blob.csv", "line 1"],
    );
}
