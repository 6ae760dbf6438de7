//! Build script of the firmware crate.
//!
//! 1. Turns the costate file (`costate.json` beside this file, or the file named by the
//!    `PURCELL_COSTATE` environment variable) into Rust constants, `$OUT_DIR/costate.rs`:
//!    every number once as `f64` and once as `f32` (rounded to nearest, as `x as f32`), both
//!    written as exact bit patterns so host and firmware start from the same bits.
//! 2. For the MCU (`target_os = "none"`): puts `memory.x` on the linker path and links with
//!    cortex-m-rt's `link.x` and defmt's `defmt.x`.
//! 3. With the `m7` feature on the MCU: refuses to build unless `-C target-cpu=cortex-m7` is in
//!    the rustflags (without it every `f64` operation would be a soft-float call); with `m3`,
//!    unless the target is `thumbv7m-none-eabi`.

use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::{env, fs};

/// A build failure with the reason, shown by cargo.
#[derive(Debug)]
struct BuildError(String);

impl<E: std::fmt::Display> From<E> for BuildError {
    fn from(e: E) -> Self {
        BuildError(e.to_string())
    }
}

fn fail<T>(msg: impl Into<String>) -> Result<T, BuildError> {
    Err(BuildError(msg.into()))
}

/// The costate file's contents (see the format in `README.md`).
struct CostateFile {
    links: [f64; 3],
    drag: f64,
    ratio: f64,
    h: f64,
    steps: u32,
    alpha0: [f64; 2],
    target: [f64; 3],
    mu: [f64; 3],
    xi0: [f64; 2],
    checkpoint_every: u32,
    checkpoints: Vec<CheckpointEntry>,
    provisional: Option<String>,
}

/// One checkpoint: the `f64` replay's `(α_k, g_k, ξ^{k−1})` at step `k`, with `g` as
/// `(x, y, cos θ, sin θ)` exactly as the core stores it.
struct CheckpointEntry {
    k: u32,
    alpha: [f64; 2],
    g: [f64; 4],
    xi: [f64; 2],
}

/// The only costate file version this build reads (see `README.md`).
const VERSION: u64 = 2;

fn field<'a>(v: &'a Value, key: &str) -> Result<&'a Value, BuildError> {
    v.get(key)
        .ok_or_else(|| BuildError(format!("costate file: missing field `{key}`")))
}

fn number(v: &Value, what: &str) -> Result<f64, BuildError> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => fail(format!("costate file: `{what}` must be a finite number")),
    }
}

fn integer(v: &Value, what: &str) -> Result<u32, BuildError> {
    v.as_u64()
        .and_then(|x| u32::try_from(x).ok())
        .ok_or_else(|| BuildError(format!("costate file: `{what}` must be an integer < 2^32")))
}

fn array<const N: usize>(v: &Value, what: &str) -> Result<[f64; N], BuildError> {
    let items = v
        .as_array()
        .filter(|a| a.len() == N)
        .ok_or_else(|| BuildError(format!("costate file: `{what}` must hold {N} numbers")))?;
    let mut out = [0.0; N];
    for (o, item) in out.iter_mut().zip(items) {
        *o = number(item, what)?;
    }
    Ok(out)
}

fn parse(text: &str) -> Result<CostateFile, BuildError> {
    let v: Value = serde_json::from_str(text)?;
    if field(&v, "format")?.as_str() != Some("purcell-costate") {
        return fail("costate file: `format` must be \"purcell-costate\"");
    }
    match field(&v, "version")?.as_u64() {
        Some(VERSION) => {}
        Some(other) => {
            return fail(format!(
                "costate file: unsupported version {other} (this build reads version {VERSION}; \
                 regenerate it with `purcell-sim solve`)"
            ));
        }
        None => return fail("costate file: `version` must be a non-negative integer"),
    }
    let model = field(&v, "model")?;
    let mut checkpoints = Vec::new();
    let list = field(&v, "checkpoints")?
        .as_array()
        .ok_or_else(|| BuildError("costate file: `checkpoints` must be an array".into()))?;
    for c in list {
        let entry = CheckpointEntry {
            k: integer(field(c, "k")?, "checkpoints[].k")?,
            alpha: array(field(c, "alpha")?, "checkpoints[].alpha")?,
            g: array(field(c, "g")?, "checkpoints[].g")?,
            xi: array(field(c, "xi")?, "checkpoints[].xi")?,
        };
        let [_, _, cos, sin] = entry.g;
        // A rotation to rounding: the core takes (cos θ, sin θ) as they are.
        if (cos * cos + sin * sin - 1.0).abs() > 1e-9 {
            return fail(format!(
                "costate file: checkpoint {}: `g` must be [x, y, cos θ, sin θ] with cos² + sin² = 1",
                entry.k
            ));
        }
        checkpoints.push(entry);
    }
    let file = CostateFile {
        links: array(field(model, "links")?, "model.links")?,
        drag: number(field(model, "drag")?, "model.drag")?,
        ratio: number(field(model, "ratio")?, "model.ratio")?,
        h: number(field(&v, "h")?, "h")?,
        steps: integer(field(&v, "steps")?, "steps")?,
        alpha0: array(field(&v, "alpha0")?, "alpha0")?,
        target: array(field(&v, "target")?, "target")?,
        mu: array(field(&v, "mu")?, "mu")?,
        xi0: array(field(&v, "xi0")?, "xi0")?,
        checkpoint_every: integer(field(&v, "checkpoint_every")?, "checkpoint_every")?,
        checkpoints,
        provisional: v
            .get("provisional")
            .and_then(Value::as_str)
            .map(str::to_owned),
    };
    // The core validates values again at run time; refuse here what would fail there anyway.
    if !(file.links.iter().all(|&l| l > 0.0) && file.drag > 0.0 && file.ratio > 0.0) {
        return fail("costate file: link lengths, drag and ratio must be positive");
    }
    if file.h <= 0.0 || file.steps == 0 {
        return fail("costate file: `h` and `steps` must be positive");
    }
    let mut last = None;
    for &CheckpointEntry { k, .. } in &file.checkpoints {
        if k >= file.steps || last.is_some_and(|l| l >= k) {
            return fail(
                "costate file: checkpoint steps must be strictly increasing and below `steps`",
            );
        }
        last = Some(k);
    }
    Ok(file)
}

/// `f64::from_bits(0x…)`: the exact value, whatever the float printer does.
fn lit64(x: f64) -> String {
    format!("f64::from_bits({:#018x})", x.to_bits())
}

/// `f32::from_bits(0x…)` of `x` rounded to nearest.
fn lit32(x: f64) -> String {
    format!("f32::from_bits({:#010x})", (x as f32).to_bits())
}

fn list(xs: &[f64], lit: fn(f64) -> String) -> String {
    let parts: Vec<String> = xs.iter().map(|&x| lit(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// The generated module: one [`Data`] static per scalar type.
fn generate(f: &CostateFile, source: &Path) -> Result<String, BuildError> {
    let mut s = String::new();
    writeln!(
        s,
        "// Generated by build.rs from {}; do not edit.",
        source.display()
    )?;
    writeln!(s, "/// Number of control steps `N`.")?;
    writeln!(s, "pub const STEPS: u32 = {};", f.steps)?;
    writeln!(s, "/// Nominal spacing of the checkpoints, in steps.")?;
    writeln!(
        s,
        "pub const CHECKPOINT_EVERY: u32 = {};",
        f.checkpoint_every
    )?;
    writeln!(
        s,
        "/// Number of checkpoints in the file (the heapless table's capacity)."
    )?;
    writeln!(
        s,
        "pub const CHECKPOINT_COUNT: usize = {};",
        f.checkpoints.len()
    )?;
    writeln!(s, "/// Whether the file says it is a provisional stand-in.")?;
    writeln!(
        s,
        "pub const PROVISIONAL: bool = {};",
        f.provisional.is_some()
    )?;
    for (name, ty, lit) in [
        ("DOUBLE", "f64", lit64 as fn(f64) -> String),
        ("SINGLE", "f32", lit32 as fn(f64) -> String),
    ] {
        let cps: Vec<String> = f
            .checkpoints
            .iter()
            .map(|c| {
                format!(
                    "CheckpointData {{ k: {}, alpha: {}, g: {}, xi: {} }}",
                    c.k,
                    list(&c.alpha, lit),
                    list(&c.g, lit),
                    list(&c.xi, lit)
                )
            })
            .collect();
        writeln!(s, "/// The costate file in `{ty}`.")?;
        writeln!(s, "pub static {name}: Data<{ty}> = Data {{")?;
        writeln!(s, "    links: {},", list(&f.links, lit))?;
        writeln!(s, "    drag: {},", lit(f.drag))?;
        writeln!(s, "    ratio: {},", lit(f.ratio))?;
        writeln!(s, "    h: {},", lit(f.h))?;
        writeln!(s, "    steps: {},", f.steps)?;
        writeln!(s, "    alpha0: {},", list(&f.alpha0, lit))?;
        writeln!(s, "    target: {},", list(&f.target, lit))?;
        writeln!(s, "    mu: {},", list(&f.mu, lit))?;
        writeln!(s, "    xi0: {},", list(&f.xi0, lit))?;
        writeln!(s, "    checkpoints: &[{}],", cps.join(", "))?;
        writeln!(s, "}};")?;
    }
    Ok(s)
}

/// Writes `path` through a temporary file in the same directory and a rename.
fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), BuildError> {
    let tmp = path.with_extension("tmp");
    fs::write(&tmp, contents)?;
    fs::rename(&tmp, path)?;
    Ok(())
}

fn main() -> Result<(), BuildError> {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR")?);
    let out = PathBuf::from(env::var("OUT_DIR")?);
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-env-changed=PURCELL_COSTATE");
    let source = match env::var_os("PURCELL_COSTATE") {
        Some(p) => PathBuf::from(p),
        None => manifest.join("costate.json"),
    };
    println!("cargo:rerun-if-changed={}", source.display());
    let text = fs::read_to_string(&source)
        .map_err(|e| BuildError(format!("cannot read {}: {e}", source.display())))?;
    let file = parse(&text).map_err(|e| BuildError(format!("{}: {}", source.display(), e.0)))?;
    if let Some(note) = &file.provisional {
        println!("cargo:warning={} is provisional: {note}", source.display());
    }
    write_atomically(
        &out.join("costate.rs"),
        generate(&file, &source)?.as_bytes(),
    )?;

    if env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("none") {
        write_atomically(&out.join("memory.x"), &fs::read(manifest.join("memory.x"))?)?;
        println!("cargo:rustc-link-search={}", out.display());
        println!("cargo:rustc-link-arg-bins=--nmagic");
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
        if env::var_os("CARGO_FEATURE_M3").is_some()
            && (env::var("TARGET").as_deref() != Ok("thumbv7m-none-eabi")
                || env::var_os("CARGO_FEATURE_M7").is_some())
        {
            return fail(
                "feature `m3` is the Cortex-M3 board: build it alone for thumbv7m-none-eabi \
                 with `cargo mcu-m3` (see benches/mcu/README.md)",
            );
        }
        if env::var_os("CARGO_FEATURE_M7").is_some() {
            let flags = env::var("CARGO_ENCODED_RUSTFLAGS").unwrap_or_default();
            if !flags
                .split('\x1f')
                .any(|f| f.ends_with("target-cpu=cortex-m7"))
            {
                return fail(
                    "feature `m7` needs `-C target-cpu=cortex-m7` (f64 would be soft-float \
                     otherwise): build with `cargo mcu-m7` (see benches/mcu/README.md)",
                );
            }
        }
    }
    Ok(())
}
