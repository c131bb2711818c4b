//! The drag build-up of the built-in estimator (issue 34, item 3): skin friction by Reynolds
//! number and surface roughness (Niskanen 2009, sec. 3.4.1; OpenRocket's technical
//! documentation, "Skin friction drag"), the `aero { finish }` field and its diagnostics.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use flexflight::aero::estimator::{
    BodyShape, DEFAULT_ROUGHNESS, FINISHES, NoseShape, body_coefficients, body_friction_correction,
    critical_reynolds, finish_roughness, friction_compressibility, roughness_limited_friction,
    skin_friction, turbulent_friction,
};

/// The fully turbulent law of the source, written out here: 1/(1.50 ln Re - 5.6)^2.
fn turbulent(re: f64) -> f64 {
    1.0 / (1.50 * re.ln() - 5.6).powi(2)
}

/// A deterministic sequence in [0, 1) (a 64-bit LCG, Knuth's MMIX constants).
fn uniform(n: usize) -> Vec<f64> {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

/// A smooth surface (R_s = 0) gives the pure turbulent law with its compressibility factors
/// (1 - 0.1 M^2 subsonic, 1/(1 + 0.15 M^2)^0.58 supersonic), at every Reynolds number from
/// 1e4 to 1e9; below 1e4 the value at 1e4, which the source gives as 1.48e-2.
#[test]
fn a_smooth_finish_gives_the_turbulent_law() {
    let u = uniform(400);
    for w in u.chunks(2) {
        let re = 10f64.powf(4.0 + 5.0 * w[0]);
        let m = 3.0 * w[1];
        let factor = if m < 0.9 {
            1.0 - 0.1 * m * m
        } else if m > 1.1 {
            1.0 / (1.0 + 0.15 * m * m).powf(0.58)
        } else {
            let t = (m - 0.9) / 0.2;
            (1.0 - t) * (1.0 - 0.1 * m * m) + t / (1.0 + 0.15 * m * m).powf(0.58)
        };
        let want = turbulent(re) * factor;
        let got = skin_friction(re, m, 0.0);
        assert!(
            (got / want - 1.0).abs() < 1e-14,
            "Re {re} M {m}: {got} vs {want}"
        );
    }
    assert!((turbulent_friction(1e4) - 1.48e-2).abs() < 2e-5);
    assert_eq!(turbulent_friction(10.0), turbulent_friction(1e4));
}

/// Property over Re in 1e4..1e9 and R_s/L in 1e-8..1e-2 at Mach 0: the friction never
/// increases with the Reynolds number and never decreases with the roughness, and it is
/// continuous in Re (a step of 1e-6 in ln Re moves it by less than 1e-6 relative). For the
/// roughness ratios of rockets and their fins, R_s/L in 1e-6..1e-3, it is the turbulent value
/// below half the critical Reynolds number 51 (R_s/L)^-1.039 and the roughness-limited
/// 0.032 (R_s/L)^0.2 above twice it (the source's two regimes; the two fits cross between
/// 0.63 and 1.33 R_crit there, further out beyond: at 1e-8, 65 R_crit).
#[test]
fn the_friction_law_has_the_sources_regimes_and_is_monotone_and_continuous() {
    let u = uniform(3000);
    for w in u.chunks(3) {
        let re = 10f64.powf(4.0 + 5.0 * w[0]);
        let ratio = 10f64.powf(-8.0 + 6.0 * w[1]);
        let cf = skin_friction(re, 0.0, ratio);
        let crit = critical_reynolds(ratio);
        let rocket = (1e-6..=1e-3).contains(&ratio);
        if rocket && re < 0.5 * crit {
            assert_eq!(cf, turbulent(re), "Re {re} R_s/L {ratio}");
        }
        if rocket && re > 2.0 * crit {
            assert_eq!(cf, 0.032 * ratio.powf(0.2), "Re {re} R_s/L {ratio}");
        }
        let k = 1.0 + w[2];
        assert!(
            skin_friction(k * re, 0.0, ratio) <= cf,
            "Re {re} R_s/L {ratio}"
        );
        assert!(
            skin_friction(re, 0.0, k * ratio) >= cf,
            "Re {re} R_s/L {ratio}"
        );
        let next = skin_friction(re * 1e-6f64.exp(), 0.0, ratio);
        assert!((next / cf - 1.0).abs() < 1e-6, "Re {re} R_s/L {ratio}");
    }
    // The two fits meet near R_crit: within 9 % for R_s/L in 1e-6..1e-3.
    for k in 0..=30 {
        let ratio = 10f64.powf(-6.0 + 0.1 * f64::from(k));
        let crit = critical_reynolds(ratio);
        let (t, r) = (turbulent(crit), roughness_limited_friction(ratio));
        assert!((t / r - 1.0).abs() < 0.09, "R_s/L {ratio}: {t} vs {r}");
    }
}

/// The compressibility factors of the roughness-limited value: 1 - 0.1 M^2 below Mach 0.9,
/// 1/(1 + 0.18 M^2) above 1.1, linear between (OpenRocket's blend), continuous at both ends;
/// the turbulent factors continuous at both ends too.
#[test]
fn the_mach_factors_are_the_sources_and_continuous() {
    let ratio: f64 = 1e-4;
    let re = 1e9;
    let rough = 0.032 * ratio.powf(0.2);
    for m in [0.0, 0.3, 0.6, 0.85, 1.2, 1.5, 2.0, 3.0, 5.0] {
        let want = if m < 0.9 {
            1.0 - 0.1 * m * m
        } else {
            1.0 / (1.0 + 0.18 * m * m)
        };
        let got = skin_friction(re, m, ratio) / rough;
        assert!((got - want).abs() < 1e-14, "M {m}: {got} vs {want}");
    }
    for edge in [0.9, 1.1] {
        let (a, b) = (
            friction_compressibility(edge - 1e-9),
            friction_compressibility(edge + 1e-9),
        );
        assert!(
            (a.0 - b.0).abs() < 1e-8 && (a.1 - b.1).abs() < 1e-8,
            "{edge}: {a:?} {b:?}"
        );
    }
}

/// OpenRocket's finishes and their heights (`ExternalComponent.Finish`), the default regular
/// paint.
#[test]
fn the_named_finishes_are_openrockets() {
    assert_eq!(DEFAULT_ROUGHNESS, 60e-6);
    use flexflight::aero::estimator::openrocket_finish;
    for (name, or, h) in [
        ("rough", "ROUGH", 500e-6),
        ("rough_unfinished", "ROUGHUNFINISHED", 250e-6),
        ("unfinished", "UNFINISHED", 150e-6),
        ("regular_paint", "NORMAL", 60e-6),
        ("smooth_paint", "SMOOTH", 20e-6),
        ("optimum_paint", "OPTIMUM", 5e-6),
        ("sheet_metal", "POLISHED", 2e-6),
        ("polished", "FINISHPOLISHED", 0.5e-6),
        ("mirror", "MIRROR", 0.0),
    ] {
        assert_eq!(finish_roughness(name), Some(h));
        assert_eq!(openrocket_finish(or), Some((name, h)));
        assert_eq!(openrocket_finish(&or.to_lowercase()), Some((name, h)));
    }
    assert_eq!(FINISHES.len(), 9);
    assert_eq!(finish_roughness("glossy"), None);
}

/// The body's friction in the table: C_f(Re on the length, R_s/L) (1 + d/(2 L)) A_wet/S, with
/// the cone's slant surface and the tube's, at Mach 0.5 and sea level; base drag added.
#[test]
fn the_body_friction_is_the_law_times_the_fineness_correction() {
    use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
    use std::f64::consts::PI;
    let (l, d, ln) = (2.0, 0.1, 0.4);
    for roughness in [0.0, 20e-6, 60e-6, 500e-6] {
        let b = BodyShape {
            length: l,
            diameter: d,
            nose: NoseShape::Cone { length: ln },
            reference_x: -1.2,
            transitions: vec![],
            roughness,
            guides: vec![],
            fin_sets: vec![],
        };
        let air = Standard1976::new().at(0.0).unwrap();
        let re = air.density * 0.5 * air.speed_of_sound * l / air.viscosity;
        let s = PI * d * d / 4.0;
        let wet = PI * 0.5 * d * (0.25 * d * d + ln * ln).sqrt() + PI * d * (l - ln);
        let cf = skin_friction(re, 0.5, roughness / l);
        let want = cf * (1.0 + d / (2.0 * l)) * wet / s + 0.12 + 0.13 * 0.25;
        let got = body_coefficients(&b, 0.5, 0.0, 0.0)[1];
        assert!(
            (got / want - 1.0).abs() < 1e-14,
            "R_s {roughness}: {got} vs {want}"
        );
    }
    assert_eq!(body_friction_correction(2.0, 0.1), 1.025);
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The HPR example copied into `dir` with its first `from` replaced by `to` (its `aero`
/// block's `source = builtin` is line 109, so a line added after it is line 110).
fn hpr_with(dir: &Path, from: &str, to: &str) -> PathBuf {
    for e in std::fs::read_dir(repo("examples/hpr_k1000")).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
        }
    }
    let text = std::fs::read_to_string(repo("examples/hpr_k1000/hpr_k1000.vdl")).unwrap();
    let t = text.replacen(from, to, 1);
    assert!(t != text || from == to, "{from} not in the example");
    let p = dir.join("finish.vdl");
    std::fs::write(&p, t).unwrap();
    p
}

/// `aero { finish }` takes OpenRocket's named finishes and a roughness height; a bad one is an
/// error at `check` with the file, line and column of the value (of the unit for a unit of
/// the wrong dimension) and exit 1.
#[test]
fn the_finish_checks_and_bad_ones_are_errors_at_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let src = "    source = builtin\n";
    for ok in ["finish = smooth_paint", "finish = 60 um", "finish = 0 m"] {
        let p = hpr_with(dir.path(), src, &format!("{src}    {ok}\n"));
        let o = bin().arg("check").arg(&p).output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{ok}: {}", stderr(&o));
    }
    for (bad, code, col) in [
        ("finish = glossy", "vdl::value::keyword", 14),
        ("finish = 20 mm", "vdl::value::range", 14),
        ("finish = -1 um", "vdl::value::range", 14),
        ("finish = 60 s", "vdl::unit::mismatch", 17),
        ("finish = \"regular_paint\"", "vdl::type::mismatch", 14),
    ] {
        let p = hpr_with(dir.path(), src, &format!("{src}    {bad}\n"));
        let o = bin().arg("check").arg(&p).output().unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{bad}: {e}");
        assert!(e.contains(code), "{bad}: {e}");
        assert!(e.contains(&format!("finish.vdl:110:{col}")), "{bad}: {e}");
    }
    // With coefficient tables the finish would do nothing: an error, not silence.
    let p = hpr_with(
        dir.path(),
        src,
        "    source = tables\n    body_table = \"b.csv\"\n    fin_table = \"f.csv\"\n    finish = rough\n",
    );
    std::fs::write(dir.path().join("b.csv"), "x\n").unwrap();
    std::fs::write(dir.path().join("f.csv"), "x\n").unwrap();
    let o = bin().arg("check").arg(&p).output().unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("vdl::aero::finish"), "{e}");
    assert!(e.contains("finish.vdl:112:14"), "{e}");
}

/// The finish moves the drag the vehicle flies with: the built-in body table of the HPR
/// example has more axial force with a rough finish than with the default, and the default
/// (regular paint) is what an unwritten finish gives.
#[test]
fn the_finish_reaches_the_flown_tables() {
    use flexflight::check::{DiskLoader, check_files};
    let dir = tempfile::tempdir().unwrap();
    let src = "    source = builtin\n";
    let ca = |p: PathBuf| {
        let c = check_files(&[p], &[], &DiskLoader);
        assert!(!c.has_errors(), "{:?}", c.diagnostics);
        let t = flexflight::runtime::forces::aero_tables(&c.program.vehicles[0]).unwrap();
        (
            t.body.body(0.5, 0.0, 1000.0).unwrap().ca,
            t.fin.fin(0.5, 0.0, 1000.0).unwrap().ca,
        )
    };
    let default = ca(hpr_with(dir.path(), src, src));
    let paint = ca(hpr_with(
        dir.path(),
        src,
        &format!("{src}    finish = regular_paint\n"),
    ));
    let rough = ca(hpr_with(
        dir.path(),
        src,
        &format!("{src}    finish = rough\n"),
    ));
    let mirror = ca(hpr_with(
        dir.path(),
        src,
        &format!("{src}    finish = mirror\n"),
    ));
    assert_eq!(default, paint);
    assert!(
        rough.0 > paint.0 && paint.0 > mirror.0,
        "{rough:?} {paint:?} {mirror:?}"
    );
    assert!(
        rough.1 > paint.1 && paint.1 > mirror.1,
        "{rough:?} {paint:?} {mirror:?}"
    );
}

/// Fin thickness wave drag (Ackeret, simple sweep theory; `thickness_wave_drag`): the
/// biconvex `airfoil` section's `(16/3) tau^2 cos L / sqrt(M^2 cos^2 L - 1)` where linear
/// theory holds (transonic similarity parameter >= 1), zero for a normal Mach <= 1 and for the
/// square and rounded sections, continuous at the normal Mach where the ramp from M_n = 1
/// meets it.
#[test]
fn fin_thickness_wave_drag_is_ackerets_with_simple_sweep() {
    use flexflight::aero::estimator::{thickness_wave_constant, thickness_wave_drag};
    use flexflight::check::ir::FinSection::{Airfoil, Rounded, Square};
    assert_eq!(thickness_wave_constant(Airfoil), 16.0 / 3.0);
    for tau in [0.01, 0.03, 0.06] {
        for sweep_deg in [0.0, 30.0, 50.0] {
            let sweep: f64 = f64::to_radians(sweep_deg);
            let c = sweep.cos();
            // The similarity parameter's threshold M_n*, solved here by bisection.
            let tau_n = tau / c;
            let g = |m: f64| (m * m - 1.0) - (2.4 * tau_n * m * m).powf(2.0 / 3.0);
            let (mut lo, mut hi) = (1.0, 3.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if g(mid) < 0.0 { lo = mid } else { hi = mid }
            }
            let m_star = hi;
            for k in 0..=40 {
                let m = 0.5 + 0.1 * f64::from(k);
                let mn = m * c;
                let got = thickness_wave_drag(Airfoil, tau, sweep, m);
                assert_eq!(thickness_wave_drag(Square, tau, sweep, m), 0.0);
                assert_eq!(thickness_wave_drag(Rounded, tau, sweep, m), 0.0);
                if mn <= 1.0 {
                    assert_eq!(got, 0.0, "M {m} sweep {sweep_deg}");
                } else if mn >= m_star + 1e-9 {
                    let want = 16.0 / 3.0 * tau * tau * c / (mn * mn - 1.0).sqrt();
                    assert!(
                        (got / want - 1.0).abs() < 1e-12,
                        "M {m} L {sweep_deg}: {got} {want}"
                    );
                } else {
                    assert!(got >= 0.0 && got.is_finite(), "M {m}");
                }
            }
            // Continuous at M_n*: the ramp meets the linear-theory value.
            let at = |mn: f64| thickness_wave_drag(Airfoil, tau, sweep, mn / c);
            let (a, b) = (at(m_star - 1e-9), at(m_star + 1e-9));
            assert!(
                (a / b - 1.0).abs() < 1e-6,
                "tau {tau} L {sweep_deg}: {a} {b}"
            );
            assert!(at(1.0 + 1e-12) < 1e-9);
        }
    }
}

/// A body with a launch lug and a rail button: the body's axial coefficient grows by exactly
/// `launch_guide_drag` of each; a rod's drag (no bore) is `0.7 (C_stag + C_base)` on its
/// frontal area (OpenRocket's `TubeCalc`); a bore adds the Darcy-Weisbach loss, growing with
/// the lug's length; a button standing far out of the boundary layer has the cylinder's C_D
/// at nearly the flight Mach, one buried in it much less.
#[test]
fn launch_guides_add_their_drag_to_the_body() {
    use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
    use flexflight::aero::estimator::{LaunchGuide, base_drag, launch_guide_drag, stagnation_drag};
    use std::f64::consts::PI;
    let body = |guides: Vec<LaunchGuide>| BodyShape {
        length: 1.0,
        diameter: 0.05,
        nose: NoseShape::Cone { length: 0.2 },
        reference_x: -0.6,
        transitions: vec![],
        roughness: DEFAULT_ROUGHNESS,
        guides,
        fin_sets: vec![],
    };
    let s = PI * 0.05 * 0.05 / 4.0;
    let air = Standard1976::new().at(0.0).unwrap();
    let nu = air.viscosity / air.density;
    let lug = |length: f64, inner: f64| LaunchGuide::Lug {
        length,
        outer_diameter: 0.006,
        inner_diameter: inner,
    };
    let button = |from_tip: f64, height: f64| LaunchGuide::Button {
        from_tip,
        outer_diameter: 0.01,
        height,
        inner_diameter: 0.006,
        inner_height: 0.3 * height,
    };
    for m in [0.0, 0.3, 0.8, 1.2, 2.0] {
        let g =
            |g: &LaunchGuide| launch_guide_drag(g, DEFAULT_ROUGHNESS, s, m, air.speed_of_sound, nu);
        let clean = body_coefficients(&body(vec![]), m, 0.0, 0.0)[1];
        let guides = vec![lug(0.05, 0.004), button(0.7, 0.008)];
        let with = body_coefficients(&body(guides.clone()), m, 0.0, 0.0)[1];
        let sum: f64 = guides.iter().map(g).sum();
        assert!(((with - clean) - sum).abs() < 1e-15, "M {m}");
        let rod = g(&lug(0.05, 0.0));
        let want = 0.7 * (stagnation_drag(m) + base_drag(m)) * PI * 0.003 * 0.003 / s;
        assert!((rod / want - 1.0).abs() < 1e-14, "M {m}: {rod} {want}");
        let (short, long) = (g(&lug(0.05, 0.004)), g(&lug(0.10, 0.004)));
        let annulus = 0.7 * (stagnation_drag(m) + base_drag(m)) * PI * (9e-6 - 4e-6) / s;
        assert!(
            ((long - annulus) / (short - annulus) - 2.0).abs() < 1e-12,
            "M {m}"
        );
        assert!(short > annulus);
        let (out, buried) = (g(&button(0.01, 0.05)), g(&button(1.0, 0.0005)));
        assert!(out / 0.05 > 20.0 * buried / 0.0005, "M {m}: {out} {buried}");
    }
}

/// `launch_lug` and `rail_button` in the body: they check, their masses become point masses
/// on the axis, and bad ones are errors at the value with line and column and exit 1.
#[test]
fn launch_guides_check_and_bad_ones_are_errors_at_the_value() {
    use flexflight::check::{DiskLoader, check_files};
    let dir = tempfile::tempdir().unwrap();
    let anchor = "        theory = euler_bernoulli\n";
    let guides = "        launch_lug {\n          station = -1.0 m\n          length = 50 mm\n          outer_diameter = 10 mm\n          inner_diameter = 8 mm\n          mass = 4 g\n        }\n        rail_button {\n          station = -1.5 m\n          outer_diameter = 11 mm\n          height = 9 mm\n          inner_diameter = 6 mm\n          inner_height = 3 mm\n          mass = 3 g\n        }\n";
    let good = hpr_with(dir.path(), anchor, &format!("{anchor}{guides}"));
    let o = bin().arg("check").arg(&good).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let c = check_files(std::slice::from_ref(&good), &[], &DiskLoader);
    let v = &c.program.vehicles[0];
    let flexflight::check::ir::Structure::Generate(g) = &v.structure else {
        panic!("generated")
    };
    let pm = |name: &str| {
        g.point_masses
            .iter()
            .find(|p| p.name.value == name)
            .map(|p| (p.position.value, p.mass.value))
    };
    let close = |a: ([f64; 3], f64), b: ([f64; 3], f64)| {
        (0..3).all(|i| (a.0[i] - b.0[i]).abs() < 1e-12) && (a.1 - b.1).abs() < 1e-15
    };
    assert!(close(
        pm("launch_lug_1").unwrap(),
        ([-1.025, 0.0, 0.0], 0.004)
    ));
    assert!(close(
        pm("rail_button_1").unwrap(),
        ([-1.5, 0.0, 0.0], 0.003)
    ));
    // Each bad value is reported at its own line and at the column after `= `.
    let text = std::fs::read_to_string(&good).unwrap();
    for (from, to, code, needle) in [
        (
            "station = -1.0 m",
            "station = -0.1 m",
            "vdl::value::range",
            "station = -0.1 m",
        ),
        (
            "station = -1.0 m",
            "station = -1.88 m",
            "vdl::value::range",
            "station = -1.88 m",
        ),
        (
            "length = 50 mm",
            "length = -50 mm",
            "vdl::value::range",
            "length = -50 mm",
        ),
        (
            "inner_diameter = 8 mm",
            "inner_diameter = 12 mm",
            "vdl::value::range",
            "inner_diameter = 12 mm",
        ),
        (
            "height = 9 mm",
            "height = 0 mm",
            "vdl::value::range",
            "height = 0 mm",
        ),
        (
            "inner_height = 3 mm",
            "inner_height = 9 mm",
            "vdl::value::range",
            "inner_height = 9 mm",
        ),
        (
            "          inner_height = 3 mm\n",
            "",
            "vdl::value::range",
            "inner_diameter = 6 mm",
        ),
        (
            "mass = 4 g",
            "mass = -4 g",
            "vdl::value::range",
            "mass = -4 g",
        ),
        (
            "mass = 3 g",
            "mass = 3 m",
            "vdl::unit::mismatch",
            "mass = 3 m",
        ),
    ] {
        let bad = text.replacen(from, to, 1);
        assert_ne!(bad, text);
        let p = dir.path().join("bad.vdl");
        std::fs::write(&p, &bad).unwrap();
        let o = bin().arg("check").arg(&p).output().unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{to}: {e}");
        assert!(e.contains(code), "{to}: {e}");
        let line = bad.lines().position(|l| l.contains(needle)).unwrap() + 1;
        // The value's column; a unit of the wrong dimension is shown at the unit.
        let l = bad.lines().nth(line - 1).unwrap();
        let col = if code == "vdl::unit::mismatch" {
            l.rfind(' ').unwrap() + 2
        } else {
            l.find('=').unwrap() + 3
        };
        assert!(
            e.contains(&format!("bad.vdl:{line}:{col}")),
            "{to}: want {line}:{col}: {e}"
        );
    }
}

/// The wave drag of the non-conical profiles (Niskanen 2009, App. B; `nose_pressure_drag`):
/// at fineness 3 Stoney's values themselves (NASA TR R-100 as OpenRocket transcribes them),
/// interpolated linearly in the shape parameter between the tabulated shapes; at fineness 0
/// the blunt cylinder's 0.85 q_stag/q; in between `C_0 (C_3/C_0)^(log_4 (f + 1))`; below the
/// data's first Mach the subsonic fit, zero for these smooth noses.
#[test]
fn profile_noses_take_stoneys_data() {
    use flexflight::aero::estimator::{nose_pressure_drag, stagnation_drag};
    use flexflight::check::ir::NoseShape as S;
    let at3 = |shape, m| nose_pressure_drag(shape, 3.0, 0.05, 0.3, m);
    for (shape, m, want) in [
        (S::Haack { c: 0.0 }, 1.4, 0.095),
        (S::Haack { c: 1.0 / 3.0 }, 1.2, 0.100),
        (S::Haack { c: 1.0 / 6.0 }, 1.4, 0.5 * (0.095 + 0.114)),
        (S::Elliptical, 2.0, 0.159),
        (S::Power { n: 0.5 }, 1.3, 0.084),
        (S::Power { n: 0.625 }, 1.2, 0.5 * (0.081 + 0.110)),
        (S::Parabolic { k: 1.0 }, 1.2, 0.119),
        (S::Parabolic { k: 0.5 }, 1.05, 0.126),
        (S::Parabolic { k: 0.75 }, 1.1, 0.107),
    ] {
        let got = at3(shape, m);
        assert!(
            (got - want).abs() < 1e-12,
            "{shape:?} M {m}: {got} vs {want}"
        );
    }
    // Fineness 0: the blunt cylinder; fineness 1: the geometric mean of log_4 2 = 1/2.
    let m = 1.4;
    let c0 = stagnation_drag(m);
    let blunt = nose_pressure_drag(S::Haack { c: 0.0 }, 0.0, 0.05, 0.0001, m);
    assert!((blunt / c0 - 1.0).abs() < 1e-12, "{blunt} {c0}");
    let one = nose_pressure_drag(S::Haack { c: 0.0 }, 1.0, 0.05, 0.1, m);
    assert!(
        (one / (c0 * (0.095 / c0).sqrt()) - 1.0).abs() < 1e-12,
        "{one}"
    );
    // Subsonic: nothing for the smooth von Kármán nose below Mach 0.9.
    assert_eq!(at3(S::Haack { c: 0.0 }, 0.5), 0.0);
}
