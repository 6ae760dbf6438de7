//! The clap side of the number flags' parser ([`crate::units`]): a flag's value parsed by
//! [`List`], refused with clap's usage error (exit 2).

pub use crate::units::{List, Quantity, angles, lengths};
use clap::builder::TypedValueParser;
use std::ffi::OsStr;

/// One angle, as a scalar flag.
pub fn angle() -> impl TypedValueParser<Value = f64> {
    List([Quantity::Angle]).map(|[a]| a)
}

impl<const N: usize> TypedValueParser for List<N> {
    type Value = [f64; N];

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<[f64; N], clap::Error> {
        let name = arg.and_then(|a| a.get_long()).unwrap_or("value");
        let parsed = match value.to_str() {
            Some(text) => self.parse(name, text),
            None => Err(format!("--{name}: not UTF-8")),
        };
        parsed.map_err(|message| {
            clap::Error::raw(clap::error::ErrorKind::ValueValidation, message + "\n").with_cmd(cmd)
        })
    }
}

/// A running cost by its name (`effort`, `power`: [`purcell_solver::problem::Cost::name`]).
pub fn cost(text: &str) -> Result<purcell_solver::problem::Cost, String> {
    use purcell_solver::problem::Cost;
    Cost::named(text).ok_or_else(|| {
        let names: Vec<_> = Cost::ALL.iter().map(|c| c.name()).collect();
        format!("unknown cost {text:?} (one of {})", names.join(", "))
    })
}
