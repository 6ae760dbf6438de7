//! `solve`'s argument lists, built from a problem preset.

use super::{LIMIT, arg, report, sim_in, stderr};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;

/// The arguments of one `solve` run: a problem preset, then flags in the order they are set
/// (setting a flag again replaces its value, so no flag is given twice), then any `extra`
/// arguments as given.
#[derive(Clone, Debug, Default)]
pub struct Solve {
    flags: Vec<(String, Option<String>)>,
    extra: Vec<String>,
    out: Option<PathBuf>,
}

impl Solve {
    /// The paper's problem: every default (100 s in steps of 0.01 s to `(0.1, 0.1, 0)`, a
    /// search of at most 1 024 starts).
    pub fn paper() -> Self {
        Self::default()
    }

    /// A problem `solve` answers in about 0.1 s: 10 s in steps of 0.1 s (100 steps) to
    /// `(0.01, 0.01, 0)`, one start.
    pub fn quick() -> Self {
        Self::paper()
            .horizon("10")
            .step("0.1")
            .target("0.01,0.01,0")
            .starts(1)
    }

    /// The figures' small problem: 10 s in steps of 0.01 s to `(0.02, 0.02, 0)`, two starts,
    /// angles in degrees.
    pub fn small() -> Self {
        Self::paper()
            .target("0.02,0.02,0")
            .horizon("10")
            .starts(2)
            .switch("degrees")
    }

    /// `--name value`.
    pub fn flag(mut self, name: &str, value: &str) -> Self {
        let (flag, value) = (format!("--{name}"), Some(value.to_string()));
        match self.flags.iter_mut().find(|(f, _)| *f == flag) {
            Some(f) => f.1 = value,
            None => self.flags.push((flag, value)),
        }
        self
    }

    /// `--name` (a switch), once.
    pub fn switch(mut self, name: &str) -> Self {
        let flag = format!("--{name}");
        if !self.flags.iter().any(|(f, _)| *f == flag) {
            self.flags.push((flag, None));
        }
        self
    }

    /// `--target X,Y,THETA`.
    pub fn target(self, xyz: &str) -> Self {
        self.flag("target", xyz)
    }

    /// `--horizon T`.
    pub fn horizon(self, t: &str) -> Self {
        self.flag("horizon", t)
    }

    /// `--step H`.
    pub fn step(self, h: &str) -> Self {
        self.flag("step", h)
    }

    /// `--starts N`.
    pub fn starts(self, n: impl ToString) -> Self {
        self.flag("starts", &n.to_string())
    }

    /// `--alpha0 A1,A2`.
    pub fn alpha0(self, a: &str) -> Self {
        self.flag("alpha0", a)
    }

    /// `--alpha-max A`.
    pub fn alpha_max(self, a: &str) -> Self {
        self.flag("alpha-max", a)
    }

    /// `--from COSTATE_JSON`.
    pub fn from(self, costate: &Path) -> Self {
        self.flag("from", arg(costate))
    }

    /// `--no-plots`.
    pub fn no_plots(self) -> Self {
        self.switch("no-plots")
    }

    /// `--force`.
    pub fn force(self) -> Self {
        self.switch("force")
    }

    /// `--out DIR`.
    pub fn out(mut self, dir: &Path) -> Self {
        self.out = Some(dir.to_path_buf());
        self.flag("out", arg(dir))
    }

    /// `extra` arguments after the others, as given.
    pub fn with(mut self, extra: &[&str]) -> Self {
        self.extra.extend(extra.iter().map(|a| a.to_string()));
        self
    }

    /// The command line after the binary's name: `solve`, the flags, the extra arguments.
    pub fn args(&self) -> Vec<&str> {
        let mut args = vec!["solve"];
        for (flag, value) in &self.flags {
            args.push(flag);
            args.extend(value.as_deref());
        }
        args.extend(self.extra.iter().map(String::as_str));
        args
    }

    /// Runs it within [`LIMIT`].
    pub fn run(&self) -> Output {
        self.run_within(LIMIT)
    }

    /// Runs it within `limit`.
    pub fn run_within(&self, limit: Duration) -> Output {
        sim_in(None, &self.args(), limit)
    }

    /// Runs it in `dir` within [`LIMIT`].
    pub fn run_in(&self, dir: &Path) -> Output {
        sim_in(Some(dir), &self.args(), LIMIT)
    }

    /// Runs it within `limit`, which must succeed; the report it wrote and its stderr.
    pub fn solved(&self, limit: Duration) -> (serde_json::Value, String) {
        let o = self.run_within(limit);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{:?}: {}",
            self.args(),
            stderr(&o)
        );
        (report(self.out.as_deref().expect("--out")), stderr(&o))
    }
}
