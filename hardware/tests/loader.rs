//! Each rule of the loader, one test each: missing, misspelled, out of range, wrong type, syntax.

use std::path::{Path, PathBuf};

use hardware::{ParamErrorKind, Params};

/// A copy of the real hardware/ folder with `edit` applied to `file`.
fn folder_with(file: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let src = Params::default_dir();
    let dir = std::env::temp_dir().join(format!(
        "tactile-hw-{}-{}",
        std::process::id(),
        rand_suffix()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") && !path.ends_with("Cargo.toml") {
            let name = path.file_name().unwrap();
            let mut text = std::fs::read_to_string(&path).unwrap();
            if Path::new(name) == Path::new(file) {
                text = edit(text);
            }
            std::fs::write(dir.join(name), text).unwrap();
        }
    }
    dir
}

fn rand_suffix() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static N: AtomicU64 = AtomicU64::new(0);
    N.fetch_add(1, Ordering::Relaxed)
}

fn only_error(dir: &Path) -> hardware::ParamError {
    let err = Params::load(dir).expect_err("edited folder must be refused");
    assert_eq!(err.0.len(), 1, "expected exactly one error, got: {err}");
    err.0[0].clone()
}

#[test]
fn the_shipped_folder_loads() {
    Params::load_default().unwrap();
}

#[test]
fn missing_key_is_named() {
    let dir = folder_with("fingertip.toml", |t| t.replace("poisson = 0.49", ""));
    let e = only_error(&dir);
    assert_eq!(e.key, "gel.poisson");
    assert_eq!(e.kind, ParamErrorKind::Missing);
    assert!(
        e.to_string()
            .contains("fingertip.toml: key `gel.poisson`: missing"),
        "{e}"
    );
}

#[test]
fn misspelled_key_is_unknown_with_a_suggestion() {
    let dir = folder_with("fingertip.toml", |t| {
        t.replace("poisson = 0.49", "poison = 0.49")
    });
    let err = Params::load(&dir).unwrap_err();
    let text = err.to_string();
    assert!(text.contains("key `gel.poisson`: missing"), "{text}");
    assert!(
        text.contains("key `gel.poison`: unknown key (did you mean `gel.poisson`?)"),
        "{text}"
    );
}

#[test]
fn out_of_range_value_names_the_range() {
    let dir = folder_with("fingertip.toml", |t| {
        t.replace("poisson = 0.49", "poisson = 0.5")
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "gel.poisson");
    assert!(
        e.to_string()
            .contains("0.5 is out of range; allowed 0 ..= 0.4999"),
        "{e}"
    );
}

#[test]
fn wrong_type_is_named() {
    let dir = folder_with("fingertip.toml", |t| {
        t.replace("poisson = 0.49", "poisson = \"soft\"")
    });
    let e = only_error(&dir);
    assert_eq!(
        e.kind,
        ParamErrorKind::WrongType {
            expected: "a number"
        }
    );
}

#[test]
fn syntax_error_names_the_file() {
    let dir = folder_with("fingertip.toml", |t| t + "\n[gel\n");
    let e = only_error(&dir);
    assert!(matches!(e.kind, ParamErrorKind::Syntax(_)));
    assert!(e.to_string().contains("fingertip.toml"), "{e}");
}

#[test]
fn missing_file_is_named() {
    let dir = folder_with("fingertip.toml", |t| t);
    std::fs::remove_file(dir.join("fingertip.toml")).unwrap();
    let e = only_error(&dir);
    assert!(matches!(e.kind, ParamErrorKind::Io(_)));
    assert!(
        e.to_string()
            .contains("fingertip.toml: cannot read the file"),
        "{e}"
    );
}

#[test]
fn cross_key_rule_is_enforced() {
    let dir = folder_with("fingertip.toml", |t| {
        t.replace("inclusion_radius_mm = 3.0", "inclusion_radius_mm = 12.0")
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "package.inclusion_radius_mm");
    assert!(matches!(e.kind, ParamErrorKind::Invalid(_)));
}

#[test]
fn chip_beams_must_leave_a_frame_inside_the_footprint() {
    let dir = folder_with("chip.toml", |t| {
        t.replace("beam_length_um = 400.0", "beam_length_um = 950.0")
    });
    let err = Params::load(&dir).expect_err("beams wider than the die must be refused");
    let e = err
        .0
        .iter()
        .find(|e| e.key == "geometry.beam_length_um")
        .expect("span rule");
    assert!(matches!(e.kind, ParamErrorKind::Invalid(_)), "{e}");
    assert!(e.to_string().contains("leaves no frame"), "{e}");
}

#[test]
fn chip_resistor_must_fit_on_its_beam() {
    let dir = folder_with("chip.toml", |t| {
        t.replacen(
            "r1 = { beam = \"A\", x_um = 375.0,",
            "r1 = { beam = \"A\", x_um = 395.0,",
            1,
        )
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "bridge.fz.r1.x_um");
    assert!(matches!(e.kind, ParamErrorKind::Invalid(_)), "{e}");
}

#[test]
fn chip_bridge_must_be_balanced_at_zero_stress() {
    let dir = folder_with("chip.toml", |t| {
        t.replace(
            "fixed_ohm = [0.0, 0.0, 10000.0, 10000.0]",
            "fixed_ohm = [0.0, 0.0, 10000.0, 12000.0]",
        )
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "bridge.fz.fixed_ohm");
    assert!(e.to_string().contains("not balanced"), "{e}");
}

#[test]
fn chip_bridge_arm_must_not_be_empty() {
    let dir = folder_with("chip.toml", |t| {
        t.replace(
            "fixed_ohm = [0.0, 0.0, 10000.0, 10000.0]",
            "fixed_ohm = [0.0, 0.0, 0.0, 0.0]",
        )
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "bridge.fz");
    assert!(e.to_string().contains("every arm"), "{e}");
}

#[test]
fn the_papers_sensor_is_read_from_its_own_file() {
    let p = Params::load_default().unwrap().paper_sensor;
    assert_eq!(p.fz_ratio(0.0), 1.0);
    let dir = folder_with("paper-sensor.toml", |t| {
        t.replace("ac_coupling_tau_s = 1000.0", "ac_coupling_tau_s = -1.0")
    });
    let e = only_error(&dir);
    assert_eq!(e.key, "offset_cut.ac_coupling_tau_s");
    assert!(e.to_string().contains("paper-sensor.toml"), "{e}");
}
