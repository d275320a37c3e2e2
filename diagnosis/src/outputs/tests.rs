use super::*;
use sysexit::ExitStatus as _;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-outputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_file_on_the_path_fails_at_once_naming_the_path_and_the_file() {
    let d = scratch("file-on-path");
    let rec = d.join("a.csv");
    std::fs::write(&rec, "a recording").unwrap();
    let out = rec.join("x.html");
    let err = check(&[&out], &[], &[]).unwrap_err();
    assert_eq!(err.exit_code(), sysexit::CANT_CREATE);
    assert_eq!(
        err.to_string(),
        format!(
            "{}: cannot be created: {} is a file, not a folder",
            out.display(),
            rec.display()
        )
    );
    // Deeper below the file, and as an output folder.
    let deep = rec.join("sub").join("x.json");
    assert!(matches!(
        check(&[&deep], &[], &[]),
        Err(OutputError::FileOnPath { file, .. }) if file == rec
    ));
    assert!(matches!(
        check(&[], &[&rec], &[]),
        Err(OutputError::IsFile(_))
    ));
    assert!(matches!(
        check(&[&d], &[], &[]),
        Err(OutputError::IsFolder(_))
    ));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn missing_folders_are_fine_and_nothing_is_created_by_the_check() {
    let d = scratch("missing-folders");
    let json = d.join("new").join("deeper").join("out.json");
    check(&[&json], &[&d.join("out-dir")], &[]).unwrap();
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "the check wrote");
    write_whole(&json, b"{}\n").unwrap();
    assert_eq!(std::fs::read(&json).unwrap(), b"{}\n");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn an_output_that_is_an_input_or_another_output_is_a_usage_error() {
    let d = scratch("clash");
    let rec = d.join("a.csv");
    std::fs::write(&rec, "a recording").unwrap();
    let dotted = d.join(".").join("a.csv");
    let err = check(&[&dotted], &[], std::slice::from_ref(&rec)).unwrap_err();
    assert!(matches!(err, OutputError::IsInput(_)), "{err}");
    assert_eq!(err.exit_code(), sysexit::USAGE);
    let (a, b) = (d.join("o.json"), d.join("x").join("..").join("o.json"));
    std::fs::create_dir_all(d.join("x")).unwrap();
    let err = check(&[&a, &b], &[], &[]).unwrap_err();
    assert!(matches!(err, OutputError::Twice { .. }), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_folder_that_cannot_be_written_into_is_refused() {
    use std::os::unix::fs::PermissionsExt as _;
    let d = scratch("read-only");
    let locked = d.join("locked");
    std::fs::create_dir_all(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    // Root writes anywhere: then there is nothing to refuse.
    let root = std::fs::write(locked.join("root"), "").is_ok();
    let got = check(&[&locked.join("out.json")], &[], &[]);
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    if !root {
        let err = got.unwrap_err();
        assert_eq!(err.exit_code(), sysexit::NO_PERM, "{err}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn files_are_written_whole_and_a_failure_changes_none() {
    let d = scratch("whole");
    let (a, b) = (d.join("a.json"), d.join("b.html"));
    std::fs::write(&a, "old").unwrap();
    // The second cannot be staged: its folder is a file.
    let blocked = d.join("file");
    std::fs::write(&blocked, "").unwrap();
    let bad = blocked.join("b.html");
    assert!(write_all_whole(&[(&a, b"new"), (&bad, b"x")]).is_err());
    assert_eq!(std::fs::read(&a).unwrap(), b"old");
    write_all_whole(&[(&a, b"new"), (&b, b"page")]).unwrap();
    assert_eq!(std::fs::read(&a).unwrap(), b"new");
    assert_eq!(std::fs::read(&b).unwrap(), b"page");
    // No temporary file stays behind.
    let mut left: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["a.json", "b.html", "file"]);
    std::fs::remove_dir_all(&d).unwrap();
}
