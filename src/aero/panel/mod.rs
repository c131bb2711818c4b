//! Panel aerodynamics of one fin (issue 12, the "strip or panel theory" the thesis names as its
//! future work, 7.1): a planar lattice on the declared trapezoid, a vortex-lattice lifting
//! surface with Prandtl-Glauert compressibility subsonic ([`vlm`]) and piston theory
//! supersonic ([`piston`]), both reduced to ONE linear map per Mach: panel forces from the
//! panels' normalwash angles, `F = q K α_e`; their unsteady (harmonic) forms in [`harmonic`]
//! (vortex rings with a convected wake, Göthert) and [`dlm`] (the doublet-lattice method, the
//! compressible unsteady kernel).
//!
//! # Coordinates and geometry
//!
//! Fin coordinates: `x` chordwise, aft (downstream) from the root leading edge, `y` along the
//! span outward from the root (the body surface), `z = x × y` normal to the fin plane. The free
//! stream is `V` along `+x`. The fin is the trapezoid of [`FinPlanform`]: leading edge
//! `x_LE(y) = x_t y / s`, chord `c(y) = c_r + (c_t - c_r) y / s`. The lattice is linear
//! (small-disturbance) theory: panels stay in the plane `z = 0`, the deformation and motion enter
//! only through the boundary condition.
//!
//! The lattice has `n_c` chordwise x `n_s` spanwise panels. Spanwise strip edges are uniform
//! (`y_j = s j / n_s`) or cosine-spaced towards the tip (`y_j = s sin(π j / (2 n_s))`, the
//! half of the full-wing cosine spacing `y = s cos θ` on the side of the reflection plane,
//! Katz & Plotkin, *Low-Speed Aerodynamics*, 2nd ed., 12.3: dense where the span load varies
//! fastest). Chordwise the panels are uniform fractions of the local chord, so every panel is a
//! trapezoid with chordwise edges on lines of constant chord fraction; the 1/4-3/4 placement of
//! the vortex-lattice method is exact for the flat plate with uniform chordwise panels in 2-D
//! (K&P 12.1, James 1972), which is why the chordwise spacing is not offered as cosine.
//! Panel index `p = j n_c + i` (strip `j`, chordwise `i` from the leading edge).
//!
//! # The normalwash angle α_e
//!
//! On every panel, `α_e` is the component of the air velocity relative to the surface along
//! `+z`, divided by `V`. For a surface displacement `z(x, y, t)` along `+z` (the fin's elastic
//! and rigid motion):
//!
//! `α_e = -∂z/∂x - (1/V) ∂z/∂t` (+ the rigid incidence of the free stream),
//!
//! (the linearised flow-tangency condition, K&P eq. (12.5)/(13.x), Bisplinghoff, Ashley &
//! Halfman, *Aeroelasticity*, eq. (5-313)). A rigid incidence `α` gives `α_e = α`, a plunge
//! `z = -h` (h down) gives `ḣ/V`, a pitch nose-up `θ` about `x_a` (`z = -(x - x_a) θ`) gives
//! `θ + (x - x_a) θ̇ / V`. Forces `F` are along `+z`.
//!
//! # Reflection plane
//!
//! The body is modelled as an infinite plane wall at the root, `y = 0` (K&P 12.3: the image of
//! every vortex in the plane, same circulation, mirrored): the fin and its image form a wing of
//! span `2 s` and aspect ratio `A = 2 s² / S` ([`FinPlanform::aspect_ratio`]). This is exact
//! for a fin on a large flat wall and neglects the curvature of the body and the upwash of the
//! body (which the coefficient tables carry through their interference factor, see
//! `runtime::forces::fin_aero`). The image carries the MIRRORED normalwash: it represents the
//! wall's no-through-flow condition, not a second fin.

pub mod dlm;
pub mod fin_model;
pub mod harmonic;
pub mod machbox;
pub mod piston;
pub mod spline;
pub mod supersonic;
pub mod vlm;

#[cfg(test)]
mod dlm_tests;
#[cfg(test)]
mod harmonic_tests;
#[cfg(test)]
mod machbox_tests;
#[cfg(test)]
mod supersonic_tests;
#[cfg(test)]
mod tests;

use super::estimator::FinPlanform;

/// Spanwise strip spacing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spacing {
    Uniform,
    /// `y_j = s sin(π j / (2 n_s))`: dense towards the tip.
    Cosine,
}

/// Errors of the panel model (bad geometry or lattice size).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PanelError {
    #[error("fin planform {what} = {value} must be finite and positive")]
    BadPlanform { what: &'static str, value: f64 },
    #[error(
        "lattice needs at least one chordwise and one spanwise panel (got {chordwise} x {spanwise})"
    )]
    EmptyLattice { chordwise: usize, spanwise: usize },
    #[error("Mach number {0} is not finite and non-negative")]
    BadMach(f64),
    #[error("vortex-lattice influence matrix is singular at Mach {0}")]
    Singular(f64),
    #[error(
        "Mach {0} is outside the trusted range of the {1} model (vortex lattice M <= 0.9, piston theory M >= 1.2)"
    )]
    Untrusted(f64, &'static str),
    /// The lattice or the wake does not resolve the reduced frequency ([`harmonic`]).
    #[error("{what} = {value:.4} m at nu = {nu} 1/m: {rule} (limit {limit:.4} m)")]
    TooCoarse {
        what: &'static str,
        value: f64,
        limit: f64,
        nu: f64,
        rule: &'static str,
    },
    #[error("reduced frequency nu = omega / V = {0} 1/m is not finite and non-negative")]
    BadFrequency(f64),
    #[error("wake setting {what} = {value} must be finite and positive")]
    BadWake { what: &'static str, value: f64 },
    #[error("normalwash columns have {got} entries, expected {expected}")]
    Shape { expected: usize, got: usize },
    /// The doublet lattice's boxes are too wide for its parabolic kernel approximation
    /// ([`dlm::MAX_BOX_ASPECT`]).
    #[error(
        "the doublet-lattice boxes reach an aspect ratio (width over chord) of {ratio:.2}, above {limit}, where the parabolic approximation of the kernel across a box is poor (Rodden, Taylor & McIntosh 1998)"
    )]
    WideBoxes { ratio: f64, limit: f64 },
}

/// One lattice panel in fin coordinates (see the module doc), metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Corners: leading-inner, leading-outer, trailing-outer, trailing-inner.
    pub corners: [[f64; 2]; 4],
    /// Bound vortex on the panel's quarter-chord line, from the inner to the outer edge.
    pub bound: [[f64; 2]; 2],
    /// Control point: mid-span of the strip, on the panel's three-quarter-chord line.
    pub control: [f64; 2],
    /// Centroid of the panel (piston theory's evaluation and load point).
    pub centroid: [f64; 2],
    /// Area, m².
    pub area: f64,
    /// Spanwise width `y_out - y_in` of the strip, m.
    pub width: f64,
}

impl Panel {
    /// Mid-point of the bound vortex, where the vortex-lattice force acts (Kutta-Joukowski).
    pub fn bound_mid(&self) -> [f64; 2] {
        [
            0.5 * (self.bound[0][0] + self.bound[1][0]),
            0.5 * (self.bound[0][1] + self.bound[1][1]),
        ]
    }
}

/// A planar lattice on a fin planform.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    pub planform: FinPlanform,
    pub chordwise: usize,
    pub spanwise: usize,
    pub spacing: Spacing,
    /// Panels, index `j * chordwise + i`.
    pub panels: Vec<Panel>,
}

impl Lattice {
    /// Lays out `chordwise` x `spanwise` panels on `planform` (the body radius is not used:
    /// the root is the reflection plane).
    pub fn new(
        planform: &FinPlanform,
        chordwise: usize,
        spanwise: usize,
        spacing: Spacing,
    ) -> Result<Lattice, PanelError> {
        // Another outline than the trapezoid may end in a point: its tip chord (the equivalent
        // trapezoid's) may be 0, and the outer strip's panels are then triangles.
        for (what, value) in [
            ("span", planform.span),
            ("root chord", planform.root_chord),
            ("tip chord", planform.tip_chord),
        ] {
            let pointed_ok = what == "tip chord" && !planform.outline.is_trapezoidal();
            if !(value.is_finite() && (value > 0.0 || (pointed_ok && value == 0.0))) {
                return Err(PanelError::BadPlanform { what, value });
            }
        }
        if !planform.tip_le_offset.is_finite() {
            return Err(PanelError::BadPlanform {
                what: "tip leading-edge offset",
                value: planform.tip_le_offset,
            });
        }
        if chordwise == 0 || spanwise == 0 {
            return Err(PanelError::EmptyLattice {
                chordwise,
                spanwise,
            });
        }
        let s = planform.span;
        let edge = |j: usize| -> f64 {
            match spacing {
                Spacing::Uniform => s * j as f64 / spanwise as f64,
                Spacing::Cosine => {
                    s * (std::f64::consts::FRAC_PI_2 * j as f64 / spanwise as f64).sin()
                }
            }
        };
        // Point at chord fraction f on the span station y.
        let at = |f: f64, y: f64| -> [f64; 2] {
            let eta = y / s;
            [planform.le_at(eta) + f * planform.chord_at(eta), y]
        };
        let mut panels = Vec::with_capacity(chordwise * spanwise);
        for j in 0..spanwise {
            let (y0, y1) = (edge(j), edge(j + 1));
            let ym = 0.5 * (y0 + y1);
            for i in 0..chordwise {
                let f0 = i as f64 / chordwise as f64;
                let f1 = (i + 1) as f64 / chordwise as f64;
                let fq = f0 + 0.25 * (f1 - f0);
                let f3 = f0 + 0.75 * (f1 - f0);
                let corners = [at(f0, y0), at(f0, y1), at(f1, y1), at(f1, y0)];
                // Trapezoid with edges parallel to x at y0 and y1: lengths l0, l1.
                let l0 = corners[3][0] - corners[0][0];
                let l1 = corners[2][0] - corners[1][0];
                let w = y1 - y0;
                let area = 0.5 * (l0 + l1) * w;
                // Centroid of the quadrilateral (shoelace).
                let centroid = polygon_centroid(&corners);
                panels.push(Panel {
                    corners,
                    bound: [at(fq, y0), at(fq, y1)],
                    control: at(f3, ym),
                    centroid,
                    area,
                    width: w,
                });
            }
        }
        Ok(Lattice {
            planform: planform.clone(),
            chordwise,
            spanwise,
            spacing,
            panels,
        })
    }

    pub fn len(&self) -> usize {
        self.panels.len()
    }

    pub fn is_empty(&self) -> bool {
        self.panels.is_empty()
    }
}

fn polygon_centroid(p: &[[f64; 2]; 4]) -> [f64; 2] {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..4 {
        let (x0, y0) = (p[k][0], p[k][1]);
        let (x1, y1) = (p[(k + 1) % 4][0], p[(k + 1) % 4][1]);
        let cr = x0 * y1 - x1 * y0;
        a += cr;
        cx += (x0 + x1) * cr;
        cy += (y0 + y1) * cr;
    }
    [cx / (3.0 * a), cy / (3.0 * a)]
}

/// Which aerodynamic theory a Mach number uses and how the transonic gap is bridged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Regime {
    /// `M <= 0.9`: vortex lattice with Prandtl-Glauert.
    Subsonic,
    /// `0.9 < M < 1.2`: linear blend in Mach of the maps at 0.9 and 1.2, weight `t` of 1.2
    /// (neither theory holds there; the same bridge as the coefficient estimator).
    Transonic { t: f64 },
    /// `M >= 1.2`: piston theory.
    Supersonic,
}

/// Upper Mach of the vortex lattice (Prandtl-Glauert breaks down towards M = 1).
pub const SUBSONIC_LIMIT: f64 = 0.9;
/// Lower Mach of piston theory as used here (see [`piston`] for the accuracy at low
/// supersonic Mach numbers).
pub const SUPERSONIC_LIMIT: f64 = 1.2;

/// The flight's steady (quasi-steady) fin-panel method at one Mach (issue 33), as
/// [`fin_model`] uses it: the vortex lattice to [`SUBSONIC_LIMIT`], from
/// [`machbox::MIN_MACH`] = 1.1 the steady supersonic constant-pressure panels
/// ([`supersonic`], subsonic and supersonic leading edges alike) or piston theory where its
/// criterion holds ([`machbox::piston_valid`]: `M >= 2.5` and a supersonic leading edge), and
/// between them the transonic bridge, the linear blend in Mach of the two ends' maps (as the
/// flutter solvers bridge their generalised forces, `analysis::flutter::fin`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SteadyMethod {
    VortexLattice,
    /// `0.9 < M < 1.1`: weight `t` of the 1.1 end.
    Bridge {
        t: f64,
    },
    SupersonicPanels,
    Piston,
}

/// The flight's steady method on `planform` at Mach `mach` ([`SteadyMethod`]).
pub fn steady_method(planform: &FinPlanform, mach: f64) -> Result<SteadyMethod, PanelError> {
    if !(mach.is_finite() && mach >= 0.0) {
        return Err(PanelError::BadMach(mach));
    }
    let hi = machbox::MIN_MACH;
    Ok(if mach <= SUBSONIC_LIMIT {
        SteadyMethod::VortexLattice
    } else if mach < hi {
        SteadyMethod::Bridge {
            t: (mach - SUBSONIC_LIMIT) / (hi - SUBSONIC_LIMIT),
        }
    } else if machbox::piston_valid(planform, mach) {
        SteadyMethod::Piston
    } else {
        SteadyMethod::SupersonicPanels
    })
}

/// The regime of Mach `mach`.
pub fn regime(mach: f64) -> Result<Regime, PanelError> {
    if !(mach.is_finite() && mach >= 0.0) {
        return Err(PanelError::BadMach(mach));
    }
    Ok(if mach <= SUBSONIC_LIMIT {
        Regime::Subsonic
    } else if mach >= SUPERSONIC_LIMIT {
        Regime::Supersonic
    } else {
        Regime::Transonic {
            t: (mach - SUBSONIC_LIMIT) / (SUPERSONIC_LIMIT - SUBSONIC_LIMIT),
        }
    })
}
