//! The pair import on synthetic logs whose truth is known: clocks, rates, units, markers,
//! outages, channel sums, and the refusals.

use super::*;
use crate::import::units::{parse as unit, FORCE_UNITS, LENGTH_UNITS, TIME_UNITS};

/// Unix time of the sensor's first row.
const T0: f64 = 1_743_486_638.0;

/// The true rod travel (mm) and load (N) at time `t` from T0: a press and release over 10 s.
fn truth(t: f64) -> (f64, f64) {
    let rod = 2.0 * (std::f64::consts::PI * t / 10.0).sin().powi(2);
    (rod, 3.0 * rod * rod)
}

/// A headerless sensor log at 100 Hz in Unix s: time, a, b, c with b - c = 10 × load + 5.
fn sensor_text(rows: usize) -> String {
    (0..rows)
        .map(|i| {
            let t = i as f64 * 0.01;
            let (_, load) = truth(t);
            format!("{},7,{},{}\n", T0 + t, 10.0 * load + 100.0, 95.0)
        })
        .collect()
}

/// A reference log with a header, time in Unix ms, from 0.5 s to 9.5 s at 40 Hz: a robot's z
/// over the sample (300 mm at contact, down presses in) and a scale in g that reads every other
/// row and writes -1 on the others.
fn reference_text() -> String {
    let mut s = String::from("time;x;z;weight\n");
    for i in 0..=360 {
        let t = 0.5 + i as f64 * 0.025;
        let (rod, load) = truth(t);
        let w = if i % 2 == 0 {
            format!("{}", load / 9.80665e-3)
        } else {
            "-1".into()
        };
        s += &format!("{};315;{};{w}\n", (T0 + t) * 1e3, 300.0 - rod);
    }
    s
}

fn options() -> PairOptions {
    PairOptions {
        sensor: SensorOptions {
            table: TableOptions::default(),
            time: ColumnRef::Index(1),
            time_unit: unit(&TIME_UNITS, "s").unwrap(),
            slots: [Some("3-4".parse().unwrap()), None, None],
            scale: 0.1,
            unit: "daN".into(),
            tare_s: None,
        },
        reference: CsvOptions {
            time: "time".parse().unwrap(),
            displacement: "z".parse().unwrap(),
            force: "4".parse().unwrap(),
            time_unit: unit(&TIME_UNITS, "ms").unwrap(),
            length_unit: unit(&LENGTH_UNITS, "mm").unwrap(),
            force_unit: unit(&FORCE_UNITS, "g").unwrap(),
            press_down: true,
            compression_negative: false,
            contact_at: Some(300.0),
            missing: Some(-1.0),
            table: TableOptions::default(),
        },
        align: Align::Clock,
        sensor_offset_s: 0.0,
        rate_hz: None,
        max_gap_s: None,
    }
}

fn meta() -> ImportMeta {
    ImportMeta {
        fingertip_radius_mm: 5.0,
        gain: [1.0; 3],
        excitation_v: 1.0,
        source: "test".into(),
    }
}

fn run(sensor: &str, reference: &str, opt: &PairOptions) -> Result<Recording, MachineExportError> {
    let s = Source {
        path: "sensor.csv",
        text: sensor,
    };
    let r = Source {
        path: "states.csv",
        text: reference,
    };
    import(s, r, opt, &meta()).map(|(rec, _)| rec)
}

/// Row `i`'s time on the sensor's clock, from T0.
fn sensor_time(rec: &Recording, i: usize) -> f64 {
    let zero: f64 = rec.meta.get("time_zero_s").unwrap().parse().unwrap();
    zero - T0 + rec.channels.t_s[i]
}

#[test]
fn same_clock_logs_merge_on_the_sensors_times() {
    let rec = run(&sensor_text(1000), &reference_text(), &options()).unwrap();
    let c = &rec.channels;
    // The overlap: 0.5 s to 9.5 s of the sensor's 100 Hz rows, both ends included.
    assert_eq!(c.len(), 901);
    assert_eq!(c.t_s[0], 0.0);
    assert!((sensor_time(&rec, 0) - 0.5).abs() < 1e-6);
    // The median step of Unix times, which carry a fraction of a microsecond of rounding.
    assert!((rec.meta.sample_rate_hz - 100.0).abs() < 1e-3);
    for i in 0..c.len() {
        let (rod, load) = truth(sensor_time(&rec, i));
        assert!((c.rod_mm[i] - rod).abs() < 2e-3, "rod at row {i}");
        assert!((c.load_n[i] - load).abs() < 2e-2, "load at row {i}");
        // 0.1 × (b - c) = load + 0.5, the sensor's own rows.
        assert!((c.fz_v[i] - load - 0.5).abs() < 1e-6, "fz at row {i}");
        assert!(c.mx_v[i].is_nan() && c.my_v[i].is_nan());
    }
    assert_eq!(rec.meta.get("fz_V_from"), Some("3-4"));
    assert_eq!(rec.meta.get("sensor_unit"), Some("daN"));
}

#[test]
fn starts_alignment_and_offsets_put_a_relative_clock_on_the_references() {
    // The sensor's clock counts from its own start; the reference's is Unix time.
    let relative: String = sensor_text(1000)
        .lines()
        .map(|l| {
            let (t, rest) = l.split_once(',').unwrap();
            format!("{},{rest}\n", t.parse::<f64>().unwrap() - T0 + 1.0)
        })
        .collect();
    let err = run(&relative, &reference_text(), &options())
        .unwrap_err()
        .to_string();
    assert!(err.contains("sensor.csv:1: field column 1:"), "{err}");
    assert!(err.contains("--sensor-offset-s"), "{err}");
    // Started together: the sensor's first row is the reference's first (0.5 s after T0).
    let mut opt = options();
    opt.align = Align::Starts;
    let rec = run(&relative, &reference_text(), &opt).unwrap();
    assert!(
        (rec.meta
            .get("sensor_offset_s")
            .unwrap()
            .parse::<f64>()
            .unwrap()
            - (T0 - 0.5))
            .abs()
            < 1e-3
    );
    // An explicit offset on the same clock: the sensor ran 0.2 s behind.
    let mut opt = options();
    opt.sensor_offset_s = T0 - 1.0;
    let rec = run(&relative, &reference_text(), &opt).unwrap();
    let (_, load) = truth(sensor_time(&rec, 300));
    assert!((rec.channels.fz_v[300] - load - 0.5).abs() < 1e-6);
}

#[test]
fn a_uniform_rate_interpolates_every_channel_and_tare_removes_the_rest_value() {
    let mut opt = options();
    opt.rate_hz = Some(30.0);
    opt.sensor.tare_s = Some(0.2);
    let rec = run(&sensor_text(1000), &reference_text(), &opt).unwrap();
    let c = &rec.channels;
    assert_eq!(rec.meta.sample_rate_hz, 30.0);
    assert_eq!(c.len(), 271);
    // t_s is rounded to the microsecond.
    assert!((c.t_s[1] - 1.0 / 30.0).abs() <= 5e-7);
    let tare: f64 = rec.meta.get("fz_V_tare").unwrap().parse().unwrap();
    assert!((tare - 0.5 - truth(0.55).1).abs() < 0.05, "tare {tare}");
    for i in 0..c.len() {
        let (_, load) = truth(sensor_time(&rec, i));
        assert!(
            (c.fz_v[i] + tare - load - 0.5).abs() < 5e-3,
            "fz at row {i}"
        );
    }
}

#[test]
fn an_outage_of_the_scale_is_left_missing_and_nothing_beyond_its_span() {
    // The scale says nothing from 3 s to 5 s; the robot's z goes on.
    let reference: String = reference_text()
        .lines()
        .map(|l| match l.split(';').next().unwrap().parse::<f64>() {
            Ok(ms) if (3.0..5.0).contains(&(ms / 1e3 - T0)) => {
                let cut = l.rsplit_once(';').unwrap().0;
                format!("{cut};-1\n")
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let rec = run(&sensor_text(1000), &reference, &options()).unwrap();
    let c = &rec.channels;
    for i in 0..c.len() {
        let t = sensor_time(&rec, i);
        assert!(c.rod_mm[i].is_finite(), "rod at {t}");
        if (3.3..4.7).contains(&t) {
            assert!(c.load_n[i].is_nan(), "load invented at {t}");
        }
        if !(2.9..5.1).contains(&t) {
            assert!(c.load_n[i].is_finite(), "load lost at {t}");
        }
    }
    // A sensor that outlasts the reference: its extra rows are not written.
    let rec = run(&sensor_text(1200), &reference_text(), &options()).unwrap();
    assert!((sensor_time(&rec, rec.channels.len() - 1) - 9.5).abs() < 1e-6);
}

#[test]
fn refusals_name_the_file_line_and_column() {
    let back =
        sensor_text(1000).replacen(&format!("{},", T0 + 0.05), &format!("{},", T0 + 0.01), 1);
    let cases = [
        (
            back,
            reference_text(),
            "sensor.csv:6: field column 1: time decreases",
        ),
        (
            sensor_text(1000),
            reference_text().replacen(";315;", ";315;x", 1),
            "states.csv:2: field z: not a number",
        ),
        (
            sensor_text(1000).replacen(
                &format!("{},7,", T0 + 0.02),
                &format!("{},7", T0 + 0.02),
                1,
            ),
            reference_text(),
            "sensor.csv:3: field column 4: the row has 3 fields",
        ),
    ];
    for (s, r, want) in cases {
        let e = run(&s, &r, &options()).unwrap_err().to_string();
        assert!(e.contains(want), "{want}: {e}");
    }
    let mut opt = options();
    opt.sensor.slots = [None, None, None];
    let e = run(&sensor_text(10), &reference_text(), &opt).unwrap_err();
    assert_eq!(sysexit::ExitStatus::exit_code(&e), sysexit::USAGE);
}
