//! [`Shown`]: a number as an error message prints it.
//!
//! Rust's `{}` never switches to scientific notation, so a coordinate of `1e300` given by
//! mistake printed as 301 digits. Messages that show a user's number wrap it in [`Shown`].

use std::fmt;

/// Moderate magnitudes print in plain notation (`{}` or `{:.p}`); below [`Shown::SMALL`]
/// (but not 0) and from [`Shown::LARGE`] on, in scientific notation (`{:e}` or `{:.pe}`).
/// NaN and ±∞ print as Rust prints them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown(pub f64);

impl Shown {
    /// The least magnitude printed in plain notation.
    pub const SMALL: f64 = 1e-4;
    /// The least magnitude printed in scientific notation.
    pub const LARGE: f64 = 1e9;
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // `+ 0.0` prints a negative zero as 0 (issue 56, D18: "-0.0000 m").
        let v = self.0 + 0.0;
        let plain = v == 0.0 || !v.is_finite() || (Self::SMALL..Self::LARGE).contains(&v.abs());
        match (plain, f.precision()) {
            (true, None) => write!(f, "{v}"),
            (true, Some(p)) => write!(f, "{v:.p$}"),
            (false, None) => write!(f, "{v:e}"),
            (false, Some(p)) => write!(f, "{v:.p$e}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Shown;

    #[test]
    fn moderate_numbers_print_plainly_and_extreme_ones_in_scientific_notation() {
        assert_eq!(Shown(0.25).to_string(), "0.25");
        assert_eq!(format!("{:.4}", Shown(-0.2)), "-0.2000");
        assert_eq!(Shown(0.0).to_string(), "0");
        // A negative zero is 0 (issue 56, D18: "-0.0000 m" for a start on the wall).
        assert_eq!(Shown(-0.0).to_string(), "0");
        assert_eq!(format!("{:.4}", Shown(-0.0)), "0.0000");
        assert_eq!(format!("{:.3}", Shown(1.4e-9)), "1.400e-9");
        assert_eq!(Shown(123_456_789.0).to_string(), "123456789");
        assert_eq!(Shown(1e300).to_string(), "1e300");
        assert_eq!(format!("{:.4}", Shown(-1e200)), "-1.0000e200");
        assert_eq!(Shown(3e-7).to_string(), "3e-7");
        assert_eq!(Shown(f64::NAN).to_string(), "NaN");
        assert_eq!(Shown(f64::NEG_INFINITY).to_string(), "-inf");
        // Never longer than a few dozen characters, whatever the magnitude.
        for e in -320..=308 {
            let v = 1.234_567_890_123_456_7 * 10f64.powi(e);
            assert!(Shown(v).to_string().len() <= 24, "{v}: {}", Shown(v));
        }
    }
}
