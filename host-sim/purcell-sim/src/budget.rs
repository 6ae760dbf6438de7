//! The one step and memory budget of every reader of a stored gait (`replay`, `export`,
//! `robustness`, `field`, the Python package): at most [`MAX_STEPS`] steps, and no more memory than
//! this process may use, checked before any work, with what a large run needs said first.

use purcell_solver::problem::MAX_STEPS;

/// What is done with a stored gait, by the memory it needs per step (measured: the maximum
/// resident set of the release build on a 10⁶-step gait at rest, less a run of few steps,
/// per step, rounded up: 72, 19 and 492 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// Read or converted only (`export` without `--tracking`).
    Read,
    /// Flown without keeping the path (`replay`'s flights).
    Fly,
    /// Flown keeping the path (`replay --trace`, `field`'s gait, the Python package's replay).
    Path,
    /// Flown closed loop with its stored tracking table (`robustness --digest`).
    Stored,
    /// Flown with a tracking table designed along it (`robustness`, `export --tracking`).
    Tracking,
}

impl Work {
    /// Bytes per step.
    pub fn bytes_per_step(self) -> u64 {
        match self {
            Work::Read | Work::Fly => 0,
            Work::Path => 100,
            Work::Stored => 32,
            Work::Tracking => 500,
        }
    }
}

/// Memory any run needs besides its steps (the program, its threads, the input file).
const BASE_BYTES: u64 = 256 << 20;
/// Above this, the memory a run needs is said before it starts.
const SAY_ABOVE: u64 = 1 << 30;

/// `Ok` with a note to print first when the run needs more than 1 GiB, or why `steps` steps
/// of `work` cannot be done: more than [`MAX_STEPS`], or more memory than this process may
/// use (its address-space limit, `ulimit -v`, or the machine's memory and swap).
pub fn check(steps: u64, work: Work) -> Result<Option<String>, String> {
    if steps > MAX_STEPS {
        return Err(format!("{steps} steps, more than the limit {MAX_STEPS}"));
    }
    let need = BASE_BYTES.saturating_add(steps.saturating_mul(work.bytes_per_step()));
    if let Some((limit, what)) = memory_limit()
        && need > limit
    {
        return Err(format!(
            "{steps} steps need about {} of memory here, more than the {} {what}",
            gb(need),
            gb(limit)
        ));
    }
    Ok((need > SAY_ABOVE).then(|| {
        format!(
            "{steps} steps: this needs about {} of memory and may take minutes",
            gb(need)
        )
    }))
}

fn gb(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// The smaller of this process's address-space limit and the machine's memory and swap, and
/// which it is; `None` where neither is known.
fn memory_limit() -> Option<(u64, &'static str)> {
    let machine = std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
        let field = |name: &str| -> Option<u64> {
            let line = m.lines().find(|l| l.starts_with(name))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib.saturating_mul(1024))
        };
        Some(field("MemTotal:")?.saturating_add(field("SwapTotal:").unwrap_or(0)))
    });
    let own = address_space_limit();
    match (own, machine) {
        (Some(a), Some(m)) if a <= m => Some((a, "this process may use (ulimit -v)")),
        (Some(a), None) => Some((a, "this process may use (ulimit -v)")),
        (_, Some(m)) => Some((m, "this machine has (memory and swap)")),
        (None, None) => None,
    }
}

#[cfg(target_os = "linux")]
fn address_space_limit() -> Option<u64> {
    // SAFETY: rlimit is plain data, filled by getrlimit.
    let mut r: libc::rlimit = unsafe { std::mem::zeroed() };
    // SAFETY: a valid resource and an out pointer to a local.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut r) } == 0;
    (ok && r.rlim_cur != libc::RLIM_INFINITY).then_some(r.rlim_cur)
}

#[cfg(not(target_os = "linux"))]
fn address_space_limit() -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_past_the_limit_are_refused_and_a_large_run_is_announced() {
        let e = check(u64::from(u32::MAX), Work::Read).unwrap_err();
        assert!(e.contains("more than the limit 10000000"), "{e}");
        assert_eq!(check(10_000, Work::Tracking), Ok(None));
        assert_eq!(check(MAX_STEPS, Work::Fly), Ok(None));
        match check(MAX_STEPS, Work::Tracking) {
            Ok(Some(note)) => assert!(note.contains("GB of memory"), "{note}"),
            Err(e) => assert!(e.contains("more than the"), "{e}"),
            Ok(None) => panic!("10^7 steps of tracking not announced"),
        }
    }
}
