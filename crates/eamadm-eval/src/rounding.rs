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

/// Decimals that show `value` to `significant` significant digits (none for large values).
pub fn decimals_for(value: f64, significant: i32) -> usize {
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let magnitude = value.abs().log10().floor() as i32;
    (significant - 1 - magnitude).clamp(0, MAX_DECIMALS) as usize
}
