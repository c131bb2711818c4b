//! Material constants that cannot be right: a Young's modulus, a density or a specific
//! stiffness outside the range of structural solids gets a warning at `check`
//! (`vdl::material::unit_slip`) that names the likely unit slip. Foams and elastomers are real
//! and lie outside the range, so it is a warning, and `expect_unusual = true` in the
//! material silences it.
//!
//! The ranges. Ashby's modulus–density chart (M. F. Ashby, *Materials Selection in Mechanical
//! Design*, chapter "Material property charts", the E–ρ chart) lays the engineering classes
//! out on log axes: the chart's own lower edge is set by foams and elastomers, and the book
//! notes that very low density foams and gels fall below even that (gelatin about
//! 1e-5 GPa). The structural classes (metals, technical ceramics, glasses, polymers,
//! composites, woods along the grain) occupy a smaller box, and it is that box a vehicle
//! made of "a material" is expected to sit in. The bounds below are flexflight's choice of
//! that box, each with the materials that set it:
//!
//! * `E` from 0.1 GPa to 1200 GPa. The softest structural polymers (polyethylene) are a few
//!   tenths of a GPa; below 0.1 GPa lie elastomers and foams. Diamond, the stiffest solid,
//!   is about 1000 GPa.
//! * `rho` from 100 kg/m^3 to 23,000 kg/m^3. Balsa, the lightest structural wood, is about
//!   100-200 kg/m^3; below it lie foams and aerogels. Osmium, the densest element, is about
//!   22,600 kg/m^3: nothing denser exists.
//! * `E/rho` from 1e5 m^2/s^2 to 5e8 m^2/s^2 (a bar wave speed sqrt(E/rho) from 316 m/s to
//!   22 km/s). The low end is set by the softest polymers (0.2 GPa / 950 kg/m^3 = 2e5) and
//!   lead (14 GPa / 11,340 kg/m^3 = 1.2e6); the high end by diamond (about 1000 GPa /
//!   3500 kg/m^3 = 2.9e8). A specific stiffness outside this with `E` and `rho` each inside
//!   their own range is a slip of one of the two (70 GPa with 27,100 kg/m^3 is caught by
//!   the density; 0.2 GPa with 7850 kg/m^3 by the specific stiffness alone).
//!
//! The values that set the bounds are textbook figures, quoted for orientation, not read
//! from one source here; the bounds are deliberately wider than the materials that set
//! them, so that only a value off by a unit prefix (a factor of 10^3 or more) is questioned.
//! The issue's slip, a G10 fin with `E = 17 MPa` (meant: GPa) and `rho = 1850 kg/m^3`, has
//! `E` 6 times below the modulus bound and `E/rho` = 9.2e3 m^2/s^2, 11 times below the
//! specific-stiffness bound.

use crate::diagnostics::Diagnostic;
use crate::syntax::Span;

/// Young's modulus range of structural solids, Pa (see the module doc).
pub const E_RANGE: (f64, f64) = (0.1e9, 1200e9);
/// Density range of structural solids, kg/m^3.
pub const RHO_RANGE: (f64, f64) = (100.0, 23_000.0);
/// Specific-stiffness range E/rho of structural solids, m^2/s^2.
pub const SPECIFIC_RANGE: (f64, f64) = (1e5, 5e8);

fn inside(x: f64, r: (f64, f64)) -> bool {
    x >= r.0 && x <= r.1
}

/// The likely slip as a factor to apply to `E` and `rho`: the smallest change of unit prefix
/// (10^±3, then 10^±6, 10^±9) of one of the two that brings `E`, `rho` and `E/rho` all into
/// range; `None` when no single prefix change does.
pub fn likely_slip(e: f64, rho: f64) -> Option<(f64, f64)> {
    let ok = |e: f64, rho: f64| {
        inside(e, E_RANGE) && inside(rho, RHO_RANGE) && inside(e / rho, SPECIFIC_RANGE)
    };
    for k in [1e3, 1e-3, 1e6, 1e-6, 1e9, 1e-9] {
        if ok(e * k, rho) {
            return Some((k, 1.0));
        }
        if ok(e, rho * k) {
            return Some((1.0, k));
        }
    }
    None
}

/// A pressure in the largest of Pa, kPa, MPa, GPa that keeps the number >= 1.
pub fn pressure_text(p: f64) -> String {
    let (v, u) = if p.abs() >= 1e9 {
        (p / 1e9, "GPa")
    } else if p.abs() >= 1e6 {
        (p / 1e6, "MPa")
    } else if p.abs() >= 1e3 {
        (p / 1e3, "kPa")
    } else {
        (p, "Pa")
    };
    format!("{} {u}", short(v))
}

/// A number with at most 4 significant digits, without trailing zeros.
pub(crate) fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The warning for a material whose constants lie outside the ranges (or `None`).
/// `name` is the material's name, the spans are those of the `E` and `rho` values.
pub fn material_warning(
    name: &str,
    e: (f64, Span),
    rho: (f64, Span),
    header: Span,
) -> Option<Diagnostic> {
    let (ev, es) = e;
    let (rv, rs) = rho;
    let specific = ev / rv;
    let mut findings = Vec::new();
    let mut d = Diagnostic::warning("vdl::material::unit_slip", String::new());
    if !inside(ev, E_RANGE) {
        findings.push(format!(
            "E = {} is {} the range of structural solids (0.1 to 1200 GPa)",
            pressure_text(ev),
            if ev < E_RANGE.0 { "below" } else { "above" }
        ));
        d = d.label(es, "Young's modulus");
    }
    if !inside(rv, RHO_RANGE) {
        findings.push(format!(
            "rho = {} kg/m^3 is {} the range of solids (100 to 23,000 kg/m^3)",
            short(rv),
            if rv < RHO_RANGE.0 { "below" } else { "above" }
        ));
        d = d.label(rs, "density");
    }
    if !inside(specific, SPECIFIC_RANGE) {
        findings.push(format!(
            "E/rho = {:.3e} m^2/s^2 is {} the range of structural solids (1e5 to 5e8 m^2/s^2)",
            specific,
            if specific < SPECIFIC_RANGE.0 {
                "below"
            } else {
                "above"
            }
        ));
        if d.labels.is_empty() {
            d = d.label(es, "Young's modulus").label(rs, "density");
        }
    }
    if findings.is_empty() {
        return None;
    }
    let guess = match likely_slip(ev, rv) {
        Some((ke, _)) if ke != 1.0 => format!("did you mean E = {}?", pressure_text(ev * ke)),
        Some((_, kr)) => format!("did you mean rho = {} kg/m^3?", short(rv * kr)),
        None => "check the units of E and rho".to_string(),
    };
    d.message = format!("material `{name}`: {}: {guess}", findings.join("; "));
    Some(d.label(header, "this material").with_help(
        "foams and elastomers lie outside these ranges: if the material is one, write \
         `expect_unusual = true` in it to silence this warning",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issues_slip_is_caught_and_named() {
        // G10 with E in MPa instead of GPa.
        assert_eq!(likely_slip(17e6, 1850.0), Some((1e3, 1.0)));
        assert_eq!(pressure_text(17e9), "17 GPa");
        // Density in g/cm^3 written as kg/m^3.
        assert_eq!(likely_slip(70e9, 2.71), Some((1.0, 1e3)));
        // Modulus in MPa written as GPa.
        assert_eq!(likely_slip(70e12, 2710.0), Some((1e-3, 1.0)));
    }
}
