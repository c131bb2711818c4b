//! Input of the built-in FE generator and its validation.
//!
//! Conventions (REFERENCE-NOTES.md): body frame origin at the nose tip, the body line along
//! -x (every point of the vehicle has x <= 0), fin i in the plane spanned by body x and the
//! span direction (0, cos delta_i, sin delta_i).

use super::GenerateError;

/// Isotropic linear-elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialProps {
    /// Young's modulus E, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio nu.
    pub poisson: f64,
    /// Density rho, kg/m^3.
    pub density: f64,
}

impl MaterialProps {
    /// Shear modulus G = E / (2 (1 + nu)).
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson))
    }
}

/// Beam theory of the body elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeamTheory {
    /// Shear-rigid (Hermite cubic) bending.
    EulerBernoulli,
    /// Shear-deformable bending with Cowper's shear coefficient (see `beam`).
    Timoshenko,
}

/// The fuselage: a thin-walled circular tube with an optional nose of revolution.
#[derive(Clone, Debug, PartialEq)]
pub struct BodySpec {
    /// Overall length L, m; the body runs from x = 0 (nose tip) to x = -L.
    pub length: f64,
    /// Outer diameter of the cylindrical part, m.
    pub outer_diameter: f64,
    /// Wall thickness t, m (also the wall of the nose cone; near the tip, where the outer
    /// radius is below t, the cone is solid).
    pub wall_thickness: f64,
    /// Nose length l_n, m; 0 = no nose. The outer diameter grows along `nose_shape`'s profile
    /// from 0 at the tip to the full diameter at x = -l_n.
    pub nose_length: f64,
    /// The nose profile (`check::nose`; conical: the outer radius grows linearly).
    pub nose_shape: crate::check::ir::NoseShape,
    /// Transitions and boat tails, fore to aft (`check::transition`): behind the nose the
    /// outer diameter is `outer_diameter` up to the first, then each one's aft diameter.
    pub transitions: Vec<crate::check::transition::TransitionGeom>,
    /// Number of uniform divisions of the body; extra stations are added (see `mesh`).
    pub elements: usize,
    pub theory: BeamTheory,
    pub material: MaterialProps,
}

/// A set of identical flat fins, clamped (rigidly linked) to the body at the root: trapezoids,
/// or any outline of `check::fin_outline` (then `root_chord`, `tip_chord` and `sweep` are the
/// equivalent trapezoid's, and the mesh follows the true edges).
#[derive(Clone, Debug, PartialEq)]
pub struct FinSpec {
    /// Number of fins n.
    pub count: usize,
    /// Exposed span b (root at the tube's outer radius), m.
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// Leading-edge sweep angle, rad (SPHADS-1: atan((c_r - c_t)/b) for an unswept trailing
    /// edge).
    pub sweep: f64,
    /// Plate thickness, m.
    pub thickness: f64,
    /// Cant angle, rad: rotation of the planform about the span axis through the middle of
    /// the root chord; positive turns the chord direction from +x toward the fin normal
    /// (0, -sin delta, cos delta).
    pub cant: f64,
    /// Fin angles delta_i about body x, rad; empty = 2 pi i / n.
    pub angles: Vec<f64>,
    /// x of the root trailing edge (<= 0, e.g. -length), m.
    pub root_trailing_edge_x: f64,
    /// Spanwise strips: for a polygon, at least one per segment between its corners
    /// ([`FinSpec::for_outline`]).
    pub span_elements: usize,
    pub chord_elements: usize,
    /// The plate's material; with `lamina` its `youngs_modulus` is `E1` (along the grain) and
    /// its `poisson` is `nu12`.
    pub material: MaterialProps,
    /// An orthotropic plate (plywood, G10, a woven laminate); `None`: isotropic.
    pub lamina: Option<FinLamina>,
    /// The outline (trapezoidal: the fields above).
    pub outline: crate::check::ir::FinOutline,
}

/// The transverse constants and the grain of an orthotropic fin plate (plane stress,
/// `shell::orthotropic_plane_stress`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinLamina {
    /// Young's modulus across the grain E2, Pa.
    pub e2: f64,
    /// In-plane shear modulus G12, Pa; also taken as the transverse shear modulus
    /// (G13 = G23 = G12, as the wind-tunnel fixture's lamina: `analysis::flutter::wing`).
    /// That overstates plywood's transverse (rolling) shear stiffness, about a quarter of its
    /// G12 (MatWeb's plywood sheet: 0.138-0.207 GPa rolling shear, 0.586-0.758 GPa edgewise);
    /// the transverse shear's share of a plate's bending deflection is of order
    /// `(t/L)^2 E/G13`, 2e-2 for a 2 mm plywood fin of 120 mm span (E 10 GPa, G13 0.14 GPa):
    /// a stiffness overestimate of order a percent for such a fin, half that in frequency.
    pub g12: f64,
    /// Angle of the grain (direction 1) from the root chord, rad, counter-clockwise about the
    /// fin's normal in the local frame (`a` toward the leading edge, `b` outboard): 0
    /// chordwise, pi/2 spanwise.
    pub grain: f64,
}

impl FinSpec {
    /// The in-plane shear modulus of the plate, Pa: `G12` of a lamina, else `E/(2(1+nu))`.
    pub fn in_plane_shear_modulus(&self) -> f64 {
        match &self.lamina {
            Some(l) => l.g12,
            None => self.material.shear_modulus(),
        }
    }

    /// Stiffness and mass of one quad of the plate (local corners `ab`, `shell`): the
    /// isotropic element, or the lamina's with its grain at `lamina.grain` from the local `a`
    /// axis (the root chord; the same in every element, the planform's frame being the
    /// element's).
    pub fn plate_element(&self, ab: &[[f64; 2]; 4]) -> (super::Mat24, super::Mat24) {
        match &self.lamina {
            None => super::shell::shell_element(ab, self.thickness, &self.material),
            Some(l) => {
                let q = super::shell::orthotropic_plane_stress(
                    self.material.youngs_modulus,
                    l.e2,
                    self.material.poisson,
                    l.g12,
                    l.grain,
                );
                super::shell::shell_element_lamina(
                    ab,
                    self.thickness,
                    &q,
                    l.g12,
                    self.material.density,
                )
            }
        }
    }

    /// The fin angles delta_i: `angles` if given, else 2 pi i / n (REFERENCE-NOTES fin frames).
    pub fn fin_angles(&self) -> Vec<f64> {
        if self.angles.is_empty() {
            (0..self.count)
                .map(|i| 2.0 * std::f64::consts::PI * i as f64 / self.count as f64)
                .collect()
        } else {
            self.angles.clone()
        }
    }

    /// x of the root leading edge.
    pub fn root_leading_edge_x(&self) -> f64 {
        self.root_trailing_edge_x + self.root_chord
    }

    /// Planform x of the cant pivot (middle of the root chord).
    pub fn pivot_x(&self) -> f64 {
        self.root_trailing_edge_x + 0.5 * self.root_chord
    }

    /// The true edges of the planform (`check::fin_outline`).
    pub fn edges(&self) -> crate::check::fin_outline::Edges<'_> {
        crate::check::fin_outline::Edges {
            outline: &self.outline,
            span: self.span,
            root_chord: self.root_chord,
            tip_chord: self.tip_chord,
            tip_le_offset: self.span * self.sweep.tan(),
        }
    }

    /// The spanwise strip count that puts a station at every corner of the outline with at
    /// least `requested` strips (`Edges::stations`); `requested` for a trapezoid or ellipse.
    pub fn strips_for(outline: &crate::check::ir::FinOutline, requested: usize) -> usize {
        match outline {
            crate::check::ir::FinOutline::Freeform { leading, trailing } => {
                let mut ys: Vec<f64> = leading.iter().chain(trailing).map(|p| p[0]).collect();
                ys.sort_by(f64::total_cmp);
                ys.dedup();
                requested.max(ys.len().saturating_sub(1))
            }
            _ => requested,
        }
    }

    /// Whether the tip collapses to a point (elliptical, or a polygon ending in a point): the
    /// mesh's tip row is then ONE node and the outermost quads are degenerate (two corners on
    /// that node; their 2 x 2 Gauss points stay inside, so the Jacobian there is regular).
    pub fn pointed_tip(&self) -> bool {
        !self.outline.is_trapezoidal() && self.edges().pointed_tip()
    }

    /// Grid nodes of one fin outside the root row.
    pub fn nodes_per_fin(&self) -> usize {
        let nc = self.chord_elements + 1;
        if self.pointed_tip() {
            (self.span_elements - 1) * nc + 1
        } else {
            self.span_elements * nc
        }
    }

    /// Planform (x, spanwise distance from the root) of chordwise station i (0 = trailing
    /// edge, `chord_elements` = leading edge) at spanwise station j (0 = root).
    pub fn planform_point(&self, i: usize, j: usize) -> (f64, f64) {
        if !self.outline.is_trapezoidal() {
            let e = self.edges();
            let eta = e.stations(self.span_elements)[j];
            let chord = e.chord(eta);
            let x_te = self.root_leading_edge_x() - e.le(eta) - chord;
            return (x_te + chord * i as f64 / self.chord_elements as f64, eta);
        }
        let eta = self.span * j as f64 / self.span_elements as f64;
        let chord = self.root_chord + (self.tip_chord - self.root_chord) * eta / self.span;
        let x_le = self.root_leading_edge_x() - eta * self.sweep.tan();
        let x_te = x_le - chord;
        (x_te + chord * i as f64 / self.chord_elements as f64, eta)
    }

    /// Corners of the planform (TE root, LE root, LE tip, TE tip), counter-clockwise in
    /// (x, eta).
    pub fn planform_corners(&self) -> [(f64, f64); 4] {
        let x_le_tip = self.root_leading_edge_x() - self.span * self.sweep.tan();
        [
            (self.root_trailing_edge_x, 0.0),
            (self.root_leading_edge_x(), 0.0),
            (x_le_tip, self.span),
            (x_le_tip - self.tip_chord, self.span),
        ]
    }
}

/// A rigid point mass (payload, motor parts, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct PointMass {
    pub name: String,
    /// Position of its centre in the body frame, m (x within [-L, 0]).
    pub position: [f64; 3],
    pub mass: f64,
    /// Principal moments of inertia about its own centre, along body axes, kg m^2.
    pub inertia: [f64; 3],
}

/// Non-structural mass spread uniformly along the body line between two stations.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributedMass {
    pub name: String,
    pub x_from: f64,
    pub x_to: f64,
    /// Total mass, kg, spread uniformly along the body line between x_from and x_to.
    pub mass: f64,
}

/// Everything the generator needs to build a vehicle FE model.
#[derive(Clone, Debug, PartialEq)]
pub struct GeneratorSpec {
    pub body: BodySpec,
    pub fins: Option<FinSpec>,
    pub point_masses: Vec<PointMass>,
    pub distributed_masses: Vec<DistributedMass>,
    /// Further fin sets (`fins NAME`, issue 34): rigid, not meshed; each set's plates are a
    /// rigid body on the body node nearest its centre of mass, with their exact mass, centre
    /// and inertia tensor (`mass_properties::rigid_fin_set`). Their mesh densities are not used.
    pub rigid_fins: Vec<FinSpec>,
}

fn positive(what: &'static str, value: f64) -> Result<(), GenerateError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GenerateError::BadGeometry {
            what,
            value,
            reason: "must be finite and positive",
        })
    }
}

fn finite(what: &'static str, value: f64) -> Result<(), GenerateError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(GenerateError::BadGeometry {
            what,
            value,
            reason: "must be finite",
        })
    }
}

/// Validate a material: E > 0, rho > 0, -1 < nu < 0.5.
pub(crate) fn check_material(what: &'static str, m: &MaterialProps) -> Result<(), GenerateError> {
    let bad = |field: &'static str, value: f64| GenerateError::BadMaterial {
        part: what,
        field,
        value,
    };
    if !(m.youngs_modulus.is_finite() && m.youngs_modulus > 0.0) {
        return Err(bad("youngs_modulus", m.youngs_modulus));
    }
    if !(m.density.is_finite() && m.density > 0.0) {
        return Err(bad("density", m.density));
    }
    if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
        return Err(bad("poisson", m.poisson));
    }
    Ok(())
}

/// Validate the body.
pub(crate) fn check_body(b: &BodySpec) -> Result<(), GenerateError> {
    positive("body.length", b.length)?;
    positive("body.outer_diameter", b.outer_diameter)?;
    positive("body.wall_thickness", b.wall_thickness)?;
    if b.wall_thickness >= 0.5 * b.outer_diameter {
        return Err(GenerateError::BadGeometry {
            what: "body.wall_thickness",
            value: b.wall_thickness,
            reason: "must be smaller than the outer radius",
        });
    }
    if !(b.nose_length.is_finite() && b.nose_length >= 0.0 && b.nose_length < b.length) {
        return Err(GenerateError::BadGeometry {
            what: "body.nose_length",
            value: b.nose_length,
            reason: "must be >= 0 and shorter than the body",
        });
    }
    if b.elements == 0 {
        return Err(GenerateError::ZeroElements {
            what: "body.elements",
        });
    }
    // The checker's rules (`check::transition`), for callers that build a spec directly.
    let mut prev = (0.5 * b.outer_diameter, b.nose_length);
    for t in &b.transitions {
        let ok = t.length > 0.0
            && t.start >= prev.1 * (1.0 - 1e-12)
            && t.end() <= b.length * (1.0 + 1e-12)
            && (t.r_fore - prev.0).abs() <= 1e-9 * prev.0
            && b.wall_thickness < t.r_fore.min(t.r_aft);
        if !ok {
            return Err(GenerateError::BadGeometry {
                what: "body.transitions",
                value: t.start,
                reason: "a transition must start at the diameter ahead of it, behind the nose and the previous transition, end within the body, and be thicker than the wall",
            });
        }
        prev = (t.r_aft, t.end());
    }
    check_material("body", &b.material)
}

/// Validate the fins against the body they are attached to.
pub(crate) fn check_fins(f: &FinSpec, body: &BodySpec) -> Result<(), GenerateError> {
    check_fin_planform(f)?;
    // The root chord (after cant) must sit on the cylindrical part of the body.
    let half = 0.5 * f.root_chord * f.cant.cos();
    let (aft, fore) = (f.pivot_x() - half, f.pivot_x() + half);
    let on_transition = body
        .transitions
        .iter()
        .any(|t| -fore < t.end() * (1.0 - 1e-12) && -aft > t.start * (1.0 + 1e-12));
    if aft < -body.length * (1.0 + 1e-12) || fore > -body.nose_length || on_transition {
        return Err(GenerateError::FinOutsideBody {
            root_from: aft,
            root_to: fore,
            body_from: -body.length,
            body_to: -body.nose_length,
        });
    }
    Ok(())
}

/// Validate a fin's planform, mesh and material (not its placement on a body).
pub(crate) fn check_fin_planform(f: &FinSpec) -> Result<(), GenerateError> {
    if f.count == 0 {
        return Err(GenerateError::ZeroElements { what: "fins.count" });
    }
    positive("fins.span", f.span)?;
    positive("fins.root_chord", f.root_chord)?;
    if f.outline.is_trapezoidal() {
        positive("fins.tip_chord", f.tip_chord)?;
    }
    positive("fins.thickness", f.thickness)?;
    finite("fins.sweep", f.sweep)?;
    finite("fins.cant", f.cant)?;
    finite("fins.root_trailing_edge_x", f.root_trailing_edge_x)?;
    if f.tip_chord > f.root_chord && f.outline.is_trapezoidal() {
        return Err(GenerateError::BadGeometry {
            what: "fins.tip_chord",
            value: f.tip_chord,
            reason: "must not exceed the root chord",
        });
    }
    if f.sweep.abs() >= 0.5 * std::f64::consts::PI || f.cant.abs() >= 0.5 * std::f64::consts::PI {
        return Err(GenerateError::BadGeometry {
            what: "fins.sweep/cant",
            value: f.sweep.max(f.cant),
            reason: "angles must lie strictly between -pi/2 and pi/2",
        });
    }
    if f.span_elements == 0 {
        return Err(GenerateError::ZeroElements {
            what: "fins.span_elements",
        });
    }
    if f.chord_elements == 0 {
        return Err(GenerateError::ZeroElements {
            what: "fins.chord_elements",
        });
    }
    if !f.angles.is_empty() && f.angles.len() != f.count {
        return Err(GenerateError::FinAngles {
            count: f.count,
            given: f.angles.len(),
        });
    }
    if f.angles.iter().any(|a| !a.is_finite()) {
        return Err(GenerateError::BadGeometry {
            what: "fins.angles",
            value: f64::NAN,
            reason: "must be finite",
        });
    }
    check_material("fins", &f.material)?;
    if let Some(l) = &f.lamina {
        let bad = |field: &'static str, value: f64| GenerateError::BadMaterial {
            part: "fins",
            field,
            value,
        };
        if !(l.e2.is_finite() && l.e2 > 0.0) {
            return Err(bad("e2", l.e2));
        }
        if !(l.g12.is_finite() && l.g12 > 0.0) {
            return Err(bad("g12", l.g12));
        }
        if !l.grain.is_finite() {
            return Err(bad("grain", l.grain));
        }
        // Positive definite plane stress: nu12 nu21 = nu12^2 E2 / E1 < 1 (`check::vehicle`).
        let nu = f.material.poisson;
        if !(nu > 0.0 && nu * nu * l.e2 / f.material.youngs_modulus < 1.0) {
            return Err(bad("poisson", nu));
        }
    }
    Ok(())
}

/// Validate point and distributed masses against the body.
pub(crate) fn check_masses(spec: &GeneratorSpec) -> Result<(), GenerateError> {
    let l = spec.body.length;
    let inside = |x: f64| x.is_finite() && x <= 0.0 && x >= -l * (1.0 + 1e-12);
    for p in &spec.point_masses {
        if !(p.mass.is_finite() && p.mass > 0.0) {
            return Err(GenerateError::BadMass {
                name: p.name.clone(),
                field: "mass",
                value: p.mass,
            });
        }
        if let Some(&i) = p.inertia.iter().find(|i| !(i.is_finite() && **i >= 0.0)) {
            return Err(GenerateError::BadMass {
                name: p.name.clone(),
                field: "inertia",
                value: i,
            });
        }
        if !inside(p.position[0]) || p.position.iter().any(|c| !c.is_finite()) {
            return Err(GenerateError::MassOutsideBody {
                name: p.name.clone(),
                x: p.position[0],
                length: l,
            });
        }
    }
    for d in &spec.distributed_masses {
        if !(d.mass.is_finite() && d.mass > 0.0) {
            return Err(GenerateError::BadMass {
                name: d.name.clone(),
                field: "mass",
                value: d.mass,
            });
        }
        for x in [d.x_from, d.x_to] {
            if !inside(x) {
                return Err(GenerateError::MassOutsideBody {
                    name: d.name.clone(),
                    x,
                    length: l,
                });
            }
        }
        if (d.x_from - d.x_to).abs() <= 1e-12 * l {
            return Err(GenerateError::BadMass {
                name: d.name.clone(),
                field: "x_to - x_from (empty range)",
                value: d.x_to - d.x_from,
            });
        }
    }
    Ok(())
}

/// Validate the whole spec.
pub(crate) fn check(spec: &GeneratorSpec) -> Result<(), GenerateError> {
    check_body(&spec.body)?;
    if let Some(f) = &spec.fins {
        check_fins(f, &spec.body)?;
    }
    for f in &spec.rigid_fins {
        check_fins(f, &spec.body)?;
    }
    check_masses(spec)
}
