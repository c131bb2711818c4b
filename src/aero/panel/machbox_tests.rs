//! Known answers of the harmonic supersonic Mach box ([`super::machbox`]).

use std::f64::consts::PI;

use faer::c64;

use super::machbox::{DEFAULT_BOXES, MachBox, piston_valid};
use super::supersonic::slope_and_centre;
use super::tests::{sphads1, trapezoid};
use super::{Lattice, PanelError, Spacing};

/// `J_0(z) = (1/π) ∫_0^π cos(z sin θ) dθ` (composite Simpson, 400 intervals: exact to
/// rounding for the |z| < 10 used here).
fn j0(z: f64) -> f64 {
    let n = 400;
    let h = PI / n as f64;
    let mut s = 0.0;
    for k in 0..=n {
        let w = if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        s += w * (z * (k as f64 * h).sin()).cos();
    }
    s * h / 3.0 / PI
}

/// Composite Simpson of a complex function on [lo, hi], `n` (even) intervals.
fn simpson(lo: f64, hi: f64, n: usize, f: &dyn Fn(f64) -> c64) -> c64 {
    let h = (hi - lo) / n as f64;
    let mut s = c64::new(0.0, 0.0);
    for k in 0..=n {
        let w = if k == 0 || k == n {
            1.0
        } else if k % 2 == 1 {
            4.0
        } else {
            2.0
        };
        s += f(lo + k as f64 * h) * w;
    }
    s * (h / 3.0)
}

/// Garrick & Rubinow's two-dimensional oscillating supersonic plate (module doc of
/// [`super::machbox`], "two-dimensional limit"), chord `c` from `x = 0`: the lift and the
/// moment about the leading edge per unit span and per unit `q`, for `α_e(x)`.
fn garrick_rubinow(mach: f64, nu: f64, c: f64, alpha: impl Fn(f64) -> c64) -> (c64, c64) {
    let b2 = mach * mach - 1.0;
    let beta = b2.sqrt();
    let kernel = |s: f64| {
        let (sn, cs) = (nu * mach * mach * s / b2).sin_cos();
        c64::new(cs, -sn) * j0(nu * mach * s / b2)
    };
    let phi = |x: f64| -> c64 {
        if x <= 0.0 {
            return c64::new(0.0, 0.0);
        }
        simpson(0.0, x, 200, &|xi| alpha(xi) * kernel(x - xi)) * (1.0 / beta)
    };
    let n = 200;
    let int_phi = simpson(0.0, c, n, &phi);
    let int_xphi = simpson(0.0, c, n, &|x| phi(x) * x);
    let end = phi(c);
    let inu = c64::new(0.0, nu);
    let lift = (end + inu * int_phi) * 4.0;
    let moment = (end * c - int_phi + inu * int_xphi) * 4.0;
    (lift, moment)
}

/// The root strip of a Mach box grid (the boxes whose centres are at `y = Δy/2`): lift and
/// moment about the root leading edge per unit span and `q`.
fn root_strip(mb: &MachBox, beta: f64, nu: f64, alpha: impl Fn(f64) -> c64) -> (c64, c64) {
    let dy = mb.box_length() / beta;
    let a: Vec<c64> = mb.centres().iter().map(|c| alpha(c[0])).collect();
    let f = mb.forces(nu, &a, 1).unwrap();
    let (mut l, mut m) = (c64::new(0.0, 0.0), c64::new(0.0, 0.0));
    for (v, c) in f.iter().zip(mb.centres()) {
        if c[1] < dy {
            l += *v;
            m += *v * c[0];
        }
    }
    (l * (1.0 / dy), m * (1.0 / dy))
}

fn rel(a: c64, b: c64) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn root_strip_is_garrick_rubinow_in_two_dimensions() {
    // A rectangle wide enough that the tip's Mach cone misses the root strip: there the
    // reflection plane makes the flow two-dimensional, Garrick & Rubinow's plate. Plunge
    // (α_e = iν h) and pitch about the leading edge (α_e = θ (1 + iν x)).
    let mut worst: f64 = 0.0;
    for mach in [1.2, 1.5, 2.0, 3.0] {
        let beta = (mach * mach - 1.0f64).sqrt();
        let p = trapezoid(1.3 / beta + 0.1, 1.0, 1.0, 0.0);
        let mb = MachBox::new(&p, mach, 40).unwrap();
        for nu in [0.0, 0.5, 2.0, 5.0] {
            let plunge = |_x: f64| c64::new(0.0, nu);
            let pitch = |x: f64| c64::new(1.0, nu * x);
            for (name, l_ref, m_ref, l, m) in [
                {
                    let (lr, mr) = garrick_rubinow(mach, nu, 1.0, pitch);
                    let (l, m) = root_strip(&mb, beta, nu, pitch);
                    ("pitch", lr, mr, l, m)
                },
                {
                    let (lr, mr) = garrick_rubinow(mach, nu, 1.0, plunge);
                    let (l, m) = root_strip(&mb, beta, nu, plunge);
                    ("plunge", lr, mr, l, m)
                },
            ] {
                if nu == 0.0 && name == "plunge" {
                    continue;
                }
                let (el, em) = (rel(l, l_ref), rel(m, m_ref));
                worst = worst.max(el).max(em);
                assert!(
                    el < TOL_2D && em < TOL_2D,
                    "M {mach} nu {nu} {name}: lift {l} vs {l_ref} ({el:.2e}), moment {m} vs {m_ref} ({em:.2e})"
                );
            }
        }
    }
    eprintln!("worst 2-D difference {worst:.3e}");
}

/// Achieved worst relative difference of the root strip against Garrick & Rubinow, 40 boxes:
/// 4.4e-3 (the plunge moment at M 1.2, ν = 5); 1e-15 steady.
const TOL_2D: f64 = 0.005;

#[test]
fn steady_limit_matches_constant_pressure_panels() {
    // SPHADS-1's fin: subsonic leading edge (57.8 deg) up to Mach 1.88; a rectangle; a
    // trapezoid with a supersonic leading edge. Lift slope and centre of pressure at ν = 0
    // against the steady constant-pressure panels (16 x 16, whose own error is below 1 %).
    let mut worst: (f64, f64) = (0.0, 0.0);
    for p in [
        sphads1(),
        trapezoid(1.0, 1.0, 1.0, 0.0),
        trapezoid(1.0, 1.0, 0.5, 0.3),
    ] {
        for mach in [1.2, 1.5, 2.0, 3.0] {
            let l = Lattice::new(&p, 16, 16, Spacing::Uniform).unwrap();
            let (a_ref, x_ref) = slope_and_centre(&l, mach).unwrap();
            let mb = MachBox::new(&p, mach, DEFAULT_BOXES).unwrap();
            let (a, x) = mb.slope_and_centre().unwrap();

            let (ea, ex) = ((a - a_ref).abs() / a_ref, (x - x_ref).abs() / p.root_chord);
            worst = (worst.0.max(ea), worst.1.max(ex));
            eprintln!("{p:?} M {mach}: slope {a:.4} vs {a_ref:.4}, x_cp {x:.4} vs {x_ref:.4}");
            assert!(
                ea < TOL_SLOPE && ex < TOL_XCP,
                "M {mach} {p:?}: slope {a} vs {a_ref}, x_cp {x} vs {x_ref}"
            );
        }
    }
    eprintln!(
        "worst slope {:.3e}, x_cp {:.3e} root chords",
        worst.0, worst.1
    );
}

/// Achieved at 48 boxes: slope 1.16 % (a rectangle at M 3, where the panels' own 16 x 16
/// error is 1.3 %: see the exact rectangle below), x_cp 0.75 % of the root chord; at the
/// default 32 boxes (the flutter forces'), asserted here: slope 2.26 % (SPHADS-1 at M 1.2,
/// 2.2077 against 2.1588), x_cp 0.72 % of the root chord.
const TOL_SLOPE: f64 = 0.025;
const TOL_XCP: f64 = 0.008;

#[test]
fn rectangle_matches_exact_linear_theory() {
    // The rectangular fin on a wall, β s >= c (`supersonic_tests::rectangular_exact`: Bonney
    // 1947, Ashley & Landahl 1965): C_Nα = (4/β)(1 - c/(4βs)). Achieved at 48 boxes: 0.43 %,
    // 0.25 %, 0.15 % at M 1.5, 2, 3.
    for mach in [1.5, 2.0, 3.0] {
        let beta = (mach * mach - 1.0f64).sqrt();
        let exact = 4.0 / beta * (1.0 - 1.0 / (4.0 * beta));
        let (a, _) = MachBox::new(&trapezoid(1.0, 1.0, 1.0, 0.0), mach, 48)
            .unwrap()
            .slope_and_centre()
            .unwrap();
        assert!(
            (a - exact).abs() < 0.005 * exact,
            "M {mach}: {a} vs {exact}"
        );
    }
}

#[test]
fn high_mach_tends_to_piston_theory() {
    // Piston theory (with Ackeret's factor 4/β) is the M >> 1 limit: on the 2-D strip the
    // difference shrinks like ν c / β² (module doc).
    let nu = 2.0;
    let mut diffs = Vec::new();
    for mach in [2.0, 4.0, 8.0] {
        let beta = (mach * mach - 1.0f64).sqrt();
        let p = trapezoid(1.3 / beta + 0.05, 1.0, 1.0, 0.0);
        let mb = MachBox::new(&p, mach, 40).unwrap();
        let pitch = |x: f64| c64::new(1.0, nu * x);
        let (l, _) = root_strip(&mb, beta, nu, pitch);
        // Piston: 4/β ∫_0^1 α_e dx.
        let piston = c64::new(1.0, 0.5 * nu) * (4.0 / beta);
        diffs.push(rel(l, piston));
    }
    eprintln!("piston differences {diffs:?}");
    assert!(diffs[0] > diffs[1] && diffs[1] > diffs[2], "{diffs:?}");
    assert!(diffs[2] < 0.04, "{diffs:?}");
}

#[test]
fn piston_criterion_needs_high_mach_and_a_supersonic_leading_edge() {
    let p = sphads1(); // tan Λ_LE = 1.59: subsonic below Mach 1.88
    assert!(!piston_valid(&p, 1.5));
    assert!(!piston_valid(&p, 2.4));
    assert!(piston_valid(&p, 2.5));
    let swept = trapezoid(1.0, 2.0, 0.5, 2.5); // tan Λ_LE = 2.5: subsonic below Mach 2.69
    assert!(!piston_valid(&swept, 2.6));
    assert!(piston_valid(&swept, 2.8));
    assert!(!piston_valid(&p, f64::NAN));
}

#[test]
fn bad_input_is_an_error() {
    let p = sphads1();
    assert!(matches!(
        MachBox::new(&p, 1.05, 40),
        Err(PanelError::BadMach(_))
    ));
    assert!(matches!(
        MachBox::new(&p, f64::NAN, 40),
        Err(PanelError::BadMach(_))
    ));
    let mb = MachBox::new(&p, 1.5, 20).unwrap();
    let a = vec![c64::new(1.0, 0.0); mb.len()];
    assert!(matches!(
        mb.forces(f64::NAN, &a, 1),
        Err(PanelError::BadFrequency(_))
    ));
    assert!(matches!(
        mb.forces(1e4, &a, 1),
        Err(PanelError::TooCoarse { .. })
    ));
    assert!(matches!(
        mb.forces(1.0, &a, 2),
        Err(PanelError::Shape { .. })
    ));
}

/// The Mach box's first Mach ([`super::machbox::MIN_MACH`] = 1.1, the supersonic end of the
/// flutter solvers' transonic bridge, `analysis::flutter::fin`) from its own error: at the
/// default box count the span holds `round(s β boxes / extent)` columns, which fall towards
/// one as `β -> 0`. Against the steady constant-pressure panels (16 x 16), measured worst over
/// the three planforms: centre of pressure 5.54 % of the root chord at M 1.02, 4.98 % at 1.05,
/// 2.62 % at 1.075, 1.09 % at 1.1, 0.77 % at 1.15, 0.30 % at 1.2 (SPHADS-1's fin the worst
/// from 1.05); slope 5.4 %, 3.0 %, 2.9 %, 3.1 %, 3.1 %, 2.3 %. The slope error stays near 3 %
/// (the panels' own 16 -> 24 change is 1-1.5 % there), the centre of pressure, which sets the
/// torsional loads of flutter, grows fivefold from 1.1 to 1.05: the method starts at 1.1.
#[test]
fn first_mach_from_the_box_error() {
    let worst = |mach: f64| -> (f64, f64) {
        let mut w: (f64, f64) = (0.0, 0.0);
        for p in [
            sphads1(),
            trapezoid(1.0, 1.0, 1.0, 0.0),
            trapezoid(1.0, 1.0, 0.5, 0.3),
        ] {
            let l = Lattice::new(&p, 16, 16, Spacing::Uniform).unwrap();
            let (a_ref, x_ref) = slope_and_centre(&l, mach).unwrap();
            let mb = MachBox::at_any_supersonic_mach(&p, mach, DEFAULT_BOXES).unwrap();
            let (a, x) = mb.slope_and_centre().unwrap();
            w.0 = w.0.max((a - a_ref).abs() / a_ref);
            w.1 = w.1.max((x - x_ref).abs() / p.root_chord);
        }
        eprintln!(
            "M {mach}: worst slope {:.4}, x_cp {:.4} root chords",
            w.0, w.1
        );
        w
    };
    let (at_first, below) = (worst(super::machbox::MIN_MACH), worst(1.05));
    assert!(at_first.0 < 0.032 && at_first.1 < 0.0115, "{at_first:?}");
    assert!(below.1 > 4.0 * at_first.1, "{below:?} against {at_first:?}");
}
