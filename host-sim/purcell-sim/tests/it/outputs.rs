//! Outputs never lose a user's data (issue 9, defects 1, 3, 5, 8): `solve --out` replaces
//! only a previous result of ours, refuses anything else before any work, replaces in one
//! step; `replay --out` never overwrites its input or a file it did not write.

use crate::common;

use common::*;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// A directory of somebody's files: text, a nested directory, a link, and names that
/// `solve` writes too.
fn users_files(dir: &Path) {
    std::fs::create_dir_all(dir.join("chapter")).unwrap();
    std::fs::write(dir.join("thesis.tex"), "precious\n").unwrap();
    std::fs::write(dir.join("chapter/notes.md"), "more\n").unwrap();
    std::fs::write(dir.join("report.json"), "{\"mine\": true}\n").unwrap();
    std::fs::write(dir.join("trajectory.csv"), "1,2\n").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("thesis.tex", dir.join("link")).unwrap();
}

/// Issue 9, defect 1: an existing directory of unrelated files was silently replaced
/// (exit 0). Now exit 2, every file byte-identical, nothing created next to it.
#[test]
fn solve_into_a_directory_of_other_files_changes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("mine");
    users_files(&dir);
    let before = snapshot(tmp.path());
    let solve = Solve::quick().out(&dir);
    assert_exit(&solve.run(), 2, "--force");
    assert_eq!(snapshot(tmp.path()), before);
    // Also when it holds only a file of a name we write, or an empty manifest.
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("costate.json"), "mine").unwrap();
    assert_eq!(solve.run().status.code(), Some(2));
    std::fs::write(dir.join("purcell-sim-manifest.json"), "{}").unwrap();
    assert_eq!(solve.run().status.code(), Some(2));
    assert_eq!(std::fs::read(dir.join("costate.json")).unwrap(), b"mine");
}

/// Issue 9, defect 1: `--out "$PWD"` emptied the current directory.
#[test]
fn solve_into_the_current_directory_changes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    users_files(tmp.path());
    let before = snapshot(tmp.path());
    let pwd = arg(tmp.path()).to_string();
    for out in [".", &pwd[..], "chapter/.."] {
        let o = Solve::quick().out(Path::new(out)).run_in(tmp.path());
        assert_eq!(o.status.code(), Some(2), "{out}: {}", stderr(&o));
        assert_eq!(snapshot(tmp.path()), before, "{out}");
    }
}

/// Issue 9, defect 1: an existing file was renamed to a hidden `.NAME.old-<pid>` and
/// replaced by a directory; a device node was moved aside. Now both refused, unchanged.
#[test]
fn solve_onto_a_file_or_a_device_changes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("results");
    std::fs::write(&file, "precious").unwrap();
    let o = Solve::quick().out(&file).run();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(
        snapshot(tmp.path()),
        [("results".into(), b"precious".to_vec())]
    );
    #[cfg(unix)]
    for force in [&[][..], &["--force"][..]] {
        let o = Solve::quick().out(Path::new("/dev/null")).with(force).run();
        assert_exit(&o, 2, "special file");
    }
}

/// The README's main job, twice in a row: the second run recognises the first one's
/// directory as ours and replaces it; the replay of the costate succeeds both times.
#[test]
fn the_main_job_twice_in_a_row_succeeds() {
    let tmp = tempfile::tempdir().unwrap();
    for _ in 0..2 {
        let o = Solve::paper()
            .out(Path::new("out/paper"))
            .run_in(tmp.path());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let costate = "out/paper/costate.json";
        let o = sim_in(Some(tmp.path()), &["replay", "--costate", costate], LIMIT);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
    // Nothing but the output (no staging or old copies).
    let names: Vec<String> = snapshot(tmp.path()).into_iter().map(|(n, _)| n).collect();
    assert!(names.iter().all(|n| n.starts_with("out/")), "{names:?}");
    assert!(names.contains(&"out/paper/purcell-sim-manifest.json".to_string()));
}

/// A result of ours that a user changed (an edited file, an added one) is theirs now.
#[test]
fn a_result_changed_by_its_user_is_not_replaced_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let solve = Solve::quick().out(&out);
    assert_eq!(solve.run().status.code(), Some(0));
    let report = out.join("report.json");
    let mut text = std::fs::read_to_string(&report).unwrap();
    text.push_str("my note\n");
    std::fs::write(&report, &text).unwrap();
    let before = snapshot(tmp.path());
    assert_exit(&solve.run(), 2, "report.json, changed since");
    assert_eq!(snapshot(tmp.path()), before);
    // With --force it is replaced, by exactly our files.
    std::fs::write(out.join("extra.txt"), "x").unwrap();
    assert_eq!(solve.clone().force().run().status.code(), Some(0));
    assert!(!out.join("extra.txt").exists());
    assert_ne!(std::fs::read_to_string(&report).unwrap(), text);
    assert_eq!(solve.run().status.code(), Some(0));
}

/// Issue 9, defect 3: replacing was two renames, and between them the output path did not
/// exist. Now one exchange: a reader polling the path never finds it missing.
#[test]
fn replacing_a_result_never_leaves_the_path_missing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    assert_eq!(Solve::quick().out(&out).run().status.code(), Some(0));
    let (stop, missing) = (
        Arc::new(AtomicBool::new(false)),
        Arc::new(AtomicUsize::new(0)),
    );
    let poller = {
        let (stop, missing, out) = (stop.clone(), missing.clone(), out.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                if std::fs::symlink_metadata(&out).is_err() {
                    missing.fetch_add(1, Ordering::Relaxed);
                }
            }
        })
    };
    for _ in 0..10 {
        solved(&out);
    }
    stop.store(true, Ordering::Relaxed);
    poller.join().unwrap();
    assert_eq!(
        missing.load(Ordering::Relaxed),
        0,
        "the output path went missing"
    );
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 1);
}

/// Issue 9, defect 8: a bad `--out` was found only after the whole solve. Now exit 2 at
/// once (the paper's problem with 100 starts would take a minute).
#[test]
fn a_bad_out_is_refused_before_the_solve() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("file");
    std::fs::write(&file, "x").unwrap();
    let under_file = file.join("out");
    for out in [
        Path::new("/proc/purcell-sim-test"),
        Path::new("/"),
        &under_file,
    ] {
        let t0 = Instant::now();
        let o = Solve::paper().starts(100).out(out).run();
        assert_eq!(o.status.code(), Some(2), "{out:?}: {}", stderr(&o));
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "{out:?}: refused only after {:?}",
            t0.elapsed()
        );
    }
    assert_eq!(std::fs::read(&file).unwrap(), b"x");
}

const COSTATE: &str = r#"{"format":"purcell-costate","version":2,
 "model":{"links":[1,1,1],"drag":1,"ratio":2},"h":0.01,"steps":200,"alpha0":[0,0],
 "target":[0.1,0.1,0],"mu":[0.1,0.2,0.0],"xi0":[0.01,-0.02],"checkpoint_every":0,
 "checkpoints":[]}"#;

/// Issue 9, defect 5: `replay --costate c.json --out c.json` overwrote its own input. It
/// is refused by any name, even with `--force`; `--out` replaces only a replay report.
#[test]
fn replay_out_never_overwrites_its_input_or_a_foreign_file() {
    let tmp = tempfile::tempdir().unwrap();
    let c = tmp.path().join("c.json");
    std::fs::write(&c, COSTATE).unwrap();
    let cs = arg(&c);
    let alias = tmp.path().join("alias.json");
    #[cfg(unix)]
    std::os::unix::fs::symlink("c.json", &alias).unwrap();
    #[cfg(not(unix))]
    std::fs::hard_link(&c, &alias).unwrap();
    for out in [cs, arg(&alias)] {
        for force in [&[][..], &["--force"][..]] {
            let args = [&["replay", "--costate", cs, "--out", out][..], force].concat();
            assert_exit(&sim(&args), 2, "input");
        }
    }
    assert_eq!(std::fs::read_to_string(&c).unwrap(), COSTATE);

    // A report of ours is replaced; somebody else's file only with --force.
    let r = tmp.path().join("r.json");
    let rs = arg(&r);
    for _ in 0..2 {
        let o = sim(&["replay", "--costate", cs, "--out", rs]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let written: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&r).unwrap()).unwrap();
        assert_eq!(written["format"], "purcell-replay");
    }
    std::fs::write(&r, "my notes").unwrap();
    let o = sim(&["replay", "--costate", cs, "--out", rs]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(std::fs::read(&r).unwrap(), b"my notes");
    let o = sim(&["replay", "--costate", cs, "--out", rs, "--force"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(&r)
            .unwrap()
            .contains("purcell-replay")
    );
    let names: Vec<String> = snapshot(tmp.path()).into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        names,
        [".r.json.purcell-sim", "alias.json", "c.json", "r.json"]
    );
}

/// [`Solve::quick`] (no figures) into `out`, which must succeed.
fn solved(out: &Path) {
    let o = Solve::quick().no_plots().out(out).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Issue 21, defect 1: `solve --from c.json --out c.json --force` and `field --costate c.json
/// --out c.json --force` replaced their input by a directory. An output that names or
/// contains an input (by any name) is refused with exit 2, with or without `--force`.
#[test]
#[cfg(target_os = "linux")]
fn no_output_names_or_contains_an_input_even_with_force() {
    let tmp = tempfile::tempdir().unwrap();
    let res = tmp.path().join("res");
    solved(&res);
    let costate = res.join("costate.json");
    let c = tmp.path().join("c.json");
    std::fs::copy(&costate, &c).unwrap();
    let alias = tmp.path().join("alias.json");
    std::os::unix::fs::symlink(&costate, &alias).unwrap();
    let before = snapshot(tmp.path());
    let cases = [
        (&c, c.clone()),
        (&costate, res.clone()),
        (&alias, res.clone()),
        (&c, tmp.path().to_path_buf()),
        (&costate, tmp.path().join("./res/")),
    ];
    for (input, out) in &cases {
        for force in [&[][..], &["--force"][..]] {
            let solve = Solve::quick().from(input).out(out).with(force);
            let field = [
                &["field", "--costate", arg(input), "--out", arg(out)][..],
                force,
            ]
            .concat();
            for args in [solve.args(), field] {
                assert_exit(&sim(&args), 2, "is or holds an input of this command");
            }
        }
    }
    assert_eq!(snapshot(tmp.path()), before);
}

/// Issue 21, defect 3: `field` panicked (exit 101) on a non-UTF-8 `--out` after writing its
/// files.
#[test]
#[cfg(target_os = "linux")]
fn field_takes_a_non_utf8_out() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join(std::ffi::OsStr::from_bytes(b"field\xff"));
    let mut c = command(&["field", "--out"]);
    c.arg(&out);
    let o = wait(c.spawn().unwrap(), LIMIT, "field --out field\\xff");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(out.join("field.csv").exists());
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(printed["out"].as_str().unwrap().ends_with("field\u{fffd}"));
}

/// Issue 21, defect 6: some unusable `--out` paths were found only after the whole solve
/// (exit 1): a mount point, an immutable directory, another user's result in a sticky
/// directory, and `--out LINK/` (blamed on a change "while the command ran"). All are
/// refused with exit 2 before the work, and nothing is left behind.
#[test]
#[cfg(target_os = "linux")]
fn unusable_outs_are_refused_before_the_work() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let tmp = tempfile::tempdir().unwrap();
    let refused = |out: &str, needle: &str, user: Option<u32>| {
        let solve = Solve::quick().out(Path::new(out)).force().no_plots();
        let mut c = command(&solve.args());
        if let Some(uid) = user {
            std::os::unix::process::CommandExt::uid(&mut c, uid);
        }
        assert_exit(&wait(c.spawn().unwrap(), LIMIT, out), 2, needle);
    };

    // A mount point (its device differs from its parent's).
    let dev = |p: &str| std::fs::metadata(p).unwrap().dev();
    if dev("/proc") != dev("/") {
        refused("/proc", "is a mount point", None);
    }

    // `LINK/`, LINK a symbolic link to a result of ours: the link, not a change.
    let real = tmp.path().join("real");
    solved(&real);
    let link = tmp.path().join("link");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    refused(&format!("{}/", arg(&link)), "is a symbolic link", None);

    // An immutable result of ours (where chattr works: root on a filesystem with flags).
    let frozen = tmp.path().join("frozen");
    solved(&frozen);
    let chattr = |flag: &str| {
        std::process::Command::new("chattr")
            .args([flag, arg(&frozen)])
            .status()
            .is_ok_and(|s| s.success())
    };
    if chattr("+i") {
        refused(arg(&frozen), "cannot be replaced", None);
        assert!(chattr("-i"));
    }

    // Another user's result in a sticky directory (run as `nobody` where the test is root).
    if unsafe { libc::geteuid() } == 0 {
        let nobody = 65534;
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        let sticky = tmp.path().join("sticky");
        std::fs::create_dir(&sticky).unwrap();
        std::fs::set_permissions(&sticky, std::fs::Permissions::from_mode(0o1777)).unwrap();
        let theirs = sticky.join("theirs");
        solved(&theirs);
        refused(arg(&theirs), "another user's", Some(nobody));
        // And a result of one's own that one cannot write into.
        let mine = sticky.join("mine");
        solved(&mine);
        let files: Vec<_> = std::fs::read_dir(&mine)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        std::os::unix::fs::lchown(&mine, Some(nobody), Some(nobody)).unwrap();
        for f in &files {
            std::os::unix::fs::lchown(f, Some(nobody), Some(nobody)).unwrap();
        }
        std::fs::set_permissions(&mine, std::fs::Permissions::from_mode(0o555)).unwrap();
        refused(arg(&mine), "cannot be replaced", Some(nobody));
        std::fs::set_permissions(&mine, std::fs::Permissions::from_mode(0o755)).unwrap();
        assert_eq!(
            std::fs::read_dir(&sticky).unwrap().count(),
            2,
            "staging left behind"
        );
    }
    let names: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(names.is_empty(), "staging left behind: {names:?}");
}

/// Issue 21 (lower): a Ctrl-C left a hidden staging folder beside the output, and nothing
/// cleaned old ones. The next run in that directory removes those that no process holds
/// locked (issue 34: not by process id), and leaves a locked one alone.
#[test]
fn staging_left_by_a_killed_run_is_removed_by_the_next() {
    let tmp = tempfile::tempdir().unwrap();
    let stale = tmp.path().join(".purcell-sim-00000000000000a1.tmp");
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join("trajectory.csv"), "half").unwrap();
    let stale_file = tmp.path().join(".purcell-sim-00000000000000a2.tmp");
    std::fs::write(&stale_file, "half").unwrap();
    let live = tmp.path().join(".purcell-sim-00000000000000a3.tmp");
    std::fs::create_dir(&live).unwrap();
    let holder = hold_lock(&live);
    solved(&tmp.path().join("out"));
    assert!(!stale.exists() && !stale_file.exists());
    assert!(live.exists());
    drop(holder);
}

/// Issue 21 (lower): names over about 230 bytes were refused because of the staging name's
/// suffix.
#[test]
fn an_output_name_of_255_bytes_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("r".repeat(255));
    solved(&out);
    let report = tmp.path().join(format!("{}.json", "r".repeat(250)));
    let costate = out.join("costate.json");
    let o = sim(&["replay", "--costate", arg(&costate), "--out", arg(&report)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Issue 21 (lower): replacing an output reset its permissions (700 became 755).
#[test]
#[cfg(unix)]
fn a_replaced_output_keeps_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let tmp = tempfile::tempdir().unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o7777;
    let out = tmp.path().join("out");
    solved(&out);
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o700)).unwrap();
    solved(&out);
    assert_eq!(mode(&out), 0o700);
    let report = tmp.path().join("r.json");
    let costate = out.join("costate.json");
    let replay = ["replay", "--costate", arg(&costate), "--out", arg(&report)];
    assert_eq!(sim(&replay).status.code(), Some(0));
    std::fs::set_permissions(&report, std::fs::Permissions::from_mode(0o600)).unwrap();
    assert_eq!(sim(&replay).status.code(), Some(0));
    assert_eq!(mode(&report), 0o600);
}

/// Issue 21 (lower): `solve --out` silently replaced a previous `sweep` result. A result of
/// another subcommand is replaced only with `--force`.
#[test]
fn a_result_of_another_subcommand_is_replaced_only_with_force() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = sim(&["field", "--out", arg(&out)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let before = snapshot(&out);
    let solve = Solve::quick().no_plots().out(&out);
    assert_exit(&solve.run(), 2, "is a result of `purcell-sim field`");
    assert_eq!(snapshot(&out), before);
    assert_exit(&solve.force().run(), 0, "");
}
