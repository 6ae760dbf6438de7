//! The output rules on a real filesystem: ours or nothing, refusals before any work,
//! replacement by exchange and file by file.

use super::classify::{Existing, classify_dir};
use super::dir::replace_file_by_file;
use super::disk::walk;
use super::manifest::{Entry, MANIFEST, Manifest};
use super::{Claim, OutputDir, OutputError, OutputFile};
use std::fs;
use std::path::{Path, PathBuf};

fn files(pairs: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    pairs
        .iter()
        .map(|(n, c)| (n.to_string(), c.as_bytes().to_vec()))
        .collect()
}

fn listing(dir: &Path) -> Vec<(String, String)> {
    let (mut names, mut dirs) = (Vec::new(), Vec::new());
    walk(dir, "", &mut names, &mut dirs).unwrap();
    names.sort();
    names
        .into_iter()
        .filter(|n| n != MANIFEST)
        .map(|n| {
            let text = fs::read_to_string(dir.join(&n)).unwrap();
            (n, text)
        })
        .collect()
}

/// Whether `r` is a refusal that `force` does (or does not) override.
fn refused<T>(r: Result<T, OutputError>, force_overrides: bool) -> bool {
    matches!(r, Err(OutputError::Refused { force_overrides: f, .. }) if f == force_overrides)
}

fn is_ours(dir: &Path) -> bool {
    matches!(classify_dir(dir, "solve", &[]).unwrap(), Existing::Ours(_))
}

/// Someone's directory `tmp/mine` (holding `notes`) and file `tmp/file`, both of `text`.
fn foreign_dir_and_file(tmp: &Path, text: &str) -> (PathBuf, PathBuf) {
    let dir = tmp.join("mine");
    fs::create_dir(&dir).unwrap();
    fs::write(dir.join("notes"), text).unwrap();
    let file = tmp.join("file");
    fs::write(&file, text).unwrap();
    (dir, file)
}

#[test]
fn a_directory_is_ours_only_with_our_manifest_and_nothing_else() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let new = files(&[("a.csv", "1,2\n"), ("fig/b.svg", "<svg/>")]);
    OutputDir::prepare(Claim::new(&out, "solve", false, &[]))
        .unwrap()
        .commit(&new)
        .unwrap();
    assert!(is_ours(&out));
    assert_eq!(listing(&out).len(), 2);
    // Only the output and nothing else next to it (no staging directory left).
    assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);

    // An edited file, an extra file, an extra link, or a damaged manifest: not ours.
    fs::write(out.join("a.csv"), "1,3\n").unwrap();
    assert!(!is_ours(&out));
    fs::write(out.join("a.csv"), "1,2\n").unwrap();
    assert!(is_ours(&out));
    fs::write(out.join("fig/notes.txt"), "mine").unwrap();
    assert!(!is_ours(&out));
    fs::remove_file(out.join("fig/notes.txt")).unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("a.csv", out.join("link")).unwrap();
        assert!(!is_ours(&out));
        fs::remove_file(out.join("link")).unwrap();
    }
    let m = fs::read(out.join(MANIFEST)).unwrap();
    fs::write(out.join(MANIFEST), &m[..m.len() / 2]).unwrap();
    assert!(!is_ours(&out));
    fs::write(out.join(MANIFEST), &m).unwrap();
    // A deleted file of ours loses nothing: still ours.
    fs::remove_file(out.join("a.csv")).unwrap();
    assert!(is_ours(&out));
}

#[test]
fn replacing_ours_by_exchange_or_file_by_file_leaves_exactly_the_new_files() {
    for exchange in [true, false] {
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("out");
        let old = files(&[("a.csv", "old"), ("old-only.svg", "x"), ("d/e.txt", "e")]);
        OutputDir::prepare(Claim::new(&out, "solve", false, &[]))
            .unwrap()
            .commit(&old)
            .unwrap();
        let new = files(&[("a.csv", "new"), ("b.png", "png")]);
        if exchange {
            OutputDir::prepare(Claim::new(&out, "solve", false, &[]))
                .unwrap()
                .commit(&new)
                .unwrap();
        } else {
            let staged = OutputDir::prepare(Claim::new(&out, "solve", false, &[])).unwrap();
            let staging = staged.staging.as_ref().unwrap().path().to_path_buf();
            let manifest = staged.stage(&staging, &new).unwrap();
            let Existing::Ours(old_manifest) = classify_dir(&out, "solve", &[]).unwrap() else {
                panic!("not ours")
            };
            replace_file_by_file(&staging, &out, &manifest, old_manifest).unwrap();
            assert!(!staging.exists());
        }
        assert_eq!(
            listing(&out),
            [
                ("a.csv".into(), "new".into()),
                ("b.png".into(), "png".into())
            ],
            "exchange: {exchange}"
        );
        assert!(!out.join("d").exists());
        assert!(is_ours(&out));
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
    }
}

#[test]
fn a_half_done_file_by_file_update_is_still_ours() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    OutputDir::prepare(Claim::new(&out, "solve", false, &[]))
        .unwrap()
        .commit(&files(&[("a.csv", "old"), ("b.csv", "old")]))
        .unwrap();
    let Existing::Ours(Some(old)) = classify_dir(&out, "solve", &[]).unwrap() else {
        panic!("not ours")
    };
    // Step 1 and half of step 2: the transition manifest, one file renamed.
    let mut both = Manifest::new(
        "solve",
        vec![Entry::of("a.csv", b"new"), Entry::of("b.csv", b"new")],
    );
    both.files.extend(old.files);
    fs::write(out.join(MANIFEST), both.to_bytes()).unwrap();
    fs::write(out.join("a.csv"), "new").unwrap();
    assert!(is_ours(&out));
}

#[test]
fn foreign_paths_are_refused_before_anything_is_created() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, file) = foreign_dir_and_file(tmp.path(), "precious");
    for (path, force_overrides) in [
        (dir.clone(), true),
        (file.clone(), true),
        (file.join("below"), false),
        (PathBuf::from("/"), false),
    ] {
        match OutputDir::prepare(Claim::new(&path, "solve", false, &[])) {
            Err(OutputError::Refused {
                force_overrides: f, ..
            }) => assert_eq!(f, force_overrides, "{path:?}"),
            Err(OutputError::Io { .. }) => assert!(!force_overrides, "{path:?}"),
            Ok(_) => panic!("{path:?} accepted"),
        }
    }
    #[cfg(unix)]
    {
        let link = tmp.path().join("link");
        std::os::unix::fs::symlink(&dir, &link).unwrap();
        assert!(refused(
            OutputDir::prepare(Claim::new(&link, "solve", true, &[])),
            false
        ));
        fs::remove_file(&link).unwrap();
    }
    #[cfg(unix)]
    assert!(refused(
        OutputDir::prepare(Claim::new(Path::new("/dev/null"), "solve", true, &[])),
        false
    ));
    assert_eq!(fs::read_to_string(dir.join("notes")).unwrap(), "precious");
    assert_eq!(fs::read_to_string(&file).unwrap(), "precious");
    assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
    assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
}

#[test]
fn force_replaces_a_foreign_directory_or_file_and_a_dropped_output_cleans_up() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, file) = foreign_dir_and_file(tmp.path(), "x");
    for path in [&dir, &file] {
        OutputDir::prepare(Claim::new(path, "solve", true, &[]))
            .unwrap()
            .commit(&files(&[("a", "1")]))
            .unwrap();
        assert_eq!(listing(path), [("a".into(), "1".into())]);
    }
    // Prepared then dropped (the command failed): staging and new parents removed.
    let deep = tmp.path().join("x/y/out");
    drop(OutputDir::prepare(Claim::new(&deep, "solve", false, &[])).unwrap());
    drop(OutputFile::prepare(Claim::new(&deep, "replay", false, &[])).unwrap());
    assert!(!tmp.path().join("x").exists());
    assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 2);
}

#[test]
fn a_single_file_is_ours_only_as_its_record_lists_it_and_never_an_input() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("r.json");
    let record = tmp.path().join(".r.json.purcell-sim");
    let write = |bytes: &[u8], force: bool| {
        OutputFile::prepare(Claim::new(&path, "replay", force, &[]))?.commit(bytes)
    };
    write(b"OURS 1", false).unwrap();
    write(b"OURS 2", false).unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"OURS 2");
    assert!(record.is_file());
    // Another subcommand's file, one with bytes appended, one with the same first bytes.
    assert!(refused(
        OutputFile::prepare(Claim::new(&path, "export", false, &[])),
        true
    ));
    for theirs in [&b"OURS 2 and a line of mine"[..], b"OURS 3", b"theirs"] {
        fs::write(&path, theirs).unwrap();
        assert!(refused(write(b"OURS 4", false), true));
        assert_eq!(fs::read(&path).unwrap(), theirs);
    }
    write(b"OURS 3", true).unwrap();
    // A file without a record is not ours, whatever it holds.
    fs::remove_file(&record).unwrap();
    assert!(refused(write(b"OURS 5", false), true));
    write(b"OURS 3", true).unwrap();
    // The input, by its own name or another one, even with force and even if ours.
    let alias = tmp.path().join("alias.json");
    fs::hard_link(&path, &alias).unwrap();
    for out in [&path, &alias] {
        assert!(refused(
            OutputFile::prepare(Claim::new(out, "replay", true, &[&path])),
            false
        ));
    }
    assert!(refused(
        OutputFile::prepare(Claim::new(tmp.path(), "replay", true, &[])),
        false
    ));
    assert_eq!(fs::read(&path).unwrap(), b"OURS 3");
    assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 3);
}
