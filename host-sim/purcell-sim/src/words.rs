//! How each front end names what its user gives, so that one message serves both: the
//! command line's flags (`--alpha-max 0.8`, `--force`) and Python's keyword arguments
//! (`alpha_max=0.8`, `force=True`). The library layer's refusals and warnings are
//! [`Worded`]; their `Display` is the command line's wording.

use std::fmt::Display;

/// A front end: who reads the message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Front {
    /// `purcell-sim`: flags.
    Cli,
    /// The Python package: keyword arguments.
    Python,
}

impl Front {
    /// The parameter `name` (snake_case, as the library's fields): `--alpha-max` or
    /// `alpha_max`.
    pub fn arg(self, name: &str) -> String {
        match self {
            Front::Cli => format!("--{}", name.replace('_', "-")),
            Front::Python => name.to_string(),
        }
    }

    /// The parameter `name` given `value`: `--starts 2048` or `starts=2048`.
    pub fn given(self, name: &str, value: impl Display) -> String {
        match self {
            Front::Cli => format!("{} {value}", self.arg(name)),
            Front::Python => format!("{name}={value}"),
        }
    }

    /// The switch `name` turned on: `--force` or `force=True`.
    pub fn on(self, name: &str) -> String {
        match self {
            Front::Cli => self.arg(name),
            Front::Python => format!("{name}=True"),
        }
    }

    /// Numbers as the front end writes a list of them: `0.1,0,1e-7` or `(0.1, 0.0, 1e-07)`
    /// (Python's repr of a tuple of floats).
    pub fn list(self, values: &[f64]) -> String {
        match self {
            Front::Cli => values
                .iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(","),
            Front::Python => {
                let items: Vec<String> = values.iter().map(|&v| python_float(v)).collect();
                format!("({})", items.join(", "))
            }
        }
    }
}

/// A float as Python's `repr` writes it (`0.0`, `1e-07`, `1.5e+20`, `inf`, `nan`).
fn python_float(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            "nan"
        } else if v > 0.0 {
            "inf"
        } else {
            "-inf"
        }
        .into();
    }
    let a = v.abs();
    if a != 0.0 && !(1e-4..1e16).contains(&a) {
        // Rust's `{:e}` is the shortest round-trip mantissa, as Python's repr.
        let s = format!("{v:e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let e: i32 = e.parse().unwrap_or(0);
        return format!("{m}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs());
    }
    format!("{v:?}")
}

/// A message worded for a front end.
pub trait Worded {
    /// The message for `front`.
    fn words(&self, front: Front) -> String;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_front_names_parameters_its_own_way() {
        assert_eq!(Front::Cli.arg("alpha_max"), "--alpha-max");
        assert_eq!(Front::Python.arg("alpha_max"), "alpha_max");
        assert_eq!(Front::Cli.given("starts", 2048), "--starts 2048");
        assert_eq!(Front::Python.given("starts", 2048), "starts=2048");
        assert_eq!(Front::Cli.on("force"), "--force");
        assert_eq!(Front::Python.on("force"), "force=True");
        assert_eq!(Front::Cli.list(&[0.1, 0.0, 1e-7]), "0.1,0,0.0000001");
        assert_eq!(Front::Python.list(&[0.1, 0.0, 1e-7]), "(0.1, 0.0, 1e-07)");
        assert_eq!(Front::Python.list(&[1.5e20, -2.0]), "(1.5e+20, -2.0)");
    }
}
