//! Verification of the built-in FE generator (structure::generate): beam and plate
//! frequencies against classical results, fin mesh convergence, rigid-body mass properties
//! and stiffness null space, input errors, and scale.

#![allow(clippy::unwrap_used)]

use flexflight::structure::generate::{
    BeamTheory, BodySpec, DistributedMass, FinSpec, GeneratorSpec, MaterialProps, PointMass,
    analytic_mass_properties, cantilever_fin_model, generate, rigid_body_projection,
};
use flexflight::structure::{Component, FeModel, modal};
use std::f64::consts::PI;

fn aluminium() -> MaterialProps {
    MaterialProps {
        youngs_modulus: 70e9,
        poisson: 0.346,
        density: 2710.0,
    }
}

fn tube(length: f64, diameter: f64, wall: f64, elements: usize, theory: BeamTheory) -> BodySpec {
    BodySpec {
        length,
        outer_diameter: diameter,
        wall_thickness: wall,
        nose_length: 0.0,
        nose_shape: flexflight::check::ir::NoseShape::Conical,
        transitions: Vec::new(),
        elements,
        theory,
        material: aluminium(),
    }
}

/// SPHADS-1 fin (Table 4.1), unswept trailing edge (App. A.2.6).
fn sphads_fin(thickness: f64, chord_elements: usize, span_elements: usize) -> FinSpec {
    let (span, root, tip) = (0.12723, 0.32468, 0.12267);
    FinSpec {
        count: 4,
        span,
        root_chord: root,
        tip_chord: tip,
        sweep: ((root - tip) / span).atan(),
        thickness,
        cant: 0.0,
        angles: vec![],
        root_trailing_edge_x: -2.75,
        span_elements,
        chord_elements,
        material: aluminium(),
        lamina: None,
        outline: flexflight::check::ir::FinOutline::Trapezoidal,
    }
}

/// The body alone: no fins, no masses.
fn body_only(body: BodySpec) -> GeneratorSpec {
    GeneratorSpec {
        body,
        fins: None,
        point_masses: vec![],
        distributed_masses: vec![],
        rigid_fins: vec![],
    }
}

fn free_free_frequencies(body: BodySpec) -> Vec<f64> {
    let spec = body_only(body);
    let model = generate(&spec).unwrap();
    modal::solve(&model, 12).unwrap().frequencies_hz()
}

/// Free-free uniform tube, Euler-Bernoulli elements (with rotary inertia): the first three
/// bending frequencies within 0.5 % of beta_n L = 4.7300, 7.8532, 10.9956,
/// f = (beta L)^2 / (2 pi L^2) sqrt(EI / (rho A)). Slender tube (r_g / L = 0.005) so that
/// rotary inertia moves the third mode by < 0.1 %.
#[test]
fn free_free_tube_matches_euler_bernoulli_theory() {
    let (l, d, t) = (2.75, 0.04, 0.002);
    let (ro, ri) = (d / 2.0, d / 2.0 - t);
    let a = PI * (ro * ro - ri * ri);
    let i = PI / 4.0 * (ro.powi(4) - ri.powi(4));
    let c = (70e9 * i / (2710.0 * a)).sqrt();
    let theory: Vec<f64> = [4.7300f64, 7.8532, 10.9956]
        .iter()
        .map(|bl| bl * bl / (2.0 * PI * l * l) * c)
        .collect();
    let eb = free_free_frequencies(tube(l, d, t, 60, BeamTheory::EulerBernoulli));
    let timo = free_free_frequencies(tube(l, d, t, 60, BeamTheory::Timoshenko));
    for f in [&eb, &timo] {
        // Six rigid-body modes first.
        for rigid in &f[..6] {
            assert!(*rigid < 1e-3 * theory[0], "rigid mode at {rigid} Hz");
        }
    }
    for n in 0..3 {
        let (f1, f2) = (eb[6 + 2 * n], eb[7 + 2 * n]);
        assert!(
            (f1 - f2).abs() < 1e-6 * f1,
            "bending pair {n}: {f1} vs {f2}"
        );
        let err = (f1 - theory[n]) / theory[n];
        let ft = timo[6 + 2 * n];
        println!(
            "bending {}: EB theory {:.4} Hz; FE Euler-Bernoulli {f1:.4} Hz ({:+.4} %); FE Timoshenko {ft:.4} Hz ({:+.4} %)",
            n + 1,
            theory[n],
            100.0 * err,
            100.0 * (ft - theory[n]) / theory[n]
        );
        assert!(err.abs() < 5e-3, "mode {n}: error {err}");
        // Rotary inertia only lowers the converged EB value; shear lowers it further.
        assert!(err < 0.0);
        assert!(ft < f1);
    }
}

/// Frequency parameters lambda = omega a^2 sqrt(rho t / D) of a cantilever plate.
fn plate_lambdas(fin: &FinSpec, a: f64) -> Vec<f64> {
    let model = cantilever_fin_model(fin).unwrap();
    let m = fin.material;
    let dflex = m.youngs_modulus * fin.thickness.powi(3) / (12.0 * (1.0 - m.poisson.powi(2)));
    modal::solve(&model, 12)
        .unwrap()
        .omega2
        .iter()
        .map(|w2| w2.sqrt() * a * a * (m.density * fin.thickness / dflex).sqrt())
        .collect()
}

fn plate(a_chord: f64, span: f64, sweep: f64, n_chord: usize, n_span: usize) -> FinSpec {
    FinSpec {
        count: 1,
        span,
        root_chord: a_chord,
        tip_chord: a_chord,
        sweep,
        thickness: a_chord / 200.0,
        cant: 0.0,
        angles: vec![],
        root_trailing_edge_x: -1.0,
        span_elements: n_span,
        chord_elements: n_chord,
        material: MaterialProps {
            youngs_modulus: 70e9,
            poisson: 0.3,
            density: 2700.0,
        },
        lamina: None,
        outline: flexflight::check::ir::FinOutline::Trapezoidal,
    }
}

/// Square cantilever plate, nu = 0.3: lambda_1 = 3.492 (first bending), lambda_2 = 8.525
/// (first torsion); Leissa, Vibration of Plates, NASA SP-160 (1969), from Barton (1951); the
/// same values are the reference of code_aster test SDLS01. Within 2 %.
#[test]
fn square_cantilever_plate_matches_leissa() {
    let a = 0.2;
    let lam = plate_lambdas(&plate(a, a, 0.0, 16, 16), a);
    for (got, want) in lam.iter().zip([3.492, 8.525]) {
        let err = (got - want) / want;
        println!(
            "square cantilever: lambda {got:.4} vs {want} ({:+.3} %)",
            100.0 * err
        );
        assert!(err.abs() < 0.02);
    }
}

/// Skew (rhombic) cantilever plate of side a, skew angle 30 deg, nu = 0.3:
/// lambda_1 = 3.961, lambda_2 = 10.19 (Barton, J. Appl. Mech. 18 (1951) 129-134, as used by
/// code_aster test SDLS02; code_aster calls Barton's expansion "limited and insufficient").
/// lambda_1 within 2 %. Barton's values come from a short Ritz expansion and are upper
/// bounds; for the second (torsion) mode the FE value (9.44 with 16 x 16) lies 7 % below
/// it, so only the bound is asserted there. This is NOT a second Leissa table check.
#[test]
fn skew_cantilever_plate_matches_barton() {
    let a = 0.2;
    let alpha = 30f64.to_radians();
    let lam = plate_lambdas(&plate(a, a * alpha.cos(), alpha, 16, 16), a);
    for (got, want) in lam.iter().zip([3.961, 10.19]) {
        let err = (got - want) / want;
        println!(
            "skew 30 deg cantilever: lambda {got:.4} vs {want} ({:+.3} %)",
            100.0 * err
        );
    }
    assert!(((lam[0] - 3.961) / 3.961).abs() < 0.02);
    assert!(lam[1] < 10.19);
}

/// SPHADS-1 fin (1 mm), clamped root: the first two frequencies converge monotonically
/// under uniform refinement, the last two meshes within 1 %. "Monotone" allows steps below
/// 1e-4 relative once converged (the first bending frequency settles to 5 digits by the
/// 16 x 8 mesh and then moves by +-5e-5 relative).
#[test]
fn sphads_fin_cantilever_converges() {
    let meshes = [(8, 4), (16, 8), (24, 12), (32, 16)];
    let mut table = Vec::new();
    for &(nc, ns) in &meshes {
        let fin = sphads_fin(0.001, nc, ns);
        let model = cantilever_fin_model(&fin).unwrap();
        let f: Vec<f64> = modal::solve(&model, 12)
            .unwrap()
            .omega2
            .iter()
            .map(|w2| w2.sqrt() / (2.0 * PI))
            .collect();
        println!(
            "mesh {nc:>2} x {ns:>2} ({:>5} DOF): f1 = {:.3} Hz, f2 = {:.3} Hz",
            model.n_dof(),
            f[0],
            f[1]
        );
        table.push([f[0], f[1]]);
    }
    for mode in 0..2 {
        let col: Vec<f64> = table.iter().map(|r| r[mode]).collect();
        let steps: Vec<f64> = col.windows(2).map(|w| w[1] - w[0]).collect();
        let settled = |s: &f64| s.abs() < 1e-4 * col[0];
        let down = steps.iter().all(|s| *s < 0.0 || settled(s));
        let up = steps.iter().all(|s| *s > 0.0 || settled(s));
        assert!(down || up, "mode {mode} not monotone: {col:?}");
        for w in steps.windows(2) {
            assert!(
                w[1].abs() < w[0].abs() || settled(&w[1]),
                "mode {mode} increments grow: {steps:?}"
            );
        }
        let n = col.len();
        let last = (col[n - 1] - col[n - 2]).abs() / col[n - 1];
        assert!(last < 0.01, "mode {mode}: last change {last}");
    }
}

/// A vehicle with nose, four canted fins, point masses (off-axis, with inertia) and
/// distributed masses.
fn full_vehicle(theory: BeamTheory) -> GeneratorSpec {
    let mut fins = sphads_fin(0.001, 12, 6);
    fins.cant = 0.02;
    fins.root_trailing_edge_x = -2.70;
    GeneratorSpec {
        body: BodySpec {
            length: 2.75,
            outer_diameter: 0.127,
            wall_thickness: 0.003,
            nose_length: 0.45,
            nose_shape: flexflight::check::ir::NoseShape::Conical,
            transitions: Vec::new(),
            elements: 40,
            theory,
            material: aluminium(),
        },
        fins: Some(fins),
        point_masses: vec![
            PointMass {
                name: "payload".into(),
                position: [-0.6, 0.01, -0.02],
                mass: 4.0,
                inertia: [0.01, 0.05, 0.06],
            },
            PointMass {
                name: "avionics".into(),
                position: [-1.13, 0.0, 0.0],
                mass: 1.5,
                inertia: [0.002, 0.003, 0.003],
            },
        ],
        distributed_masses: vec![
            DistributedMass {
                name: "propellant".into(),
                x_from: -1.2,
                x_to: -2.6,
                mass: 20.0,
            },
            DistributedMass {
                name: "liner".into(),
                x_to: -0.3,
                x_from: -2.75,
                mass: 2.0,
            },
        ],
        rigid_fins: vec![],
    }
}

fn assert_rigid_projection_matches(model: &FeModel, spec: &GeneratorSpec) {
    let fe = rigid_body_projection(model);
    let exact = analytic_mass_properties(spec).rigid_mass_matrix();
    let m = exact[0][0];
    let c = (0..3)
        .map(|i| exact[3 + ((i + 1) % 3)][(i + 2) % 3].abs())
        .fold(0.0, f64::max);
    let j = exact[3][3] + exact[4][4] + exact[5][5];
    for a in 0..6 {
        for b in 0..6 {
            let scale = match (a < 3, b < 3) {
                (true, true) => m,
                (false, false) => j,
                _ => c,
            };
            let err = (fe[a][b] - exact[a][b]).abs() / scale;
            assert!(
                err < 1e-9,
                "({a},{b}): FE {} vs analytic {} (rel {err:e})",
                fe[a][b],
                exact[a][b]
            );
        }
    }
}

/// R^T M R of the assembled model equals the closed-form mass, first moment and inertia
/// tensor about the nose tip to 1e-9 (relative to the block's scale).
#[test]
fn rigid_body_projection_of_mass_matches_analytic() {
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let spec = full_vehicle(theory);
        let model = generate(&spec).unwrap();
        assert_rigid_projection_matches(&model, &spec);
        let mp = analytic_mass_properties(&spec);
        println!(
            "{theory:?}: mass {:.4} kg, x_cm {:.4} m",
            mp.mass,
            mp.first_moment[0] / mp.mass
        );
    }
}

/// The stiffness annihilates the six rigid-body vectors (to round-off relative to ||K||).
#[test]
fn stiffness_annihilates_rigid_body_vectors() {
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let spec = full_vehicle(theory);
        let model = generate(&spec).unwrap();
        let r = flexflight::structure::generate::rigid_body_vectors(&model);
        let kmax = model
            .stiffness
            .val()
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let rmax = r.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut kr = vec![[0.0f64; 6]; model.n_dof()];
        for t in model.stiffness.triplet_iter() {
            for q in 0..6 {
                kr[t.row][q] += t.val * r[t.col][q];
            }
        }
        let worst = kr.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        println!(
            "{theory:?}: max |K r| / (max|K| max|r|) = {:e}",
            worst / (kmax * rmax)
        );
        assert!(worst < 1e-12 * kmax * rmax);
    }
}

/// Node 0 (id 1) is the nose tip; components and symmetry.
#[test]
fn model_layout_and_symmetry() {
    let spec = full_vehicle(BeamTheory::EulerBernoulli);
    let model = generate(&spec).unwrap();
    assert_eq!(model.nodes[0].id, 1);
    assert_eq!(model.nodes[0].position, [0.0, 0.0, 0.0]);
    let fin_nodes = model
        .nodes
        .iter()
        .filter(|n| matches!(n.component, Component::Fin(_)))
        .count();
    assert_eq!(fin_nodes, 4 * 6 * 13);
    for mat in [&model.mass, &model.stiffness] {
        let d = mat.to_dense();
        let scale = d.norm_max();
        for i in 0..d.nrows() {
            for j in 0..i {
                assert!((d[(i, j)] - d[(j, i)]).abs() <= 1e-12 * scale);
            }
        }
    }
    // Fin 1 lies along +z (delta = pi/2): its nodes have y ~ 0 up to the cant offset.
    for n in model
        .nodes
        .iter()
        .filter(|n| n.component == Component::Fin(1))
    {
        assert!(n.position[2] > 0.0635 - 1e-12);
        assert!(n.position[1].abs() < 0.02 * 0.33);
    }
}

/// Invalid input is rejected with a typed error and a stable code.
#[test]
fn bad_input_is_rejected() {
    let base = full_vehicle(BeamTheory::EulerBernoulli);
    type Mutation = Box<dyn Fn(&mut GeneratorSpec)>;
    let cases: Vec<(Mutation, &str)> = vec![
        (Box::new(|s| s.body.length = -1.0), "generate::bad_geometry"),
        (
            Box::new(|s| s.body.wall_thickness = 0.07),
            "generate::bad_geometry",
        ),
        (
            Box::new(|s| s.body.nose_length = 3.0),
            "generate::bad_geometry",
        ),
        (Box::new(|s| s.body.elements = 0), "generate::zero_elements"),
        (
            Box::new(|s| s.body.material.poisson = 0.5),
            "generate::bad_material",
        ),
        (
            Box::new(|s| s.fins.as_mut().unwrap().tip_chord = 0.4),
            "generate::bad_geometry",
        ),
        (
            Box::new(|s| s.fins.as_mut().unwrap().root_trailing_edge_x = -2.9),
            "generate::fin_outside_body",
        ),
        (
            Box::new(|s| s.fins.as_mut().unwrap().root_trailing_edge_x = -0.5),
            "generate::fin_outside_body",
        ),
        (
            Box::new(|s| s.fins.as_mut().unwrap().chord_elements = 0),
            "generate::zero_elements",
        ),
        (
            Box::new(|s| s.fins.as_mut().unwrap().angles = vec![0.0; 3]),
            "generate::bad_fin_angles",
        ),
        (
            Box::new(|s| s.distributed_masses[0].x_to = -3.0),
            "generate::mass_outside_body",
        ),
        (
            Box::new(|s| s.point_masses[0].position[0] = 0.1),
            "generate::mass_outside_body",
        ),
        (
            Box::new(|s| s.point_masses[0].mass = 0.0),
            "generate::bad_mass",
        ),
        (
            Box::new(|s| s.point_masses[0].inertia[1] = -1.0),
            "generate::bad_mass",
        ),
    ];
    for (i, (mutate, code)) in cases.iter().enumerate() {
        let mut s = base.clone();
        mutate(&mut s);
        let err = generate(&s).expect_err(&format!("case {i} accepted"));
        assert_eq!(err.code(), *code, "case {i}: {err}");
    }
}

/// Dense fin meshes build a ~100,000-DOF model from triplets.
#[test]
fn large_model_builds() {
    let mut spec = full_vehicle(BeamTheory::Timoshenko);
    let fins = spec.fins.as_mut().unwrap();
    fins.chord_elements = 80;
    fins.span_elements = 50;
    spec.body.elements = 400;
    let t0 = std::time::Instant::now();
    let model = generate(&spec).unwrap();
    println!(
        "large model: {} DOF, nnz(K) = {}, nnz(M) = {}, built in {:.2} s",
        model.n_dof(),
        model.stiffness.compute_nnz(),
        model.mass.compute_nnz(),
        t0.elapsed().as_secs_f64()
    );
    assert!(model.n_dof() > 95_000);
    assert_rigid_projection_matches(&model, &spec);
}

/// Mass and first moment about the tip (`∫ rho A s ds`) of a body of length `length`, radius
/// `r` and wall `t` whose nose of length `ln` has `shape`: the nose (between r(s) and
/// max(r(s) - t, 0)) by composite Simpson's rule in s on 400,000 panels, independent of the
/// generator's substituted Gauss rule; the tube by its closed form.
fn simpson_body_mass(
    shape: flexflight::check::ir::NoseShape,
    length: f64,
    r: f64,
    t: f64,
    ln: f64,
    rho: f64,
) -> (f64, f64) {
    let n = 400_000;
    let h = ln / n as f64;
    let (mut m_nose, mut mx_nose) = (0.0, 0.0);
    for i in 0..=n {
        let s = i as f64 * h;
        let ro = shape.radius(s, r, ln);
        let ri = (ro - t).max(0.0);
        let a = PI * (ro * ro - ri * ri);
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        m_nose += w * a * h / 3.0;
        mx_nose += w * a * s * h / 3.0;
    }
    let a_tube = PI * (r * r - (r - t) * (r - t));
    (
        rho * (m_nose + a_tube * (length - ln)),
        rho * (mx_nose + a_tube * (length * length - ln * ln) / 2.0),
    )
}

/// Every nose shape (issue 34): the generated body's rigid-body projection (the FE mass
/// matrix's mass, first moment and inertia) equals the profile's integrals, and its mass
/// equals the solid of revolution between r(s) and max(r(s) - t, 0) integrated independently
/// here by composite Simpson's rule in s on 400,000 panels (not the generator's substituted
/// Gauss rule). Closed form for the thin-wall limit: the shell's mass tends to
/// rho t ∫ 2 pi r ds (the profile's side surface times the wall, to first order in t).
#[test]
fn every_nose_shape_has_the_mass_and_inertia_of_its_profile() {
    use flexflight::check::ir::NoseShape;
    let shapes = [
        NoseShape::Conical,
        NoseShape::Ogive { k: 1.0 },
        NoseShape::Ogive { k: 0.5 },
        NoseShape::Elliptical,
        NoseShape::Parabolic { k: 1.0 },
        NoseShape::Parabolic { k: 0.5 },
        NoseShape::Power { n: 0.5 },
        NoseShape::Power { n: 0.3 },
        NoseShape::Haack { c: 0.0 },
        NoseShape::Haack { c: 1.0 / 3.0 },
    ];
    let (length, d, t, ln) = (2.0, 0.102, 0.002, 0.4);
    let (r, rho) = (0.5 * d, aluminium().density);
    let mut worst = (0.0f64, 0.0f64);
    for shape in shapes {
        let mut body = tube(length, d, t, 40, BeamTheory::EulerBernoulli);
        body.nose_length = ln;
        body.nose_shape = shape;
        let spec = body_only(body);
        let model = generate(&spec).unwrap();
        let fe = rigid_body_projection(&model);
        let analytic = analytic_mass_properties(&spec);
        // Independent quadrature of the nose, plus the tube's closed form.
        let (m, mx) = simpson_body_mass(shape, length, r, t, ln, rho);
        let e_mass = (fe[0][0] - m).abs() / m;
        // First moment about the tip: -m x_cm = -mx (x = -s).
        let e_first = (fe[4][2].abs() - mx).abs() / mx;
        worst = (worst.0.max(e_mass), worst.1.max(e_first));
        assert!(
            e_mass < 3e-10 && e_first < 1e-12,
            "{shape:?}: FE mass {} vs {m} ({e_mass:e}), first moment ({e_first:e})",
            fe[0][0]
        );
        assert_rigid_projection_matches(&model, &spec);
        assert!((analytic.mass - m).abs() / m < 3e-10, "{shape:?}");
    }
    eprintln!(
        "nose shapes: worst mass {:e}, first moment {:e}",
        worst.0, worst.1
    );
}

/// A nose's solid-tip end (r_o = t) within 0.3 of a division of the tip is no body station
/// (an elliptical nose's is t^2 l_n / (2 R^2) from the tip: 36 um on RockSim's
/// BodyTubeChildrenTest, whose element hid the body's modes under the rigid-mode threshold),
/// and the beam element across it is integrated in its two parts: with a wall thick enough
/// that the solid tip is a fifth of a division, its mass and first moment equal the solid of
/// revolution's (composite Simpson on 400,000 panels) to 1e-12 (5e-14 measured; one rule
/// across the kink in A(s) gave 1.1e-7). On the old mesh the station was a node.
#[test]
fn a_solid_tip_end_near_the_tip_is_integrated_not_meshed() {
    use flexflight::check::ir::NoseShape;
    let (length, d, ln, elements) = (2.0, 0.102, 0.4, 40);
    let r = 0.5 * d;
    let h = length / elements as f64;
    for (shape, s_solid) in [
        (NoseShape::Elliptical, 0.2 * h),
        (NoseShape::Elliptical, 0.02 * h),
        (NoseShape::Conical, 0.25 * h),
    ] {
        // The wall that puts the solid-tip end at s_solid.
        let t = shape.radius(s_solid, r, ln);
        let mut body = tube(length, d, t, elements, BeamTheory::EulerBernoulli);
        body.nose_length = ln;
        body.nose_shape = shape;
        let s0 = shape.solid_tip_end(t, r, ln);
        assert!(
            (s0 - s_solid).abs() < 1e-9 * h,
            "{shape:?}: {s0} vs {s_solid}"
        );
        let spec = body_only(body);
        let model = generate(&spec).unwrap();
        let first_aft_of_tip = model
            .nodes
            .iter()
            .filter(|n| n.component == Component::Body && n.position[0] < 0.0)
            .map(|n| -n.position[0])
            .fold(f64::INFINITY, f64::min);
        assert!(
            first_aft_of_tip > 0.3 * h,
            "{shape:?}: a body node {first_aft_of_tip} m aft of the tip (solid-tip end {s0})"
        );
        let fe = rigid_body_projection(&model);
        let (m, mx) = simpson_body_mass(shape, length, r, t, ln, aluminium().density);
        let e_mass = (fe[0][0] - m).abs() / m;
        let e_first = (fe[4][2].abs() - mx).abs() / mx;
        eprintln!("{shape:?}, solid tip {s0:.3e} m: mass {e_mass:e}, first moment {e_first:e}");
        assert!(
            e_mass < 1e-12 && e_first < 1e-12,
            "{shape:?}: FE mass {} vs {m} ({e_mass:e}), first moment ({e_first:e})",
            fe[0][0]
        );
        assert_rigid_projection_matches(&model, &spec);
    }
}

/// A canted fin's root nodes sit `(1 - cos cant)` of their distance from the pivot forward of
/// the root's ends; with the root's trailing edge at the tail, at 1 deg that is 25 um ahead
/// of it. The body stations no longer take such a root node's x when another hard station
/// lies within 1e-3 of a division of it (the node is linked to that station with its offset):
/// no body element is shorter than that. The old mesh's 25 um element made the modal solve
/// of a canted SPHADS-1 run past 100 s and `hpr_k1000` with `fins.cant = 1 deg` end in
/// `modal::mechanisms`; it now compiles with the uncanted vehicle's body and fin
/// frequencies to 1e-3.
#[test]
fn a_canted_fins_root_leaves_no_sliver_body_element() {
    let mut spec = full_vehicle(BeamTheory::EulerBernoulli);
    let mut fins = spec.fins.take().unwrap();
    fins.root_trailing_edge_x = -2.75;
    fins.cant = 1f64.to_radians();
    spec.fins = Some(fins);
    let model = generate(&spec).unwrap();
    let mut xs: Vec<f64> = model
        .nodes
        .iter()
        .filter(|n| n.component == Component::Body)
        .map(|n| n.position[0])
        .collect();
    xs.sort_by(f64::total_cmp);
    let h = 2.75 / 40.0;
    let shortest = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    assert!(shortest > 1e-3 * h, "shortest body element {shortest} m");

    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let vehicle = |sets: &[String]| {
        let checked = flexflight::check::check_files(
            std::slice::from_ref(&file),
            sets,
            &flexflight::check::DiskLoader,
        );
        assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
        checked.program.vehicles[0].clone()
    };
    let (flat, _) = flexflight::structure::compile::compile(&vehicle(&[])).unwrap();
    let (canted, _) =
        flexflight::structure::compile::compile(&vehicle(&["fins.cant=1 deg".to_string()]))
            .unwrap();
    assert_same_modes(&flat, &canted, 1e-3);
}

/// The two compiled vehicles have the same modes, class by class, their frequencies within
/// `tol` relative.
fn assert_same_modes(
    a: &flexflight::structure::compile::CompiledVehicle,
    b: &flexflight::structure::compile::CompiledVehicle,
    tol: f64,
) {
    assert_eq!(a.modes.len(), b.modes.len());
    for (a, b) in a.modes.iter().zip(&b.modes) {
        assert_eq!(a.class, b.class);
        assert!(
            (b.frequency_hz / a.frequency_hz - 1.0).abs() < tol,
            "{}: {} Hz against {} Hz",
            a.class,
            b.frequency_hz,
            a.frequency_hz
        );
    }
}

/// Two hard stations a few micrometres apart are one station (`mesh::body_stations`): an
/// imported design wrote a distributed mass's end 5 um short of the tail (its stations
/// rounded to 10 um, its lengths to 0.1 um), and RockSim's "FooBar Test" ended in
/// `modal::mechanisms` (a 5 um beam's K_ii/M_ii, 7e17, put the rigid-mode threshold at
/// 1344 Hz, above the body's real modes) or, with a fin tip chord, ran its modal solve past
/// 5 minutes. hpr_k1000 with its motor mount's mass ending 5 um short of the tail: no body
/// element shorter than 1e-3 of a division, the tail exactly at -L, the compiled frequencies those of the exact stations
/// to 1e-5. On the old mesh the compile failed with `modal::mechanisms`.
#[test]
fn near_coincident_stations_leave_no_sliver_body_element() {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let text = std::fs::read_to_string(&file).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for e in std::fs::read_dir(file.parent().unwrap()).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.path().join(p.file_name().unwrap())).unwrap();
        }
    }
    let vehicle = |name: &str, body: &str| {
        let t = text.replacen("        to = -1.9 m\n", body, 1);
        assert_eq!(
            t.len(),
            text.len() - "        to = -1.9 m\n".len() + body.len()
        );
        let p = dir.path().join(name);
        std::fs::write(&p, t).unwrap();
        let checked = flexflight::check::check_files(&[p], &[], &flexflight::check::DiskLoader);
        assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
        checked.program.vehicles[0].clone()
    };
    let exact = vehicle("exact.vdl", "        to = -1.9 m\n");
    let near = vehicle("near.vdl", "        to = -1.899995 m\n");
    let flexflight::check::ir::Structure::Generate(g) = &near.structure else {
        panic!("generated")
    };
    let spec = flexflight::structure::compile::generator_spec(&near, g);
    let model = generate(&spec).unwrap();
    let mut xs: Vec<f64> = model
        .nodes
        .iter()
        .filter(|n| n.component == Component::Body)
        .map(|n| n.position[0])
        .collect();
    xs.sort_by(f64::total_cmp);
    let h = spec.body.length / spec.body.elements as f64;
    let shortest = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    assert!(shortest > 1e-3 * h, "shortest body element {shortest} m");
    assert_eq!(xs[0], -spec.body.length);
    let (a, _) = flexflight::structure::compile::compile(&exact).unwrap();
    let (b, _) = flexflight::structure::compile::compile(&near).unwrap();
    assert_same_modes(&a, &b, 1e-5);
}
