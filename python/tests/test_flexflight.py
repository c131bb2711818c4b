"""The Python package against the command line and its own promises (issue 37)."""

import json
import math
import os
import shutil
import struct
import subprocess
import sys

import pytest

import flexflight

K1000 = os.path.join("examples", "hpr_k1000", "hpr_k1000.vdl")
CALISTO = os.path.join("examples", "calisto", "calisto.vdl")
THESIS = os.path.join("examples", "thesis", "section_6_5.vdl")

# Wall-clock fields of summary.json: the only ones that may differ between two runs of the
# same inputs (`wall_time_s`, the flight's; `seconds` of the flutter margin's solve).
WALL_CLOCK = {("wall_time_s",), ("flutter_margin", "seconds")}


def _strip_wall_clock(summary):
    s = json.loads(json.dumps(summary))
    for path in WALL_CLOCK:
        d = s
        for k in path[:-1]:
            d = d.get(k) if isinstance(d, dict) else None
            if d is None:
                break
        if isinstance(d, dict):
            d.pop(path[-1], None)
    return s


def _path(root, rel):
    return os.path.join(root, rel)


def test_run_gives_the_same_bits_as_the_cli(root, cache_dir, binary, tmp_path):
    """`Project.run` + `Run.write` and `flexflight run` on hpr_k1000 / k1000: the same
    history.csv bytes, the same summary.json but for the wall-clock fields, and the
    in-memory history is history.csv's numbers bit for bit. A first run warms the cache, so
    that both compared runs find the same artifacts (`summary.json` says hit or miss)."""
    cli_out, py_out = tmp_path / "cli", tmp_path / "py"
    for out in (tmp_path / "warm", cli_out):
        subprocess.run(
            [binary, "run", _path(root, K1000), "--scenario", "k1000", "--out", str(out),
             "--cache-dir", cache_dir],
            check=True, capture_output=True,
        )
    run = flexflight.open(_path(root, K1000), cache_dir=cache_dir).run("k1000")
    run.write(py_out)
    cli_hist = (cli_out / "history.csv").read_bytes()
    assert (py_out / "history.csv").read_bytes() == cli_hist
    cli_summary = json.loads((cli_out / "summary.json").read_text())
    py_summary = json.loads((py_out / "summary.json").read_text())
    assert "wall_time_s" in cli_summary  # the field the comparison leaves out exists
    assert _strip_wall_clock(py_summary) == _strip_wall_clock(cli_summary)
    assert _strip_wall_clock(run.summary) == _strip_wall_clock(cli_summary)
    assert sorted(os.listdir(py_out)) == sorted(os.listdir(cli_out))
    if (cli_out / "flutter_margin.csv").exists():
        assert (py_out / "flutter_margin.csv").read_bytes() == (cli_out / "flutter_margin.csv").read_bytes()
    # The history columns: every value the float history.csv reads back to, same bits.
    lines = cli_hist.decode().splitlines()
    header = lines[0].split(",")
    cols = run.columns
    assert list(cols) == header
    assert len(cols[header[0]]) == len(lines) - 1
    bits = lambda x: struct.pack("<d", float(x))  # noqa: E731
    for i, line in enumerate(lines[1:]):
        for name, text in zip(header, line.split(",")):
            assert bits(cols[name][i]) == bits(text), (i, name)


def test_open_errors_carry_the_diagnostic(root, tmp_path):
    """A unit error: `open` raises `flexflight.Error` with the checker's code, file, line
    and column; `check` returns the same diagnostic without raising."""
    text = open(_path(root, K1000)).read()
    bad = text.replace("    thickness = 2 mm\n", "    thickness = 2 kg\n", 1)
    assert bad != text
    f = tmp_path / "bad.vdl"
    f.write_text(bad)
    shutil.copy(_path(root, "examples/hpr_k1000/AeroTech_K1000T.eng"), tmp_path)
    line = bad[: bad.index("thickness = 2 kg")].count("\n") + 1
    with pytest.raises(flexflight.Error) as e:
        flexflight.open(f)
    err = e.value
    assert err.diagnostics, "the error carries diagnostics"
    d = err.diagnostics[0]
    assert d.severity == "error"
    assert d.code.startswith("vdl::")
    assert d.file is not None and d.file.endswith("bad.vdl")
    assert d.line == line
    assert d.column is not None and d.column >= 1
    assert (err.code, err.file, err.line, err.column) == (d.code, d.file, d.line, d.column)
    found = flexflight.check(f)
    assert [x.code for x in found if x.is_error] == [x.code for x in err.diagnostics if x.is_error]


def test_usage_errors_are_exceptions(root, cache_dir):
    with pytest.raises(flexflight.Error) as e:
        flexflight.open(os.path.join(root, "no", "such.vdl"))
    assert e.value.code == "usage"
    p = flexflight.open(_path(root, K1000), cache_dir=cache_dir)
    with pytest.raises(flexflight.Error) as e:
        p.run("no_such_scenario")
    assert e.value.code == "usage" and "k1000" in e.value.message
    with pytest.raises(flexflight.Error):
        p.flutter("k1000", aero="no-such-aero")
    with pytest.raises(flexflight.Error):
        p.flutter("k1000", speeds=[100.0, float("nan")])
    with pytest.raises(flexflight.Error):
        flexflight.open(_path(root, K1000), sets={"no.such.path": "1 m"})


def test_sets_override_like_the_command_line(root, cache_dir):
    """`sets` is `--set`: a shorter stop time stops the flight there."""
    p = flexflight.open(_path(root, K1000), sets={"run.stop_time": "1.5 s"}, cache_dir=cache_dir)
    assert "k1000" in p.scenarios
    assert p.check() == []
    r = p.run("k1000", flutter_margin=False)
    assert r.summary["t_end"] == pytest.approx(1.5, abs=1e-12)
    assert r.summary["stop_reason"] == "completed"
    assert r.flutter_margin is None
    t = r.columns["t"]
    assert t[-1] == r.summary["t_end"]


def test_history_without_pandas_is_numpy(root, cache_dir, monkeypatch):
    import numpy as np

    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` fails
    r = flexflight.open(_path(root, K1000), sets={"run.stop_time": "1 s"}, cache_dir=cache_dir).run(
        "k1000", flutter_margin=False
    )
    h = r.history
    assert isinstance(h, dict)
    assert all(isinstance(v, np.ndarray) and v.dtype == np.float64 for v in h.values())
    assert len({len(v) for v in h.values()}) == 1


def test_history_with_pandas_is_a_dataframe(root, cache_dir):
    pd = pytest.importorskip("pandas")
    r = flexflight.open(_path(root, K1000), sets={"run.stop_time": "1 s"}, cache_dir=cache_dir).run(
        "k1000", flutter_margin=False
    )
    assert isinstance(r.history, pd.DataFrame)
    assert list(r.history.columns) == list(r.columns)


def test_progress_is_monotone_and_ends_at_the_stop(root, cache_dir):
    seen = []
    r = flexflight.open(_path(root, K1000), sets={"run.stop_time": "2 s"}, cache_dir=cache_dir).run(
        "k1000", flutter_margin=False, progress=lambda t, t_end: seen.append((t, t_end))
    )
    assert len(seen) >= 2
    ts = [t for t, _ in seen]
    assert ts == sorted(ts)
    assert seen[0][0] == 0.0 and seen[-1][0] == r.summary["t_end"]
    assert all(te == 2.0 for _, te in seen)


def test_progress_exception_is_raised(root, cache_dir):
    def boom(t, t_end):
        raise RuntimeError("stop it")

    p = flexflight.open(_path(root, K1000), sets={"run.stop_time": "1 s"}, cache_dir=cache_dir)
    with pytest.raises(RuntimeError, match="stop it"):
        p.run("k1000", flutter_margin=False, progress=boom)


def test_events_are_the_summarys(root, cache_dir):
    r = flexflight.open(_path(root, K1000), sets={"run.stop_time": "4 s"}, cache_dir=cache_dir).run(
        "k1000", flutter_margin=False
    )
    ev = r.events
    assert ev["rail_exit"] is not None and ev["burnout"] is not None
    assert 0.0 < ev["rail_exit"]["t"] < ev["burnout"]["t"] <= r.summary["t_end"]
    assert ev["apogee"] is None and ev["landing"] is None  # the flight stopped at 4 s


def test_compile_gives_mass_properties_and_modes(root, cache_dir):
    c = flexflight.open(_path(root, K1000), cache_dir=cache_dir).compile()
    assert c["vehicle"] == "hpr_k1000"
    assert 8.0 < c["total_mass_kg"] < 10.5  # "total mass about 9 kg" (the example's brief)
    assert len(c["modes"]) >= 1
    freqs = [m["frequency_hz"] for m in c["modes"]]
    # Ascending but for the eigen-solver's rounding within a degenerate pair (symmetric fins:
    # 143.02132837961 and 143.02132837941 Hz).
    assert all(f > 0 for f in freqs)
    assert all(b >= a * (1 - 1e-11) for a, b in zip(freqs, freqs[1:]))
    assert len(c["mode_table"]["frequency_hz"]) == len(freqs)


def test_flutter_is_the_clis(root, cache_dir, binary):
    """`Project.flutter(clamped=True)` and `analyze flutter --clamped --format json`: the
    same flutter.json (but the GAF cache's hit or miss); the V-g table's flutter branch
    changes the sign of its damping at the flutter point."""
    p = flexflight.open(_path(root, K1000), cache_dir=cache_dir)
    # Speeds from 200 m/s: the lattice resolves the modes' reduced frequencies there (the
    # default 0.3 a is refused at this Mach as analysis::flutter::too_few_panels).
    f = p.flutter("k1000", clamped=True, mach=0.5, altitude=1000.0, speeds=[200.0 + 20.0 * i for i in range(36)])
    out = subprocess.run(
        [binary, "analyze", "flutter", _path(root, K1000), "--scenario", "k1000", "--clamped",
         "--mach", "0.5", "--altitude", "1000 m", "--speeds", "200m/s:900m/s:36", "--format", "json", "--cache-dir", cache_dir],
        check=True, capture_output=True, text=True,
    ).stdout
    cli = json.loads(out)
    a, b = dict(f.summary), dict(cli)
    a.pop("gaf_cache"), b.pop("gaf_cache")
    assert a == b
    t = f.table
    assert set(["speed_m_s", "branch", "g", "frequency_hz"]) <= set(t.keys() if isinstance(t, dict) else t.columns)
    pts = f.flutter_points
    if pts:
        v = pts[0]["speed_m_s"]
        name = pts[0]["mode"]
        rows = [(s, g) for s, n, g in zip(t["speed_m_s"], t["name"], t["g"]) if n == name and not math.isnan(g)]
        below = [g for s, g in rows if s < v]
        above = [g for s, g in rows if s > v]
        assert below and above and below[-1] <= 0.0 <= above[0]


def test_sweep_is_the_clis(root, cache_dir, binary, tmp_path):
    """`Project.sweep` writes the same `sweep.csv` as `flexflight sweep`, bit for bit,
    whatever the number of jobs; progress counts the cases up to the total."""
    p = flexflight.open(_path(root, THESIS), cache_dir=cache_dir)
    calls = []
    r = p.sweep("subsonic_thickness_planar", tmp_path / "py", jobs=2,
                progress=lambda done, total: calls.append((done, total)))
    subprocess.run(
        [binary, "sweep", _path(root, THESIS), "--sweep", "subsonic_thickness_planar",
         "--jobs", "1", "--out", str(tmp_path / "cli"), "--cache-dir", cache_dir],
        check=True, capture_output=True,
    )
    with open(tmp_path / "py" / "sweep.csv", "rb") as a, open(tmp_path / "cli" / "sweep.csv", "rb") as b:
        assert a.read() == b.read()
    assert r.summary["cases"] == 8 and r.summary["failed"] == 0 and r.summary["ran"] == 8
    assert calls and calls[-1] == (8, 8)
    assert all(x[0] <= y[0] for x, y in zip(calls, calls[1:]))
    t = r.table
    assert len(t[list(t.keys() if isinstance(t, dict) else t.columns)[0]]) == 8
    # A second call resumes: every case is found finished.
    again = p.sweep("subsonic_thickness_planar", tmp_path / "py", jobs=1)
    assert again.summary["resumed"] == 8 and again.summary["ran"] == 0
    with pytest.raises(flexflight.Error) as e:
        p.sweep("no_such_sweep", tmp_path / "x")
    assert "subsonic_thickness_planar" in str(e.value)


def test_montecarlo_is_the_clis(root, cache_dir, binary, tmp_path):
    """`Project.montecarlo` writes the same `samples.csv` and `statistics.json` as
    `flexflight montecarlo`, bit for bit, with another number of jobs; progress counts the
    samples up to the total; the statistics and the samples table read back."""
    p = flexflight.open(_path(root, K1000), cache_dir=cache_dir)
    calls = []
    r = p.montecarlo("k1000_flight", tmp_path / "py", samples=3, jobs=2,
                     progress=lambda done, total: calls.append((done, total)))
    subprocess.run(
        [binary, "montecarlo", _path(root, K1000), "--dispersion", "k1000_flight",
         "--samples", "3", "--jobs", "1", "--out", str(tmp_path / "cli"), "--cache-dir", cache_dir],
        check=True, capture_output=True,
    )
    for name in ["samples.csv", "statistics.json"]:
        with open(tmp_path / "py" / name, "rb") as a, open(tmp_path / "cli" / name, "rb") as b:
            assert a.read() == b.read(), name
    assert r.summary["samples"] == 3 and r.summary["failed"] == 0 and r.summary["ran"] == 3
    assert calls and calls[-1] == (3, 3)
    assert isinstance(r.statistics, dict) and r.text
    t = r.samples
    assert len(t[list(t.keys() if isinstance(t, dict) else t.columns)[0]]) == 3
    with pytest.raises(flexflight.Error) as e:
        p.montecarlo("no_such_dispersion", tmp_path / "x")
    assert "k1000_flight" in str(e.value)


def test_montecarlo_options_reach_the_runner(root, cache_dir, tmp_path):
    """`exact_boundaries` and `full_outputs` are the CLI's `--exact-boundaries` and
    `--full-outputs`: a fin-thickness dispersion's boundaries are interpolated between node
    thicknesses (`montecarlo.json` names them) unless `exact_boundaries`; the complete run
    summary gives the fast path's `samples.csv` bits."""
    vdl = tmp_path / "t.vdl"
    vdl.write_text(
        f'import "{_path(root, K1000)}"\n'
        "dispersion k1000_t {\n  scenario = k1000\n  samples = 2\n  seed = 2026\n"
        "  vary {\n    fins.thickness = truncated_normal(mean = 2 mm, sd = 0.05 mm, "
        "min = 1.85 mm, max = 2.15 mm)\n  }\n}\n"
    )
    p = flexflight.open(str(vdl), cache_dir=cache_dir)
    family = p.montecarlo("k1000_t", tmp_path / "family", jobs=1)
    exact = p.montecarlo("k1000_t", tmp_path / "exact", jobs=1, exact_boundaries=True)
    assert family.summary["failed"] == 0 and exact.summary["failed"] == 0
    manifests = {}
    for name in ["family", "exact"]:
        with open(tmp_path / name / "montecarlo.json") as f:
            manifests[name] = json.load(f)
    assert len(manifests["family"]["boundary_nodes"]) >= 2
    assert "boundary_nodes" not in manifests["exact"]
    fast = p.montecarlo("k1000_t", tmp_path / "fast", jobs=1, flutter_margin=False)
    full = p.montecarlo("k1000_t", tmp_path / "full", jobs=1, flutter_margin=False, full_outputs=True)
    assert fast.summary["failed"] == 0 and full.summary["failed"] == 0
    with open(tmp_path / "fast" / "samples.csv", "rb") as a, open(tmp_path / "full" / "samples.csv", "rb") as b:
        assert a.read() == b.read()


def test_linear_roots(root, cache_dir):
    lin = flexflight.open(_path(root, K1000), cache_dir=cache_dir).linear("k1000")
    assert lin["scenario"] == "k1000" and lin["vehicle"] == "hpr_k1000"
    assert "analysis" in lin


def test_drag_curve_is_rocketpys_for_calisto(root, cache_dir, tmp_path):
    """Calisto's body table carries RocketPy's power-off drag curve as its axial force and
    its fin table none (examples/calisto/README.md): the drag curve written back in
    RocketPy's format is RocketPy's curve at the table's Machs."""
    r = flexflight.open(_path(root, CALISTO), sets={"run.stop_time": "0.5 s"}, cache_dir=cache_dir).run(
        "calisto", flutter_margin=False
    )
    curve = r.drag_curve()
    assert curve and [m for m, _ in curve] == sorted(m for m, _ in curve)
    out = tmp_path / "drag.csv"
    flexflight.write_rocketpy_drag_curve(curve, out)
    back = [tuple(float(x) for x in line.split(",")) for line in out.read_text().splitlines()]
    assert back == [(float(m), float(c)) for m, c in curve]
    ref = {}
    for line in open(_path(root, "tools/rocketpy/data/powerOffDragCurve.csv")):
        m, c = (float(x) for x in line.strip().split(",")[:2])
        ref[m] = c
    common = [(m, c) for m, c in curve if m in ref]
    assert len(common) >= 10
    for m, c in common:
        assert c == pytest.approx(ref[m], rel=1e-12), m
