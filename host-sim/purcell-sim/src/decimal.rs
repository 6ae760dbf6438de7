//! Exact decimals for the outputs' keys: a time `t_k = k·h` and a grid value
//! `a + i·(b − a)/(n − 1)`, computed in decimal from the numbers as typed (or from their
//! shortest round-trip form), so that the text written is the decimal the user meant
//! (`99.99`, not `99.99000000000001`) and reads back as the very `f64` the program used
//! (the one nearest that decimal).

use std::fmt;

/// Most decimal places kept (beyond, a value is not the short decimal a user types).
const MAX_SCALE: u32 = 30;

/// The decimal `digits · 10^(−scale)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decimal {
    digits: i128,
    scale: u32,
}

impl Decimal {
    /// A plain decimal as typed: `[+-]digits[.digits][e[+-]digits]` (`None` for anything
    /// else, or more than about 30 digits).
    pub fn parse(text: &str) -> Option<Self> {
        let (mantissa, exponent) = match text.split_once(['e', 'E']) {
            Some((m, e)) => (m, e.parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (negative, unsigned) = match mantissa.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, mantissa.strip_prefix('+').unwrap_or(mantissa)),
        };
        let (whole, fraction) = unsigned.split_once('.').unwrap_or((unsigned, ""));
        let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
        if whole.len() + fraction.len() == 0 || !all_digits(whole) || !all_digits(fraction) {
            return None;
        }
        let digits: i128 = format!("{whole}{fraction}").parse().ok()?;
        let scale = i64::try_from(fraction.len()).ok()? - i64::from(exponent);
        let d = if scale >= 0 {
            Decimal {
                digits,
                scale: u32::try_from(scale).ok()?,
            }
        } else {
            let up = 10i128.checked_pow(u32::try_from(-scale).ok()?)?;
            Decimal {
                digits: digits.checked_mul(up)?,
                scale: 0,
            }
        };
        let d = d.trimmed();
        (d.scale <= MAX_SCALE).then_some(if negative { d.negated() } else { d })
    }

    /// The shortest round-trip form of `x` (`None` if not finite or too long).
    pub fn of_f64(x: f64) -> Option<Self> {
        if !x.is_finite() {
            return None;
        }
        Self::parse(&x.to_string())
    }

    /// The `f64` nearest this decimal.
    pub fn to_f64(self) -> f64 {
        self.to_string().parse().unwrap_or(f64::NAN)
    }

    /// `k · self`, exactly (`None` on overflow).
    pub fn times(self, k: u64) -> Option<Self> {
        Some(Decimal {
            digits: self.digits.checked_mul(i128::from(k))?,
            scale: self.scale,
        })
    }

    /// `a + i·(b − a)/(n − 1)` (`a` for `n = 1`), exactly, if it is a decimal of at most
    /// 30 places (`None` otherwise: e.g. thirds).
    pub fn lerp(a: Self, b: Self, i: usize, n: usize) -> Option<Self> {
        if n <= 1 {
            return Some(a);
        }
        let scale = a.scale.max(b.scale);
        let (a, b) = (a.rescaled(scale)?, b.rescaled(scale)?);
        let (i, d) = (i128::try_from(i).ok()?, i128::try_from(n - 1).ok()?);
        // (a·(n−1) + i·(b − a)) / (n − 1), shifted by 10^t until the division is exact.
        let mut numerator = a
            .digits
            .checked_mul(d)?
            .checked_add(i.checked_mul(b.digits.checked_sub(a.digits)?)?)?;
        for t in 0..=MAX_SCALE - scale {
            if numerator % d == 0 {
                let exact = Decimal {
                    digits: numerator / d,
                    scale: scale + t,
                };
                return Some(exact.trimmed());
            }
            numerator = numerator.checked_mul(10)?;
        }
        None
    }

    /// The same value with `scale` places (`None` if fewer than it has, or on overflow).
    fn rescaled(self, scale: u32) -> Option<Self> {
        let up = 10i128.checked_pow(scale.checked_sub(self.scale)?)?;
        Some(Decimal {
            digits: self.digits.checked_mul(up)?,
            scale,
        })
    }

    /// Without trailing zero places.
    fn trimmed(mut self) -> Self {
        while self.scale > 0 && self.digits % 10 == 0 {
            self.digits /= 10;
            self.scale -= 1;
        }
        self
    }

    fn negated(self) -> Self {
        Decimal {
            digits: -self.digits,
            ..self
        }
    }
}

/// Plain notation, no trailing zero places: `99.99`, `-0.05`, `3`.
impl fmt::Display for Decimal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = self.trimmed();
        let sign = if d.digits < 0 { "-" } else { "" };
        let magnitude = d.digits.unsigned_abs().to_string();
        let places = d.scale as usize;
        if places == 0 {
            return write!(f, "{sign}{magnitude}");
        }
        let padded = format!("{magnitude:0>width$}", width = places + 1);
        let (whole, fraction) = padded.split_at(padded.len() - places);
        write!(f, "{sign}{whole}.{fraction}")
    }
}

/// The time `t_k = k·h` as text: exact in decimal from `h`'s shortest form (`99.99` for
/// `k = 9999`, `h = 0.01`), so that it reads back as the `f64` nearest `k·h`.
pub fn time(k: u64, h: f64) -> String {
    Decimal::of_f64(h)
        .and_then(|h| h.times(k))
        .map_or_else(|| (k as f64 * h).to_string(), |t| t.to_string())
}

/// The time `t_k` of [`time`] as a number: the `f64` nearest the decimal `k·h`.
pub fn time_value(k: u64, h: f64) -> f64 {
    time(k, h).parse().unwrap_or(k as f64 * h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_plain_decimals() {
        for (text, shown) in [
            ("0.1", "0.1"),
            ("-0.30", "-0.3"),
            ("+2", "2"),
            ("1e-3", "0.001"),
            ("2.5E1", "25"),
            (".5", "0.5"),
            ("0", "0"),
            ("-0.05", "-0.05"),
        ] {
            assert_eq!(Decimal::parse(text).unwrap().to_string(), shown, "{text}");
        }
        for bad in ["", "-", "1deg", "0x10", "1.2.3", "inf", "nan", "1e"] {
            assert_eq!(Decimal::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn times_are_exact_multiples() {
        assert_eq!(time(9999, 0.01), "99.99");
        assert_eq!(time_value(9999, 0.01), 99.99);
        assert_eq!(time(0, 0.01), "0");
        assert_eq!(time(3, 0.1), "0.3");
        assert_eq!(time(7, 1e-7), "0.0000007");
    }

    #[test]
    fn grid_values_are_the_decimals_meant() {
        let (a, b) = (
            Decimal::parse("-0.3").unwrap(),
            Decimal::parse("0.3").unwrap(),
        );
        let values: Vec<String> = (0..13)
            .map(|i| Decimal::lerp(a, b, i, 13).unwrap().to_string())
            .collect();
        assert_eq!(values[5], "-0.05");
        assert_eq!(values[7], "0.05");
        assert_eq!(values[8], "0.1");
        assert_eq!(values[12], "0.3");
        // Thirds are no decimal.
        let (zero, one) = (Decimal::parse("0").unwrap(), Decimal::parse("1").unwrap());
        assert_eq!(Decimal::lerp(zero, one, 1, 4), None);
        assert_eq!(Decimal::lerp(zero, one, 1, 1), Some(zero));
    }
}
