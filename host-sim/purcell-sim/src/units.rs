//! The one parser of the number flags (no clap: the command line's parser calls it): a value or a comma list whose entries are lengths
//! (metres, a plain number) or angles (radians, plain or with `rad`; degrees with `deg`:
//! `30deg` is `30·π/180`), refused with the flag's name (exit 2) when a length carries an
//! angle unit, an entry is no number, or the list has the wrong length.

/// What an entry of a number flag measures, which fixes the unit suffixes it takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// A length in metres: a plain number.
    Length,
    /// An angle: radians as a plain number or with `rad`, degrees with `deg`.
    Angle,
}

/// The number of entry `text` of kind `q` as typed, and whether it is in degrees; why
/// not, for a message (a length with an angle unit).
pub fn split_unit(text: &str, q: Quantity) -> Result<(&str, bool), String> {
    let text = text.trim();
    let (number, degrees) = match (text.strip_suffix("deg"), text.strip_suffix("rad")) {
        (Some(n), _) => (n, true),
        (_, Some(n)) => (n, false),
        _ => (text, false),
    };
    if q == Quantity::Length && number.len() != text.len() {
        return Err(format!(
            "{text:?} is a length, in metres: it takes no angle unit (deg or rad)"
        ));
    }
    Ok((number.trim_end(), degrees))
}

/// `value` in radians if it is in `degrees`, as is otherwise.
pub fn radians(value: f64, degrees: bool) -> f64 {
    if degrees { value.to_radians() } else { value }
}

/// One entry of kind `q` in SI units (radians for an angle); why not, for a message.
fn quantity(text: &str, q: Quantity) -> Result<f64, String> {
    let (number, degrees) = split_unit(text, q)?;
    let value: f64 = number.parse().map_err(|_| {
        format!(
            "{:?} is not a number{}",
            text.trim(),
            match q {
                Quantity::Length => " (a length in metres)",
                Quantity::Angle => " (an angle: radians, or degrees with deg, e.g. 30deg)",
            }
        )
    })?;
    Ok(radians(value, degrees))
}

/// The parser of a number flag of `N` comma-separated entries of kinds `.0` (one entry for a
/// scalar flag), giving the values in SI units (the command line's clap parser).
#[derive(Clone, Copy, Debug)]
pub struct List<const N: usize>(pub [Quantity; N]);

/// `N` lengths in metres.
pub const fn lengths<const N: usize>() -> List<N> {
    List([Quantity::Length; N])
}

/// `N` angles.
pub const fn angles<const N: usize>() -> List<N> {
    List([Quantity::Angle; N])
}

impl<const N: usize> List<N> {
    /// The values of `text` (the flag's value), or the message naming flag `name`.
    pub fn parse(&self, name: &str, text: &str) -> Result<[f64; N], String> {
        let entries: Vec<&str> = text.split(',').collect();
        if entries.len() != N {
            return Err(format!(
                "--{name} takes {N} comma-separated {} (got {})",
                if N == 1 { "number" } else { "numbers" },
                entries.len()
            ));
        }
        let mut values = [0.0; N];
        for ((v, entry), q) in values.iter_mut().zip(entries).zip(self.0) {
            *v = quantity(entry, q).map_err(|e| format!("--{name}: {e}"))?;
        }
        Ok(values)
    }
}

/// `theta` modulo 2π in `]−π, π]` (as given if it is there already; NaN if not finite).
pub fn wrap_angle(theta: f64) -> f64 {
    use core::f64::consts::{PI, TAU};
    if -PI < theta && theta <= PI {
        return theta;
    }
    let t = theta.rem_euclid(TAU);
    if t > PI { t - TAU } else { t }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_take_degrees_and_radians() {
        let a = angles::<2>();
        assert_eq!(a.parse("alpha0", "0.5,-0.25rad"), Ok([0.5, -0.25]));
        let [d, r] = a.parse("alpha0", "30deg,-90 deg").unwrap();
        assert_eq!(d, 30f64.to_radians());
        assert_eq!(r, -core::f64::consts::FRAC_PI_2);
    }

    #[test]
    fn lengths_refuse_angle_units_and_lists_their_length() {
        let e = lengths::<3>().parse("links", "1,1deg,1").unwrap_err();
        assert!(e.contains("--links") && e.contains("metres"), "{e}");
        let e = lengths::<3>().parse("links", "1,1").unwrap_err();
        assert_eq!(e, "--links takes 3 comma-separated numbers (got 2)");
        let e = angles::<1>().parse("alpha-max", "ten").unwrap_err();
        assert!(e.contains("30deg"), "{e}");
    }
}
