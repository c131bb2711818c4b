//! Transitions and boat tails of the generated body (`body { transition { ... } }`, issue 34):
//! the profile of a body of more than one diameter, its checking, and the integrals the
//! structure generator and the built-in aerodynamics take from it.
//!
//! # Profile
//!
//! A transition joins the section ahead of it (the nose's base diameter `diameter`, or the
//! aft diameter of the previous transition) to a section of another diameter behind it; the
//! body keeps the aft diameter until the next transition or its tail. Its fore end lies at
//! `s0 = -fore_station` aft of the nose tip, its length is `l`, its fore and aft radii
//! `r_f`, `r_a`. Its shape is one of the nose shapes (`check::nose`), applied as OpenRocket
//! applies them to a transition (`Transition.getRadius`, core/src/main/java/info/openrocket/
//! core/rocketcomponent/Transition.java; Niskanen 2009, sec. 3.1.1): the nose profile of base
//! radius `|r_a - r_f|` and length `l` is added to the smaller radius, its tip at the smaller
//! end. With `u = s - s0`:
//!
//! - growing (`r_f < r_a`, a shoulder): `r(u) = r_f + p(u; r_a - r_f, l)`;
//! - shrinking (`r_f > r_a`, a boat tail): `r(u) = r_a + p(l - u; r_f - r_a, l)`,
//!
//! `p(s; R, L)` the nose profile of `check::nose`. The conical shape is the frustum.
//! OpenRocket's "clipped" variants (the nose profile cut where its radius reaches the smaller
//! one) are not offered: the importer says so where a design uses one.
//!
//! # Wall and integrals
//!
//! The transition is a shell of revolution of the body's wall `t` measured radially, as the
//! nose and the tube are (`structure::generate::beam::section_at`): the section at `s` is the
//! annulus between `r(s)` and `r(s) - t` (the checker keeps `t` below both radii, so the
//! annulus never closes). Integrals over it use [`NoseShape::rule`] in the nose coordinate
//! (`u` from the small end), which makes the profiles' power-law ends smooth; on the frustum
//! the integrands are polynomials and the structure generator integrates them in closed form.

use serde::{Deserialize, Serialize};

use super::nose::NoseShape;

/// A transition's geometry in plain numbers (module doc): `start` m aft of the nose tip,
/// `length`, fore and aft outer radii, shape.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TransitionGeom {
    pub start: f64,
    pub length: f64,
    pub r_fore: f64,
    pub r_aft: f64,
    pub shape: NoseShape,
}

/// Panels of [`NoseShape::rule`] for the transition's integrals (5 points each).
const PANELS: usize = 64;

impl TransitionGeom {
    /// Distance of the aft end aft of the nose tip, m.
    pub fn end(&self) -> f64 {
        self.start + self.length
    }

    /// Whether it narrows (a boat tail or a reducer).
    pub fn narrows(&self) -> bool {
        self.r_aft < self.r_fore
    }

    /// Outer radius at `s` aft of the nose tip (clamped to the transition; module doc).
    pub fn radius(&self, s: f64) -> f64 {
        let l = self.length;
        let u = (s - self.start).clamp(0.0, l);
        if self.shape.is_conical() {
            return self.r_fore + (self.r_aft - self.r_fore) * u / l;
        }
        if self.narrows() {
            self.r_aft + self.shape.radius(l - u, self.r_fore - self.r_aft, l)
        } else {
            self.r_fore + self.shape.radius(u, self.r_aft - self.r_fore, l)
        }
    }

    /// Quadrature points and weights `(s, w)` for `∫_a^b g(s) ds`, `start <= a < b <= end`,
    /// `s` aft of the nose tip: [`NoseShape::rule`] in the nose coordinate from the small end.
    pub fn rule(&self, a: f64, b: f64, panels: usize) -> Vec<(f64, f64)> {
        let l = self.length;
        if self.narrows() {
            let e = self.end();
            NoseShape::rule(l, e - b, e - a, panels)
                .into_iter()
                .map(|(v, w)| (e - v, w))
                .collect()
        } else {
            NoseShape::rule(l, a - self.start, b - self.start, panels)
                .into_iter()
                .map(|(u, w)| (self.start + u, w))
                .collect()
        }
    }

    /// `∫_a^b f(s, r(s)) ds` by [`Self::rule`].
    pub fn integrate(&self, a: f64, b: f64, f: impl Fn(f64, f64) -> f64) -> f64 {
        self.rule(a, b, PANELS)
            .into_iter()
            .map(|(s, w)| w * f(s, self.radius(s)))
            .sum()
    }

    /// Volume `∫ pi r^2 ds` (the frustum's `pi l (r_f^2 + r_f r_a + r_a^2)/3` in closed form).
    pub fn volume(&self) -> f64 {
        let pi = std::f64::consts::PI;
        if self.shape.is_conical() {
            let (a, b) = (self.r_fore, self.r_aft);
            return pi * self.length * (a * a + a * b + b * b) / 3.0;
        }
        self.integrate(self.start, self.end(), |_, r| pi * r * r)
    }

    /// Planform (side-view) area `∫ 2 r ds` and its centroid, m aft of the nose tip.
    pub fn planform(&self) -> (f64, f64) {
        if self.shape.is_conical() {
            let (a, b, l) = (self.r_fore, self.r_aft, self.length);
            let area = (a + b) * l;
            // Trapezoid of parallel sides 2a (fore) and 2b (aft): centroid l (a + 2b)/(3(a + b)).
            return (area, self.start + l * (a + 2.0 * b) / (3.0 * (a + b)));
        }
        let a = self.integrate(self.start, self.end(), |_, r| 2.0 * r);
        let m = self.integrate(self.start, self.end(), |s, r| 2.0 * r * s);
        (a, m / a)
    }

    /// Wetted area `∫ 2 pi r sqrt(1 + r'^2) ds` (the frustum's `pi (r_f + r_a) slant`).
    pub fn wetted_area(&self) -> f64 {
        let pi = std::f64::consts::PI;
        let (a, b, l) = (self.r_fore, self.r_aft, self.length);
        if self.shape.is_conical() {
            return pi * (a + b) * ((b - a) * (b - a) + l * l).sqrt();
        }
        let h = 1e-6 * l;
        self.integrate(self.start, self.end(), |s, r| {
            let (p, q) = ((s - h).max(self.start), (s + h).min(self.end()));
            let slope = (self.radius(q) - self.radius(p)) / (q - p);
            2.0 * pi * r * (1.0 + slope * slope).sqrt()
        })
    }

    /// Barrowman's potential normal force of the transition (slender-body theory; Barrowman,
    /// "The practical calculation of the aerodynamic characteristics of slender finned
    /// vehicles", M.Sc. thesis, Catholic University of America, 1967, sec. 3 (eq. 3-36 ff.);
    /// Niskanen 2009, sec. 3.2.1, eqs. 3.19-3.27 for any body component):
    /// `C_Nα = 2 (A(l) - A(0))/A_ref` per rad, at `X = (l A(l) - V)/(A(l) - A(0))` aft of its
    /// fore end. Returns `(A(l) - A(0), centre of pressure m aft of the nose tip)`; the area
    /// difference is negative for a boat tail: a negative normal force aft of the others, which
    /// moves the vehicle's centre of pressure forward. On the frustum `X = l/3 (1 + (1 - ρ)/(1 - ρ^2))`,
    /// `ρ = d_f/d_a`, Barrowman's closed form (`tests` check the two agree).
    pub fn potential(&self) -> (f64, f64) {
        let pi = std::f64::consts::PI;
        let (a0, a1) = (pi * self.r_fore.powi(2), pi * self.r_aft.powi(2));
        let x = (self.length * a1 - self.volume()) / (a1 - a0);
        (a1 - a0, self.start + x)
    }
}

/// The outer radius at `s` aft of the nose tip of a body whose section behind the nose has
/// radius `r0` and which carries `transitions` (sorted, disjoint, as the checker leaves
/// them), outside the nose.
pub fn section_radius(r0: f64, transitions: &[TransitionGeom], s: f64) -> f64 {
    let mut r = r0;
    for t in transitions {
        if s < t.start {
            break;
        }
        if s <= t.end() {
            return t.radius(s);
        }
        r = t.r_aft;
    }
    r
}

/// The largest outer diameter of such a body (the default reference length).
pub fn max_diameter(d0: f64, transitions: &[TransitionGeom]) -> f64 {
    transitions
        .iter()
        .fold(d0, |d, t| d.max(2.0 * t.r_fore).max(2.0 * t.r_aft))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(shape: NoseShape, rf: f64, ra: f64) -> TransitionGeom {
        TransitionGeom {
            start: 1.0,
            length: 0.2,
            r_fore: rf,
            r_aft: ra,
            shape,
        }
    }

    #[test]
    fn frustum_centre_of_pressure_is_barrowmans_closed_form() {
        for (rf, ra) in [(0.05, 0.04), (0.04, 0.05), (0.05, 0.02)] {
            let g = t(NoseShape::Conical, rf, ra);
            let rho = rf / ra;
            let x = g.length / 3.0 * (1.0 + (1.0 - rho) / (1.0 - rho * rho));
            let (_, cp) = g.potential();
            assert!(((cp - g.start) - x).abs() < 1e-14, "{cp} {x}");
        }
    }

    #[test]
    fn shaped_profiles_meet_their_ends_and_stay_between_the_radii() {
        for shape in [
            NoseShape::Conical,
            NoseShape::Ogive { k: 1.0 },
            NoseShape::Elliptical,
            NoseShape::Parabolic { k: 0.5 },
            NoseShape::Power { n: 0.5 },
            NoseShape::Haack { c: 0.0 },
        ] {
            for (rf, ra) in [(0.05, 0.03), (0.03, 0.05)] {
                let g = t(shape, rf, ra);
                // The elliptical and power profiles have an infinite slope at the small end:
                // the one-ulp rounding of `end() - start` shows as its square root there.
                assert!((g.radius(g.start) - rf).abs() < 1e-9, "{shape:?}");
                assert!((g.radius(g.end()) - ra).abs() < 1e-9, "{shape:?}");
                for k in 0..=50 {
                    let r = g.radius(g.start + g.length * k as f64 / 50.0);
                    assert!(r >= rf.min(ra) - 1e-15 && r <= rf.max(ra) + 1e-15);
                }
                // The quadrature's volume against a fine midpoint sum.
                let n = 200_000;
                let h = g.length / n as f64;
                let mid: f64 = (0..n)
                    .map(|i| {
                        let r = g.radius(g.start + (i as f64 + 0.5) * h);
                        std::f64::consts::PI * r * r * h
                    })
                    .sum();
                let v = g.volume();
                assert!((v - mid).abs() < 1e-7 * v, "{shape:?}: {v} {mid}");
            }
        }
    }
}
