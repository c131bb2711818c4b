//! The float text of `history.csv`: the shortest round-trip form, laid out as Rust's
//! `{}` for `1e-4 <= |v| < 1e15` (and zero) and `{:e}` outside that range, written from the
//! shortest digits of [`zmij`] (Schubfach, R. Giulietti 2020) instead of `core::fmt`
//! (Grisu with a Dragon fallback), several times faster. Both produce a shortest digit
//! string that reads back to the same double and, among those, the one closest to it. They
//! differ only in an exact tie between two shortest candidates, which happens where the
//! spacing of doubles is a multiple of the last digit's unit (e.g. 1000000000000000.25
//! between "...0.2" and "...0.3", only for |v| above about 1e14 or in the 17th digit):
//! `core::fmt` rounds the tie up, Schubfach to the even digit. Both read back to the same
//! number. Tests: a million random bit patterns, every power of two and of ten, the
//! neighbours of the range limits and the special values read back to the same bits, have
//! the layout and the number of digits of `format!`, and equal its bytes except in such a
//! tie (the last digit one apart).

use std::fmt::Write;

/// Append `v` as [`std::fmt`] would with the rule above.
pub fn push_shortest(out: &mut String, v: f64, buf: &mut zmij::Buffer) {
    let a = v.abs();
    if !v.is_finite() || a == 0.0 {
        // "NaN", "inf", "-inf", "0", "-0": rare, left to core::fmt.
        if a != 0.0 && !(1e-4..1e15).contains(&a) {
            let _ = write!(out, "{v:e}");
        } else {
            let _ = write!(out, "{v}");
        }
        return;
    }
    let text = buf.format_finite(v);
    if (1e-4..1e15).contains(&a) {
        // zmij writes fixed notation for decimal exponents -5..=15 (`FIXED_DEC_EXP`),
        // which covers this range: the text of `{}` but for the ".0" of an integer (the
        // shortest digits never end in another zero).
        out.push_str(text.strip_suffix(".0").unwrap_or(text));
        return;
    }
    // The exponent sits in the last five bytes ("e-324" at most): search from the end.
    if let Some(i) = text.bytes().rposition(|b| b == b'e') {
        // Exponent form: "1.5e-7" as `{:e}`; "1e+20" is `{:e}`'s "1e20".
        let (mantissa, exponent) = text.split_at(i + 1);
        out.push_str(mantissa);
        out.push_str(exponent.strip_prefix('+').unwrap_or(exponent));
        return;
    }
    // Fixed text outside the range (decimal exponent -5 or 15): re-laid out from the digits.
    let (negative, body) = match text.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, text),
    };
    // Split into the significant digits and the decimal exponent of the first one:
    // v = d1.d2d3... x 10^exp.
    let (mantissa, exp_part) = match body.find('e') {
        Some(i) => (&body[..i], body[i + 1..].parse::<i32>().unwrap_or(0)),
        None => (body, 0),
    };
    let mut digits = [0u8; 40];
    let mut count = 0usize;
    let mut point = None;
    for (i, c) in mantissa.bytes().enumerate() {
        if c == b'.' {
            point = Some(i);
        } else if count < digits.len() {
            digits[count] = c;
            count += 1;
        }
    }
    let int_len = point.unwrap_or(mantissa.len()) as i32;
    // Strip leading zeros (0.00123) and trailing zeros (123.0, 1000.0).
    let mut first = 0;
    while first < count && digits[first] == b'0' {
        first += 1;
    }
    let mut last = count;
    while last > first && digits[last - 1] == b'0' {
        last -= 1;
    }
    let sig = &digits[first..last];
    // The first significant digit sits at position `int_len - 1 - first` of the mantissa.
    let exp = exp_part + int_len - 1 - first as i32;
    if negative {
        out.push('-');
    }
    // Digits are ASCII by construction.
    let sig = std::str::from_utf8(sig).unwrap_or("0");
    if (1e-4..1e15).contains(&a) {
        // Plain decimal, as `{}`: no exponent, no trailing ".0".
        if exp < 0 {
            out.push_str("0.");
            for _ in 0..(-exp - 1) {
                out.push('0');
            }
            out.push_str(sig);
        } else {
            let int_digits = exp as usize + 1;
            if sig.len() <= int_digits {
                out.push_str(sig);
                for _ in sig.len()..int_digits {
                    out.push('0');
                }
            } else {
                out.push_str(&sig[..int_digits]);
                out.push('.');
                out.push_str(&sig[int_digits..]);
            }
        }
    } else {
        // Exponent form, as `{:e}`: "1e-7", "1.25e20".
        out.push_str(&sig[..1]);
        if sig.len() > 1 {
            out.push('.');
            out.push_str(&sig[1..]);
        }
        let _ = write!(out, "e{exp}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(v: f64) -> String {
        let a = v.abs();
        if a != 0.0 && !(1e-4..1e15).contains(&a) {
            format!("{v:e}")
        } else {
            format!("{v}")
        }
    }

    fn ours(v: f64) -> String {
        let mut s = String::new();
        push_shortest(&mut s, v, &mut zmij::Buffer::new());
        s
    }

    /// Reads back to `v`, has `format!`'s layout and length, and equals it byte for byte
    /// unless both end in a shortest-digit tie (the last digit one apart). Returns whether
    /// the bytes differ.
    fn check(v: f64) -> bool {
        let (a, b) = (ours(v), reference(v));
        if a == b {
            return false;
        }
        let back: f64 = a.parse().expect("parses");
        assert_eq!(back.to_bits(), v.to_bits(), "{a} does not read back to {b}");
        assert_eq!(a.len(), b.len(), "{a} vs {b}");
        let (x, y) = (a.as_bytes(), b.as_bytes());
        let diff: Vec<usize> = (0..x.len()).filter(|&i| x[i] != y[i]).collect();
        assert_eq!(diff.len(), 1, "{a} vs {b}");
        let i = diff[0];
        assert!(
            x[i].is_ascii_digit() && (x[i] as i32 - y[i] as i32).abs() == 1,
            "{a} vs {b}"
        );
        // The digit after which the text ends or the exponent starts: the last one.
        assert!(i + 1 == x.len() || x[i + 1] == b'e', "{a} vs {b}");
        true
    }

    #[test]
    fn random_bit_patterns_read_back_and_format_as_core_fmt() {
        let mut rng = crate::testutil::XorShift64Star::new(0x9E37_79B9_7F4A_7C15);
        let mut ties = 0;
        let n = 1_000_000;
        for _ in 0..n {
            let v = f64::from_bits(rng.next_u64());
            ties += usize::from(check(v));
        }
        // Measured: 261 of the million (0.03 %) end in such a tie.
        assert!(ties < 500, "{ties} ties in {n}");
    }

    #[test]
    fn range_limits_powers_and_specials_format_as_core_fmt() {
        let mut values = vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            5e-324,
            1.0,
            0.1,
            0.3,
            2.0 / 3.0,
            123.0,
            1234.5,
            9.999e14,
        ];
        for limit in [1e-4_f64, 1e15] {
            let mut v = limit;
            for _ in 0..4 {
                v = f64::from_bits(v.to_bits() - 1);
            }
            for _ in 0..8 {
                values.push(v);
                values.push(-v);
                v = f64::from_bits(v.to_bits() + 1);
            }
        }
        for e in -1074..=1023 {
            values.push(2f64.powi(e));
        }
        for e in -323..=308 {
            values.push(format!("1e{e}").parse().unwrap());
            values.push(format!("9.87654321e{e}").parse().unwrap());
        }
        for v in values {
            if v.is_nan() {
                assert_eq!(ours(v), "NaN");
            } else {
                check(v);
            }
        }
        // The tie of the module doc.
        assert_eq!(ours(1e15 + 0.25), "1.0000000000000002e15");
        assert_eq!(reference(1e15 + 0.25), "1.0000000000000003e15");
    }
}
