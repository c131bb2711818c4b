#![allow(clippy::needless_range_loop)]
//! The panel models of a compiled vehicle's fins (issue 12): the projection of the lattice
//! forces on the modes and the rigid normalwash, on the compiled SPHADS-1.

use std::sync::OnceLock;

use flexflight::aero::estimator::ESTIMATOR_MACH;
use flexflight::aero::panel::fin_model::{self, PanelSettings};
use flexflight::check::ir;
use flexflight::structure::compile::CompiledVehicle;

fn sphads1() -> &'static (ir::Vehicle, CompiledVehicle) {
    static MODEL: OnceLock<(ir::Vehicle, CompiledVehicle)> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/vehicles/sphads1.vdl");
        let checked =
            flexflight::check::check_files(&[path.into()], &[], &flexflight::check::DiskLoader);
        let v = checked.program.vehicles[0].clone();
        let c = flexflight::structure::compile::compile(&v).unwrap().0;
        (v, c)
    })
}

/// A copy of the compiled vehicle whose mode 0 is a unit plunge of fin `fin` (`z = 1` along
/// the panel normal) and mode 1 a unit pitch about `x_a` (`z = -(x - x_a)`, x aft of the root
/// leading edge), on EVERY node (so that the virtual root nodes, attached to body nodes, carry
/// the same field); all other modes zero.
fn rigid_field_vehicle(
    v: &ir::Vehicle,
    c: &CompiledVehicle,
    fin: usize,
    x_a: f64,
) -> CompiledVehicle {
    let f = v.fins.as_ref().unwrap();
    let delta = f.angles[fin].value;
    // Panel +z = -n, n = (0, -sin δ, cos δ) for zero cant.
    let n_vec = [0.0, -delta.sin(), delta.cos()];
    let root_le_x = f.root_trailing_edge_x.value + f.root_chord.value;
    let n = c.modes.len();
    let mut out = c.clone();
    out.shapes.iter_mut().for_each(|s| *s = 0.0);
    for (k, r) in c.node_positions.iter().enumerate() {
        let x = root_le_x - r[0];
        for d in 0..3 {
            out.shapes[(6 * k + d) * n] = -n_vec[d];
            out.shapes[(6 * k + d) * n + 1] = (x - x_a) * n_vec[d];
        }
    }
    out
}

#[test]
fn rigid_plunge_and_pitch_fields_give_the_rigid_columns() {
    let (v, c) = sphads1();
    let n = c.modes.len();
    let machs = [0.3, 0.62, 1.0, 2.0];
    for fin in 0..4 {
        let x_a = 0.1;
        let cv = rigid_field_vehicle(v, c, fin, x_a);
        let model = fin_model::compile(&cv, v, &machs, PanelSettings::default()).unwrap();
        let t = &model.fins[fin];
        let cols = t.cols();
        for g in 0..machs.len() {
            let m = t.at(g);
            let col = |r: usize, j: usize| m[r * cols + j];
            let a0 = 2 * n;
            let ax = 2 * n + 1;
            let scale = col(n, a0).abs();
            assert!(scale > 0.0);
            for r in 0..t.rows() {
                let e = [
                    col(r, 0),                                       // plunge: no slope
                    col(r, n) + col(r, a0),                          // plunge rate: -a_0
                    col(r, 1) - col(r, a0),                          // pitch: +a_0
                    col(r, n + 1) - (col(r, ax) - x_a * col(r, a0)), // pitch rate
                ];
                for (i, e) in e.iter().enumerate() {
                    assert!(
                        e.abs() < 1e-8 * scale,
                        "fin {fin}, Mach {}, row {r}, identity {i}: {e}",
                        machs[g]
                    );
                }
            }
            // Generalised forces of the rigid fields: Q_0 = net force, Q_1 = -(Σ F x) + x_a Σ F.
            for j in 0..t.cols() {
                let q0 = col(0, j) - col(n, j);
                let q1 = col(1, j) - (-col(n + 2, j) + x_a * col(n, j));
                assert!(
                    q0.abs() < 1e-8 * scale && q1.abs() < 1e-8 * scale,
                    "column {j}"
                );
            }
        }
    }
}

#[test]
fn sphads1_panel_matrices_figures_and_compile_time() {
    let (v, c) = sphads1();
    let n = c.modes.len();
    let t0 = std::time::Instant::now();
    let model = fin_model::compile(c, v, &ESTIMATOR_MACH, PanelSettings::default()).unwrap();
    let elapsed = t0.elapsed();
    println!(
        "panel model of SPHADS-1: {} fins x {} Mach, {:?} (this profile)",
        model.fins.len(),
        ESTIMATOR_MACH.len(),
        elapsed
    );
    let area = {
        let f = v.fins.as_ref().unwrap();
        0.5 * (f.root_chord.value + f.tip_chord.value) * f.span.value
    };
    let t = &model.fins[0];
    let cols = t.cols();
    for (g, mach) in ESTIMATOR_MACH.iter().enumerate() {
        let m = t.at(g);
        let cna = m[n * cols + 2 * n] / area;
        let x_cp = m[(n + 2) * cols + 2 * n] / m[n * cols + 2 * n];
        let mut diag = String::new();
        for (j, mode) in c.modes.iter().enumerate() {
            if mode.fin == 0 {
                diag += &format!(
                    " {}: K {:+.3e} C {:+.3e};",
                    mode.name,
                    m[j * cols + j],
                    m[j * cols + n + j]
                );
            }
        }
        println!("M {mach}: C_Na {cna:.4} /rad, x_cp {x_cp:.4} m;{diag}");
        // Damping of fin 0's flap modes (plunge-like motion) is dissipative at every Mach.
        for (j, mode) in c.modes.iter().enumerate() {
            if mode.fin == 0 && mode.class == "fin_flap" {
                assert!(m[j * cols + n + j] < 0.0, "M {mach}: {} damping", mode.name);
            }
        }
    }
    // Fins other than 0 do not feel fin 0's modes (their modal rows vanish there).
    let other = &model.fins[1];
    for (j, mode) in c.modes.iter().enumerate() {
        if mode.fin == 0 && mode.class == "fin_flap" {
            let m = other.at(3);
            let own = t.at(3)[j * cols + n + j].abs();
            assert!(m[j * cols + n + j].abs() < 1e-3 * own, "{}", mode.name);
        }
    }
}

/// Between grid points the outputs are the linear interpolation of the grid outputs, and at
/// a grid Mach they are exactly `q T u`.
#[test]
fn apply_interpolates_in_mach() {
    let (v, c) = sphads1();
    let machs = [0.3, 0.6, 0.9, 1.2, 2.0];
    let model = fin_model::compile(c, v, &machs, PanelSettings::default()).unwrap();
    let t = &model.fins[2];
    let (rows, cols) = (t.rows(), t.cols());
    let u: Vec<f64> = (0..cols)
        .map(|i| ((i * 7 + 3) % 11) as f64 * 0.1 - 0.5)
        .collect();
    let mut y = vec![0.0; rows];
    let direct = |g: usize| -> Vec<f64> {
        (0..rows)
            .map(|r| 2.0 * (0..cols).map(|k| t.at(g)[r * cols + k] * u[k]).sum::<f64>())
            .collect()
    };
    assert!(model.apply(2, 0.6, 2.0, &u, &mut y));
    assert_eq!(y, direct(1));
    assert!(model.apply(2, 0.75, 2.0, &u, &mut y));
    let (a, b) = (direct(1), direct(2));
    for r in 0..rows {
        let want = 0.5 * a[r] + 0.5 * b[r];
        assert!((y[r] - want).abs() <= 1e-12 * want.abs().max(1e-9), "{r}");
    }
    // Clamped outside the grid; refused for bad inputs.
    assert!(model.apply(2, 9.0, 2.0, &u, &mut y));
    assert_eq!(y, direct(4));
    assert!(!model.apply(2, f64::NAN, 2.0, &u, &mut y));
    assert!(!model.apply(7, 0.6, 2.0, &u, &mut y));
    assert!(!model.apply(2, 0.6, 2.0, &u[1..], &mut y));
}

/// A fin-alone estimate (NOT the vehicle's `analyze linear`): fin 0's own modes of the
/// 0.6 mm vehicle, their modal mass scaled with thickness t and their modal stiffness with
/// t³ (a uniform plate: the shapes do not change; the body's share of these modes is
/// ignored), with the panel model's quasi-steady aerodynamic stiffness and damping at
/// 200 m/s, 5 km: `M η̈ = (-K + q T_s) η + (q / V) T_d η̇`. Prints the thickness where the
/// least stable root crosses zero (bisection); asserts only that thin fins are unstable and
/// thick fins stable there.
#[test]
fn fin_alone_quasi_steady_flutter_thickness_at_200_m_s_5_km() {
    use faer::Mat;
    let (v, c) = sphads1();
    let n = c.modes.len();
    let (rho, a) = (0.736_116, 320.529); // U.S. 1976 at 5 km
    let speed = 200.0;
    let mach = speed / a;
    let q = 0.5 * rho * speed * speed;
    let model = fin_model::compile(c, v, &[mach], PanelSettings::default()).unwrap();
    let t = model.fins[0].at(0);
    let cols = model.fins[0].cols();
    let own: Vec<usize> = (0..n).filter(|&j| c.modes[j].fin == 0).collect();
    let m = own.len();
    let t0 = v.fins.as_ref().unwrap().thickness.value;
    let max_re = |th: f64| -> f64 {
        let r = th / t0;
        let a = Mat::<f64>::from_fn(2 * m, 2 * m, |i, k| {
            if i < m {
                return if k == i + m { 1.0 } else { 0.0 };
            }
            let (ji, row) = (own[i - m], i - m);
            let mode = &c.modes[ji];
            let mass = mode.generalised_mass * r;
            let w = 2.0 * std::f64::consts::PI * mode.frequency_hz;
            let stiff = mode.generalised_mass * w * w * r * r * r;
            if k < m {
                let jk = own[k];
                let s = if k == row { -stiff } else { 0.0 };
                (s + q * t[ji * cols + jk]) / mass
            } else {
                let jk = own[k - m];
                q / speed * t[ji * cols + n + jk] / mass
            }
        });
        let evd = a.eigen().unwrap();
        let s = evd.S();
        (0..2 * m)
            .map(|i| s[i].re)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let (mut lo, mut hi) = (0.05e-3, 5e-3);
    assert!(
        max_re(lo) > 0.0 && max_re(hi) < 0.0,
        "{} {}",
        max_re(lo),
        max_re(hi)
    );
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if max_re(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    println!(
        "fin-alone quasi-steady boundary at M {mach:.3}, q {q:.0} Pa: {:.3} mm; least stable root at 0.6 mm {:+.2} 1/s",
        1e3 * hi,
        max_re(0.6e-3)
    );
}

#[test]
fn bad_mach_grids_and_finless_vehicles_are_errors() {
    let (v, c) = sphads1();
    let s = PanelSettings::default();
    assert!(fin_model::compile(c, v, &[0.5, f64::NAN], s).is_err());
    assert!(fin_model::compile(c, v, &[-0.1], s).is_err());
    let mut finless = v.clone();
    finless.fins = None;
    assert_eq!(
        fin_model::compile(c, &finless, &[0.5], s),
        Err(fin_model::FinPanelError::NoFins)
    );
    let bad = PanelSettings { chordwise: 0, ..s };
    assert!(fin_model::compile(c, v, &[0.5], bad).is_err());
}

/// Issue 33: above Mach 1 the flight's lifting-surface fin loads come from the steady
/// supersonic constant-pressure panels where piston theory's criterion fails. SPHADS-1's fin
/// has a subsonic leading edge (57.8 deg) up to Mach 1.88: at Mach 1.3 fin 0's rigid
/// normal-force slope and centre of pressure in the panel model are the supersonic panels'
/// (`supersonic::slope_and_centre` on the same 8 x 12 cosine lattice; the same linear algebra,
/// achieved to 1e-15). Fails on the old code (piston theory with Ackeret's factor from 1.2).
/// In the band the model is the straight line between 0.9 and 1.1.
#[test]
fn flight_slope_above_mach_one_is_the_supersonic_panels() {
    use flexflight::aero::estimator::planform;
    use flexflight::aero::panel::{Lattice, Spacing, supersonic};
    let (v, c) = sphads1();
    let n = c.modes.len();
    let machs = [0.9, 1.0, 1.1, 1.3];
    let model = fin_model::compile(c, v, &machs, PanelSettings::default()).unwrap();
    let pf = planform(v.fins.as_ref().unwrap(), 0.0);
    let lattice = Lattice::new(&pf, 8, 12, Spacing::Cosine).unwrap();
    let t = &model.fins[0];
    let cols = t.cols();
    let slope = |g: usize| t.at(g)[n * cols + 2 * n] / pf.area();
    let centre = |g: usize| t.at(g)[(n + 2) * cols + 2 * n] / t.at(g)[n * cols + 2 * n];
    for (g, mach) in [(2, 1.1), (3, 1.3)] {
        let (a, x) = supersonic::slope_and_centre(&lattice, mach).unwrap();
        eprintln!(
            "M {mach}: flight {} /rad at {} m, panels {a} at {x}",
            slope(g),
            centre(g)
        );
        assert!(
            (slope(g) / a - 1.0).abs() < 1e-12,
            "M {mach}: {} vs {a}",
            slope(g)
        );
        assert!((centre(g) - x).abs() < 1e-12 * pf.root_chord, "M {mach}");
    }
    // Mach 1.0: half way between the 0.9 vortex lattice and the 1.1 panels, entry by entry.
    for (e, (a, b)) in t.at(0).iter().zip(t.at(2)).enumerate() {
        let want = 0.5 * a + 0.5 * b;
        assert!(
            (t.at(1)[e] - want).abs() <= 1e-12 * want.abs().max(1e-12),
            "entry {e}"
        );
    }
}
