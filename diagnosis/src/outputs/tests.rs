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

/// A node made with `mknod` in `dir` (`c 1 3`: null, `c 1 7`: full), where this process may
/// make one (root); never one in /dev.
fn device(dir: &Path, name: &str, minor: &str) -> Option<PathBuf> {
    let p = dir.join(name);
    let made = std::process::Command::new("mknod")
        .args([p.as_os_str(), "c".as_ref(), "1".as_ref(), minor.as_ref()])
        .status()
        .is_ok_and(|s| s.success());
    made.then_some(p)
}

fn is_char_device(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt as _;
    std::fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

#[test]
fn a_device_is_written_as_it_is_and_never_replaced() {
    let d = scratch("device");
    // A null device of our own where we may make one, else /dev/null itself (checked after).
    let null = device(&d, "null", "3").unwrap_or_else(|| PathBuf::from("/dev/null"));
    assert_eq!(Sink::of(&null), Sink::AsIs(null.clone()));
    check(&[&null], &[], &[]).unwrap();
    write_all_whole(&[(&null, b"{}\n")]).unwrap();
    assert!(is_char_device(&null), "{} was replaced", null.display());
    assert!(is_char_device(Path::new("/dev/null")));
    // No temporary file beside it either.
    let left = std::fs::read_dir(&d).unwrap().count();
    assert!(left <= 1, "{left} files in {}", d.display());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_full_device_is_an_error_naming_it_and_leaves_the_regular_files_unchanged() {
    let d = scratch("full");
    let full = device(&d, "full", "7").unwrap_or_else(|| PathBuf::from("/dev/full"));
    let page = d.join("page.html");
    std::fs::write(&page, "old").unwrap();
    let err = write_all_whole(&[(&full, b"{}\n"), (&page, b"new")]).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::StorageFull, "{err}");
    assert!(
        err.to_string()
            .starts_with(&format!("writing {}: ", full.display())),
        "{err}"
    );
    // The exit code follows the cause: an I/O error (74).
    let chain: &(dyn std::error::Error + 'static) = &err;
    assert_eq!(sysexit::code_of(sysexit::causes(chain)), Some(sysexit::IO));
    assert!(is_char_device(&full));
    assert_eq!(std::fs::read(&page).unwrap(), b"old");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_fifo_is_written_to_its_reader() {
    let d = scratch("fifo");
    let fifo = d.join("pipe");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    assert_eq!(Sink::of(&fifo), Sink::AsIs(fifo.clone()));
    check(&[&fifo], &[], &[]).unwrap();
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(&fifo).unwrap())
    };
    write_whole(&fifo, b"through the pipe\n").unwrap();
    assert_eq!(reader.join().unwrap(), b"through the pipe\n");
    use std::os::unix::fs::FileTypeExt as _;
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the FIFO was replaced");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_link_is_written_through_and_kept() {
    let d = scratch("link");
    let (target, link) = (d.join("real.json"), d.join("link.json"));
    std::fs::write(&target, "old").unwrap();
    std::os::unix::fs::symlink("real.json", &link).unwrap();
    check(&[&link], &[], &[]).unwrap();
    write_whole(&link, b"new").unwrap();
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    assert_eq!(std::fs::read(&target).unwrap(), b"new");
    // A link to a file not there yet: the file is created, the link kept.
    let (later, dangling) = (d.join("sub").join("later.json"), d.join("dangling.json"));
    std::os::unix::fs::symlink(&later, &dangling).unwrap();
    write_whole(&dangling, b"made").unwrap();
    assert!(std::fs::symlink_metadata(&dangling).unwrap().is_symlink());
    assert_eq!(std::fs::read(&later).unwrap(), b"made");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn dash_and_dev_stdout_are_the_standard_output_and_streams_are_never_renamed_over() {
    assert_eq!(Sink::of(Path::new("-")), Sink::Stdout);
    assert_eq!(Sink::of(Path::new("/dev/stdout")), Sink::Stdout);
    // A descriptor's path resolves to whatever is behind it, a regular file too: never renamed.
    assert!(matches!(Sink::of(Path::new("/dev/fd/2")), Sink::AsIs(_)));
    assert!(matches!(
        Sink::of(Path::new("/proc/self/fd/2")),
        Sink::AsIs(_)
    ));
    // A link to a descriptor's path counts as one.
    let d = scratch("fd-link");
    let link = d.join("err");
    std::os::unix::fs::symlink("/dev/stderr", &link).unwrap();
    assert!(matches!(Sink::of(&link), Sink::AsIs(_)));
    // Two outputs to the standard output would interleave; to one device, harmless.
    let err = check(&[Path::new("-"), Path::new("/dev/stdout")], &[], &[]).unwrap_err();
    assert!(matches!(err, OutputError::Twice { .. }), "{err}");
    check(&[Path::new("/dev/null"), Path::new("/dev/null")], &[], &[]).unwrap();
    assert!(matches!(Sink::of(&d.join("x.json")), Sink::Whole(_)));
    std::fs::remove_dir_all(&d).unwrap();
}
