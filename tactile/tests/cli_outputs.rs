//! Outputs where the user points (`docs/bad-input.md`, "Outputs"), through the binary: a
//! device or FIFO written as it is, never replaced; a full device an error naming it (74); `-`
//! the standard output; a link written through; the page of one recording alone. Devices are
//! nodes made in a scratch folder where this process may (root), never /dev's own, which are
//! only checked to be devices still.

mod common;

use std::os::unix::fs::FileTypeExt as _;
use std::path::{Path, PathBuf};

use common::{fails, tactile};

fn scratch(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-outputs-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A short simulated recording (the standard test at a low rate).
fn recording(d: &Path) -> PathBuf {
    let rec = d.join("r.csv");
    let o = tactile(&[
        "simulate",
        "--contact-angle",
        "15",
        "--azimuth",
        "30",
        "--peak-load",
        "2",
        "--rate",
        "100",
        "--noise-v",
        "1e-5",
        "--out",
        s(&rec),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    rec
}

/// `mknod` in `d` (minor 3: null, 7: full) where allowed; else the one in /dev.
fn device(d: &Path, name: &str, minor: &str) -> PathBuf {
    let p = d.join(name);
    let made = std::process::Command::new("mknod")
        .args([s(&p), "c", "1", minor])
        .status()
        .is_ok_and(|st| st.success());
    if made {
        p
    } else {
        PathBuf::from(format!("/dev/{name}"))
    }
}

fn char_device(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

#[test]
fn devices_fifos_links_and_dash_are_written_where_the_user_points() {
    let d = scratch("all");
    let rec = recording(&d);
    // The page alone, to a null device; the JSON to the standard output.
    let null = device(&d, "null", "3");
    let o = tactile(&["diagnose", s(&rec), "--json", "-", "--report", s(&null)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["format"], "tactile-diagnosis/1");
    assert!(char_device(&null) && char_device(Path::new("/dev/null")));
    // A full device: one line naming it, exit 74, the device still a device, and the page
    // beside it (a regular file) not written.
    let full = device(&d, "full", "7");
    let page = d.join("page.html");
    fails(
        &tactile(&[
            "diagnose",
            s(&rec),
            "--json",
            s(&full),
            "--report",
            s(&page),
        ]),
        74,
        &[s(&full), "No space left"],
    );
    assert!(char_device(&full) && !page.exists());
    // A symlink: written through, the link kept.
    let (target, link) = (d.join("real.json"), d.join("link.json"));
    std::fs::write(&target, "old").unwrap();
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = tactile(&["diagnose", s(&rec), "--json", s(&link)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    assert!(std::fs::read_to_string(&target)
        .unwrap()
        .contains("tactile-diagnosis/1"));
    // A FIFO, with a reader.
    let fifo = d.join("pipe");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(&fifo).unwrap())
    };
    let o = tactile(&["diagnose", s(&rec), "--report", s(&fifo)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = String::from_utf8(reader.join().unwrap()).unwrap();
    assert!(
        got.starts_with("<!doctype html>") || got.contains("<html"),
        "{got:.80}"
    );
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    // The page alone, to a regular file.
    let alone = d.join("alone.html");
    let o = tactile(&["diagnose", s(&rec), "--report", s(&alone)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read_to_string(&alone).unwrap().contains("<html"));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn simulate_and_import_write_through_the_same_rule() {
    let d = scratch("commands");
    let null = device(&d, "null", "3");
    let o = tactile(&[
        "simulate",
        "--contact-angle",
        "15",
        "--azimuth",
        "30",
        "--peak-load",
        "2",
        "--rate",
        "100",
        "--out",
        s(&null),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(char_device(&null));
    let o = tactile(&[
        "simulate",
        "--contact-angle",
        "15",
        "--azimuth",
        "30",
        "--peak-load",
        "2",
        "--rate",
        "100",
        "--out",
        "-",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout.starts_with(b"# format = tactile-recording/1"));
    let full = device(&d, "full", "7");
    fails(
        &tactile(&[
            "simulate",
            "--contact-angle",
            "15",
            "--azimuth",
            "30",
            "--peak-load",
            "2",
            "--rate",
            "100",
            "--out",
            s(&full),
        ]),
        74,
        &[s(&full)],
    );
    assert!(char_device(&full));
    let export = d.join("m.csv");
    std::fs::write(
        &export,
        "t,z,f\n0,0,0\n0.1,0.1,0.5\n0.2,0.2,1.0\n0.3,0.3,1.6\n",
    )
    .unwrap();
    let o = tactile(&[
        "import",
        "--format",
        "csv",
        s(&export),
        "--radius-mm",
        "2",
        "-o",
        "-",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stdout.starts_with(b"# format = tactile-recording/1"));
    std::fs::remove_dir_all(&d).unwrap();
}
