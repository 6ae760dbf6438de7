//! `purcell.replay`: a stored gait through the core as firmware flies it, with the checks and
//! the digest of `purcell-sim replay`, and the trajectory as arrays.

use crate::solution::Solution;
use crate::{array1, array2, error, input_error, py_any, repr};
use numpy::{PyArray1, PyArray2};
use purcell_core::cost::RunningCost;
use purcell_core::gait::Stored;
use purcell_core::{Gait, Real};
use purcell_sim::budget::Work;
use purcell_sim::costate_file::CostateFile;
use purcell_sim::replay::{ReplayReport, check_stored, replay_gait};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict};

/// One replay of a gait through the core (MODEL.md §6), as `purcell-sim replay --precision`.
#[pyclass(frozen, get_all, module = "purcell")]
pub struct Replay {
    /// `"f32"` or `"f64"`.
    precision: &'static str,
    /// Whether the gait's costate checkpoints were applied.
    checkpoints: bool,
    /// The trajectory digest, `0x` and 16 hex digits (what `purcell-sim replay` prints).
    digest: String,
    /// Bits of (alpha1, alpha2, x, y, cos theta, sin theta) at the end, `0x…` (f32 widened).
    final_state_bits: Vec<String>,
    /// max |alpha_N - alpha_end|, radians (alpha_end: alpha0 for a loop).
    alpha_error: f64,
    /// max |log(g_bar^-1 g_N)| over its components, metres / radians.
    g_error: f64,
    /// Times t_k = k h, seconds, shape (N+1,) (the float nearest the decimal k h).
    t: Py<PyArray1<f64>>,
    /// Shapes alpha_k, radians, shape (N+1, 2).
    alpha: Py<PyArray2<f64>>,
    /// Controls u_k, rad/s, shape (N, 2).
    u: Py<PyArray2<f64>>,
    /// Positions g_k = (x, y, theta), metres and radians, shape (N+1, 3).
    g: Py<PyArray2<f64>>,
}

#[pymethods]
impl Replay {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        repr(
            "Replay",
            [
                ("precision", py_any(py, self.precision)),
                ("checkpoints", py_any(py, self.checkpoints)),
                ("digest", py_any(py, &self.digest)),
                ("alpha_error", py_any(py, self.alpha_error)),
                ("g_error", py_any(py, self.g_error)),
            ],
        )
    }
}

/// Replays a gait through the core in f32 or f64, as firmware flies it (`purcell-sim replay`).
///
/// costate_or_gait: a Solution, the bytes of a gait file or costate file, or the path of
/// either (str or os.PathLike). precision: "f32" (the Cortex-M4F's) or "f64". checkpoints:
/// apply the gait's costate checkpoints (without: only those at joint-limit arcs' exits).
/// Raises InputError for a file the command line refuses, ReplayFailed where a replay stops.
#[pyfunction]
#[pyo3(signature = (costate_or_gait, precision = "f32", checkpoints = true))]
pub fn replay(
    py: Python<'_>,
    costate_or_gait: &Bound<'_, PyAny>,
    precision: &str,
    checkpoints: bool,
) -> PyResult<Replay> {
    let (name, bytes) = gait_bytes(py, costate_or_gait)?;
    let gait = Gait::from_bytes(&bytes).map_err(|e| input_error(format!("{name}: {e}")))?;
    let refused = |e| input_error(format!("{name}: {e}"));
    // The command line's step and memory budget: the replay keeps the whole path.
    purcell_sim::budget::check(u64::from(gait.params().steps), Work::Path)
        .map_err(|e| input_error(format!("{name}: {e}")))?;
    let f32 = match precision {
        "f32" => true,
        "f64" => false,
        other => {
            let why = format!("precision must be 'f32' or 'f64' (got '{other}')");
            return Err(input_error(why));
        }
    };
    check_stored(&gait, f32).map_err(refused)?;
    match f32 {
        true => fly::<f32>(py, &gait, "f32", checkpoints),
        false => fly::<f64>(py, &gait, "f64", checkpoints),
    }
}

/// The gait file's bytes of `obj` and a name for messages: a `Solution`'s gait; bytes of a
/// gait file as they are; a costate file's text encoded; a path read (bounded, as the
/// command line reads) and taken as either.
fn gait_bytes(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<(String, Vec<u8>)> {
    if let Ok(s) = obj.cast::<Solution>() {
        return Ok(("solution".into(), s.get().gait_bytes().to_vec()));
    }
    let (name, raw) = if let Ok(b) = obj.cast::<PyBytes>() {
        ("bytes".to_string(), b.as_bytes().to_vec())
    } else if let Ok(b) = obj.cast::<PyByteArray>() {
        ("bytes".to_string(), b.to_vec())
    } else {
        let path: std::path::PathBuf =
            py.import("os")?.call_method1("fspath", (obj,))?.extract()?;
        let raw = purcell_sim::input::read(&path)
            .map_err(|e| input_error(format!("reading {}: {e}", path.display())))?;
        (path.display().to_string(), raw)
    };
    if raw.starts_with(&purcell_core::gait::MAGIC) {
        return Ok((name, raw));
    }
    let text = String::from_utf8(raw)
        .map_err(|e| input_error(format!("{name}: malformed costate file: {e}")))?;
    let file = CostateFile::parse(&text).map_err(|e| input_error(format!("{name}: {e}")))?;
    let bytes = file
        .to_gait()
        .map_err(|e| input_error(format!("{name}: {e}")))?;
    Ok((name, bytes))
}

/// Flies `gait` in `T`: the command line's report (digest, final bits, terminal error) and a
/// second, recorded flight for the arrays.
fn fly<T: Stored>(
    py: Python<'_>,
    gait: &Gait<'_>,
    precision: &'static str,
    checkpoints: bool,
) -> PyResult<Replay> {
    let report = replay_gait::<T>(gait, precision, checkpoints);
    let (Some(digest), Some(bits), Some(alpha_error), Some(g_error)) = (
        report.digest.clone(),
        report.final_state_bits.clone(),
        report.alpha_error,
        report.g_error,
    ) else {
        return Err(failure(py, gait, &report));
    };
    let path = record::<T>(gait, checkpoints).map_err(|e| input_error(e.to_string()))?;
    let h = gait.params().h;
    let t: Vec<f64> = (0..path.alpha.len())
        .map(|k| purcell_sim::decimal::time_value(k as u64, h))
        .collect();
    Ok(Replay {
        precision,
        checkpoints,
        digest,
        final_state_bits: bits,
        alpha_error,
        g_error,
        t: array1(py, &t)?.unbind(),
        alpha: array2(py, path.alpha.into_iter())?.unbind(),
        u: array2(py, path.u.into_iter())?.unbind(),
        g: array2(py, path.g.into_iter())?.unbind(),
    })
}

/// `purcell.ReplayFailed` with the command line's message and the step it failed at.
fn failure(py: Python<'_>, gait: &Gait<'_>, r: &ReplayReport) -> PyErr {
    let message = r.failure_message(gait);
    let message = message.unwrap_or_else(|| format!("{} replay: no result", r.precision));
    let attrs = PyDict::new(py);
    match attrs.set_item("step", r.failed_at_step) {
        Ok(()) => error("ReplayFailed", message, Some(&attrs)),
        Err(e) => e,
    }
}

/// A replay's states and controls, widened to `f64`.
struct Path {
    alpha: Vec<[f64; 2]>,
    u: Vec<[f64; 2]>,
    g: Vec<[f64; 3]>,
}

/// Replays `gait` in `T` with the law of its cost, recording every state and control.
fn record<T: Stored>(gait: &Gait<'_>, checkpoints: bool) -> Result<Path, purcell_core::Error> {
    purcell_core::with_cost!(gait.params().cost, C => record_for::<T, C>(gait, checkpoints))
}

/// [`record`] with the law of `C`, the gait's cost.
fn record_for<T: Stored, C: RunningCost>(
    gait: &Gait<'_>,
    checkpoints: bool,
) -> Result<Path, purcell_core::Error> {
    let mut r = gait.replay_for::<T, C>(checkpoints)?;
    let mut path = Path {
        alpha: Vec::new(),
        u: Vec::new(),
        g: Vec::new(),
    };
    let push_state = |path: &mut Path, s: &purcell_core::State<T>| {
        path.alpha.push([s.alpha.x.to_f64(), s.alpha.y.to_f64()]);
        path.g.push(s.g.to_xytheta().map(Real::to_f64).into());
    };
    while let Some(sample) = r.step()? {
        push_state(&mut path, &sample.state);
        path.u.push([sample.u.x.to_f64(), sample.u.y.to_f64()]);
    }
    push_state(&mut path, r.state());
    Ok(path)
}
