//! Regimes of the public Mach-1 recordings (read from their zip beside the checkout, never
//! copied in): Hayes's ramp and long hold, Static's staircase of three slow quantised ramps with
//! holds, Dynamic's sinusoids over a large preload. Both at the full rate with the load and on
//! the decimated series the diagnosis fits. Run with `--nocapture` to see the segments.

#[path = "../../tests/support/mach1_zip.rs"]
mod mach1_zip;

use crate::data::Data;
use crate::regimes::{self, HeldoutKind, Protocol, Regime, Segment};
use mach1_zip::{blocks, recording};
use recording::Recording;

/// Regimes at the full rate with the load, as `Data` carries them onto the decimated series,
/// and detected on the decimated series from the rod alone (as the pipeline calls it today);
/// the protocol of each, printed.
fn all(rec: &Recording, what: &str) -> [Protocol; 3] {
    let c = &rec.channels;
    let (_, full) = regimes::detect_with_load(&c.t_s, &c.rod_mm, Some(&c.load_n));
    let data = Data::new(rec).expect("the diagnosis reads the import");
    let (_, fit) = regimes::detect(&data.fit.t_s, &data.fit.rod_mm);
    let (ft, fr) = (&data.fit.t_s, &data.fit.rod_mm);
    let out = [
        regimes::protocol(&c.t_s, &c.rod_mm, Some(&c.load_n), &full),
        regimes::protocol(ft, fr, Some(&data.fit.y[0]), &data.segments),
        regimes::protocol(ft, fr, Some(&data.fit.y[0]), &fit),
    ];
    println!("{what} full rate: {}", show(&c.t_s, &full));
    println!("{what} carried: {}", show(ft, &data.segments));
    println!("{what} decimated: {}", show(ft, &fit));
    for p in &out {
        println!("  {p:?}");
    }
    out
}

fn show(t: &[f64], segs: &[Segment]) -> String {
    let list: Vec<String> = segs
        .iter()
        .enumerate()
        .filter(|(k, s)| *k < 8 || !matches!(s.regime, Regime::Loading | Regime::Release))
        .map(|(_, s)| s)
        .map(|s| format!("{}@{:.1}-{:.1}s", s.regime.name(), t[s.start], t[s.end - 1]))
        .collect();
    format!("{} segments: {}", segs.len(), list.join(" "))
}

#[test]
fn hayes_first_site_is_a_ramp_and_a_long_hold() {
    let b = blocks("Hayes_data.txt");
    let block = b.iter().find(|b| b.kind == "Stress Relaxation").unwrap();
    let rec = recording(block, "Hayes_data.txt");
    let end = block.duration_s();
    for p in all(&rec, "Hayes site 1") {
        assert_eq!(
            (p.loadings, p.holds, p.releases, p.cycles),
            (1, 1, 0, 1),
            "{p:?}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::EndOfHold);
        // The ramp ends near 1.3 s; the last third of the 300 s hold is held out.
        assert!(
            (p.heldout.0 - (1.3 + 2.0 / 3.0 * (end - 1.3))).abs() < 2.0,
            "{p:?}"
        );
        assert!(p.separates_rate_effects && !p.has_unloading);
    }
}

#[test]
fn static_is_a_staircase_of_three_ramps_and_holds_over_a_preload() {
    let b = blocks("Static_data.txt");
    let rec = recording(&b[0], "Static_data.txt");
    let ps = all(&rec, "Static");
    for p in &ps {
        assert_eq!(
            (p.loadings, p.holds, p.releases, p.cycles),
            (3, 3, 0, 1),
            "{p:?}"
        );
        assert_eq!(p.heldout_kind, HeldoutKind::EndOfHold);
        // Three ramps at the programmed 0.0007 mm/s.
        assert!(
            p.rates_mm_per_s
                .iter()
                .all(|v| (v / 7e-4 - 1.0).abs() < 0.2),
            "{p:?}"
        );
        // The calibration keeps the first two ramps and holds and most of the third.
        assert!(p.heldout.0 > 1000.0, "{p:?}");
    }
    assert!(
        ps[0].starts_in_contact && ps[1].starts_in_contact,
        "a 0.25 N preload"
    );
}

#[test]
fn dynamic_is_twenty_cycles_per_block_over_a_preload() {
    let b = blocks("Dynamic_data.txt");
    assert_eq!(b.len(), 5);
    for block in &b {
        let rec = recording(block, "Dynamic_data.txt");
        let what = format!("Dynamic block {}", block.index);
        let ps = all(&rec, &what);
        let c = &rec.channels;
        let (_, segs) = regimes::detect_with_load(&c.t_s, &c.rod_mm, Some(&c.load_n));
        let inner = &segs[..segs.len() - 1];
        assert!(inner.iter().all(|s| s.regime != Regime::Hold), "{what}");
        for p in &ps {
            // One swing down per period, none split; the rod may stop after the last one
            // (block 5 stands still for 0.7 s at its end), never between.
            assert_eq!(p.releases, 20, "{what}: {p:?}");
            assert!(p.holds <= 1, "{what}: {p:?}");
            assert!((20..=21).contains(&p.cycles), "{what}: {p:?}");
            assert_eq!(p.heldout_kind, HeldoutKind::LastCycle);
        }
        assert!(
            ps[0].starts_in_contact,
            "{what}: ~200 N preload: {:?}",
            ps[0]
        );
    }
}
