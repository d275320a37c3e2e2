//! Helpers shared by the CLI tests: run the `tactile` binary, check a failure's one line.

use std::process::{Command, Output};

/// Run `tactile` with `args`.
pub fn tactile(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(args)
        .output()
        .unwrap()
}

/// Exit code `code`, exactly one stderr line containing every `needle`, no panic.
pub fn fails(out: &Output, code: u8, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(i32::from(code)), "stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "expected one line: {err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} not in: {err}");
    }
}
