//! Build script of the QEMU firmware (for the MCU, `target_os = "none"`, only; nothing on the
//! host, where the binary is a stub):
//!
//! 1. names the gait the firmware embeds: `$PURCELL_GAIT` (absolute, or relative to the
//!    workspace root), or the committed paper's gait `core/examples/paper.gait`, as
//!    `PURCELL_GAIT_FILE` for `include_bytes!(env!("PURCELL_GAIT_FILE"))`; cargo rebuilds when
//!    the variable or the file changes, and a missing file stops the build with its name;
//! 2. puts `memory.x` on the linker path and links the firmware and the control-loop example
//!    with cortex-m-rt's `link.x` and defmt's `defmt.x`;
//! 3. with the `m7` feature, refuses to build unless `-C target-cpu=cortex-m7` is in the
//!    rustflags (without it every `f64` operation would be a soft-float call); with `m3`,
//!    unless the target is `thumbv7m-none-eabi` (and `m7` is off).
//!
//! The gait itself is read at run time by `purcell_core::Gait::from_bytes`, as in any user's
//! firmware: this script does not parse it.

use std::path::PathBuf;
use std::{env, fs};

fn main() -> Result<(), String> {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-env-changed=PURCELL_GAIT");
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return Ok(());
    }
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
    let root = manifest.join("../..");
    let gait = match env::var_os("PURCELL_GAIT") {
        Some(p) => root.join(p),
        None => root.join("core/examples/paper.gait"),
    };
    let gait = gait
        .canonicalize()
        .map_err(|e| format!("PURCELL_GAIT: cannot open {}: {e}", gait.display()))?;
    println!("cargo:rerun-if-changed={}", gait.display());
    println!("cargo:rustc-env=PURCELL_GAIT_FILE={}", gait.display());

    let out = PathBuf::from(env::var("OUT_DIR").map_err(|e| e.to_string())?);
    let memory = fs::read(manifest.join("memory.x")).map_err(|e| e.to_string())?;
    fs::write(out.join("memory.x"), memory).map_err(|e| e.to_string())?;
    println!("cargo:rustc-link-search={}", out.display());
    for kind in ["bins", "examples"] {
        for arg in ["--nmagic", "-Tlink.x", "-Tdefmt.x"] {
            println!("cargo:rustc-link-arg-{kind}={arg}");
        }
    }
    if env::var_os("CARGO_FEATURE_M3").is_some()
        && (env::var("TARGET").as_deref() != Ok("thumbv7m-none-eabi")
            || env::var_os("CARGO_FEATURE_M7").is_some())
    {
        return Err(
            "feature `m3` is the Cortex-M3 board: build it alone for thumbv7m-none-eabi \
             with `cargo mcu-m3` (see firmware/README.md)"
                .into(),
        );
    }
    if env::var_os("CARGO_FEATURE_M7").is_some() {
        let flags = env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
        if !flags
            .split('\x1f')
            .any(|f| f.ends_with("target-cpu=cortex-m7"))
        {
            return Err(
                "feature `m7` needs `-C target-cpu=cortex-m7` (f64 would be soft-float \
                        otherwise): build with `cargo mcu-m7` (see firmware/README.md)"
                    .into(),
            );
        }
    }
    Ok(())
}
