//! The clamped fin's GAF tables `Q(k, M)` through the artifact cache (issue 13, deliverable
//! 1): the key covers every input of the table, a warm solution equals the cold one bit for
//! bit without building the table, and a bad entry is rebuilt, never trusted.

mod common;

use std::process::Command;

use flexflight::aero::panel::piston::Correction;
use flexflight::analysis::flutter::fin::{
    FinAero, FinFlutterSettings, clamped_fin_modes, fin_lattice, gaf_table,
};
use flexflight::analysis::flutter::pk::GafTable;
use flexflight::artifact::{Cache, CacheOutcome, write_atomic};
use flexflight::check::{DiskLoader, check_files, ir};
use flexflight::ops::gaf_cache::{GafArtifact, cached_gaf_table, gaf_key};

fn sphads1() -> ir::Vehicle {
    let file = common::root().join("examples/thesis/section_6_5.vdl");
    let checked = check_files(&[file], &[], &DiskLoader);
    assert!(!checked.has_errors());
    checked
        .program
        .scenario("subsonic_t06")
        .unwrap()
        .vehicle
        .clone()
}

/// A small unsteady table: 3 modes, 6 reduced frequencies, a coarse lattice.
fn small() -> FinFlutterSettings {
    FinFlutterSettings {
        aero: FinAero::Unsteady,
        chordwise: 6,
        spanwise: 6,
        correction: Correction::Ackeret,
        k_count: 6,
        k_max: 0.6,
    }
}

fn same_bits(a: &GafTable, b: &GafTable) -> bool {
    a.ks().len() == b.ks().len()
        && a.ks()
            .iter()
            .zip(b.ks())
            .all(|(x, y)| x.to_bits() == y.to_bits())
        && (0..a.ks().len()).all(|i| {
            a.at(i)
                .iter()
                .zip(b.at(i))
                .all(|(x, y)| x.re.to_bits() == y.re.to_bits() && x.im.to_bits() == y.im.to_bits())
        })
}

/// Every field of the settings, the Mach, the mode count and every structural input of the
/// clamped fin change the key; the body, the motor and the masses (which the clamped fin
/// does not see) do not. Fails if the key drops any of them.
#[test]
fn every_input_of_the_table_changes_the_key() {
    let v = sphads1();
    let s = small();
    let base = gaf_key(&v, 3, 0.6, &s).unwrap();
    let settings: Vec<(&str, FinFlutterSettings)> = vec![
        (
            "aero",
            FinFlutterSettings {
                aero: FinAero::QuasiSteady,
                ..s
            },
        ),
        ("chordwise", FinFlutterSettings { chordwise: 7, ..s }),
        ("spanwise", FinFlutterSettings { spanwise: 7, ..s }),
        (
            "correction",
            FinFlutterSettings {
                correction: Correction::None,
                ..s
            },
        ),
        ("k count", FinFlutterSettings { k_count: 7, ..s }),
        (
            "k max",
            FinFlutterSettings {
                k_max: 0.6000000000000001,
                ..s
            },
        ),
    ];
    for (what, t) in &settings {
        assert_ne!(gaf_key(&v, 3, 0.6, t).unwrap(), base, "{what}");
    }
    assert_ne!(gaf_key(&v, 4, 0.6, &s).unwrap(), base, "modes");
    assert_ne!(
        gaf_key(&v, 3, 0.6000000000000001, &s).unwrap(),
        base,
        "mach"
    );
    type Edit = Box<dyn Fn(&mut ir::Vehicle)>;
    let seen: Vec<(&str, Edit)> = vec![
        (
            "thickness",
            Box::new(|v| v.fins.as_mut().unwrap().thickness.value *= 1.01),
        ),
        (
            "span",
            Box::new(|v| v.fins.as_mut().unwrap().span.value *= 1.01),
        ),
        (
            "root chord",
            Box::new(|v| v.fins.as_mut().unwrap().root_chord.value *= 1.01),
        ),
        (
            "tip chord",
            Box::new(|v| v.fins.as_mut().unwrap().tip_chord.value *= 1.01),
        ),
        (
            "sweep",
            Box::new(|v| v.fins.as_mut().unwrap().leading_edge_sweep.value += 0.01),
        ),
        (
            "Young's modulus",
            Box::new(|v| v.fins.as_mut().unwrap().material.youngs_modulus.value *= 1.01),
        ),
        (
            "density",
            Box::new(|v| v.fins.as_mut().unwrap().material.density.value *= 1.01),
        ),
        (
            "Poisson ratio",
            Box::new(|v| v.fins.as_mut().unwrap().material.poisson.value *= 1.01),
        ),
        (
            "fin mesh",
            Box::new(|v| {
                if let ir::Structure::Generate(g) = &mut v.structure {
                    g.fin_span_elements.value += 1;
                }
            }),
        ),
    ];
    for (what, edit) in &seen {
        let mut w = v.clone();
        edit(&mut w);
        assert_ne!(gaf_key(&w, 3, 0.6, &s).unwrap(), base, "{what}");
    }
    let mut w = v.clone();
    w.material.density.value *= 1.5;
    w.motor = None;
    if let ir::Structure::Generate(g) = &mut w.structure {
        g.point_masses.clear();
    }
    assert_ne!(w, v);
    assert_eq!(gaf_key(&w, 3, 0.6, &s).unwrap(), base);
}

/// Cold: built and stored (a miss), bit for bit the direct table. Warm: read (a hit), bit for
/// bit the same. A corrupt file, and a well-formed entry built on other modes, are rebuilt and
/// replaced, the table again the direct one. Fails if the cache is not consulted, if a read
/// table differs from the built one, or if a bad entry is used.
#[test]
fn a_warm_table_is_the_cold_one_and_a_bad_entry_is_rebuilt() {
    let v = sphads1();
    let s = small();
    let modes = clamped_fin_modes(&v, 3).unwrap();
    let lattice = fin_lattice(&modes, &s).unwrap();
    let direct = gaf_table(&modes, &lattice, 0.6, &s).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());

    let cold = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    assert!(
        matches!(cold.outcome, CacheOutcome::Miss),
        "{}",
        cold.outcome
    );
    assert!(cold.warning.is_none());
    assert!(same_bits(&cold.table, &direct));
    let key = cold.key.unwrap();
    let path = cache.path_for(&key);
    assert!(path.exists());

    let warm = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    assert!(warm.outcome.is_hit(), "{}", warm.outcome);
    assert!(same_bits(&warm.table, &direct));

    // Another Mach is another entry.
    let other = cached_gaf_table(&v, &modes, &lattice, 0.5, &s, &cache).unwrap();
    assert!(matches!(other.outcome, CacheOutcome::Miss));
    assert!(!same_bits(&other.table, &direct));

    // A truncated file.
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    let again = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    assert!(
        matches!(again.outcome, CacheOutcome::Rebuilt { .. }),
        "{}",
        again.outcome
    );
    assert!(same_bits(&again.table, &direct));
    assert!(
        cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache)
            .unwrap()
            .outcome
            .is_hit()
    );

    // A valid container under the key, built on other modes (one frequency changed): not
    // paired with these modes.
    let mut art = GafArtifact::new(&direct, &modes, 0.6);
    art.omega[0] *= 1.0 + 1e-12;
    art.re[0] += 1.0;
    write_atomic(dir.path(), &key, &art).unwrap();
    let again = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    assert!(
        matches!(again.outcome, CacheOutcome::Rebuilt { .. }),
        "{}",
        again.outcome
    );
    assert!(same_bits(&again.table, &direct));

    // Another reduced-frequency grid under the key.
    let mut art = GafArtifact::new(&direct, &modes, 0.6);
    art.ks[1] *= 1.0 + 1e-12;
    write_atomic(dir.path(), &key, &art).unwrap();
    let again = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    assert!(matches!(again.outcome, CacheOutcome::Rebuilt { .. }));
    assert!(same_bits(&again.table, &direct));
}

/// Revision 1's table at a supersonic Mach was unsteady piston theory; revision 2's is the
/// Mach box (SPHADS-1's fin has a subsonic leading edge to Mach 1.88). An entry stored by
/// revision 1, under its key, is not served: the lookup misses and the table is the new
/// method's. Fails on the old code (one revision, one key: the piston table is read back).
#[test]
fn a_table_of_the_previous_revision_is_not_served() {
    use flexflight::ops::gaf_cache::gaf_key_at_revision;
    let v = sphads1();
    let s = FinFlutterSettings {
        k_max: 0.3,
        k_count: 3,
        ..small()
    };
    let modes = clamped_fin_modes(&v, 3).unwrap();
    let lattice = fin_lattice(&modes, &s).unwrap();
    let mach = 1.5;
    let fresh = gaf_table(&modes, &lattice, mach, &s).unwrap();
    // The old table: unsteady piston theory, as revision 1 computed it, is the quasi-steady
    // piston map, exactly linear in k.
    let qs = gaf_table(
        &modes,
        &lattice,
        mach,
        &FinFlutterSettings {
            aero: FinAero::QuasiSteady,
            ..s
        },
    )
    .unwrap();
    let (q0, q1) = (qs.at(0), qs.at(1));
    let values: Vec<Vec<_>> = fresh
        .ks()
        .iter()
        .map(|k| {
            let t = k / s.k_max;
            q0.iter().zip(q1).map(|(a, b)| *a + (*b - *a) * t).collect()
        })
        .collect();
    let piston = GafTable::new(3, fresh.ks().to_vec(), values).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());
    let old_key = gaf_key_at_revision("clamped-fin GAF 1", &v, 3, mach, &s).unwrap();
    let art = GafArtifact::new(&piston, &modes, mach);
    write_atomic(dir.path(), &old_key, &art).unwrap();
    let got = cached_gaf_table(&v, &modes, &lattice, mach, &s, &cache).unwrap();
    assert!(matches!(got.outcome, CacheOutcome::Miss), "{}", got.outcome);
    assert!(same_bits(&got.table, &fresh));
    assert!(!same_bits(&got.table, &piston));
}

/// Revision 3 answers the transonic band (the blend of the band's end tables, issue 33): an
/// entry stored under revision 2's key at a Mach in the band (here a table twice the right
/// one) is not served; the lookup misses and the table is the bridge's. Fails on the old code
/// (one revision: the stored table is read back; and the band was refused).
#[test]
fn a_table_of_revision_2_is_not_served_in_the_band() {
    use flexflight::ops::gaf_cache::gaf_key_at_revision;
    let v = sphads1();
    let s = FinFlutterSettings {
        k_max: 0.3,
        k_count: 3,
        ..small()
    };
    let modes = clamped_fin_modes(&v, 3).unwrap();
    let lattice = fin_lattice(&modes, &s).unwrap();
    let mach = 1.0;
    let fresh = gaf_table(&modes, &lattice, mach, &s).unwrap();
    let values: Vec<Vec<_>> = (0..fresh.ks().len())
        .map(|i| fresh.at(i).iter().map(|z| *z * 2.0).collect())
        .collect();
    let stale = GafTable::new(3, fresh.ks().to_vec(), values).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());
    let old_key = gaf_key_at_revision("clamped-fin GAF 2", &v, 3, mach, &s).unwrap();
    write_atomic(
        dir.path(),
        &old_key,
        &GafArtifact::new(&stale, &modes, mach),
    )
    .unwrap();
    let got = cached_gaf_table(&v, &modes, &lattice, mach, &s, &cache).unwrap();
    assert!(matches!(got.outcome, CacheOutcome::Miss), "{}", got.outcome);
    assert!(same_bits(&got.table, &fresh));
}

fn flexflight() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

/// `analyze flutter --clamped` twice on one cache: the first builds the table (miss), the
/// second reads it (hit) and writes the same V-g table byte for byte and the same summary
/// but for the cache outcome.
#[test]
fn a_warm_analyze_flutter_reads_the_table_and_writes_the_same_results() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let run = |name: &str| {
        let out = dir.path().join(name);
        let o = flexflight()
            .args(["analyze", "flutter"])
            .arg(common::root().join("examples/thesis/section_6_5.vdl"))
            .args(["--scenario", "subsonic_t06", "--clamped", "--modes", "3"])
            .args(["--set", "fins.thickness=0.875 mm", "--cache-dir"])
            .arg(&cache)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(
            o.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("flutter.json")).unwrap())
                .unwrap();
        let csv = std::fs::read(out.join("vg.csv")).unwrap();
        (stdout, json, csv)
    };
    let (s1, mut j1, c1) = run("cold");
    let (s2, mut j2, c2) = run("warm");
    assert_eq!(j1["gaf_cache"]["outcome"], "miss");
    assert_eq!(j2["gaf_cache"]["outcome"], "hit");
    assert_eq!(j1["gaf_cache"]["hash"], j2["gaf_cache"]["hash"]);
    assert!(
        cache
            .join(format!("{}.ffa", j1["gaf_cache"]["hash"].as_str().unwrap()))
            .exists()
    );
    assert!(s1.contains("Q(k): built and stored"), "{s1}");
    assert!(s2.contains("Q(k): read from the cache"), "{s2}");
    assert_eq!(c1, c2);
    j1["gaf_cache"]["outcome"] = serde_json::Value::Null;
    j2["gaf_cache"]["outcome"] = serde_json::Value::Null;
    assert_eq!(j1, j2);
}

/// `inspect` of a cached GAF table prints its matrices, equal to the stored ones.
#[test]
fn inspect_shows_a_cached_gaf_table() {
    let v = sphads1();
    let s = small();
    let modes = clamped_fin_modes(&v, 3).unwrap();
    let lattice = fin_lattice(&modes, &s).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());
    let c = cached_gaf_table(&v, &modes, &lattice, 0.6, &s, &cache).unwrap();
    let o = flexflight()
        .arg("inspect")
        .arg(cache.path_for(&c.key.unwrap()))
        .args(["--format", "json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["mach"], 0.6);
    let q = &j["q_of_k"];
    assert_eq!(q.as_array().unwrap().len(), c.table.ks().len());
    for (i, k) in c.table.ks().iter().enumerate() {
        assert_eq!(q[i]["k"].as_f64().unwrap(), *k);
        for r in 0..3 {
            for col in 0..3 {
                let z = c.table.at(i)[r * 3 + col];
                assert_eq!(q[i]["q"][r][col][0].as_f64().unwrap(), z.re);
                assert_eq!(q[i]["q"][r][col][1].as_f64().unwrap(), z.im);
            }
        }
    }
}
