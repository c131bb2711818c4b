//! Checking `material` and `vehicle` blocks.

use std::f64::consts::PI;

use crate::diagnostics::{Diagnostic, did_you_mean};
use crate::syntax::ast::{Block, Value, ValueKind};
use crate::syntax::{Span, Spanned};
use crate::units::Dim;

use super::Cx;
use super::fields::{self as f, Fields};
use super::ir::*;

pub(crate) fn check_material(cx: &mut Cx, b: &Block) -> Option<Material> {
    let name = b.name.as_ref()?;
    let mut fl = Fields::new(cx, format!("material `{}`", name.name), b.header, &b.body);
    let e = fl
        .required(cx, "E", "70 GPa")
        .and_then(|v| f::quantity(cx, v, Dim::PRESSURE));
    let e = f::positive(e, cx);
    let nu = fl.required(cx, "nu", "0.33").and_then(|v| f::number(cx, v));
    let nu = f::check_range(nu, cx, |x| x > 0.0 && x < 0.5, "0 < nu < 0.5");
    let rho = fl
        .required(cx, "rho", "2710 kg/m^3")
        .and_then(|v| f::quantity(cx, v, Dim::DENSITY));
    let rho = f::positive(rho, cx);
    let y = fl
        .value("yield")
        .and_then(|v| f::quantity(cx, v, Dim::PRESSURE));
    let y = f::positive(y, cx);
    let u = fl
        .value("ultimate")
        .and_then(|v| f::quantity(cx, v, Dim::PRESSURE));
    let u = f::positive(u, cx);
    let e2 = fl
        .value("E2")
        .and_then(|v| f::quantity(cx, v, Dim::PRESSURE));
    let e2 = f::positive(e2, cx);
    let g12 = fl
        .value("G12")
        .and_then(|v| f::quantity(cx, v, Dim::PRESSURE));
    let g12 = f::positive(g12, cx);
    let orthotropic = match (
        fl.value("E2").map(|v| v.span),
        fl.value("G12").map(|v| v.span),
    ) {
        (None, None) => None,
        (Some(_), Some(_)) => Some(Orthotropic { e2: e2?, g12: g12? }),
        (Some(s), None) | (None, Some(s)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::material::orthotropic",
                    "an orthotropic lamina needs both `E2` and `G12`",
                )
                .label(s, "only one of the two")
                .with_help("`E` is the modulus along the grain, `E2` across it, `G12` the in-plane shear modulus, `nu` is nu_12"),
            );
            return None;
        }
    };
    let expect_unusual = fl
        .value("expect_unusual")
        .and_then(|v| f::boolean(cx, v))
        .unwrap_or(false);
    fl.finish(cx);
    // Constants outside the range of structural solids: a warning naming the likely unit
    // slip (check/plausible.rs), unless the file says the material is meant to be unusual.
    if let (Some(e), Some(rho), false) = (e, rho, expect_unusual) {
        if let Some(d) = super::plausible::material_warning(
            &name.name,
            (e.value, e.span),
            (rho.value, rho.span),
            name.span,
        ) {
            cx.push(d);
        }
    }
    // A positive definite plane-stress lamina: nu_12 nu_21 = nu_12^2 E2 / E1 < 1.
    if let (Some(o), Some(e), Some(nu)) = (&orthotropic, e, nu) {
        if nu.value * nu.value * o.e2.value / e.value >= 1.0 {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the lamina is not positive definite: nu^2 E2 / E >= 1",
                )
                .label(nu.span, "nu_12")
                .label(o.e2.span, "E2"),
            );
        }
    }
    if let (Some(y), Some(u)) = (y, u) {
        if u.value < y.value {
            cx.push(
                Diagnostic::error("vdl::value::range", "ultimate stress is below yield stress")
                    .label(u.span, "ultimate")
                    .label(y.span, "yield"),
            );
        }
    }
    Some(Material {
        name: Spanned::new(name.name.clone(), name.span),
        youngs_modulus: e?,
        poisson: nu?,
        density: rho?,
        yield_stress: y,
        ultimate_stress: u,
        orthotropic,
    })
}

/// A vehicle's body is an isotropic beam: an orthotropic material is refused as the
/// vehicle's material (its fins may be a lamina: [`check_fins`]).
fn isotropic_only(cx: &mut Cx, m: &Material, at: Span) {
    if m.orthotropic.is_some() {
        cx.push(
            Diagnostic::error(
                "vdl::material::orthotropic",
                format!(
                    "material `{}` is orthotropic: a vehicle's body is an isotropic beam",
                    m.name.value
                ),
            )
            .label(at, "used here")
            .label(m.name.span, "declared orthotropic here (`E2`, `G12`)")
            .with_help("a lamina is taken by the fins (`fins { material = ... }`) and by a `fixture`'s surface"),
        );
    }
}

/// Resolve `material = NAME`.
pub(crate) fn material_ref(cx: &mut Cx, v: &Value, materials: &[Material]) -> Option<Material> {
    let ValueKind::Name(id) = &v.kind else {
        cx.push(
            Diagnostic::error(
                "vdl::type::mismatch",
                format!("expected a material name, found {}", v.describe()),
            )
            .label(v.span, "should name a `material`"),
        );
        return None;
    };
    if let Some(m) = materials.iter().find(|m| m.name.value == id.name) {
        return Some(m.clone());
    }
    let mut d = Diagnostic::error(
        "vdl::reference::unknown",
        format!("no material named `{}`", id.name),
    )
    .label(id.span, "unknown material");
    d = match did_you_mean(&id.name, materials.iter().map(|m| m.name.value.as_str())) {
        Some(s) => d.with_help(format!("did you mean `{s}`?")),
        None => {
            d.with_help("declare it with `material NAME { ... }` or `import \"std/materials.vdl\"`")
        }
    };
    cx.push(d);
    None
}

pub(crate) fn node_ref(cx: &mut Cx, v: &Value) -> Option<NodeRef> {
    if let ValueKind::Call { name, args } = &v.kind {
        match (name.name.as_str(), args.as_slice()) {
            ("node", [a]) if a.name.is_none() => {
                let id = f::integer(cx, &a.value)?;
                return Some(NodeRef::Id(Spanned::new(id, v.span)));
            }
            ("nearest", [a]) if a.name.is_none() => {
                return f::vector3(cx, &a.value, Dim::LENGTH).map(NodeRef::Nearest);
            }
            _ => {}
        }
    }
    cx.push(
        Diagnostic::error(
            "vdl::type::mismatch",
            format!("expected a node, found {}", v.describe()),
        )
        .label(v.span, "not a node designation")
        .with_help("write `node(ID)` or `nearest((x, y, z) m)`"),
    );
    None
}

pub(crate) fn check_vehicle(cx: &mut Cx, b: &Block, materials: &[Material]) -> Option<Vehicle> {
    let name = b.name.as_ref()?;
    let what = format!("vehicle `{}`", name.name);
    let mut fl = Fields::new(cx, what.clone(), b.header, &b.body);
    let material = fl
        .required(cx, "material", "aluminium_6061_t6")
        .and_then(|v| material_ref(cx, v, materials).inspect(|m| isotropic_only(cx, m, v.span)));
    let origin = fl
        .required(cx, "origin", "node(1)")
        .and_then(|v| node_ref(cx, v));
    let structure_block = fl.required_block(cx, "structure");
    // The unnamed `fins` block is the vehicle's flexible, meshed set; named ones
    // (`fins canards { ... }`) are further, rigid sets (`check::fin_sets`).
    let all_fins = fl.blocks("fins");
    let fins_block = all_fins.iter().find(|b| b.name.is_none()).copied();
    let set_blocks: Vec<&Block> = all_fins
        .iter()
        .filter(|b| b.name.is_some())
        .copied()
        .collect();
    let key_block = fl.required_block(cx, "key_nodes");
    let modes_block = fl.required_block(cx, "modes");
    let aero_block = fl.required_block(cx, "aero");
    let forces_block = fl.required_block(cx, "forces");
    let motor_blocks = fl.blocks("motor");
    fl.finish(cx);

    let structure = structure_block.and_then(|sb| check_structure(cx, sb));
    let body_length = match &structure {
        Some(Structure::Generate(g)) => Some(g.body.length.value),
        _ => None,
    };
    let fins =
        fins_block.and_then(|fb| check_fins(cx, fb, material.as_ref(), materials, body_length));
    // A fins block that failed its own checks has been reported: do not also report
    // "no fins" wherever fins are referred to.
    let fins_failed = fins_block.is_some() && fins.is_none();
    let key_nodes = key_block.and_then(|kb| check_key_nodes(cx, kb, fins.as_ref(), fins_failed));
    let modes = modes_block.and_then(|mb| check_modes(cx, mb, fins.as_ref(), fins_failed));
    if let (Some(Structure::Generate(g)), Some(f)) = (&structure, &fins) {
        if !super::transition_check::check_fins_clear(cx, &g.body, f) {
            return None;
        }
    }
    let diameter = match &structure {
        Some(Structure::Generate(g)) => Some(Some(g.body.max_diameter())),
        Some(Structure::Files(_)) => Some(None),
        None => None,
    };
    let aero = aero_block.and_then(|ab| check_aero(cx, ab, diameter));
    let forces = forces_block.and_then(|fb| check_forces(cx, fb));
    let fin_sets = super::fin_sets::check_fin_sets(
        cx,
        &set_blocks,
        fins.as_ref(),
        structure.as_ref(),
        aero.as_ref(),
        |cx, b| check_fins(cx, b, material.as_ref(), materials, body_length),
    )?;
    if let [_, second, ..] = motor_blocks.as_slice() {
        cx.push(
            Diagnostic::error(
                "vdl::duplicate",
                "a vehicle has one motor (clusters and stages are not modelled)",
            )
            .label(second.header, "second motor")
            .label(motor_blocks[0].header, "first motor"),
        );
        return None;
    }
    let motor = match motor_blocks.first() {
        Some(mb) => Some(super::motor::check_motor(cx, mb, structure.as_ref())?),
        None => None,
    };
    if let (Some(m), Some(t)) = (&motor, forces.as_ref().and_then(|f| f.thrust.as_ref())) {
        if t.curve.value.as_os_str() != "" {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::thrust_curve",
                    format!(
                        "the thrust comes from motor `{}`: the `thrust` block takes only `offset` and `misalignment`",
                        m.name.value
                    ),
                )
                .label(t.curve.span, "remove this curve")
                .label(m.curve.span, "the motor's curve"),
            );
            return None;
        }
    }
    if let (None, Some(t)) = (&motor, forces.as_ref().and_then(|f| f.thrust.as_ref())) {
        if t.curve.value.as_os_str() == "" {
            cx.push(
                Diagnostic::error(
                    "vdl::field::missing",
                    "the `thrust` block needs a `curve`, or the vehicle a `motor`",
                )
                .label(t.span, "thrust enabled here")
                .with_help("add `curve = \"motors/motor.eng\"`, or a `motor NAME { ... }` block"),
            );
            return None;
        }
    }
    if let (Some(k), Some(fo), None) = (&key_nodes, &forces, &motor) {
        if let (Some(t), None) = (&fo.thrust, &k.nozzle) {
            cx.push(
                Diagnostic::error(
                    "vdl::key_node::missing",
                    "thrust is enabled but no `nozzle` key node is given",
                )
                .label(t.span, "thrust enabled here")
                .label(k.span, "add `nozzle = ...` here"),
            );
            return None;
        }
    }
    // A `fins` block that failed its own checks has been reported already.
    if let (Some(fo), None, None) = (&forces, &fins, fins_block) {
        if let Some(fa) = &fo.fin_aero {
            cx.push(
                Diagnostic::error(
                    "vdl::block::missing",
                    "fin aerodynamics is enabled but the vehicle has no `fins` block",
                )
                .label(fa.span, "fin aerodynamics enabled here")
                .label(b.header, "no `fins` block in this vehicle"),
            );
            return None;
        }
    }
    // `body_aero { rate_terms = true }` applies the body table's `cn_q`, `cm_q` columns: a
    // table without them is refused here (the plan would refuse it too, later). A table that
    // does not parse is left to the plan, which reports it with its line.
    if let (Some(a), Some(fo)) = (&aero, &forces) {
        if let (AeroSource::Tables { body, .. }, Some(ba)) = (&a.source, &fo.body_aero) {
            use crate::aero::tables::{CoefficientTable, TableKind};
            let parsed = cx.loader.read(&body.value).ok().and_then(|text| {
                CoefficientTable::parse_csv(TableKind::Body, &body.value, &text, OutOfRange::Clamp)
                    .ok()
            });
            if ba.rate_terms && parsed.is_some_and(|t| !t.has_rates()) {
                cx.push(
                    Diagnostic::error(
                        "vdl::aero::rate_columns",
                        "`rate_terms = true` needs the body table's rate derivatives, but it has no `cn_q,cm_q` columns",
                    )
                    .label(ba.span, "rate terms asked for here")
                    .label(body.span, "this body table has the six base columns only")
                    .with_help("add the columns `cn_q,cm_q` (C_Nq + C_Nalpha-dot, C_mq + C_malpha-dot per rad of omega b/(2V)) to the table, or set `rate_terms = false`"),
                );
                return None;
            }
        }
    }
    // A `fins` block that failed its own checks has been reported: no DATCOM follow-on.
    if let (Some(a), false) = (&aero, fins.is_none() && fins_block.is_some()) {
        if !super::datcom_source::check_vehicle(cx, a, fins.as_ref(), forces.as_ref()) {
            return None;
        }
    }
    // The fin generator meshes each fin with MITC4 quadrilaterals between the root and the
    // tip chord (structure/generate/spec.rs): a pointed fin (tip chord 0) would need
    // degenerate elements. The aerodynamics take it; the generated structure does not.
    if let (Some(fi), Some(Structure::Generate(_))) = (&fins, &structure) {
        if fi.tip_chord.value == 0.0 && fi.outline.is_trapezoidal() {
            cx.push(
                Diagnostic::error(
                    "vdl::fins::tip_chord",
                    "a generated fin needs a tip chord > 0: its shell mesh is quadrilaterals from the root chord to the tip chord",
                )
                .label(fi.tip_chord.span, "tip chord 0 (a pointed fin)")
                .with_help("give a small tip chord (the aerodynamics of a nearly pointed fin are continuous), or import the fin's FE model with `structure { files { ... } }`"),
            );
            return None;
        }
    }
    // The supersonic load model of the `theory` distribution (App. A.2.6 generalised to any
    // trapezoid, aero/fin_loads.rs) builds on the apex of the leading edge at the
    // root: a leading edge swept forward has none. Its weights are tabulated over the whole
    // Mach axis, so this is refused here whatever the flight's Mach number.
    if let (Some(fi), Some(fo)) = (&fins, &forces) {
        if let Some(fa) = &fo.fin_aero {
            let tan_le = fi.leading_edge_sweep.value.tan();
            if fa.distribution.value == Distribution::Theory
                && tan_le < -crate::aero::fin_loads::FORWARD_SWEEP_TOL
            {
                cx.push(
                    Diagnostic::error(
                        "vdl::fins::forward_sweep",
                        format!(
                            "the fin's leading edge is swept forward ({:.6} deg): the `theory` load distribution needs a leading edge swept back or unswept",
                            fi.leading_edge_sweep.value.to_degrees()
                        ),
                    )
                    .label(fi.leading_edge_sweep.span, "this sweep makes the leading edge point forward")
                    .label(fa.distribution.span, "load distribution `theory` (App. A)")
                    .with_help("sweep the leading edge back (tan(leading_edge_sweep) = tan(trailing_edge_sweep) + (root_chord - tip_chord)/span >= 0), or use `distribution = uniform`"),
                );
                return None;
            }
        }
    }
    Some(Vehicle {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        material: material?,
        structure: structure?,
        origin: origin?,
        key_nodes: key_nodes?,
        modes: modes?,
        fins,
        fin_sets,
        aero: aero?,
        forces: forces?,
        motor,
    })
}

fn check_structure(cx: &mut Cx, b: &Block) -> Option<Structure> {
    let mut fl = Fields::new(cx, "the `structure` block", b.header, &b.body);
    let generate = fl.block("generate");
    let files = fl.block("files");
    fl.finish(cx);
    match (generate, files) {
        (Some(g), None) => check_generate(cx, g).map(Structure::Generate),
        (None, Some(fb)) => check_fe_files(cx, fb).map(Structure::Files),
        (Some(g), Some(fb)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::structure::ambiguous",
                    "a structure is either generated or read from files, not both",
                )
                .label(g.header, "generate")
                .label(fb.header, "files"),
            );
            None
        }
        (None, None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::block::missing",
                    "the `structure` block needs `generate { ... }` or `files { ... }`",
                )
                .label(b.header, "empty structure"),
            );
            None
        }
    }
}

fn check_generate(cx: &mut Cx, b: &Block) -> Option<Generate> {
    let mut fl = Fields::new(cx, "the `generate` block", b.header, &b.body);
    let body_b = fl.required_block(cx, "body");
    let mesh_b = fl.block("fin_mesh");
    let pms = fl.blocks("point_mass");
    let dms = fl.blocks("distributed_mass");
    fl.finish(cx);

    let body = body_b.and_then(|bb| {
        let mut fl = Fields::new(cx, "the `body` block", bb.header, &bb.body);
        let length = fl
            .required(cx, "length", "2.75 m")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        let length = f::positive(length, cx);
        let diameter = fl
            .required(cx, "diameter", "127 mm")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        let diameter = f::positive(diameter, cx);
        let wall = fl
            .required(cx, "wall", "2 mm")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        let wall = f::positive(wall, cx);
        let nose = match fl.value("nose_length") {
            Some(v) => f::non_negative(f::quantity(cx, v, Dim::LENGTH), cx),
            None => Some(Spanned::new(0.0, bb.header)),
        };
        let nose_shape = match fl.value("nose_shape") {
            Some(v) => nose_shape(cx, v),
            None => Some(Spanned::new(NoseShape::Conical, bb.header)),
        };
        let elements_v = fl.required(cx, "elements", "40");
        let elements = elements_v.and_then(|v| f::count(cx, v, 1, 100_000));
        if let (Some(n), Some(v)) = (elements, elements_v) {
            if n > MAX_BODY_ELEMENTS {
                cx.push(
                    Diagnostic::error(
                        "vdl::body::elements",
                        format!(
                            "{n} body elements are more than the modal solve can resolve (at most {MAX_BODY_ELEMENTS}): a uniform beam of n elements has its largest stiffness-to-mass ratio 0.0645 n^4 = {:.1e} times its first bending eigenvalue, and from about 1e12 on the eigensolver no longer tells the lowest elastic modes from rigid-body modes (it reported them as mechanisms)",
                            0.0645 * (n as f64).powi(4)
                        ),
                    )
                    .label(v.span, "too many elements")
                    .with_help("40 to 100 elements converge the body's low modes; the fins' modes do not depend on it"),
                );
                return None;
            }
        }
        let theory = match fl.value("theory") {
            Some(v) => f::keyword(
                cx,
                v,
                &[
                    ("euler_bernoulli", BeamTheory::EulerBernoulli),
                    ("timoshenko", BeamTheory::Timoshenko),
                ],
            )
            .map(|t| Spanned::new(t, v.span)),
            None => Some(Spanned::new(BeamTheory::EulerBernoulli, bb.header)),
        };
        let transition_blocks = fl.blocks("transition");
        let lug_blocks = fl.blocks("launch_lug");
        let button_blocks = fl.blocks("rail_button");
        fl.finish(cx);
        let guides = super::launch_guide::check_launch_guides(
            cx,
            &lug_blocks,
            &button_blocks,
            nose.as_ref().map(|n| n.value),
            length.as_ref().map(|l| l.value),
        );
        let transitions = super::transition_check::check_transitions(
            cx,
            &transition_blocks,
            diameter.as_ref(),
            wall.as_ref(),
            nose.as_ref(),
            length.as_ref(),
        );
        if let (Some(d), Some(w)) = (diameter, wall) {
            if w.value * 2.0 >= d.value {
                cx.push(
                    Diagnostic::error(
                        "vdl::value::range",
                        "the wall is as thick as the tube's radius or more",
                    )
                    .label(w.span, "wall thickness")
                    .label(d.span, "outer diameter")
                    .with_help("the wall must be thinner than half the diameter"),
                );
                return None;
            }
        }
        if let (Some(n), Some(shape)) = (nose, nose_shape) {
            if n.value == 0.0 && shape.span != bb.header {
                cx.push(
                    Diagnostic::error(
                        "vdl::nose::no_nose",
                        format!(
                            "a {} nose shape on a body without a nose",
                            shape.value.describe()
                        ),
                    )
                    .label(shape.span, "nose shape")
                    .with_help("give the nose's length: `nose_length = 400 mm`"),
                );
                return None;
            }
        }
        if let (Some(l), Some(n)) = (length, nose) {
            if n.value >= l.value {
                cx.push(
                    Diagnostic::error(
                        "vdl::value::range",
                        "the nose is as long as the body or longer",
                    )
                    .label(n.span, "nose length")
                    .label(l.span, "body length"),
                );
                return None;
            }
        }
        Some(BodyGeometry {
            length: length?,
            diameter: diameter?,
            wall: wall?,
            nose_length: nose?,
            nose_shape: nose_shape?,
            elements: Spanned::new(elements?, bb.header),
            theory: theory?,
            transitions: transitions?,
            launch_lugs: guides.as_ref()?.0.clone(),
            rail_buttons: guides?.1,
        })
    });

    let (span_el, chord_el) = match mesh_b {
        Some(mb) => {
            let mut fl = Fields::new(cx, "the `fin_mesh` block", mb.header, &mb.body);
            let s = fl
                .required(cx, "span_elements", "6")
                .and_then(|v| f::count(cx, v, 1, 2000));
            let c = fl
                .required(cx, "chord_elements", "12")
                .and_then(|v| f::count(cx, v, 1, 2000));
            fl.finish(cx);
            (
                s.map(|s| Spanned::new(s, mb.header)),
                c.map(|c| Spanned::new(c, mb.header)),
            )
        }
        None => (
            Some(Spanned::new(6, b.header)),
            Some(Spanned::new(12, b.header)),
        ),
    };

    let length = body.as_ref().map(|b| b.length.value);
    let mut point_masses = Vec::new();
    for pb in pms {
        let Some(pname) = block_name(cx, pb) else {
            continue;
        };
        let mut fl = Fields::new(
            cx,
            format!("point mass `{}`", pname.value),
            pb.header,
            &pb.body,
        );
        let pos = fl
            .required(cx, "position", "(-0.5, 0, 0) m")
            .and_then(|v| f::vector3(cx, v, Dim::LENGTH));
        let mass = fl
            .required(cx, "mass", "1 kg")
            .and_then(|v| f::quantity(cx, v, Dim::MASS));
        let mass = f::positive(mass, cx);
        let inertia = match fl.value("inertia") {
            Some(v) => f::vector3(cx, v, Dim::INERTIA),
            None => Some(Spanned::new([0.0; 3], pb.header)),
        };
        fl.finish(cx);
        if let (Some(p), Some(l)) = (&pos, length) {
            station_in_body(cx, p.value[0], p.span, l);
        }
        if let Some(i) = &inertia {
            if i.value.iter().any(|x| *x < 0.0) {
                cx.push(
                    Diagnostic::error("vdl::value::range", "moments of inertia cannot be negative")
                        .label(i.span, "negative moment"),
                );
            }
        }
        if let (Some(position), Some(mass), Some(inertia)) = (pos, mass, inertia) {
            point_masses.push(PointMass {
                name: pname,
                position,
                mass,
                inertia,
            });
        }
    }
    let mut distributed_masses = Vec::new();
    for db in dms {
        let Some(dname) = block_name(cx, db) else {
            continue;
        };
        let mut fl = Fields::new(
            cx,
            format!("distributed mass `{}`", dname.value),
            db.header,
            &db.body,
        );
        let from = fl
            .required(cx, "from", "-1.6 m")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        let to = fl
            .required(cx, "to", "-2.7 m")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        let mass = fl
            .required(cx, "mass", "5 kg")
            .and_then(|v| f::quantity(cx, v, Dim::MASS));
        let mass = f::positive(mass, cx);
        fl.finish(cx);
        if let (Some(a), Some(z), Some(l)) = (from, to, length) {
            station_in_body(cx, a.value, a.span, l);
            station_in_body(cx, z.value, z.span, l);
            if a.value == z.value {
                cx.push(
                    Diagnostic::error(
                        "vdl::value::range",
                        "a distributed mass needs `from` and `to` to differ",
                    )
                    .label(z.span, "same station as `from`"),
                );
            }
        }
        if let (Some(from), Some(to), Some(mass)) = (from, to, mass) {
            distributed_masses.push(DistributedMass {
                name: dname,
                from,
                to,
                mass,
            });
        }
    }
    let body = body?;
    point_masses.extend(super::launch_guide::guide_masses(
        &body.launch_lugs,
        &body.rail_buttons,
    ));
    Some(Generate {
        span: b.header,
        body,
        fin_span_elements: span_el?,
        fin_chord_elements: chord_el?,
        point_masses,
        distributed_masses,
    })
}

fn station_in_body(cx: &mut Cx, x: f64, span: Span, length: f64) {
    if x > 0.0 || x < -length {
        cx.push(
            Diagnostic::error(
                "vdl::value::range",
                format!("body station x = {x} m is outside the body (0 to -{length} m)"),
            )
            .label(span, "outside the body")
            .with_help(
                "the body frame's origin is the nose tip and x points forward: stations are <= 0",
            ),
        );
    }
}

pub(crate) fn block_name(cx: &mut Cx, b: &Block) -> Option<Spanned<String>> {
    match &b.name {
        Some(n) => Some(Spanned::new(n.name.clone(), n.span)),
        None => {
            cx.push(
                Diagnostic::error(
                    "vdl::name::missing",
                    format!("a `{}` needs a name", b.kind.name),
                )
                .label(b.header, format!("write `{} NAME {{`", b.kind.name)),
            );
            None
        }
    }
}

fn check_fe_files(cx: &mut Cx, b: &Block) -> Option<FeFiles> {
    let mut fl = Fields::new(cx, "the `files` block", b.header, &b.body);
    let format = fl.required(cx, "format", "matrix_market").and_then(|v| {
        f::keyword(
            cx,
            v,
            &[
                ("matrix_market", FeFormat::MatrixMarket),
                ("op4", FeFormat::Op4),
                ("dmig", FeFormat::Dmig),
            ],
        )
        .map(|k| Spanned::new(k, v.span))
    });
    let file = |cx: &mut Cx, fl: &mut Fields, name: &'static str, required: bool, what: &str| {
        let v = if required {
            fl.required(cx, name, "\"model/file\"")
        } else {
            fl.value(name)
        };
        let v = v?;
        let s = f::string(cx, v)?;
        cx.resolve_file(&s, v.span, what)
            .map(|p| Spanned::new(p, v.span))
    };
    let (mass, stiffness, nodes) = match format.map(|f| f.value) {
        Some(FeFormat::MatrixMarket) | None => (
            file(cx, &mut fl, "mass", true, "mass matrix file"),
            file(cx, &mut fl, "stiffness", true, "stiffness matrix file"),
            file(cx, &mut fl, "nodes", true, "node table"),
        ),
        Some(FeFormat::Op4) => {
            let m = file(cx, &mut fl, "matrices", true, "OP4 file");
            let n = file(cx, &mut fl, "nodes", true, "GRID bulk data file");
            (m.clone(), m, n)
        }
        Some(FeFormat::Dmig) => {
            let m = file(cx, &mut fl, "matrices", true, "DMIG bulk data file");
            let n = match fl.value("nodes") {
                Some(_) => file(cx, &mut fl, "nodes", false, "GRID bulk data file"),
                None => m.clone(),
            };
            (m.clone(), m, n)
        }
    };
    let elements = file(cx, &mut fl, "elements", false, "element list");
    let name =
        |cx: &mut Cx, fl: &mut Fields, field: &'static str, default: &str| match fl.value(field) {
            Some(v) => f::string(cx, v).map(|s| Spanned::new(s, v.span)),
            None => Some(Spanned::new(default.to_string(), b.header)),
        };
    let mass_matrix = name(cx, &mut fl, "mass_matrix", "MAA");
    let stiffness_matrix = name(cx, &mut fl, "stiffness_matrix", "KAA");
    let dof_order = match fl.value("dof_order") {
        Some(v) => dof_order(cx, v),
        None => Some(Spanned::new([0, 1, 2, 3, 4, 5], b.header)),
    };
    let length_scale = match fl.value("coordinates_unit") {
        Some(v) => match &v.kind {
            ValueKind::Name(id) => match crate::units::lookup(&id.name) {
                Some(u) if u.dim == Dim::LENGTH => Some(Spanned::new(u.scale, v.span)),
                _ => {
                    cx.push(
                        Diagnostic::error(
                            "vdl::unit::mismatch",
                            format!("`{}` is not a unit of length", id.name),
                        )
                        .label(v.span, "expected m, mm, cm, in, ..."),
                    );
                    None
                }
            },
            _ => {
                cx.push(
                    Diagnostic::error("vdl::type::mismatch", "expected a length unit such as `mm`")
                        .label(v.span, "not a unit name"),
                );
                None
            }
        },
        None => Some(Spanned::new(1.0, b.header)),
    };
    fl.finish(cx);
    Some(FeFiles {
        span: b.header,
        format: format?,
        mass: mass?,
        stiffness: stiffness?,
        nodes: nodes?,
        elements,
        mass_matrix: mass_matrix?,
        stiffness_matrix: stiffness_matrix?,
        dof_order: dof_order?,
        length_scale: length_scale?,
    })
}

/// `dof_order = [u, v, w, rx, ry, rz]`: the file's per-node order.
fn dof_order(cx: &mut Cx, v: &Value) -> Option<Spanned<[u8; 6]>> {
    const NAMES: [&str; 6] = ["u", "v", "w", "rx", "ry", "rz"];
    let ValueKind::List(items) = &v.kind else {
        cx.push(
            Diagnostic::error(
                "vdl::type::mismatch",
                "expected a list of the six DOF names",
            )
            .label(v.span, "write e.g. `[u, v, w, rx, ry, rz]`"),
        );
        return None;
    };
    let mut order = [0u8; 6];
    let mut seen = [false; 6];
    if items.len() != 6 {
        cx.push(
            Diagnostic::error(
                "vdl::vector::arity",
                format!("a DOF order lists 6 names, found {}", items.len()),
            )
            .label(v.span, "expected u, v, w, rx, ry, rz in the file's order"),
        );
        return None;
    }
    for (k, it) in items.iter().enumerate() {
        let opts: Vec<(&'static str, u8)> = NAMES
            .iter()
            .enumerate()
            .map(|(i, n)| (*n, i as u8))
            .collect();
        let c = f::keyword(cx, it, &opts)?;
        if seen[c as usize] {
            cx.push(
                Diagnostic::error("vdl::duplicate", "a DOF appears twice in `dof_order`")
                    .label(it.span, "repeated"),
            );
            return None;
        }
        seen[c as usize] = true;
        order[k] = c;
    }
    Some(Spanned::new(order, v.span))
}

/// The most elements of a generated body.
///
/// Not a mesh limit but one of the modal solve's conditioning. Both of its paths
/// (structure/modal) call an eigenvalue "zero" (a rigid-body mode) below 1e-10 of the
/// largest translational `K_ii / M_ii`, the scale of the top of the spectrum, and more than
/// six such modes is reported as mechanisms. For a uniform Euler–Bernoulli beam of `n`
/// elements of length `h = L/n` with consistent mass (Przemieniecki 11.3), the largest
/// `K_ii / M_ii` is `24 EI/h^3 / (312/420 rho A h) = 32.31 (EI/rho A)/h^4`, and the first
/// free-free bending eigenvalue is `4.7300^4 (EI/rho A)/L^4 = 500.56 (EI/rho A)/L^4`; their
/// ratio `0.0645 n^4` depends on the element count alone, not on the material or the
/// section. The spectrum widens as the fourth power of the count, and the eigensolver in
/// double precision no longer resolves the lowest elastic modes from the rigid ones.
/// Measured on this code: the HPR K1000 vehicle (1.9 m, 98 mm, fibreglass) solves at 2500
/// elements (body bending 62.51 Hz, the same as at 40 to 2000) and fails as "8 mechanisms" at
/// 3000; SPHADS-1 (fins at 36.5 Hz, below its body bending) fails at 2000 and 3000. The
/// ratio `0.0645 n^4` is 1.0e12 at 2000 elements, 2.5e12 at 2500 and 5.2e12 at 3000 (the
/// vehicles' lowest elastic modes lie below the bare beam's first bending, the thin fins of
/// SPHADS-1 far below, which widens their spectrum further). At 1000 elements it is 6.5e10,
/// 16 times below the first failure seen, and SPHADS-1 solves there (body bending
/// 90.50 Hz, fin flap 36.55 Hz, as with its 40 elements); 40 to 100 elements converge the
/// low modes
/// (62.51 Hz from 40 to 2500 elements on the HPR vehicle).
pub const MAX_BODY_ELEMENTS: usize = 1000;

/// The largest fin thickness against the smaller of its root chord and span.
///
/// The fin is a flat plate meshed with MITC4 (Reissner–Mindlin) shells and loaded by
/// thin-aerofoil (strip, piston or lifting-surface) theory. Both are expansions in the
/// thickness ratio: plate theory in t/L, the plate's thickness against its in-plane extent,
/// and thin-aerofoil theory in t/c. 0.2 is flexflight's bound: beyond it the section is
/// thicker than any fin section in use, and a thickness of the order of the chord (the
/// issue's 250 mm on a 203 mm chord) is a unit slip, not a fin. The root chord and the span
/// are the fin's in-plane extents (the tip chord, up to 0 for a nearly pointed fin, is not:
/// a thin fin may taper to a tip as narrow as it is thick).
pub const MAX_FIN_THICKNESS_RATIO: f64 = 0.2;

/// A `fins` block, unnamed (the vehicle's flexible set) or named (a further set,
/// `check::fin_sets`): the same fields, the same checks.
pub(super) fn check_fins(
    cx: &mut Cx,
    b: &Block,
    vehicle_material: Option<&Material>,
    materials: &[Material],
    body_length: Option<f64>,
) -> Option<Fins> {
    let what = match &b.name {
        Some(n) => format!("the `fins {}` block", n.name),
        None => "the `fins` block".to_string(),
    };
    let mut fl = Fields::new(cx, what, b.header, &b.body);
    let count = fl
        .required(cx, "count", "4")
        .and_then(|v| f::count(cx, v, 1, 64).map(|n| Spanned::new(n, v.span)));
    let len = |cx: &mut Cx, fl: &mut Fields, n: &'static str, ex: &str| {
        let q = fl
            .required(cx, n, ex)
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        f::positive(q, cx)
    };
    // The outline (issue 34): `trapezoidal` (root and tip chord, a sweep), `elliptical` (root
    // chord and span) or `freeform` (the polygon's points).
    let planform_v = fl.value("planform");
    let kind = match planform_v {
        Some(v) => f::keyword(
            cx,
            v,
            &[
                ("trapezoidal", PlanformKind::Trapezoidal),
                ("elliptical", PlanformKind::Elliptical),
                ("freeform", PlanformKind::Freeform),
            ],
        ),
        None => Some(PlanformKind::Trapezoidal),
    };
    let (span, root, tip, outline) = match kind {
        Some(PlanformKind::Trapezoidal) | None => {
            let span = len(cx, &mut fl, "span", "127.23 mm");
            let root = len(cx, &mut fl, "root_chord", "324.68 mm");
            let tip = fl
                .required(cx, "tip_chord", "122.67 mm")
                .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
            (
                span,
                root,
                f::non_negative(tip, cx),
                Some(FinOutline::Trapezoidal),
            )
        }
        Some(PlanformKind::Elliptical) => {
            let span = len(cx, &mut fl, "span", "127.23 mm");
            let root = len(cx, &mut fl, "root_chord", "324.68 mm");
            let pv = planform_v.map_or(b.header, |v| v.span);
            refuse_for_outline(cx, &mut fl, "elliptical", pv);
            // The equivalent trapezoid's tip chord (same area): pi/4 c_r s = (c_r + c_t) s / 2.
            let tip = root.map(|r| Spanned::new((0.5 * std::f64::consts::PI - 1.0) * r.value, pv));
            (span, root, tip, Some(FinOutline::Elliptical))
        }
        Some(PlanformKind::Freeform) => {
            let pv = planform_v.map_or(b.header, |v| v.span);
            refuse_for_outline(cx, &mut fl, "freeform", pv);
            match fl
                .required(
                    cx,
                    "points",
                    "[(0, 0) mm, (150, 120) mm, (250, 120) mm, (300, 0) mm]",
                )
                .and_then(|v| freeform_points(cx, v))
            {
                Some((outline, root, span, vspan)) => {
                    let area = outline_area(&outline, span, root);
                    let tip = (2.0 * area / span - root).max(0.0);
                    (
                        Some(Spanned::new(span, vspan)),
                        Some(Spanned::new(root, vspan)),
                        Some(Spanned::new(tip, vspan)),
                        Some(outline),
                    )
                }
                None => (None, None, None, None),
            }
        }
    };
    let thickness = len(cx, &mut fl, "thickness", "0.6 mm");
    let cross_section = match fl.value("cross_section") {
        Some(v) => f::keyword(
            cx,
            v,
            &[
                ("square", FinSection::Square),
                ("rounded", FinSection::Rounded),
                ("airfoil", FinSection::Airfoil),
            ],
        )
        .map(|s| Spanned::new(s, v.span)),
        None => Some(Spanned::new(FinSection::Square, b.header)),
    };
    let le = fl
        .value("leading_edge_sweep")
        .map(|v| (v, f::quantity(cx, v, Dim::ANGLE)));
    let te = fl
        .value("trailing_edge_sweep")
        .map(|v| (v, f::quantity(cx, v, Dim::ANGLE)));
    let cant = match fl.value("cant") {
        Some(v) => f::check_range(
            f::quantity(cx, v, Dim::ANGLE),
            cx,
            |x| x.abs() < PI / 4.0,
            "|cant| < 45 deg",
        ),
        None => Some(Spanned::new(0.0, b.header)),
    };
    let angles_v = fl.value("angles");
    let station = fl
        .value("root_trailing_edge")
        .map(|v| f::quantity(cx, v, Dim::LENGTH));
    let material = match fl.value("material") {
        // A fin may be an orthotropic lamina (plywood, G10, a woven laminate): its shells take
        // it (`structure::generate::FinSpec::lamina`); the body stays isotropic.
        Some(v) => material_ref(cx, v, materials),
        None => vehicle_material.cloned(),
    };
    // The fins' own material constants, over those of `material` (a measured laminate, or a
    // dispersion: `fins.E = normal(...)`), checked as a material's.
    let e_fin = fl
        .value("E")
        .map(|v| f::positive(f::quantity(cx, v, Dim::PRESSURE), cx));
    let nu_fin = fl
        .value("nu")
        .map(|v| f::check_range(f::number(cx, v), cx, |x| x > 0.0 && x < 0.5, "0 < nu < 0.5"));
    let rho_fin = fl
        .value("rho")
        .map(|v| f::positive(f::quantity(cx, v, Dim::DENSITY), cx));
    let e2_fin = fl
        .value("E2")
        .map(|v| (v.span, f::positive(f::quantity(cx, v, Dim::PRESSURE), cx)));
    let g12_fin = fl
        .value("G12")
        .map(|v| (v.span, f::positive(f::quantity(cx, v, Dim::PRESSURE), cx)));
    let grain_v = fl.value("grain");
    let grain = match grain_v {
        Some(v) => f::keyword(
            cx,
            v,
            &[
                ("chordwise", FinGrain::Chordwise),
                ("spanwise", FinGrain::Spanwise),
            ],
        ),
        None => Some(FinGrain::Chordwise),
    };
    let fillet = check_fillet(cx, &mut fl, b.header, body_length.is_some());
    fl.finish(cx);
    let material = match material {
        Some(mut m) if e_fin.is_some() || nu_fin.is_some() || rho_fin.is_some() => {
            for (over, field) in [
                (e_fin, &mut m.youngs_modulus),
                (nu_fin, &mut m.poisson),
                (rho_fin, &mut m.density),
            ] {
                match over {
                    Some(Some(q)) => *field = q,
                    Some(None) => return None,
                    None => {}
                }
            }
            if let Some(d) = super::plausible::material_warning(
                &m.name.value,
                (m.youngs_modulus.value, m.youngs_modulus.span),
                (m.density.value, m.density.span),
                b.header,
            ) {
                cx.push(d);
            }
            Some(m)
        }
        m => m,
    };
    let material = fin_lamina(cx, material, e2_fin, g12_fin, grain_v, b.header)?;
    let grain = grain?;

    if let (Some(r), Some(t), Some(FinOutline::Trapezoidal)) = (root, tip, &outline) {
        if t.value > r.value {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the tip chord is longer than the root chord",
                )
                .label(t.span, "tip chord")
                .label(r.span, "root chord")
                .with_help("flexflight models trapezoidal fins with tip chord <= root chord"),
            );
            return None;
        }
    }
    let (span_q, root_q, tip_q) = (span?, root?, tip?);
    // A fin is a thin plate (MITC4 shells) with thin-aerofoil loads: its thickness must be
    // small against its chord and its span (see `MAX_FIN_THICKNESS_RATIO`).
    if let Some(t) = thickness {
        let (extent, which) = if root_q.value <= span_q.value {
            (root_q, "root chord")
        } else {
            (span_q, "span")
        };
        let ratio = t.value / extent.value;
        if ratio > MAX_FIN_THICKNESS_RATIO {
            cx.push(
                Diagnostic::error(
                    "vdl::fins::thickness",
                    format!(
                        "the fin is {} mm thick on a {} mm {which} (thickness/{which} = {ratio:.3}): a fin is modelled as a thin plate with thin-aerofoil loads, which needs the ratio <= {MAX_FIN_THICKNESS_RATIO}",
                        super::plausible::short(t.value * 1e3),
                        super::plausible::short(extent.value * 1e3),
                    ),
                )
                .label(t.span, "thickness")
                .label(extent.span, which)
                .with_help("check the thickness's unit (mm, not cm)"),
            );
            return None;
        }
    }
    // Leading-edge sweep: given, or from the trailing-edge sweep and the taper:
    // x_LE(tip) - x_LE(root) = -(span tan(Lambda_LE)); the tip's trailing edge sits at
    // span tan(Lambda_TE) behind the root's, so tan(Lambda_LE) = tan(Lambda_TE) + (c_r - c_t)/s.
    let outline = outline?;
    let sweep = match (le, te) {
        _ if !outline.is_trapezoidal() => {
            // The equivalent trapezoid's leading edge puts its mean aerodynamic chord's leading
            // edge where the fin's is: x_MAC = x_t (c_r + 2 c_t) / (3 (c_r + c_t)).
            let e = crate::check::fin_outline::Edges {
                outline: &outline,
                span: span_q.value,
                root_chord: root_q.value,
                tip_chord: tip_q.value,
                tip_le_offset: 0.0,
            };
            let (_, x_mac) = e.mean_aerodynamic_chord();
            let (cr, ct) = (root_q.value, tip_q.value);
            let x_t = x_mac * 3.0 * (cr + ct) / (cr + 2.0 * ct);
            Some(Spanned::new((x_t / span_q.value).atan(), tip_q.span))
        }
        (Some(_), Some((tv, _))) => {
            cx.push(
                Diagnostic::error(
                    "vdl::fins::sweep",
                    "give either `leading_edge_sweep` or `trailing_edge_sweep`, not both",
                )
                .label(tv.span, "second sweep"),
            );
            None
        }
        (Some((_, q)), None) => f::check_range(q, cx, |x| x.abs() < 1.4, "|sweep| < 80 deg"),
        (None, Some((v, q))) => {
            let q = f::check_range(q, cx, |x| x.abs() < 1.4, "|sweep| < 80 deg")?;
            let tan_le = q.value.tan() + (root_q.value - tip_q.value) / span_q.value;
            Some(Spanned::new(tan_le.atan(), v.span))
        }
        (None, None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::field::missing",
                    "the `fins` block needs `leading_edge_sweep` or `trailing_edge_sweep`",
                )
                .label(b.header, "sweep missing")
                .with_help("SPHADS-1 has an unswept trailing edge: `trailing_edge_sweep = 0 deg`"),
            );
            None
        }
    };
    let n = count?.value;
    let angles = match angles_v {
        Some(v) => match &v.kind {
            ValueKind::List(items) => {
                let qs: Vec<Option<Q>> = items
                    .iter()
                    .map(|it| f::quantity(cx, it, Dim::ANGLE))
                    .collect();
                if qs.len() != n {
                    cx.push(
                        Diagnostic::error(
                            "vdl::fins::angles",
                            format!("{} fin angles for {n} fins", qs.len()),
                        )
                        .label(v.span, format!("expected {n} angles")),
                    );
                    return None;
                }
                qs.into_iter().collect::<Option<Vec<_>>>()?
            }
            _ => {
                cx.push(
                    Diagnostic::error(
                        "vdl::type::mismatch",
                        format!("expected a list of angles, found {}", v.describe()),
                    )
                    .label(v.span, "write e.g. `[0 deg, 90 deg, 180 deg, 270 deg]`"),
                );
                return None;
            }
        },
        // delta_i = 2 pi (i - 1) / n (REFERENCE-NOTES, fin frames).
        None => (0..n)
            .map(|i| Spanned::new(2.0 * PI * i as f64 / n as f64, b.header))
            .collect(),
    };
    let station = match (station, body_length) {
        (Some(q), l) => {
            let q = q?;
            if let Some(l) = l {
                station_in_body(cx, q.value, q.span, l);
                if q.value + root_q.value > 0.0 {
                    cx.push(
                        Diagnostic::error(
                            "vdl::value::range",
                            "the fin root extends forward of the nose",
                        )
                        .label(q.span, "root trailing edge station"),
                    );
                }
            }
            q
        }
        (None, Some(l)) => Spanned::new(-l, b.header),
        (None, None) => {
            cx.push(
                Diagnostic::error("vdl::field::missing", "the `fins` block needs `root_trailing_edge` when the structure is read from files")
                    .label(b.header, "add `root_trailing_edge = -2.75 m`"),
            );
            return None;
        }
    };
    Some(Fins {
        span_: b.header,
        count: count?,
        span: span_q,
        root_chord: root_q,
        tip_chord: tip_q,
        leading_edge_sweep: sweep?,
        thickness: thickness?,
        cross_section: cross_section?,
        cant: cant?,
        angles,
        root_trailing_edge_x: station,
        material,
        grain,
        outline,
        fillet: fillet?,
    })
}

/// The fins' `E2` and `G12` over their material's (a dispersion draws `fins.G12`): over an
/// orthotropic material each replaces its own; on an isotropic one both make it a lamina
/// (one alone is refused, as in a `material` block). The lamina must stay positive definite
/// (`nu^2 E2 / E < 1`, [`check_material`]), and `grain` needs a lamina to orient.
fn fin_lamina(
    cx: &mut Cx,
    material: Option<Material>,
    e2: Option<(Span, Option<Q>)>,
    g12: Option<(Span, Option<Q>)>,
    grain_v: Option<&Value>,
    header: Span,
) -> Option<Material> {
    let mut m = material?;
    let (e2, g12) = match (e2, g12) {
        (Some((_, None)), _) | (_, Some((_, None))) => return None,
        (Some((_, Some(a))), Some((_, Some(b)))) => (Some(a), Some(b)),
        (Some((_, Some(a))), None) => (Some(a), None),
        (None, Some((_, Some(b)))) => (None, Some(b)),
        (None, None) => (None, None),
    };
    match (&mut m.orthotropic, e2, g12) {
        (_, None, None) => {}
        (Some(o), e2, g12) => {
            if let Some(q) = e2 {
                o.e2 = q;
            }
            if let Some(q) = g12 {
                o.g12 = q;
            }
        }
        (None, Some(e2), Some(g12)) => m.orthotropic = Some(Orthotropic { e2, g12 }),
        (None, Some(q), None) | (None, None, Some(q)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::material::orthotropic",
                    format!(
                        "material `{}` is isotropic: making the fins a lamina needs both `E2` and `G12`",
                        m.name.value
                    ),
                )
                .label(q.span, "only one of the two")
                .with_help("`E` is the modulus along the grain, `E2` across it, `G12` the in-plane shear modulus, `nu` is nu_12"),
            );
            return None;
        }
    }
    match (&m.orthotropic, grain_v) {
        (Some(o), _) => {
            let (e, nu) = (m.youngs_modulus.value, m.poisson.value);
            if nu * nu * o.e2.value / e >= 1.0 {
                cx.push(
                    Diagnostic::error(
                        "vdl::value::range",
                        "the fins' lamina is not positive definite: nu^2 E2 / E >= 1",
                    )
                    .label(header, "these fins")
                    .label(m.poisson.span, "nu_12")
                    .label(o.e2.span, "E2"),
                );
                return None;
            }
        }
        (None, Some(v)) => {
            grain_without_lamina(cx, v.span, &m, "the fins' material");
            return None;
        }
        (None, None) => {}
    }
    Some(m)
}

/// `fillet_radius` and `fillet_density` of a fin set: both or neither (a fillet's material
/// is rarely the fin's, and its mass needs a density: never a silent default); only for a
/// generated structure (a structure read from files holds its own masses). `None` on an
/// error, `Some(None)` without a fillet.
fn check_fillet(
    cx: &mut Cx,
    fl: &mut Fields,
    header: Span,
    generated: bool,
) -> Option<Option<Fillet>> {
    let radius_v = fl.value("fillet_radius");
    let density_v = fl.value("fillet_density");
    let radius = radius_v.map(|v| f::positive(f::quantity(cx, v, Dim::LENGTH), cx));
    let density = density_v.map(|v| f::positive(f::quantity(cx, v, Dim::DENSITY), cx));
    let (radius, density) = match (radius, density) {
        (None, None) => return Some(None),
        (Some(r), Some(d)) => (r?, d?),
        (r, _) => {
            let (given, missing) = if r.is_some() {
                ("fillet_radius", "fillet_density = 1150 kg/m^3")
            } else {
                ("fillet_density", "fillet_radius = 6 mm")
            };
            let at = radius_v.or(density_v).map_or(header, |v| v.span);
            cx.push(
                Diagnostic::error(
                    "vdl::fins::fillet",
                    format!("`{given}` without the other half of the fillet"),
                )
                .label(at, "given alone")
                .with_help(format!(
                    "a root fillet needs its radius and its density (its material is rarely the fin's): add e.g. `{missing}` (an epoxy), or remove `{given}`"
                )),
            );
            return None;
        }
    };
    if !generated {
        cx.push(
            Diagnostic::error(
                "vdl::fins::fillet",
                "a fillet's mass is added to a generated structure; a structure read from files holds its own masses",
            )
            .label(radius.span, "fillet")
            .with_help("put the fillets' mass in the FE model's mass matrix, and remove `fillet_radius` and `fillet_density`"),
        );
        return None;
    }
    Some(Some(Fillet { radius, density }))
}

#[derive(Clone, Copy)]
enum PlanformKind {
    Trapezoidal,
    Elliptical,
    Freeform,
}

/// The trapezoid's fields have no meaning for an elliptical or freeform fin: a diagnostic at
/// each one written (marked read so it is not also reported as unknown).
fn refuse_for_outline(cx: &mut Cx, fl: &mut Fields, which: &str, planform: Span) {
    let fields: &[&'static str] = if which == "elliptical" {
        &[
            "tip_chord",
            "leading_edge_sweep",
            "trailing_edge_sweep",
            "points",
        ]
    } else {
        &[
            "span",
            "root_chord",
            "tip_chord",
            "leading_edge_sweep",
            "trailing_edge_sweep",
        ]
    };
    for &name in fields {
        if let Some(v) = fl.value(name) {
            cx.push(
                Diagnostic::error(
                    "vdl::fins::planform",
                    format!(
                        "`{name}` does not describe {} {which} fin",
                        if which == "elliptical" { "an" } else { "a" }
                    ),
                )
                .label(v.span, "remove this")
                .label(planform, format!("the planform is {which}"))
                .with_help(if which == "elliptical" {
                    "an elliptical fin is given by `root_chord` and `span` (the half ellipse on the root chord)"
                } else {
                    "a freeform fin is given by its `points` alone: its span, root and tip chords follow from them"
                }),
            );
        }
    }
}

/// Area of an outline of span `span` and root chord `root` (`check::fin_outline`).
fn outline_area(outline: &FinOutline, span: f64, root: f64) -> f64 {
    crate::check::fin_outline::Edges {
        outline,
        span,
        root_chord: root,
        tip_chord: 0.0,
        tip_le_offset: 0.0,
    }
    .area()
}

/// A freeform fin's `points = [(x, y) mm, ...]` (x aft, y outward from the root, from the
/// root leading edge out and back to the root trailing edge): the outline, root chord and span,
/// or a diagnostic at the point that makes it no fin (`check::fin_outline::freeform`).
fn freeform_points(cx: &mut Cx, v: &Value) -> Option<(FinOutline, f64, f64, Span)> {
    use crate::check::fin_outline::{OutlineError, freeform};
    let ValueKind::List(items) = &v.kind else {
        cx.push(
            Diagnostic::error(
                "vdl::type::mismatch",
                format!("expected a list of points, found {}", v.describe()),
            )
            .label(
                v.span,
                "write e.g. `[(0, 0) mm, (150, 120) mm, (250, 120) mm, (300, 0) mm]`",
            ),
        );
        return None;
    };
    let pts: Vec<Option<[f64; 2]>> = items
        .iter()
        .map(|it| f::vector(cx, it, Dim::LENGTH, 2).map(|(c, _)| [c[0], c[1]]))
        .collect();
    let pts: Vec<[f64; 2]> = pts.into_iter().collect::<Option<_>>()?;
    if let Some(k) = pts
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        cx.push(
            Diagnostic::error("vdl::value::range", "a fin point is not finite")
                .label(items[k].span, "this point"),
        );
        return None;
    }
    match freeform(&pts) {
        Ok((outline, root, span)) => Some((outline, root, span, v.span)),
        Err(e) => {
            let (at, msg, label) = match e {
                OutlineError::TooFew => (
                    v.span,
                    "a freeform fin needs at least three points".to_string(),
                    "too few points".to_string(),
                ),
                OutlineError::RootNotOnBody(k) => (
                    items[k].span,
                    "the fin's root edge is not on the body: the first and the last point need y = 0".to_string(),
                    "y is not 0".to_string(),
                ),
                OutlineError::BelowRoot(k) => (
                    items[k].span,
                    "only the first and the last point of a freeform fin may lie on the body (y = 0)".to_string(),
                    "y <= 0 between the root points".to_string(),
                ),
                OutlineError::NotSingleValued(k) => (
                    items[k].span,
                    "the outline is not single-valued in chord per span station: it must go out to the tip with y increasing and back to the root with y decreasing".to_string(),
                    "y turns back here".to_string(),
                ),
                OutlineError::Crosses(k) => (
                    items[k].span,
                    "the freeform outline crosses itself: the leading edge meets or passes the trailing edge".to_string(),
                    "the edges cross at or next to this point".to_string(),
                ),
                OutlineError::RootChord => (
                    v.span,
                    "the root chord (from the first to the last point) is zero".to_string(),
                    "root chord 0".to_string(),
                ),
            };
            cx.push(
                Diagnostic::error("vdl::fins::outline", msg)
                    .label(at, label)
                    .with_help("list the points from the root leading edge (0, 0) out to the tip and back to the root trailing edge (c_r, 0), x aft and y outward"),
            );
            None
        }
    }
}

fn check_key_nodes(
    cx: &mut Cx,
    b: &Block,
    fins: Option<&Fins>,
    fins_failed: bool,
) -> Option<KeyNodes> {
    let mut fl = Fields::new(cx, "the `key_nodes` block", b.header, &b.body);
    let body = fl
        .required(cx, "body", "nearest((-1.59, 0, 0) m)")
        .and_then(|v| node_ref(cx, v));
    let nozzle = fl.value("nozzle").map(|v| node_ref(cx, v));
    let fins_v = fl.value("fins");
    fl.finish(cx);
    if fins_failed {
        return None;
    }
    let fin_nodes = match (fins_v, fins) {
        (None, None) => FinKeyNodes::None,
        (None, Some(fi)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::key_node::missing",
                    "the vehicle has fins but no fin key nodes",
                )
                .label(b.header, "add `fins = fin_point(span = 0.5, chord = 0.5)`")
                .label(fi.span_, "fins declared here"),
            );
            return None;
        }
        (Some(v), None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::reference::kind",
                    "fin key nodes are given but the vehicle has no `fins` block",
                )
                .label(v.span, "no fins to put these on"),
            );
            return None;
        }
        (Some(v), Some(fi)) => match &v.kind {
            ValueKind::Call { name, args } if name.name == "fin_point" => {
                let mut span = None;
                let mut chord = None;
                for a in args {
                    let q = f::check_range(
                        f::number(cx, &a.value),
                        cx,
                        |x| (0.0..=1.0).contains(&x),
                        "a fraction from 0 to 1",
                    );
                    match a.name.as_ref().map(|n| n.name.as_str()) {
                        Some("span") => span = q,
                        Some("chord") => chord = q,
                        _ => cx.push(
                            Diagnostic::error(
                                "vdl::argument",
                                "`fin_point` takes `span = FRACTION, chord = FRACTION`",
                            )
                            .label(a.value.span, "unexpected argument"),
                        ),
                    }
                }
                match (span, chord) {
                    (Some(span), Some(chord)) => FinKeyNodes::Fraction { span, chord },
                    _ => {
                        cx.push(
                            Diagnostic::error(
                                "vdl::argument",
                                "`fin_point` needs both `span` and `chord`",
                            )
                            .label(v.span, "e.g. fin_point(span = 0.5, chord = 0.5)"),
                        );
                        return None;
                    }
                }
            }
            ValueKind::List(items) => {
                if items.len() != fi.count.value {
                    cx.push(
                        Diagnostic::error(
                            "vdl::key_node::count",
                            format!("{} fin key nodes for {} fins", items.len(), fi.count.value),
                        )
                        .label(v.span, "one node per fin"),
                    );
                    return None;
                }
                let nodes: Option<Vec<NodeRef>> = items.iter().map(|it| node_ref(cx, it)).collect();
                FinKeyNodes::PerFin(nodes?)
            }
            _ => {
                cx.push(
                    Diagnostic::error(
                        "vdl::type::mismatch",
                        format!(
                            "expected `fin_point(...)` or a list of nodes, found {}",
                            v.describe()
                        ),
                    )
                    .label(v.span, "not a fin key-node designation"),
                );
                return None;
            }
        },
    };
    let nozzle = match nozzle {
        Some(n) => Some(n?),
        None => None,
    };
    Some(KeyNodes {
        span: b.header,
        body: body?,
        nozzle,
        fins: fin_nodes,
    })
}

fn check_modes(
    cx: &mut Cx,
    b: &Block,
    fins: Option<&Fins>,
    fins_failed: bool,
) -> Option<ModeSelection> {
    let mut fl = Fields::new(cx, "the `modes` block", b.header, &b.body);
    let mut rules = Vec::new();
    let mut ok = true;
    if let Some(v) = fl.value("indices") {
        match &v.kind {
            ValueKind::List(items) if !items.is_empty() => {
                let idx: Option<Vec<usize>> = items
                    .iter()
                    .map(|it| f::count(cx, it, 1, 100_000))
                    .collect();
                match idx {
                    Some(i) => rules.push(ModeRule::Indices(Spanned::new(i, v.span))),
                    None => ok = false,
                }
            }
            _ => {
                cx.push(
                    Diagnostic::error(
                        "vdl::type::mismatch",
                        "expected a non-empty list of mode indices",
                    )
                    .label(v.span, "write e.g. `[1, 2, 5]` (elastic modes, 1-based)"),
                );
                ok = false;
            }
        }
    }
    if let Some(v) = fl.value("band") {
        match &v.kind {
            ValueKind::List(items) if items.len() == 2 => {
                let lo = f::non_negative(f::quantity(cx, &items[0], Dim::FREQUENCY), cx);
                let hi = f::positive(f::quantity(cx, &items[1], Dim::FREQUENCY), cx);
                match (lo, hi) {
                    (Some(lo), Some(hi)) if lo.value < hi.value => {
                        rules.push(ModeRule::BandHz { lo, hi })
                    }
                    (Some(_), Some(hi)) => {
                        cx.push(
                            Diagnostic::error(
                                "vdl::value::range",
                                "the band's upper frequency is not above its lower one",
                            )
                            .label(hi.span, "upper bound"),
                        );
                        ok = false;
                    }
                    _ => ok = false,
                }
            }
            _ => {
                cx.push(
                    Diagnostic::error("vdl::type::mismatch", "expected `[LOW Hz, HIGH Hz]`")
                        .label(v.span, "a frequency band is a list of two frequencies"),
                );
                ok = false;
            }
        }
    }
    for (field, class) in [
        ("body_bending", ModeClass::BodyBending),
        ("fin_flap", ModeClass::FinFlap),
        ("fin_twist", ModeClass::FinTwist),
    ] {
        let Some(v) = fl.value(field) else { continue };
        let count = match &v.kind {
            ValueKind::Name(id) if id.name == "per_fin" => {
                if fins_failed {
                    ok = false;
                    continue;
                }
                if fins.is_none() {
                    cx.push(
                        Diagnostic::error(
                            "vdl::modes::no_fins",
                            format!("`{field} = per_fin` but the vehicle has no fins"),
                        )
                        .label(v.span, "no fins"),
                    );
                    ok = false;
                    continue;
                }
                ModeCount::PerFin
            }
            _ => match f::count(cx, v, 1, 1000) {
                Some(n) => ModeCount::Count(n),
                None => {
                    ok = false;
                    continue;
                }
            },
        };
        if class != ModeClass::BodyBending && fins.is_none() && !fins_failed {
            cx.push(
                Diagnostic::error(
                    "vdl::modes::no_fins",
                    format!("`{field}` modes are asked for but the vehicle has no fins"),
                )
                .label(v.span, "no fins"),
            );
            ok = false;
            continue;
        }
        rules.push(ModeRule::Class {
            class: Spanned::new(class, v.span),
            count: Spanned::new(count, v.span),
        });
    }
    let fixity_origin = match fl.value("fixity") {
        Some(v) => f::keyword(cx, v, &[("origin", true), ("none", false)]),
        None => Some(true),
    };
    let damping = match fl.value("damping") {
        None => Some(Vec::new()),
        Some(v) => match &v.kind {
            ValueKind::List(items) => items
                .iter()
                .map(|it| {
                    f::check_range(
                        f::number(cx, it),
                        cx,
                        |x| (0.0..1.0).contains(&x),
                        "a damping ratio 0 <= zeta < 1",
                    )
                })
                .collect(),
            _ => f::check_range(
                f::number(cx, v),
                cx,
                |x| (0.0..1.0).contains(&x),
                "a damping ratio 0 <= zeta < 1",
            )
            .map(|q| vec![q]),
        },
    };
    fl.finish(cx);
    if rules.is_empty() && ok {
        cx.push(
            Diagnostic::error("vdl::modes::empty", "the `modes` block selects no modes")
                .label(b.header, "nothing selected")
                .with_help("use `indices = [...]`, `band = [lo Hz, hi Hz]`, or classes like `body_bending = 2`, `fin_flap = per_fin`"),
        );
        return None;
    }
    if !ok {
        return None;
    }
    Some(ModeSelection {
        span: b.header,
        rules,
        fixity_origin: fixity_origin?,
        damping: damping?,
    })
}

/// `diameter`: `Some(Some(d))` for a generated body, `Some(None)` for FE files (no default
/// reference area), `None` when the structure failed (no cascade of "missing" errors).
fn check_aero(cx: &mut Cx, b: &Block, diameter: Option<Option<f64>>) -> Option<Aero> {
    let mut fl = Fields::new(cx, "the `aero` block", b.header, &b.body);
    let source_v = fl.required(cx, "source", "builtin");
    // `datcom("for006.dat", ...)`: Missile DATCOM output (check/datcom_source.rs).
    let datcom_v = source_v.filter(|v| {
        matches!(&v.kind, crate::syntax::ast::ValueKind::Call { name, .. } if name.name == "datcom")
    });
    let source_kind = match datcom_v {
        Some(_) => None,
        None => source_v.and_then(|v| f::keyword(cx, v, &[("builtin", false), ("tables", true)])),
    };
    let policy = |cx: &mut Cx, fl: &mut Fields, default: OutOfRange| match fl.value("out_of_range")
    {
        Some(v) => f::keyword(
            cx,
            v,
            &[("stop", OutOfRange::Stop), ("clamp", OutOfRange::Clamp)],
        )
        .map(|k| Spanned::new(k, v.span)),
        None => Some(Spanned::new(default, b.header)),
    };
    // Some(true): the built-in estimator; Some(false): tables or DATCOM; None: no source.
    let builtin = match (source_kind, datcom_v) {
        (Some(k), _) => Some(!k),
        (None, Some(_)) => Some(false),
        (None, None) => None,
    };
    let finish = check_finish(cx, &mut fl, b.header, builtin);
    let source = match source_kind {
        Some(false) => match (policy(cx, &mut fl, OutOfRange::Clamp), finish) {
            (Some(out_of_range), Some(roughness)) => Some(AeroSource::Builtin {
                out_of_range,
                roughness,
            }),
            _ => None,
        },
        Some(true) => {
            let table = |cx: &mut Cx, fl: &mut Fields, name: &'static str| {
                let v = fl.required(cx, name, "\"aero/table.csv\"")?;
                let s = f::string(cx, v)?;
                cx.resolve_file(&s, v.span, "coefficient table")
                    .map(|p| Spanned::new(p, v.span))
            };
            let body = table(cx, &mut fl, "body_table");
            let fins = table(cx, &mut fl, "fin_table");
            let oor = policy(cx, &mut fl, OutOfRange::Stop);
            match (body, fins, oor) {
                (Some(body), Some(fins), Some(out_of_range)) => Some(AeroSource::Tables {
                    body,
                    fins,
                    out_of_range,
                }),
                _ => None,
            }
        }
        None => datcom_v.and_then(|v| {
            let (file, sel) = super::datcom_source::call(cx, v)?;
            let out_of_range = policy(cx, &mut fl, OutOfRange::Stop)?;
            Some(AeroSource::Datcom {
                file,
                case: sel.case,
                fin_set: sel.fin_set,
                out_of_range,
            })
        }),
    };
    let area = match (fl.value("reference_area"), diameter) {
        (Some(v), _) => f::positive(f::quantity(cx, v, Dim::AREA), cx),
        (None, Some(Some(d))) => Some(Spanned::new(PI * d * d / 4.0, b.header)),
        (None, Some(None)) => {
            fl.required(cx, "reference_area", "0.012668 m^2");
            None
        }
        (None, None) => None,
    };
    let length = match (fl.value("reference_length"), diameter) {
        (Some(v), _) => f::positive(f::quantity(cx, v, Dim::LENGTH), cx),
        (None, Some(Some(d))) => Some(Spanned::new(d, b.header)),
        (None, Some(None)) => {
            fl.required(cx, "reference_length", "127 mm");
            None
        }
        (None, None) => None,
    };
    let point = fl
        .required(cx, "reference_point", "(-1.59, 0, 0) m")
        .and_then(|v| f::vector3(cx, v, Dim::LENGTH));
    fl.finish(cx);
    if let Some(p) = &point {
        if p.value[0] > 0.0 {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the reference point lies ahead of the nose (x > 0)",
                )
                .label(p.span, "x must be <= 0 in the body frame"),
            );
            return None;
        }
    }
    Some(Aero {
        span: b.header,
        source: source?,
        reference_area: area?,
        reference_length: length?,
        reference_point: point?,
    })
}

/// `aero { finish = regular_paint }` (a named finish of `check::finish::FINISHES`) or
/// `finish = 60 um` (a roughness height, 0 to 10 mm): the surface roughness of the built-in
/// drag model, OpenRocket's default regular paint (60 um) when not written. With another
/// source it would have no effect: `vdl::aero::finish` (only when the source was read).
fn check_finish(
    cx: &mut Cx,
    fl: &mut Fields,
    header: Span,
    builtin: Option<bool>,
) -> Option<Spanned<f64>> {
    use super::finish::{DEFAULT_ROUGHNESS, FINISHES};
    let Some(v) = fl.value("finish") else {
        return Some(Spanned::new(DEFAULT_ROUGHNESS, header));
    };
    if builtin != Some(true) {
        builtin?;
        cx.push(
            Diagnostic::error(
                "vdl::aero::finish",
                "`finish` is the surface roughness of the built-in drag model; this `aero` block reads its coefficients from files",
            )
            .label(v.span, "no effect with this source")
            .with_help("remove `finish`, or use `source = builtin`"),
        );
        return None;
    }
    if let ValueKind::Name(_) = &v.kind {
        let options: Vec<(&'static str, f64)> = FINISHES.iter().map(|f| (f.0, f.2)).collect();
        return f::keyword(cx, v, &options).map(|r| Spanned::new(r, v.span));
    }
    f::check_range(
        f::quantity(cx, v, Dim::LENGTH),
        cx,
        |x| (0.0..=0.01).contains(&x),
        "a roughness height 0 <= R_s <= 10 mm",
    )
}

/// `enabled = false` turns a force block off (useful in overrides).
fn enabled(cx: &mut Cx, fl: &mut Fields) -> bool {
    fl.value("enabled")
        .and_then(|v| f::boolean(cx, v))
        .unwrap_or(true)
}

fn check_forces(cx: &mut Cx, b: &Block) -> Option<Forces> {
    let mut fl = Fields::new(cx, "the `forces` block", b.header, &b.body);
    let g = fl.block("gravity");
    let t = fl.block("thrust");
    let ba = fl.block("body_aero");
    let fa = fl.block("fin_aero");
    fl.finish(cx);
    let mut forces = Forces::default();
    let mut ok = true;
    if let Some(g) = g {
        let mut fl = Fields::new(cx, "the `gravity` block", g.header, &g.body);
        let on = enabled(cx, &mut fl);
        let alt = fl
            .value("altitude_correction")
            .and_then(|v| f::boolean(cx, v))
            .unwrap_or(true);
        fl.finish(cx);
        if on {
            forces.gravity = Some(Gravity {
                span: g.header,
                altitude_correction: alt,
            });
        }
    }
    if let Some(t) = t {
        let mut fl = Fields::new(cx, "the `thrust` block", t.header, &t.body);
        let on = enabled(cx, &mut fl);
        // Without `curve` the vehicle's motor gives the thrust (checked with the vehicle);
        // the path is then empty. A curve given here is read and checked now.
        let curve = match fl.value("curve") {
            Some(v) => f::string(cx, v).and_then(|s| {
                let p = cx.resolve_file(&s, v.span, "thrust curve")?;
                super::motor::read_curve(cx, &p, v.span)?;
                Some(Spanned::new(p, v.span))
            }),
            None => Some(Spanned::new(std::path::PathBuf::new(), t.header)),
        };
        let offset = match fl.value("offset") {
            Some(v) => f::vector3(cx, v, Dim::LENGTH),
            None => Some(Spanned::new([0.0; 3], t.header)),
        };
        let mis = match fl.value("misalignment") {
            Some(v) => f::vector3(cx, v, Dim::ANGLE),
            None => Some(Spanned::new([0.0; 3], t.header)),
        };
        fl.finish(cx);
        match (curve, offset, mis) {
            (Some(curve), Some(offset), Some(misalignment)) => {
                if on {
                    forces.thrust = Some(Thrust {
                        span: t.header,
                        curve,
                        offset,
                        misalignment,
                    });
                }
            }
            _ => ok = false,
        }
    }
    if let Some(ba) = ba {
        let mut fl = Fields::new(cx, "the `body_aero` block", ba.header, &ba.body);
        let on = enabled(cx, &mut fl);
        let rate = fl
            .value("rate_terms")
            .and_then(|v| f::boolean(cx, v))
            .unwrap_or(false);
        fl.finish(cx);
        if on {
            forces.body_aero = Some(BodyAero {
                span: ba.header,
                rate_terms: rate,
            });
        }
    }
    if let Some(fa) = fa {
        let mut fl = Fields::new(cx, "the `fin_aero` block", fa.header, &fa.body);
        let on = enabled(cx, &mut fl);
        let dist = match fl.value("distribution") {
            Some(v) => f::keyword(
                cx,
                v,
                &[
                    ("theory", Distribution::Theory),
                    ("uniform", Distribution::Uniform),
                ],
            )
            .map(|d| Spanned::new(d, v.span)),
            None => Some(Spanned::new(Distribution::Theory, fa.header)),
        };
        let lw = fl
            .value("leeward_reduction")
            .and_then(|v| f::boolean(cx, v))
            .unwrap_or(true);
        let incidence_value = fl.value("incidence");
        let incidence = match incidence_value {
            Some(v) => f::keyword(
                cx,
                v,
                &[
                    ("key_node", FinIncidence::KeyNode),
                    ("load_weighted", FinIncidence::LoadWeighted),
                ],
            )
            .map(|d| Spanned::new(d, v.span)),
            None => Some(Spanned::new(FinIncidence::KeyNode, fa.header)),
        };
        let incidence_given = incidence_value.is_some();
        let model = match fl.value("model") {
            Some(v) => f::keyword(
                cx,
                v,
                &[
                    ("key_node", FinAeroModel::KeyNode),
                    ("lifting_surface", FinAeroModel::LiftingSurface),
                ],
            )
            .map(|d| Spanned::new(d, v.span)),
            None => Some(Spanned::new(FinAeroModel::LiftingSurface, fa.header)),
        };
        // `incidence` chooses where the key-node model reads the fin's deformation; the
        // lifting-surface model reads all of it from the panels, so the field would be
        // silently ignored.
        if let (Some(m), Some(i), true) = (&model, &incidence, incidence_given) {
            if m.value == FinAeroModel::LiftingSurface {
                cx.push(
                    Diagnostic::error(
                        "vdl::fin_aero::incidence_unused",
                        "`incidence` only applies to `model = key_node`: the lifting-surface model takes the fin's deformation from its panels",
                    )
                    .label(i.span, "`incidence` given here")
                    .label(m.span, "the fin aerodynamic model in effect")
                    .with_help("remove `incidence`, or set `model = key_node`"),
                );
                ok = false;
            }
        }
        let stress = fl.value("stress_limit").map(|v| {
            f::check_range(
                f::number(cx, v),
                cx,
                |x| x > 0.0 && x <= 10.0,
                "a fraction of yield in (0, 10]",
            )
        });
        fl.finish(cx);
        let stress = match stress {
            Some(None) => {
                ok = false;
                None
            }
            Some(s) => s,
            None => None,
        };
        match (dist, incidence, model) {
            (Some(distribution), Some(incidence), Some(model)) if on => {
                forces.fin_aero = Some(FinAero {
                    span: fa.header,
                    distribution,
                    leeward_reduction: lw,
                    stress_limit_fraction: stress,
                    incidence,
                    model,
                })
            }
            (Some(_), Some(_), Some(_)) => {}
            _ => ok = false,
        }
    }
    ok.then_some(forces)
}

/// `nose_shape = conical | ogive | elliptical | parabolic | von_karman | lv_haack` or
/// `ogive(k) | parabolic(K) | power(n) | haack(C)` (`check::nose`); an unknown shape
/// (`vdl::value::keyword`) or a parameter outside its range (`vdl::nose::parameter`) is an
/// error at its span.
pub(super) fn nose_shape(cx: &mut Cx, v: &Value) -> Option<Spanned<NoseShape>> {
    use super::nose::{NAMED, WITH_PARAMETER};
    if let ValueKind::Call { name, args } = &v.kind {
        f::record_keywords(WITH_PARAMETER.iter().map(|(n, _, _)| *n));
        let Some((_, what, range)) = WITH_PARAMETER.iter().find(|(n, _, _)| *n == name.name) else {
            let names = WITH_PARAMETER.iter().map(|(n, _, _)| *n);
            let mut d = Diagnostic::error(
                "vdl::value::keyword",
                format!(
                    "`{}(...)` is not a nose shape with a parameter: {}",
                    name.name,
                    WITH_PARAMETER
                        .iter()
                        .map(|(n, w, _)| format!("`{n}({w})`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
            .label(v.span, "unknown nose shape");
            if let Some(s) = did_you_mean(&name.name, names) {
                d = d.with_help(format!("did you mean `{s}`?"));
            }
            cx.push(d);
            return None;
        };
        let [arg] = args.as_slice() else {
            cx.push(
                Diagnostic::error(
                    "vdl::nose::parameter",
                    format!("`{}` takes one parameter, its {what} ({range})", name.name),
                )
                .label(v.span, format!("{} given", args.len())),
            );
            return None;
        };
        let p = f::number(cx, &arg.value)?;
        return match NoseShape::with_parameter(&name.name, p.value) {
            Ok(s) => Some(Spanned::new(s, v.span)),
            Err(range) => {
                cx.push(
                    Diagnostic::error(
                        "vdl::nose::parameter",
                        format!(
                            "the {} nose's {what} = {} is outside {range}",
                            name.name, p.value
                        ),
                    )
                    .label(arg.value.span, format!("must be {range}"))
                    .with_help(
                        "outside this range the profile would not rise from the tip to the base (docs/language.md, nose shapes)",
                    ),
                );
                None
            }
        };
    }
    f::keyword(cx, v, NAMED).map(|s| Spanned::new(s, v.span))
}

/// `grain` on an isotropic material (a fin set's or a fixture surface's):
/// `vdl::material::orthotropic` at the `grain` and at the material's name; `what` is how the
/// message names the material.
pub(super) fn grain_without_lamina(cx: &mut Cx, grain: Span, m: &Material, what: &str) {
    cx.push(
        Diagnostic::error(
            "vdl::material::orthotropic",
            format!(
                "`grain` orients an orthotropic lamina; {what} `{}` is isotropic",
                m.name.value
            ),
        )
        .label(grain, "no grain to orient")
        .label(m.name.span, "declared without `E2` and `G12`"),
    );
}
