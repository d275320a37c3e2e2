//! The public Mach-1 exports (read from their zip beside the checkout, never copied in) import
//! into recordings the reader accepts, with loads and rod travels that look physically right.
//! Run with `--nocapture` to see the summary numbers.

use std::io::Read;

use recording::import::{self, mach1, ImportMeta};
use recording::Recording;

const ZIP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/real-data/mach1/examples.zip"
);

/// The text of `name` in the examples zip (Latin-1 decoded); fails loudly if the data is absent.
fn example(name: &str) -> String {
    let file = std::fs::File::open(ZIP).unwrap_or_else(|e| {
        panic!("{ZIP}: {e}: the Mach-1 examples must sit in shared/real-data/mach1/ beside the checkout")
    });
    let mut zip = zip::ZipArchive::new(file).expect("examples.zip is a zip archive");
    let mut entry = zip
        .by_name(name)
        .unwrap_or_else(|e| panic!("{name} in {ZIP}: {e}"));
    let mut raw = Vec::new();
    entry.read_to_end(&mut raw).unwrap();
    raw.iter().map(|&b| char::from(b)).collect()
}

/// Import block `pick` of `name`, write it, read it back through the recording reader.
fn import(name: &str, pick: impl Fn(&mach1::Block) -> bool) -> Recording {
    let blocks = mach1::parse(&example(name), name).unwrap_or_else(|e| panic!("{e}"));
    let block = blocks.iter().find(|b| pick(b)).expect("the block");
    let meta = ImportMeta {
        fingertip_radius_mm: 1.0,
        gain: [1100.0, 110.0, 110.0],
        excitation_v: 3.3,
        source: format!("Mach-1 export {name}, block {}", block.index),
    };
    let rec = import::to_recording(&block.to_export(), &meta, name).unwrap();
    let mut text = Vec::new();
    rec.write_to(&mut text).unwrap();
    let back = Recording::parse(std::str::from_utf8(&text).unwrap())
        .unwrap_or_else(|e| panic!("{name}: the reader refuses the import: {e}"));
    for s in ["fz_V", "mx_V", "my_V"] {
        assert!(!back.measured(s), "{name}: {s} must be not measured");
    }
    assert_eq!(back.without_gaps().channels.len(), back.channels.len());
    back
}

/// Rows, duration, peak load, and the share of the peak lost by the end.
fn summary(name: &str, r: &Recording) -> (f64, f64) {
    let c = &r.channels;
    let peak = c.load_n.iter().cloned().fold(f64::MIN, f64::max);
    let at = c.load_n.iter().position(|&v| v == peak).unwrap();
    let end = *c.load_n.last().unwrap();
    let start = c.load_n[0];
    let share = (peak - end) / (peak - start);
    println!(
        "{name}: {} rows, {:.1} s at {} Hz, rod {:.4}..{:.4} mm, load {:.4} -> peak {:.4} N at {:.1} s -> end {:.4} N, relaxation share {:.2}",
        c.len(),
        c.t_s[c.len() - 1],
        r.meta.sample_rate_hz,
        c.rod_mm.iter().cloned().fold(f64::MAX, f64::min),
        c.rod_mm.iter().cloned().fold(f64::MIN, f64::max),
        start,
        peak,
        c.t_s[at],
        end,
        share
    );
    (peak, share)
}

#[test]
fn hayes_first_stress_relaxation_relaxes_by_about_half() {
    let r = import("Hayes_data.txt", |b| b.kind == "Stress Relaxation");
    assert_eq!(r.meta.sample_rate_hz, 100.0);
    let (peak, share) = summary("Hayes site 1", &r);
    let rod_end = *r.channels.rod_mm.last().unwrap();
    assert!(
        (rod_end - 0.2096).abs() < 0.005,
        "ramp of 0.2096 mm: {rod_end}"
    );
    assert!(peak > 0.0, "compression is positive");
    assert!((0.3..0.8).contains(&share), "relaxation share {share}");
}

#[test]
fn static_three_ramps_press_in_and_relax() {
    let r = import("Static_data.txt", |_| true);
    let (peak, _) = summary("Static", &r);
    let c = &r.channels;
    assert!(
        (c.load_n[0] - 0.25).abs() < 0.02,
        "pre-load ~0.25 N: {}",
        c.load_n[0]
    );
    let rod_end = *c.rod_mm.last().unwrap();
    assert!(
        (rod_end - 3.0 * 0.0393).abs() < 0.005,
        "three 0.0393 mm ramps: {rod_end}"
    );
    assert!(peak > c.load_n[0], "pressing in raises the load");
    assert!(c.t_s.windows(2).all(|w| w[1] >= w[0]));
}

#[test]
fn dynamic_sinusoids_load_follows_rod() {
    let blocks = mach1::parse(&example("Dynamic_data.txt"), "Dynamic_data.txt").unwrap();
    assert_eq!(blocks.len(), 5);
    assert!(blocks.iter().all(|b| b.kind == "Sinusoid"));
    let r = import("Dynamic_data.txt", |b| b.index == 1);
    summary("Dynamic block 1", &r);
    let c = &r.channels;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mr, ml) = (mean(&c.rod_mm), mean(&c.load_n));
    let cov: f64 = c
        .rod_mm
        .iter()
        .zip(&c.load_n)
        .map(|(r, l)| (r - mr) * (l - ml))
        .sum();
    assert!(cov > 0.0, "pressing in must raise the compressive load");
}
