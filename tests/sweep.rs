//! `flexflight sweep` and `merge` on a small, cheap sweep (a 0.2 s free tumble of SPHADS-1,
//! two fin thicknesses, so two structural variants, times three initial velocities, one of
//! which cannot be planned): the table does not depend on the thread count, shards merge
//! back into the unsharded table, a re-run resumes, a failing case is recorded, and bad
//! sweeps are diagnosed with a span and a non-zero exit.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::analysis::sweep::{Shard, merge};
use flexflight::check::{DiskLoader, check_files};
use flexflight::ops::sweep::{SweepOptions, read_shard, run_sweep, write_merged};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("sweep-test-cache")
}

/// A free tumble (no loads: cheap and well posed) with a gust and a turbulence patch, and
/// sweeps over it. `AXES` replaces the axes of sweep `small`.
const SWEEP_FILE: &str = r#"
import "VEHICLE"

scenario tumble {
  vehicle = sphads1
  with {
    forces.gravity.enabled = false
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
  }
  initial {
    velocity = (20, 10, 6) m/s
    angular_velocity = (6, 6, 6) rad/s
    attitude = euler(0 deg, 0 deg, 0 deg)
    altitude = 5 km
  }
  stimuli {
    gust first {
      start = 0.01 s
      duration = 0.01 s
      velocity = (0, 0, 5) m/s
      frame = body
    }
    # Turbulence needs an airspeed: the case with V = 0 fails at planning.
    turbulence air {
      model = dryden
      intensity = 1 m/s
      scale_length = 533 m
      seed = 3
      start = 0.1 s
      duration = 0.05 s
    }
  }
  run {
    stop_time = 0.2 s
    integrator = dopri5
    rtol = 1e-6
    atol = 1e-9
    output_interval = 1 ms
    stop_on_ground = false
  }
}

sweep small {
  scenario = tumble
  grid {
    AXES
  }
}
"#;

const GOOD_AXES: &str = "fins.thickness = [0.6 mm, 0.8 mm]\n    initial.velocity = [(20, 10, 6) m/s, (0, 0, 0) m/s, (25, 0, 0) m/s]";

fn write_sweep(dir: &Path, axes: &str) -> PathBuf {
    let vehicle = Path::new(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let text = SWEEP_FILE
        .replace("VEHICLE", &vehicle.display().to_string())
        .replace("AXES", axes);
    let path = dir.join("sweep.vdl");
    std::fs::write(&path, text).unwrap();
    path
}

fn opts(jobs: usize, shard: Shard) -> SweepOptions {
    SweepOptions {
        jobs,
        shard,
        cache_dir: Some(cache()),
        sets: Vec::new(),
        progress: None,
    }
}

fn sweep_in(file: &Path, out: &Path, o: &SweepOptions) -> flexflight::ops::sweep::SweepReport {
    let checked = check_files(&[file.to_path_buf()], &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let sweep = checked.program.sweep("small").unwrap();
    let scenario = &checked.program.scenarios[sweep.scenario].name.value;
    run_sweep(file, sweep, scenario, out, o).unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

#[test]
fn one_and_two_threads_give_the_same_table_and_a_failed_case_is_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_sweep(dir.path(), GOOD_AXES);
    let one = sweep_in(&file, &dir.path().join("j1"), &opts(1, Shard::ALL));
    let two = sweep_in(&file, &dir.path().join("j2"), &opts(2, Shard::ALL));
    let t1 = read(&dir.path().join("j1/sweep.csv"));
    let t2 = read(&dir.path().join("j2/sweep.csv"));
    assert_eq!(t1, t2, "sweep.csv differs between 1 and 2 threads");
    assert_eq!((one.ran, one.failed, one.artifacts), (6, 2, 2));
    assert_eq!(two.rows, one.rows);

    let lines: Vec<&str> = t1.lines().collect();
    assert_eq!(lines.len(), 7);
    assert!(lines[0].starts_with("index,case_id,fins.thickness,initial.velocity,status,"));
    // Case 1 = (0.6 mm, V = 0): planning fails; its error is in the table, the sweep went on.
    assert!(
        lines[2].starts_with("1,case_0001,0.6 mm,\"(0, 0, 0) m/s\",failed,"),
        "{}",
        lines[2]
    );
    assert!(lines[2].contains("airspeed"), "{}", lines[2]);
    assert!(dir.path().join("j1/cases/case_0001/error.txt").is_file());
    assert!(!dir.path().join("j1/cases/case_0001/summary.json").exists());
    // The other cases completed, with histories, summaries and an identification.
    for k in [0, 2, 3, 5] {
        assert!(
            lines[k + 1].contains(",ok,completed,0.2,"),
            "{}",
            lines[k + 1]
        );
        let case = dir.path().join(format!("j1/cases/case_000{k}"));
        assert!(read(&case.join("history.csv")).lines().count() > 150);
        let s: serde_json::Value = serde_json::from_str(&read(&case.join("summary.json"))).unwrap();
        assert_eq!(s["status"], "ok");
        assert_eq!(s["sweep_case"]["index"], k);
        let ids = s["identification"].as_array().unwrap();
        // Two stimuli times two channels.
        assert_eq!(ids.len(), 4);
        assert_eq!(ids[0]["stimulus"], "first");
        assert_eq!(ids[0]["window_start"], 0.02);
        assert_eq!(ids[0]["window_end"], 0.1);
    }
}

#[test]
fn shards_merge_into_the_unsharded_table_and_a_rerun_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_sweep(dir.path(), GOOD_AXES);
    let all = dir.path().join("all");
    sweep_in(&file, &all, &opts(2, Shard::ALL));
    let s0 = sweep_in(
        &file,
        &dir.path().join("s0"),
        &opts(1, Shard { index: 0, count: 2 }),
    );
    let s1 = sweep_in(
        &file,
        &dir.path().join("s1"),
        &opts(1, Shard { index: 1, count: 2 }),
    );
    assert_eq!((s0.rows.len(), s1.rows.len()), (3, 3));
    assert!(
        s0.rows
            .iter()
            .all(|r| r[0].parse::<usize>().unwrap() % 2 == 0)
    );

    let tables = [
        read_shard(&dir.path().join("s1")).unwrap(),
        read_shard(&dir.path().join("s0")).unwrap(),
    ];
    let merged = merge(&tables).unwrap();
    assert!(merged.missing.is_empty());
    write_merged(&dir.path().join("merged"), &merged).unwrap();
    assert_eq!(
        read(&dir.path().join("merged/sweep.csv")),
        read(&all.join("sweep.csv"))
    );
    assert_eq!(
        read(&dir.path().join("merged/sweep.json")),
        read(&all.join("sweep.json"))
    );

    // The binary's merge: a missing shard is reported (exit 1), a shard twice is refused.
    let out = bin()
        .args(["merge", "--out"])
        .arg(dir.path().join("m1"))
        .arg(dir.path().join("s0"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("3 case(s) missing: 1, 3, 5"));
    let out = bin()
        .args(["merge", "--out"])
        .arg(dir.path().join("m2"))
        .arg(dir.path().join("s0"))
        .arg(&all)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("appears twice"));

    // Resume: mark a finished case, delete another's summary as if interrupted; the re-run
    // keeps the marked one untouched, runs the deleted one and the failed ones again.
    let marked = all.join("cases/case_0000/summary.json");
    let mut v: serde_json::Value = serde_json::from_str(&read(&marked)).unwrap();
    v["marker"] = "kept".into();
    std::fs::write(&marked, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    std::fs::remove_file(all.join("cases/case_0003/summary.json")).unwrap();
    let before = read(&all.join("sweep.csv"));
    let again = sweep_in(&file, &all, &opts(2, Shard::ALL));
    assert_eq!((again.skipped, again.ran, again.failed), (3, 3, 2));
    assert_eq!(read(&all.join("sweep.csv")), before);
    assert!(read(&marked).contains("\"marker\": \"kept\""));
    assert!(all.join("cases/case_0003/summary.json").is_file());

    // An edited scenario is a different variant: nothing is reused.
    std::fs::write(
        &file,
        read(&file).replace("stop_time = 0.2 s", "stop_time = 0.15 s"),
    )
    .unwrap();
    let edited = sweep_in(&file, &all, &opts(2, Shard::ALL));
    assert_eq!((edited.skipped, edited.ran), (0, 6));
    assert!(read(&all.join("sweep.csv")).contains(",ok,completed,0.15,"));
}

#[test]
fn bad_sweeps_are_diagnosed_with_a_span_and_a_nonzero_exit() {
    let dir = tempfile::tempdir().unwrap();
    let run = |axes: &str, name: &str| {
        let file = write_sweep(dir.path(), axes);
        bin()
            .args(["sweep", "--sweep", name, "--out"])
            .arg(dir.path().join("out"))
            .arg("--cache-dir")
            .arg(cache())
            .arg(&file)
            .env("NO_COLOR", "1")
            .output()
            .unwrap()
    };
    let unknown_field = run("fins.thicknes = [0.6 mm]", "small");
    let err = String::from_utf8_lossy(&unknown_field.stderr).to_string();
    assert_eq!(unknown_field.status.code(), Some(1), "{err}");
    assert!(
        err.contains("thicknes") && err.contains("sweep.vdl:"),
        "{err}"
    );
    assert!(err.contains("did you mean `thickness`"), "{err}");

    let empty = run(
        "fins.thickness = range(1 mm, 0.5 mm, step = 0.1 mm)",
        "small",
    );
    let err = String::from_utf8_lossy(&empty.stderr).to_string();
    assert_eq!(empty.status.code(), Some(1), "{err}");
    assert!(
        err.contains("vdl::sweep::range") && err.contains("the range is empty"),
        "{err}"
    );

    let no_values = run("fins.thickness = []", "small");
    let err = String::from_utf8_lossy(&no_values.stderr).to_string();
    assert_eq!(no_values.status.code(), Some(1), "{err}");
    assert!(err.contains("vdl::sweep::empty"), "{err}");

    let unknown_sweep = run("fins.thickness = [0.6 mm]", "smal");
    let err = String::from_utf8_lossy(&unknown_sweep.stderr).to_string();
    assert_eq!(unknown_sweep.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no sweep named `smal`; declared: small"),
        "{err}"
    );
    assert!(
        !dir.path().join("out").exists(),
        "nothing is written for bad input"
    );

    let file = write_sweep(dir.path(), "fins.thickness = [0.6 mm]");
    let bad_shard = bin()
        .args(["sweep", "--sweep", "small", "--shard", "2/2", "--out"])
        .arg(dir.path().join("out"))
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(bad_shard.status.code(), Some(2));
    let env_shard = bin()
        .args(["sweep", "--sweep", "small", "--shard", "env", "--out"])
        .arg(dir.path().join("out"))
        .arg(&file)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    assert_eq!(env_shard.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&env_shard.stderr).contains("SLURM_ARRAY_TASK_ID"));
}

#[test]
fn slurm_environment_selects_the_shard() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_sweep(
        dir.path(),
        "initial.velocity = [(20, 10, 6) m/s, (25, 0, 0) m/s, (30, 0, 0) m/s]",
    );
    let out = bin()
        .args([
            "sweep", "--sweep", "small", "--shard", "env", "--jobs", "1", "--format", "json",
            "--out",
        ])
        .arg(dir.path().join("out"))
        .arg("--cache-dir")
        .arg(cache())
        .arg(&file)
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "2")
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = read(&dir.path().join("out/sweep.csv"));
    let ids: Vec<&str> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    assert_eq!(ids, ["case_0001"]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["shard"]["index"], 1);
    assert_eq!(report["cases"], 1);
}

/// Eigen-analysis sweeps: every case gets the least stable root and its class, no history;
/// the planar pinned model and the linearised 3-D model agree that the thinnest fins
/// flutter and the thickest are stable at 200 m/s, 5 km.
#[test]
fn planar_and_linear_sweeps_classify_every_case() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    for (sweep, analysis) in [
        ("subsonic_thickness_planar", "planar_pinned"),
        ("subsonic_thickness_linear", "linear3d"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join(sweep);
        let o = bin()
            .arg("sweep")
            .arg(&file)
            .args(["--sweep", sweep, "--jobs", "2", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(cache())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let table = read(&out.join("sweep.csv"));
        let mut lines = table.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 8, "{sweep}");
        for r in &rows {
            assert_eq!(r[col("status")], "ok", "{sweep}: {r:?}");
            assert_eq!(r[col("fit_channel")], analysis);
            let sigma: f64 = r[col("sigma_d")].parse().unwrap();
            let class = r[col("stability_class")];
            assert_eq!(sigma > 0.0, class == "flutter" || class == "divergence");
        }
        assert_eq!(
            rows[0][col("stability_class")],
            "flutter",
            "{sweep}: 0.3 mm"
        );
        assert_eq!(rows[7][col("stability_class")], "stable", "{sweep}: 1.0 mm");
        let case = out.join("cases/case_0000");
        assert!(case.join("summary.json").is_file());
        assert!(!case.join("history.csv").exists());
    }
}
