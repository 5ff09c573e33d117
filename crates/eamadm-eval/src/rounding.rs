//! Numbers as text, rounded to the digits they can support: what the report's tables and the
//! margins' reasons print (`eamadm::margins` states a margin with [`format_fixed`]).
//!
//! ```
//! use eamadm_eval::rounding::{decimals_for, format_fixed};
//!
//! assert_eq!(format_fixed(-0.0001, 2), "0.00"); // never a negative zero
//! assert_eq!(format_fixed(1.796_1, decimals_for(1.796_1, 4)), "1.796");
//! assert_eq!(decimals_for(1234.5, 3), 0);
//! ```

/// Most decimals any number in the report gets.
const MAX_DECIMALS: i32 = 6;

/// Formats `value` with `decimals` decimals, never printing a negative zero.
pub fn format_fixed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => text,
    }
}

/// `value` rounded to `digits` significant digits (at least 1), in its shortest form: what the
/// fixtures store (`cargo xtask regen-fixtures`, six digits), so a change in the last bits of a
/// float does not change a committed file. Zero (either sign) is `0`.
#[must_use]
pub fn round_significant(value: f64, digits: usize) -> String {
    let rounded: f64 = format!("{value:.prec$e}", prec = digits.max(1) - 1)
        .parse()
        .unwrap_or(value);
    if rounded == 0.0 {
        "0".to_owned()
    } else {
        rounded.to_string()
    }
}

/// Decimals that show `value` to `significant` significant digits (none for large values).
pub fn decimals_for(value: f64, significant: i32) -> usize {
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let magnitude = value.abs().log10().floor() as i32;
    (significant - 1 - magnitude).clamp(0, MAX_DECIMALS) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_rounded_to_significant_digits_in_their_shortest_form() {
        assert_eq!(round_significant(155.123_456_7, 6), "155.123");
        assert_eq!(round_significant(-0.000_123_456_78, 6), "-0.000123457");
        assert_eq!(round_significant(-0.0, 6), "0");
        assert_eq!(
            round_significant(1e-30, 6),
            "0.000000000000000000000000000001"
        );
        assert_eq!(round_significant(2.0, 6), "2");
        assert_eq!(round_significant(0.987, 1), "1");
    }
}
