//! `fin_aero { model = key_node | lifting_surface }` (issue 12, deliverables 4-6): the key-node
//! model's histories are those of before the panel model existed; the lifting-surface model
//! does not depend on `key_nodes.fins` (flight and linearised roots); both agree in the
//! rigid-fin limit.

use std::path::{Path, PathBuf};

use flexflight::analysis::linear::Variant;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The checked scenario `scenario` of the thesis 6.5 file with `sets`, compiled and planned.
fn variant(scenario: &str, sets: &[&str]) -> Variant {
    variant_of(&repo("examples/thesis/section_6_5.vdl"), scenario, sets)
}

/// The checked scenario `scenario` of `file` with `sets`, compiled and planned.
fn variant_of(file: &Path, scenario: &str, sets: &[&str]) -> Variant {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = flexflight::check::check_files(
        &[file.to_path_buf()],
        &sets,
        &flexflight::check::DiskLoader,
    );
    assert!(checked.diagnostics.is_empty(), "{:?}", checked.diagnostics);
    let scenario = checked
        .program
        .scenario(scenario)
        .cloned()
        .expect("scenario");
    let compiled = flexflight::structure::compile::compile(&scenario.vehicle)
        .unwrap()
        .0;
    let plan = flexflight::plan::build(&scenario, &compiled).unwrap();
    Variant {
        plan,
        scenario,
        compiled,
    }
}

/// The history rows of a run of `v`.
fn history(v: &Variant) -> Vec<Vec<f64>> {
    flexflight::run::run(&v.plan, &v.compiled.reduced, &mut |_, _| {})
        .unwrap()
        .rows
}

/// blake3 of the rows' bits.
fn digest(rows: &[Vec<f64>]) -> String {
    digest_without(rows, None)
}

/// blake3 of the rows' bits, column `skip` left out.
fn digest_without(rows: &[Vec<f64>], skip: Option<usize>) -> String {
    let mut h = blake3::Hasher::new();
    for r in rows {
        for (j, x) in r.iter().enumerate() {
            if Some(j) != skip {
                h.update(&x.to_bits().to_le_bytes());
            }
        }
    }
    h.finalize().to_hex().to_string()
}

/// The thesis' key-node model flies bit for bit as it did before the lifting-surface model
/// existed: 0.6 mm fins, 1.2 s (the run stops at the fin stress limit), the vehicle's
/// key-node settings. The digest dfea711f... recorded on commit f68d3e8 (before
/// `fin_aero.model`) held with the lifting-surface model added; merging main 0d940e8 (launch
/// work: segmented run driver, Mach-0 tables, wind by altitude) changed the history, and this
/// digest was re-recorded after that merge (the key-node path of the fin block has no edit of
/// its arithmetic). Re-recorded again after merging h11-speed (the PI step-size controller is
/// the new DOPRI5 default, and the restructured RHS rounds differently): those change the
/// bits of every adaptive history; how far this history moved is not measured. The digest
/// pins the key-node path against later fin-model work. Since issue 32 the run would stop
/// at 0.25 s with a flutter verdict; `run.model_limits = false` keeps the pinned history.
///
/// Re-recorded on 3 December 2026 for one column only: the output rows now take the aero
/// channels from the row's own right-hand side with its force blocks summed block by block
/// (`ForceBlocks::keep_each`), which rounds the `acceleration` channel differently (at most
/// 1.9e-14 relative on the 10 s flight). The digest of every other column is the one the
/// previous code gives (f4c257b5..., computed from that code's `history.csv`, whose shortest
/// round-trip digits read back to the same bits; the same method gives 99d37276... for all
/// the columns, the digest this test held before), so the state, the loads and every other
/// channel are bit for bit unchanged.
///
/// Re-recorded on 4 December 2026 for every column: the equations of motion solve the
/// 6 x 6 Schur complement by a block Cholesky factorisation with the constant `S_vv` factored
/// once (`runtime::eom`, test `the_schur_solve_inverts_the_assembled_mass_matrix`), which
/// rounds differently. How far this history moved, measured with `tools/history_error.py`
/// (largest difference over the range of each channel group, 313 rows): at most 5.6e-13
/// (acceleration), 1.5e-13 position, 3.6e-13 angular rate, 1.8e-13 `η̇`, 1.0e-13 fin root
/// stress; against a DOP853 reference (rtol 1e-10, atol 1e-13) both the old and the new
/// history err by the same two digits (3.5e-5 `η`, 6.7e-5 fin root stress, 4.3e-8 position).
///
/// Re-recorded on 6 December 2026: the estimator's subsonic fin slope is now computed on the
/// fin's own area and then scaled by `A_f / S` (issue 33's lifting surface shares the
/// function), a different order of the same product, so its last bits move. Compared with the
/// binary of `206023f` (the same run, `tools/outputs`): the body states agree to the last one
/// or two bits (`v_body_x` 199.99533856292143 against ...142); the channels of fin 2, which
/// sits in the plane of symmetry and carries only roundoff (root stress 0.04 Pa), differ by at
/// most 3.6e-5 of their range; 313 rows and the stop at 0.3116 s unchanged.
///
/// Re-recorded on 6 December 2026 (later): issue 34's fin drag by cross-section (the
/// default `square` adds leading- and trailing-edge pressure drag and the thickness factor on
/// the friction) raises the built-in tables' fin axial coefficient, so the flight moves.
/// With those three terms removed from `aero::estimator`'s fin axial coefficient (a
/// temporary patch, not committed) this test gives the previous digest (7cc41337...) again:
/// nothing else moved. How far the history moved was not measured.
///
/// Re-recorded on 6 December 2026 (evening): issue 34's skin friction by Reynolds number and
/// surface roughness (Niskanen's law, the body's fineness correction, `aero { finish }`'s
/// default 60 um) raises the built-in tables' axial coefficient again, so the flight moves.
/// Evidence: the same test passes unchanged on main plus the speed branch merged beside it
/// (its changes keep the bits), and fails only with the drag build-up, whose friction law
/// patched back to Prandtl-Schlichting gives the tables' old digests (`tests/aero.rs`).
///
/// Re-recorded on 7 December 2026: SPHADS-1's conical nose becomes solid 17.7 mm from the tip,
/// 0.26 of a body division, and the mesh no longer makes that a station (within 0.3 of a
/// division of the tip the beam element across it is integrated in its two parts:
/// `mesh::body_stations`), so the body has 363 nodes, not 364. Its mass, centre of mass and
/// every selected frequency are unchanged to the snapshot's 8 digits
/// (`tests/snapshots/coefficient_snapshots__sphads1_coefficients.snap`); the modes'
/// generalised masses moved by 1.6e-5 (their shapes at the tip). Evidence: with the station
/// rule alone put back (the beam's split kept), this test and the snapshot pass unchanged.
///
/// Re-recorded again on 7 December 2026 for the built-in tables over every flow direction
/// (aerodynamics revision 8): the flight through the blow-up passes beyond 20 deg, where
/// the old tables were clamped, and the axial coefficients now carry Niskanen's scaling with
/// the angle of attack. Evidence: with the three estimator changes patched out
/// (`axial_scaling` 1, `fin_incidence` the angle, the old grid), the old digests returned
/// (`aero::conical_nose_tables_are_bit_identical_to_before_nose_shapes`' note).
#[test]
fn key_node_history_is_unchanged() {
    // The 0.6 mm fins flutter in this model (0.25 s): the pinned history flies on through
    // the blow-up as it always did, with the verdict stop off.
    let v = variant(
        "subsonic_t06",
        &["run.stop_time=1.2s", "run.model_limits=false"],
    );
    let rows = history(&v);
    let d = digest(&rows);
    let acc = v.plan.channels.iter().position(|c| c == "acceleration");
    let others = digest_without(&rows, acc);
    eprintln!(
        "rows {} digest {d}, without acceleration {others}",
        rows.len()
    );
    assert_eq!(
        others,
        "cade3f276852f7325fbfe7880908aecabf4237c34011bee25509b1fd1edc1bf5"
    );
    assert_eq!(
        d,
        "6cb39409e3ea45c1b37537e7a6a332922a47c71172d8f2e6a81b8a9aec9ece61"
    );
}

const LIFTING: &str = "forces.fin_aero.model=lifting_surface";
const KEY_NODE_ELSEWHERE: &str = "key_nodes.fins=fin_point(span = 0.9, chord = 0.75)";

/// The lifting-surface model flies the same bits wherever the fin key nodes are; the thesis'
/// key-node model does not (the control that shows the perturbation matters).
#[test]
fn lifting_surface_flight_does_not_depend_on_the_fin_key_nodes() {
    // 2 mm fins: stable with both models at 200 m/s, 5 km, so the run reaches the gust.
    let base = ["run.stop_time=1.2s", "fins.thickness=2mm", LIFTING];
    let a = variant("subsonic_t06", &base);
    let b = variant(
        "subsonic_t06",
        &[base[0], base[1], base[2], KEY_NODE_ELSEWHERE],
    );
    assert_ne!(a.compiled.key_fins, b.compiled.key_fins);
    let (ha, hb) = (history(&a), history(&b));
    assert_eq!(ha.len(), hb.len());
    assert!(ha.len() > 1000, "{} rows", ha.len());
    for (ra, rb) in ha.iter().zip(&hb) {
        for (x, y) in ra.iter().zip(rb) {
            assert_eq!(x.to_bits(), y.to_bits(), "{x} vs {y}");
        }
    }
    let c = variant("subsonic_t06", &base[..2]);
    let d = variant("subsonic_t06", &[base[0], base[1], KEY_NODE_ELSEWHERE]);
    assert_ne!(digest(&history(&c)), digest(&history(&d)));
}

/// The linearised roots `(Re, Im)` of a variant, sorted.
fn roots(v: &Variant) -> Vec<(f64, f64)> {
    let r = flexflight::analysis::linear::analyse(
        v,
        flexflight::analysis::linearise::LineariseOptions::default(),
    )
    .unwrap();
    let mut out: Vec<(f64, f64)> = r.eigen.roots.iter().map(|r| (r.real, r.imag)).collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    out
}

/// `analyze linear` sees the lifting-surface model (its roots differ from the key-node ones)
/// and, like the flight, not the fin key nodes.
#[test]
fn lifting_surface_roots_do_not_depend_on_the_fin_key_nodes() {
    let a = roots(&variant("subsonic_t06", &[LIFTING]));
    let b = roots(&variant("subsonic_t06", &[LIFTING, KEY_NODE_ELSEWHERE]));
    let scale = a.iter().map(|r| r.0.hypot(r.1)).fold(0.0, f64::max);
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x.0 - y.0).abs().max((x.1 - y.1).abs()))
        .fold(0.0, f64::max);
    eprintln!("worst root difference {worst:e} (scale {scale:e})");
    assert!(worst <= 1e-12 * scale, "worst {worst:e}");
    let k = roots(&variant("subsonic_t06", &[]));
    let differ = a
        .iter()
        .zip(&k)
        .map(|(x, y)| (x.0 - y.0).abs().max((x.1 - y.1).abs()))
        .fold(0.0, f64::max);
    assert!(
        differ > 1e-3,
        "the models should give different roots: {differ:e}"
    );
}

/// `linear-map` (the thickness x Mach map) with the lifting-surface model: the same map
/// wherever the fin key nodes are.
#[test]
fn lifting_surface_linear_map_does_not_depend_on_the_fin_key_nodes() {
    let map = |extra: &[&'static str]| {
        flexflight::analysis::linear::linear_map(
            &[0.5e-3, 1.0e-3],
            &[0.5, 0.6],
            |t| {
                let th = format!("fins.thickness={} mm", t * 1e3);
                let mut sets: Vec<&str> = vec![LIFTING, &th];
                sets.extend_from_slice(extra);
                Ok(variant("subsonic_t06", &sets))
            },
            flexflight::analysis::linearise::LineariseOptions::default(),
        )
        .unwrap()
        .map
    };
    let (a, b) = (map(&[]), map(&[KEY_NODE_ELSEWHERE]));
    for (x, y) in a.sigma.iter().zip(&b.sigma) {
        assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
    }
    for (x, y) in a.omega.iter().zip(&b.omega) {
        assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
    }
}

/// The largest difference of a history column between two runs, relative to its largest
/// magnitude in the first.
fn column_difference(a: &[Vec<f64>], b: &[Vec<f64>], col: usize) -> f64 {
    let scale = a.iter().map(|r| r[col].abs()).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x[col] - y[col]).abs())
        .fold(0.0, f64::max)
        / scale
}

/// The thesis 6.5 scenarios and SPHADS-1 copied into `dir`, the vehicle made of a material
/// `factor` times stiffer than the thesis aluminium (same density): every mode `sqrt(factor)`
/// faster, every elastic deformation under the same loads `1/factor` smaller.
fn stiff_copy(dir: &Path, factor: f64) -> PathBuf {
    std::fs::create_dir_all(dir.join("examples/thesis")).unwrap();
    std::fs::create_dir_all(dir.join("vehicles")).unwrap();
    let v = std::fs::read_to_string(repo("vehicles/sphads1.vdl")).unwrap();
    let from = "  material = aluminium_thesis\n";
    assert_eq!(v.matches(from).count(), 1);
    let e = 70e9 * factor;
    let stiff = format!(
        "material stiff {{ E = {e} Pa; nu = 0.346; rho = 2710 kg/m^3; yield = 275 MPa; ultimate = 310 MPa; expect_unusual = true }}\n"
    );
    let v = v.replacen("vehicle sphads1", &format!("{stiff}vehicle sphads1"), 1);
    std::fs::write(
        dir.join("vehicles/sphads1.vdl"),
        v.replace(from, "  material = stiff\n"),
    )
    .unwrap();
    let scenario = dir.join("examples/thesis/section_6_5.vdl");
    std::fs::copy(repo("examples/thesis/section_6_5.vdl"), &scenario).unwrap();
    scenario
}

/// The largest relative difference of a few rigid-body channels of the history (1.2 s, the
/// gust included) between the lifting-surface model and the key-node model with
/// `incidence = incidence`, for SPHADS-1 `factor` times stiffer.
fn model_difference(factor: f64, incidence: &str) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let file = stiff_copy(dir.path(), factor);
    let inc = format!("forces.fin_aero.incidence={incidence}");
    let base = "run.stop_time=1.2s";
    let lifting = variant_of(&file, "subsonic_t06", &[base, LIFTING]);
    let key = variant_of(&file, "subsonic_t06", &[base, inc.as_str()]);
    let (hl, hk) = (history(&lifting), history(&key));
    assert_eq!(hl.len(), hk.len());
    let ch = &lifting.plan.channels;
    ["v_body_z", "omega_body_y", "pitch", "alpha"]
        .iter()
        .map(|name| {
            let col = ch.iter().position(|c| c == name).expect("channel");
            column_difference(&hl, &hk, col)
        })
        .fold(0.0, f64::max)
}

/// Rigid-fin limit: as the structure stiffens, the elastic increments vanish and both models
/// fly the coefficient tables at the load model's centre of pressure (where the key-node
/// model's `incidence = load_weighted` reads the fin's incidence too): the trajectories
/// converge, the difference falling like the deformations, `1/factor`. (With the thesis'
/// `incidence = key_node` the rigid incidence is read at the key node instead, which stays a
/// difference of the rigid models.)
#[test]
fn stiff_fins_fly_the_same_trajectory_with_both_models() {
    let d: Vec<f64> = [1e2, 1e4]
        .iter()
        .map(|&f| model_difference(f, "load_weighted"))
        .collect();
    let k = model_difference(1e4, "key_node");
    eprintln!("lifting vs load_weighted at 1e2, 1e4 x stiffer: {d:?}; vs key_node at 1e4: {k:e}");
    // Measured: 2.34e-2, 3.53e-4; 9.24e-4.
    assert!(d[1] <= 4e-4 && d[1] * 50.0 < d[0], "{d:?}");
    assert!(k <= 1e-3, "{k:e}");
}

/// The right-hand side of a variant's equations of motion at `x`.
fn rhs(v: &Variant, x: &[f64]) -> Vec<f64> {
    use flexflight::runtime::integrate::OdeSystem;
    let forces = flexflight::run::build_force_blocks(&v.plan, &v.compiled.reduced).unwrap();
    let mut eom = flexflight::runtime::eom::Eom::new(&v.compiled.reduced, forces).unwrap();
    let mut dx = vec![0.0; x.len()];
    eom.rhs(0.0, x, &mut dx).unwrap();
    dx
}

/// At zero deformation the lifting-surface model's fin loads ARE the coefficient tables'
/// at the load model's centre of pressure, as the key-node model with
/// `incidence = load_weighted` computes them: without rotation the two right-hand sides
/// agree to round-off at any incidence and sideslip; a deformation then separates them.
#[test]
fn zero_deformation_loads_follow_the_coefficient_tables() {
    let lifting = variant("subsonic_t06", &[LIFTING]);
    let weighted = variant("subsonic_t06", &["forces.fin_aero.incidence=load_weighted"]);
    let mut x = lifting.plan.initial_state.clone();
    // V_B at alpha 4 deg, beta 2 deg (state layout p, q, V_B, omega_B, eta, eta_dot).
    x[7] = 200.0 * 0.07f64.cos();
    x[8] = 200.0 * 0.035f64.sin();
    x[9] = 200.0 * 0.07f64.sin();
    let (a, b) = (rhs(&lifting, &x), rhs(&weighted, &x));
    let scale = a.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 1e-14 * scale, "worst {worst:e} of {scale:e}");
    let n = lifting.plan.n_modes;
    x[13 + n - 1] = 1e-4;
    let (a, b) = (rhs(&lifting, &x), rhs(&weighted, &x));
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    assert!(
        worst > 1e-6 * scale,
        "a deformed fin should differ: {worst:e}"
    );
}

/// The diagnostic codes of checking the thesis file with `sets`.
fn codes(sets: &[&str]) -> Vec<&'static str> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = flexflight::check::check_files(
        &[repo("examples/thesis/section_6_5.vdl")],
        &sets,
        &flexflight::check::DiskLoader,
    );
    checked.diagnostics.iter().map(|d| d.code).collect()
}

/// A bad `model` and an `incidence` the lifting-surface model would ignore are refused at
/// check time, with a span.
#[test]
fn bad_fin_models_are_check_time_diagnostics() {
    assert!(codes(&[LIFTING]).is_empty());
    assert!(codes(&["forces.fin_aero.model=key_node"]).is_empty());
    assert!(codes(&["forces.fin_aero.model=panels"]).contains(&"vdl::value::keyword"));
    assert!(
        codes(&["forces.fin_aero.model=1"])
            .iter()
            .any(|c| c.starts_with("vdl::"))
    );
    let c = codes(&[LIFTING, "forces.fin_aero.incidence=load_weighted"]);
    assert_eq!(c, ["vdl::fin_aero::incidence_unused"]);
    // An explicit `incidence` with the key-node model is fine.
    assert!(codes(&["forces.fin_aero.incidence=load_weighted"]).is_empty());
}

/// The panel matrices are part of the cached aerodynamic artifact: a warm plan takes them
/// from it (a doctored artifact's matrices are the ones the plan's fin block flies), so a
/// warm run does no panel work; the key-node model caches none.
#[test]
fn panel_matrices_are_cached_with_the_aerodynamics() {
    use flexflight::artifact::{Cache, CacheOutcome};
    use flexflight::ops::compile::{aero_cache_key, cache_key, plan_cached, vehicle_aero_cached};
    use flexflight::plan::aero::AeroArtifact;
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());
    let v = variant("subsonic_t06", &[LIFTING]);
    let structural = cache_key(&v.scenario.vehicle).unwrap();
    let cold = vehicle_aero_cached(&v.scenario.vehicle, &v.compiled, &structural, &cache)
        .unwrap()
        .unwrap();
    assert!(matches!(cold.outcome, CacheOutcome::Miss));
    let panels = cold
        .aero
        .panels
        .clone()
        .expect("lifting surface caches its panels");
    assert_eq!(
        Some(&panels),
        v.plan
            .aero
            .as_ref()
            .unwrap()
            .fin
            .as_ref()
            .unwrap()
            .panel_model()
    );
    let warm = vehicle_aero_cached(&v.scenario.vehicle, &v.compiled, &structural, &cache)
        .unwrap()
        .unwrap();
    assert!(matches!(warm.outcome, CacheOutcome::Hit));
    assert_eq!(warm.aero, cold.aero, "the artifact reads back bit for bit");
    // Doctor the cached matrices: the warm plan must fly them.
    let mut doctored = cold.aero.clone();
    let p = doctored.panels.as_mut().unwrap();
    for f in &mut p.fins {
        f.t.iter_mut().for_each(|x| *x *= 2.0);
    }
    let key = aero_cache_key(&v.scenario.vehicle, &structural).unwrap();
    flexflight::artifact::write_atomic(dir.path(), &key, &AeroArtifact::new(&doctored)).unwrap();
    let (plan, _) =
        plan_cached(&v.scenario, &v.compiled, &structural, &cache, &mut |_| {}).unwrap();
    let flown = plan
        .aero
        .as_ref()
        .unwrap()
        .fin
        .as_ref()
        .unwrap()
        .panel_model()
        .unwrap();
    assert_eq!(flown, doctored.panels.as_ref().unwrap());
    // The key-node model builds and caches no panels.
    let k = variant("subsonic_t06", &[]);
    let ks = cache_key(&k.scenario.vehicle).unwrap();
    let kc = vehicle_aero_cached(&k.scenario.vehicle, &k.compiled, &ks, &cache)
        .unwrap()
        .unwrap();
    assert!(kc.aero.panels.is_none());
}

/// The lifting-surface model's elastic increments are the panel loads `q T(M) u` scaled by the
/// leeward factor: the modal forces, the net normal force and the root bending moment (so the
/// root stress monitor sees them), fin by fin, in a crossflow where some fins are leeward.
/// The tables see the rigid motion of each fin's root body node (issue 38, item 3), so the
/// modal state is taken where those nodes do not move (`η`, `η̇` orthogonal to their six
/// shape rows): there the rigid airspeed ignores the state, and the panels' relative
/// deformation is the whole deformation. A state that moves the root changes the tables'
/// airspeed.
#[test]
fn lifting_surface_increments_are_the_panel_loads() {
    use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
    use flexflight::runtime::eom::{ForceModel, StateLayout, StateView};
    let v = variant("subsonic_t06", &[LIFTING]);
    let mut block = v.plan.aero.as_ref().unwrap().fin.clone().unwrap();
    let panels = block.panel_model().unwrap().clone();
    let n = v.plan.n_modes;
    let altitude = 5000.0;
    let eval = |block: &mut flexflight::runtime::forces::FinAero, eta: &[f64], eta_dot: &[f64]| {
        let layout = StateLayout { n };
        let x = layout.state(
            [0.0, 0.0, -altitude],
            [0.0, 0.0, 0.0, 1.0],
            [200.0, 6.0, 15.0],
            [0.0; 3],
            eta,
            eta_dot,
        );
        let view = StateView::new(layout, &x);
        let mut out = vec![0.0; 6 + n];
        block.generalized_forces(0.0, &view, &mut out);
        let samples: Vec<_> = (0..block.n_fins())
            .map(|i| block.last(i).unwrap())
            .collect();
        (out, samples)
    };
    let eta: Vec<f64> = (0..n).map(|k| 1e-4 * (k as f64 + 1.0)).collect();
    let eta_dot: Vec<f64> = (0..n).map(|k| 1e-2 * (k as f64 - 3.0)).collect();
    let (out0, s0) = eval(&mut block, &vec![0.0; n], &vec![0.0; n]);
    // A state that moves the root body nodes changes the tables' airspeed.
    let (_, moved) = eval(&mut block, &eta, &eta_dot);
    assert!(
        s0.iter()
            .zip(&moved)
            .any(|(p, d)| (p.mach - d.mach).abs() > 1e-9 * p.mach),
        "the tables see the root's motion"
    );
    // The six shape rows of every fin's root body node, orthonormalised (modified
    // Gram-Schmidt), and the state projected off them.
    let c = &v.compiled;
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for fin in 0..block.n_fins() {
        let m = flexflight::aero::panel::fin_model::root_body_node(c, &v.scenario.vehicle, fin)
            .unwrap();
        for d in 0..6 {
            let mut r: Vec<f64> = c.shapes[(6 * m + d) * n..(6 * m + d + 1) * n].to_vec();
            for b in &basis {
                let dot: f64 = r.iter().zip(b).map(|(x, y)| x * y).sum();
                r.iter_mut().zip(b).for_each(|(x, y)| *x -= dot * y);
            }
            let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm > 1e-9 {
                basis.push(r.iter().map(|x| x / norm).collect());
            }
        }
    }
    assert!(basis.len() < n, "{} root rows, {n} modes", basis.len());
    let off_root = |x: &[f64]| {
        let mut x = x.to_vec();
        for b in &basis {
            let dot: f64 = x.iter().zip(b).map(|(p, q)| p * q).sum();
            x.iter_mut().zip(b).for_each(|(p, q)| *p -= dot * q);
        }
        x
    };
    let (eta, eta_dot) = (off_root(&eta), off_root(&eta_dot));
    assert!(eta.iter().any(|x| x.abs() > 1e-6) && eta_dot.iter().any(|x| x.abs() > 1e-4));
    let (out1, s1) = eval(&mut block, &eta, &eta_dot);
    let a = Standard1976::new().at(altitude).unwrap().speed_of_sound;
    let mut q_sum = vec![0.0; n];
    let mut leeward = 0;
    for (i, (p, d)) in s0.iter().zip(&s1).enumerate() {
        assert!(
            (p.mach - d.mach).abs() <= 1e-15 * p.mach,
            "the rigid airspeed ignores a state that does not move the root: {} vs {}",
            p.mach,
            d.mach
        );
        assert!((p.leeward_factor - d.leeward_factor).abs() <= 1e-15);
        if d.leeward_factor < 1.0 {
            leeward += 1;
        }
        let speed = d.mach * a;
        let mut u: Vec<f64> = eta.clone();
        u.extend(eta_dot.iter().map(|e| e / speed));
        u.extend([0.0; 3]);
        let mut y = vec![0.0; n + 3];
        assert!(panels.apply(i, d.mach, d.dynamic_pressure * d.leeward_factor, &u, &mut y));
        let close = |x: f64, y: f64, what: &str| {
            assert!(
                (x - y).abs() <= 1e-12 * y.abs().max(1e-9),
                "fin {i} {what}: {x} vs {y}"
            )
        };
        close(d.root_moment - p.root_moment, -y[n + 1], "root moment");
        close(d.force_fin[2] - p.force_fin[2], -y[n], "normal force");
        let stress = block.stress_model(i).unwrap().stress(d.root_moment);
        assert_eq!(stress.to_bits(), d.root_stress.to_bits());
        for j in 0..n {
            q_sum[j] += y[j];
        }
    }
    assert!(leeward > 0, "a crossflow makes some fins leeward");
    for j in 0..n {
        let dq = out1[6 + j] - out0[6 + j];
        assert!(
            (dq - q_sum[j]).abs() <= 1e-12 * q_sum[j].abs().max(1e-9),
            "mode {j}: {dq} vs {}",
            q_sum[j]
        );
    }
}

/// `flexflight run` formats `history.csv` from the rows as the flight appends them
/// (`run::run_with_rows`, `cli::run::HistoryText`): the rows handed over are exactly
/// the run's rows, bit for bit and in order, and their text is `history_csv`'s. Two flights
/// cover the three places a row is appended: the 0.6 mm flight stops at the fin stress
/// limit inside a step (the cut row), the 1.0 mm flight ends at a stop time between output
/// times (the closing row after the integration).
#[test]
fn streamed_history_text_is_the_history_csv() {
    for sets in [
        &["run.stop_time=1.2s"][..],
        &["fins.thickness=1mm", "run.stop_time=0.3005s"][..],
    ] {
        let v = variant("subsonic_t06", sets);
        let mut seen: Vec<Vec<f64>> = Vec::new();
        let mut text = flexflight::ops::run::HistoryText::new(&v.plan.channels, 0);
        let out = flexflight::run::run_with_rows(
            &v.plan,
            &v.compiled.reduced,
            &mut |_, _| {},
            &mut |row| {
                seen.push(row.to_vec());
                text.push_row(row);
            },
        )
        .unwrap();
        assert!(out.rows.len() > 10, "{sets:?}: {} rows", out.rows.len());
        assert_eq!(seen.len(), out.rows.len(), "{sets:?}");
        assert_eq!(digest(&seen), digest(&out.rows), "{sets:?}");
        assert_eq!(text.rows(), out.rows.len());
        assert_eq!(
            text.finish(),
            flexflight::ops::run::history_csv(&out),
            "{sets:?}"
        );
    }
}

/// The root body node's rigid normal motion over the fin plane, `z = c0 + c1 x + c2 y`
/// (`fin_model::rigid_normal_of_node`, issue 38 item 3), is the normal row that the panel
/// model's spline gives a point rigidly attached to that node: the virtual root-row nodes of
/// `fin_structure` whose nearest body node is the root body node, checked mode by mode.
#[test]
fn root_rigid_normal_is_the_attached_points_normal_row() {
    use flexflight::aero::panel::fin_model::{
        fin_structure, nearest_body_node, rigid_normal_of_node, root_body_node,
    };
    let v = variant("subsonic_t06", &[LIFTING]);
    let c = &v.compiled;
    let veh = &v.scenario.vehicle;
    let f = veh.fins.as_ref().unwrap();
    let n = c.modes.len();
    let root_le_x = f.root_trailing_edge_x.value + f.root_chord.value;
    let flexflight::check::ir::Structure::Generate(g) = &veh.structure else {
        panic!("SPHADS-1's structure is generated");
    };
    let y_root = 0.5 * g.body.diameter.value;
    let mut compared = 0;
    for fin in 0..f.angles.len() {
        let m = root_body_node(c, veh, fin).unwrap();
        let coef = rigid_normal_of_node(c, veh, fin, m).unwrap();
        let s = fin_structure(c, veh, fin).unwrap();
        let (sd, cd) = f.angles[fin].value.sin_cos();
        for (k, node) in s.nodes.iter().enumerate() {
            if node[1] != 0.0 {
                continue;
            }
            let p = [root_le_x - node[0], y_root * cd, y_root * sd];
            if nearest_body_node(c, &p) != Some(m) {
                continue;
            }
            for (j, [c0, c1, c2]) in coef.iter().enumerate() {
                let z = c0 + c1 * node[0] + c2 * node[1];
                let row = s.normal_rows[k * n + j];
                assert!(
                    (z - row).abs() <= 1e-12 * row.abs().max(1e-9),
                    "fin {fin} node {k} mode {j}: {z} vs {row}"
                );
            }
            compared += 1;
        }
    }
    assert!(compared >= 4, "{compared} attached root points compared");
}
