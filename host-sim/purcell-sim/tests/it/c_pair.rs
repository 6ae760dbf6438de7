//! Issue 34, "never lose a user's file", the C pair: `export --format c` under a kill or a
//! full disk, a single file ours only byte for byte, and C that always compiles.

use crate::common;

use common::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `export --format c` of `gait` to `out` with `extra` flags.
/// `export --gait GAIT --format c --out OUT`.
fn export_c_args<'a>(gait: &'a Path, out: &'a Path) -> [&'a str; 7] {
    [
        "export",
        "--gait",
        arg(gait),
        "--format",
        "c",
        "--out",
        arg(out),
    ]
}

fn export_c(gait: &Path, out: &Path, extra: &[&str]) -> Output {
    sim(&[&export_c_args(gait, out)[..], extra].concat())
}

/// Whether `dir/NAME.c` compiles (with its header) under `gcc -std=c11`; `None` without gcc.
fn compiles(c: &Path) -> Option<bool> {
    let o = Command::new("gcc")
        .args(["-std=c11", "-Wall", "-Werror", "-fsyntax-only"])
        .arg(c)
        .output()
        .ok()?;
    Some(o.status.success())
}

/// The length the header declares and the number of bytes the array holds.
fn pair_lengths(c: &Path) -> (usize, usize) {
    let h = std::fs::read_to_string(c.with_extension("h")).unwrap();
    let declared = h
        .lines()
        .find(|l| l.starts_with("#define") && l.contains("_LEN "))
        .and_then(|l| l.split_whitespace().nth(2))
        .map(|n| n.trim_end_matches('u').parse().unwrap())
        .unwrap();
    let c = std::fs::read_to_string(c).unwrap();
    let held = c.split_once("] = {").unwrap().1.matches("0x").count();
    (declared, held)
}

/// Two gaits of different lengths, and `g.c` / `g.h` exported from the first.
fn c_pair(tmp: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let small = tmp.join("small.gait");
    std::fs::write(&small, gait_with_steps(200)).unwrap();
    let big = tmp.join("big.gait");
    export_tracking(&big);
    let c = tmp.join("g.c");
    let o = export_c(&small, &c, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    (small, big, c)
}

/// Defect 2 (kill): `export --format c` renamed `.h` then `.c`; killed between the two it
/// left a pair that disagreed and compiled. Killed after each rename of the export now
/// (debug builds' hook), the pair either agrees or fails to compile, and the next export
/// without `--force` puts a matching pair in place.
#[test]
fn a_c_export_killed_between_its_renames_never_leaves_a_pair_that_builds() {
    if !cfg!(debug_assertions) {
        println!("skipped: the abort hook exists in builds with debug assertions only");
        return;
    }
    for after in 1..=5 {
        let tmp = tempfile::tempdir().unwrap();
        let (small, big, c) = c_pair(tmp.path());
        let o = wait(
            command(&export_c_args(&big, &c))
                .env("PURCELL_SIM_TEST_ABORT_AFTER_RENAMES", after.to_string())
                .spawn()
                .unwrap(),
            LIMIT,
            "export",
        );
        assert_eq!(
            o.status.code(),
            None,
            "{after}: not interrupted: {}",
            stderr(&o)
        );
        let (declared, held) = pair_lengths(&c);
        if let Some(builds) = compiles(&c) {
            assert!(
                declared == held || !builds,
                "{after}: a pair that disagrees ({declared} declared, {held} held) compiles"
            );
        }
        assert!(
            declared == held || after < 5,
            "{after}: the last rename is a record"
        );
        for gait in [&small, &big] {
            let o = export_c(gait, &c, &[]);
            assert_eq!(o.status.code(), Some(0), "{after}: {}", stderr(&o));
            let (declared, held) = pair_lengths(&c);
            assert_eq!(declared, held);
            assert_ne!(compiles(&c), Some(false));
        }
    }
}

/// Defect 2 (full disk): with the disk full after the first file, the pair was left
/// disagreeing (`g.h` new, `g.c` old) and compiling, with exit 1. Every file is now written
/// before any is renamed: the old pair stays as it was. (`ulimit -f` makes the write fail
/// as a full disk does.)
#[test]
fn a_c_export_on_a_full_disk_leaves_the_old_pair() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, big, c) = c_pair(tmp.path());
    let before = (
        std::fs::read(&c).unwrap(),
        std::fs::read(c.with_extension("h")).unwrap(),
    );
    let o = shell(
        "trap '' XFSZ; ulimit -f 16; exec \"$0\" \"$@\"",
        &export_c_args(&big, &c),
        LIMIT,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let after = (
        std::fs::read(&c).unwrap(),
        std::fs::read(c.with_extension("h")).unwrap(),
    );
    assert!(before == after, "the pair changed");
    assert!(staging(tmp.path()).is_empty());
}

/// Defect 3: a single output was ours when its first bytes matched: a user's function
/// appended to `g.c`, or a user's file starting with `PURCGAIT`, was replaced with exit 0.
/// Now only a file whose record lists exactly its contents is replaced without `--force`.
#[test]
fn a_file_is_ours_only_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let (small, _, c) = c_pair(tmp.path());
    let mut edited = std::fs::read(&c).unwrap();
    edited.extend_from_slice(b"int f(void){return 1;}\n");
    std::fs::write(&c, &edited).unwrap();
    assert_exit(&export_c(&small, &c, &[]), 2, "--force");
    assert_eq!(std::fs::read(&c).unwrap(), edited);

    let mine = tmp.path().join("mine.gait");
    let mut theirs = purcell_core::gait::MAGIC.to_vec();
    theirs.extend_from_slice(b" my own notes");
    std::fs::write(&mine, &theirs).unwrap();
    let o = sim(&["export", "--gait", arg(&small), "--out", arg(&mine)]);
    assert_exit(&o, 2, "--force");
    assert_eq!(std::fs::read(&mine).unwrap(), theirs);
    // A complete gait file that export did not write there is not ours either.
    std::fs::copy(&small, &mine).unwrap();
    let o = sim(&["export", "--gait", arg(&small), "--out", arg(&mine)]);
    assert_exit(&o, 2, "--force");
    // With --force, and then again without it: ours now.
    for force in [&["--force"][..], &[]] {
        let args = ["export", "--gait", arg(&small), "--out", arg(&mine)];
        let o = sim(&[&args[..], force].concat());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
}

/// Defect 6: `export --format c --out int.c` (a keyword, a `<stdint.h>` name, ...) wrote C
/// that does not compile; a name with a quote, a newline or non-UTF-8 bytes too. Now the
/// array's name is made a valid identifier, and a header name that `#include "..."` cannot
/// hold is refused (exit 2).
#[test]
fn every_c_export_compiles_or_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let gait = tmp.path().join("g.gait");
    std::fs::write(&gait, gait_with_steps(200)).unwrap();
    let good = [
        "int",
        "for",
        "sizeof",
        "while",
        "static_assert",
        "bool",
        "class",
        "new",
        "uint8_t",
        "size_t",
        "INT8_MAX",
        "UINT32_C",
        "main",
        "_Bool",
        "__x",
        "2gait",
        "a b",
        "a-b.v2",
        "my_gait",
        "Gait",
        "NULL",
        "x+y",
        "g,h",
        "a=b",
        "at@",
        "~t",
        "PURCELL_H",
    ];
    for stem in good {
        let c = tmp.path().join(format!("{stem}.c"));
        let o = export_c(&gait, &c, &[]);
        assert_eq!(o.status.code(), Some(0), "{stem}: {}", stderr(&o));
        assert_ne!(compiles(&c), Some(false), "{stem}.c does not compile");
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        for stem in [
            &b"q\"uote"[..],
            b"new\nline",
            b"back\\slash",
            b"caf\xe9",
            b"a/*b",
        ] {
            let name = [stem, b".c"].concat();
            let c = tmp.path().join(std::ffi::OsStr::from_bytes(&name));
            if name.contains(&b'/') {
                continue;
            }
            let o = command(&[])
                .args(["export", "--gait", arg(&gait), "--format", "c", "--out"])
                .arg(&c)
                .output()
                .unwrap();
            assert_exit(&o, 2, "#include");
            assert!(!c.exists());
        }
    }
}
