//! Shared by the rule tests of frontend.toml, adc.toml and board.toml: a copy of the shipped
//! hardware/ folder with one file edited, and the single error loading it must give.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use hardware::{ParamError, ParamErrorKind, Params};

/// A copy of the real hardware/ folder with `from` replaced by `to` in `file`; the replacement
/// must happen (a test editing nothing would pass for the wrong reason).
pub fn folder_with(file: &str, from: &str, to: &str) -> PathBuf {
    static N: AtomicU64 = AtomicU64::new(0);
    let src = Params::default_dir();
    let n = N.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("tactile-hw-rules-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") && !path.ends_with("Cargo.toml") {
            let name = path.file_name().unwrap();
            let mut text = std::fs::read_to_string(&path).unwrap();
            if Path::new(name) == Path::new(file) {
                assert!(text.contains(from), "{file} has no `{from}`");
                text = text.replace(from, to);
            }
            std::fs::write(dir.join(name), text).unwrap();
        }
    }
    dir
}

/// The one error that loading `dir` must report, checked to be a broken cross-key rule on `key`.
pub fn rule_broken(dir: &Path, file: &str, key: &str) -> ParamError {
    let err = Params::load(dir).expect_err("edited folder must be refused");
    assert_eq!(err.0.len(), 1, "expected exactly one error, got: {err}");
    let e = err.0[0].clone();
    assert_eq!(e.key, key, "{e}");
    assert!(matches!(e.kind, ParamErrorKind::Invalid(_)), "{e}");
    assert!(e.to_string().contains(file), "{e}");
    e
}
