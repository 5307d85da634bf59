//! Numbers as text in the data files (`stats.csv`, `sweep.csv`, `study.csv`,
//! OBJ surfaces): the shortest text that reads back to the same number.
//!
//! The rule: of Rust's two shortest round-trip forms, the plain one
//! (`format!("{x}")`) and the exponent one (`format!("{x:e}")`), the shorter
//! is written; on a tie the plain one. So `0.5` stays `0.5`, `1500.0` is
//! `1500` (a whole number has no `.0`), `15000.0` is `15000`, `150000.0` is
//! `1.5e5`, and `2.566835632933362e-13` is written so, not as
//! `0.0000000000002566835632933362`. Both forms hold the fewest significant
//! digits that parse back to exactly the same value, so the choice changes
//! only where the decimal point is written. NaN is `NaN`, the infinities
//! `inf` and `-inf`, negative zero `-0` (what Rust's `Display` writes, and
//! what `str::parse` reads back).

use std::fmt::{Display, LowerExp};

/// `x` as the shorter of its plain and its exponent form (the plain one on
/// a tie); both round-trip exactly. For `f64` and `f32`.
pub fn format_number<T: Display + LowerExp>(x: T) -> String {
    let plain = x.to_string();
    let exponent = format!("{x:e}");
    if exponent.len() < plain.len() {
        exponent
    } else {
        plain
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_examples_of_the_rule() {
        for (x, text) in [
            (2.566835632933362e-13, "2.566835632933362e-13"),
            (0.5, "0.5"),
            (1500.0, "1500"),
            (15000.0, "15000"),
            (150000.0, "1.5e5"),
            (1e6, "1e6"),
            (0.01, "0.01"),
            (0.001, "1e-3"),
            (0.0025, "0.0025"),
            (0.0001, "1e-4"),
            (-0.25, "-0.25"),
            (-3.0e-9, "-3e-9"),
            (0.0, "0"),
            (-0.0, "-0"),
            (1.0 / 3.0, "0.3333333333333333"),
            (f64::MAX, "1.7976931348623157e308"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (5e-324, "5e-324"),
        ] {
            assert_eq!(format_number(x), text, "{x:?}");
        }
    }

    #[test]
    fn nan_and_the_infinities_keep_rusts_names() {
        assert_eq!(format_number(f64::NAN), "NaN");
        assert_eq!(format_number(f64::INFINITY), "inf");
        assert_eq!(format_number(f64::NEG_INFINITY), "-inf");
        assert!(format_number(f64::NAN).parse::<f64>().unwrap().is_nan());
        assert_eq!("inf".parse::<f64>().unwrap(), f64::INFINITY);
        assert_eq!("-inf".parse::<f64>().unwrap(), f64::NEG_INFINITY);
    }

    #[test]
    fn f32_values_are_written_at_their_own_precision() {
        assert_eq!(format_number(0.1f32), "0.1");
        assert_eq!(format_number(1e-7f32), "1e-7");
        assert_eq!(format_number(1.2345678e-5f32), "1.2345678e-5");
    }

    /// Every value reads back bit for bit, and is never longer than either form.
    #[test]
    fn random_values_round_trip_exactly() {
        // xorshift64*: random bit patterns cover every exponent and sign.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_f491_4f6c_dd1d)
        };
        for _ in 0..200_000 {
            let bits = next();
            let x = f64::from_bits(bits);
            let text = format_number(x);
            let back: f64 = text.parse().unwrap();
            if x.is_nan() {
                assert!(back.is_nan(), "{text}");
            } else {
                assert_eq!(back.to_bits(), x.to_bits(), "{x:?} written as {text}");
            }
            assert!(text.len() <= x.to_string().len());
            assert!(text.len() <= format!("{x:e}").len());
            // No f64 needs more than 24 characters: sign, 17 digits, point, `e-308`.
            assert!(text.len() <= 24, "{text}");
            let y = f32::from_bits((bits >> 32) as u32);
            let back: f32 = format_number(y).parse().unwrap();
            assert!(y.is_nan() && back.is_nan() || back.to_bits() == y.to_bits());
        }
        // Values of ordinary size, as the data files mostly hold.
        for _ in 0..100_000 {
            let x = (next() as f64 / u64::MAX as f64 - 0.5) * 10f64.powi((next() % 40) as i32 - 20);
            let back: f64 = format_number(x).parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:?}");
        }
    }
}
