//! Number parsing shared by the readers: Fortran/NASTRAN real numbers.

/// Parses a NASTRAN/Fortran real: `1.5`, `1.5E+3`, `1.5D+03`, `1.5-3` (implicit exponent,
/// = 1.5e-3), `-.5+2`, `1.`. Returns `None` if the text is not a number. NaN and infinity
/// spelled out (`nan`, `inf`) parse, so that the caller can report them as non-finite.
pub fn parse_nastran_real(text: &str) -> Option<f64> {
    let s = text.trim();
    if s.is_empty() {
        return None;
    }
    let mut t: String = s.replace(['D', 'd'], "E");
    if !t.contains(['E', 'e']) {
        // Implicit exponent: a sign after the first character that follows a digit or '.'.
        let bytes = t.as_bytes();
        if let Some(pos) = (1..bytes.len()).find(|&k| {
            (bytes[k] == b'+' || bytes[k] == b'-')
                && (bytes[k - 1].is_ascii_digit() || bytes[k - 1] == b'.')
        }) {
            t.insert(pos, 'E');
        }
    }
    let lower = t.to_ascii_lowercase();
    let plain = lower.trim_start_matches(['+', '-']);
    if plain.starts_with("nan") || plain.starts_with("inf") {
        return lower.parse::<f64>().ok();
    }
    if !plain.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        return None;
    }
    t.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::parse_nastran_real as p;

    #[test]
    fn fortran_exponents() {
        assert_eq!(p("1.0D+00"), Some(1.0));
        assert_eq!(p("1.0-3"), Some(1.0e-3));
        assert_eq!(p("-2.5+2"), Some(-250.0));
        assert_eq!(p(" 1. "), Some(1.0));
        assert_eq!(p(".5E1"), Some(5.0));
        assert_eq!(p("5.9496052872D+08"), Some(5.9496052872e8));
        assert_eq!(p("-4.992800582D+07"), Some(-4.992800582e7));
        assert_eq!(p("abc"), None);
        assert_eq!(p("1.2.3"), None);
        assert_eq!(p(""), None);
        assert!(p("NaN").is_some_and(f64::is_nan));
    }
}
