"""flexflight from Python: flight simulation and flutter analysis of flexible rockets.

A vehicle file (the VDL language, ``docs/language.md``) opens as a :class:`Project`; its
operations are those of the ``flexflight`` command line, with Python results::

    import flexflight

    project = flexflight.open("examples/hpr_k1000/hpr_k1000.vdl")
    run = project.run("k1000")
    run.summary["flight"]["apogee"]       # dict, as summary.json
    run.history["altitude"]               # pandas DataFrame column (dict of numpy arrays
                                          # without pandas)
    run.flutter_margin                    # flutter margin over the flight (table)
    run.write("out/")                     # history.csv, summary.json, ... as `flexflight run`

    vg = project.flutter("k1000", clamped=True)
    vg.table                              # the V-g table
    vg.flutter_points                     # list of flutter points

The numbers are those of the command line, bit for bit: the same library (``flexflight::ops``)
computes them. Long operations release the GIL. Errors raise :class:`Error`, whose
``diagnostics`` carry the code, message, file, line, column and help.
"""

from __future__ import annotations

import builtins
import csv
import io
import os
import sys
from array import array
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from . import _native
from ._errors import Diagnostic, Error

__all__ = [
    "Diagnostic",
    "Error",
    "FlutterResult",
    "MonteCarloResult",
    "Project",
    "Run",
    "SweepResult",
    "check",
    "open",
    "write_rocketpy_drag_curve",
    "__version__",
]

__version__: str = _native.__version__

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[None, bool, Callable[[float, float], Any], Any]


def _sets(sets: Optional[Dict[str, Any]]) -> List[str]:
    """``{"path": value}`` as the command line's ``--set PATH=VALUE`` strings."""
    out: List[str] = []
    for k, v in (sets or {}).items():
        if isinstance(v, bool):
            v = "true" if v else "false"
        out.append(f"{k}={v}")
    return out


def _files(path: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    if isinstance(path, (str, os.PathLike)):
        return [os.fspath(path)]
    return [os.fspath(p) for p in path]


def _columns(channels: Sequence[str], rows: int, data: bytes) -> Dict[str, Any]:
    """Row-major little-endian doubles as one column per channel (numpy arrays when numpy
    is installed, else ``array('d')``): the same bits as the run's rows."""
    width = len(channels)
    try:
        import numpy as np
    except ImportError:  # pragma: no cover - numpy is a dependency
        flat = array("d")
        flat.frombytes(data)
        if sys.byteorder != "little":
            flat.byteswap()
        return {c: flat[j::width] for j, c in enumerate(channels)}
    flat = np.frombuffer(data, dtype="<f8").reshape(rows, width) if width else np.empty((rows, 0))
    return {c: np.ascontiguousarray(flat[:, j]).astype(np.float64, copy=False) for j, c in enumerate(channels)}


def _table(columns: Dict[str, Any]) -> Any:
    """A pandas DataFrame of ``columns`` when pandas is installed, else the dict itself."""
    try:
        import pandas as pd
    except ImportError:
        return columns
    return pd.DataFrame(columns)


def _csv_columns(text: str) -> Dict[str, Any]:
    """A CSV (header line, numbers or quoted names) as columns; numeric columns as numpy
    arrays (lists without numpy), empty cells as NaN."""
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    cols: Dict[str, Any] = {}
    for j, name in enumerate(header):
        raw = [r[j] if j < len(r) else "" for r in body]
        try:
            vals: List[Any] = [float(x) if x != "" else float("nan") for x in raw]
        except ValueError:
            cols[name] = raw
            continue
        try:
            import numpy as np

            cols[name] = np.asarray(vals, dtype=np.float64)
        except ImportError:  # pragma: no cover
            cols[name] = vals
    return cols


class _ProgressAdapter:
    """A ``progress(t, t_end)`` callable from ``True`` (a tqdm bar when tqdm is installed),
    a callable, or a tqdm bar."""

    def __init__(self, progress: Progress, label: str, unit: str = "s") -> None:
        self.bar = None
        self.fn: Optional[Callable[[float, float], Any]] = None
        if progress is True:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                return
            if unit == "s":
                self.bar = tqdm(total=1.0, desc=label, unit="s", bar_format="{l_bar}{bar}| t = {n:.3f} of {total:.3f} s")
            else:
                self.bar = tqdm(total=0, desc=label, unit=unit)
        elif callable(progress):
            self.fn = progress
        elif progress is not None and progress is not False and hasattr(progress, "update"):
            self.bar = progress

    def __call__(self, t: float, t_end: float) -> None:
        if self.fn is not None:
            self.fn(t, t_end)
        elif self.bar is not None:
            if self.bar.total != t_end:
                self.bar.total = t_end
            self.bar.update(t - self.bar.n)

    def active(self) -> bool:
        return self.fn is not None or self.bar is not None

    def close(self) -> None:
        if self.bar is not None and hasattr(self.bar, "close"):
            self.bar.close()


def check(path: Union[PathLike, Sequence[PathLike]], sets: Optional[Dict[str, Any]] = None) -> List[Diagnostic]:
    """Checks vehicle files (``flexflight check``) and returns every diagnostic, errors
    and warnings, without raising for errors in the files.

    Args:
        path: a ``.vdl`` file, or several.
        sets: overrides as ``{"vehicle.fins.thickness": "3 mm"}`` (``--set PATH=VALUE``).

    Raises:
        Error: a file cannot be read (code ``usage``).
    """
    return [Diagnostic._from_json(d) for d in _native.check(_files(path), _sets(sets))]


def open(  # noqa: A001 - the package's entry point, as `flexflight.open(...)`
    path: Union[PathLike, Sequence[PathLike]],
    sets: Optional[Dict[str, Any]] = None,
    cache_dir: Optional[PathLike] = None,
) -> "Project":
    """Opens vehicle files: checks them and returns a :class:`Project`.

    Args:
        path: a ``.vdl`` file, or several (one program).
        sets: overrides, ``{"PATH": value}``, as ``--set PATH=VALUE`` of the command line;
            values are strings with units (``"3 mm"``) or numbers.
        cache_dir: the artifact cache (default: ``$FLEXFLIGHT_CACHE``, else
            ``target/flexflight-cache``), as ``--cache-dir``.

    Raises:
        Error: the files have errors (``.diagnostics`` lists them with file, line and
            column) or cannot be read.
    """
    return Project(path, sets=sets, cache_dir=cache_dir)


class Project:
    """Checked vehicle files: compile, fly and analyse their vehicles and scenarios.

    Open one with :func:`open`. Warnings of the check are in :attr:`warnings`.
    """

    def __init__(
        self,
        path: Union[PathLike, Sequence[PathLike]],
        sets: Optional[Dict[str, Any]] = None,
        cache_dir: Optional[PathLike] = None,
    ) -> None:
        self.files: List[str] = _files(path)
        self.sets: Dict[str, Any] = dict(sets or {})
        self.cache_dir: Optional[str] = os.fspath(cache_dir) if cache_dir is not None else None
        self._p = _native.NativeProject(self.files, _sets(self.sets), self.cache_dir)
        vehicles, scenarios, tunnel = self._p.names()
        self.vehicles: List[str] = list(vehicles)
        """Names of the declared vehicles."""
        self.scenarios: List[str] = list(scenarios)
        """Names of the flown scenarios (``run``, ``flutter``, ``linear``)."""
        self.tunnel_scenarios: List[str] = list(tunnel)
        """Names of the wind-tunnel scenarios."""

    def __repr__(self) -> str:
        return f"flexflight.Project({self.files!r}, scenarios={self.scenarios!r})"

    @property
    def warnings(self) -> List[Diagnostic]:
        """The warnings of the check when the project was opened."""
        return [Diagnostic._from_json(d) for d in self._p.warnings()]

    def check(self) -> List[Diagnostic]:
        """Checks the files again as they are now on disk (``flexflight check``) and returns
        every diagnostic (errors and warnings); empty when the files are clean. The project
        itself keeps the program it was opened with (open again to use edited files)."""
        return check(self.files, self.sets)

    def compile(self, vehicle: Optional[str] = None) -> Dict[str, Any]:
        """Compiles a vehicle's structure through the artifact cache (``flexflight compile
        --format json``).

        Args:
            vehicle: the vehicle's name (default: the only vehicle of the files).

        Returns:
            A dict: ``total_mass_kg``, ``centre_of_mass_m``, ``inertia_cm_kg_m2``,
            ``nodes``, ``rigid_modes``, ``modes`` (the mode table: one dict per mode with
            its name, frequency and generalised mass), ``artifact``, ``hash``, ``cache``,
            ``seconds`` (wall-clock), and ``mode_table`` (the modes as a DataFrame, or a
            dict of columns without pandas).
        """
        out = self._p.compile(vehicle)
        modes = out.get("modes") or []
        keys: List[str] = []
        for m in modes:
            for k, v in m.items():
                if k not in keys and not isinstance(v, (list, dict)):
                    keys.append(k)
        out["mode_table"] = _table({k: [m.get(k) for m in modes] for k in keys})
        return out

    def run(
        self,
        scenario: str,
        flutter_margin: Optional[bool] = None,
        progress: Progress = None,
    ) -> "Run":
        """Flies a scenario (``flexflight run FILE --scenario NAME``).

        Args:
            scenario: the scenario's name.
            flutter_margin: compute the flutter margin over the flight (default: for a
                launch from a rail), as ``--flutter-margin``.
            progress: ``True`` for a tqdm bar (when tqdm is installed), a tqdm bar, or a
                callable ``progress(t, t_end)`` of the simulated time (called at most ten
                times a second from the flight, with the GIL held; an exception it raises
                is raised when the flight ends).

        Returns:
            The :class:`Run`. A flight that leaves its model (flutter, divergence) is a
            result, not an error: see ``run.summary["verdict"]``. A flight whose
            integration failed before it reached a stop of its scenario (``stop_reason``
            ``step_underflow``, ``non_finite`` or ``max_steps``) is cut short:
            ``run.summary["complete"]`` is ``False`` (the command line exits with 4).

        Raises:
            Error: an unknown scenario, a scenario that cannot be compiled, planned or
                started (with its diagnostics).
        """
        adapter = _ProgressAdapter(progress, f"run {scenario}")
        try:
            native, warnings = self._p.run(scenario, flutter_margin, adapter if adapter.active() else None)
        finally:
            adapter.close()
        return Run(native, list(warnings))

    def flutter(
        self,
        scenario: str,
        clamped: bool = True,
        mach: Optional[float] = None,
        altitude: Optional[float] = None,
        speeds: Optional[Iterable[float]] = None,
        modes: Optional[int] = None,
        aero: str = "doublet-lattice",
    ) -> "FlutterResult":
        """Flutter analysis of a scenario's fins (``flexflight analyze flutter``).

        Args:
            scenario: the scenario's name.
            clamped: the fin alone clamped at its root (``True``) or the free flexible
                vehicle (``False``: its modes and rigid-body motions, every fin).
            mach: Mach number of the aerodynamics (default: the scenario's initial Mach).
            altitude: altitude of the air, m (default: the scenario's initial altitude).
            speeds: the speeds of the sweep, m/s (default: 0.3 a to 3 a, 40 speeds for the
                clamped fin and 120 for the free vehicle; 0.1 a for ``quasi-steady``).
            modes: clamped-fin modes (default 6).
            aero: ``"doublet-lattice"`` (the default, as the CLI's), ``"vortex-lattice"``
                (also ``"unsteady"``) or ``"quasi-steady"``.

        Returns:
            The :class:`FlutterResult` (``summary`` as ``flutter.json``, ``table`` as
            ``vg.csv``, ``flutter_points``).

        Raises:
            Error: an unknown scenario, no fins, a transonic Mach, a lattice too coarse.
        """
        sp = None if speeds is None else [float(v) for v in speeds]
        summary, vg, warnings = self._p.flutter(
            scenario,
            bool(clamped),
            None if altitude is None else float(altitude),
            None if mach is None else float(mach),
            sp,
            modes,
            aero,
        )
        return FlutterResult(summary, vg, list(warnings))

    def sweep(
        self,
        name: str,
        out: PathLike,
        jobs: Optional[int] = None,
        shard: Optional[str] = None,
        progress: Progress = None,
    ) -> "SweepResult":
        """Runs a declared sweep (``flexflight sweep FILE --sweep NAME --out DIR``).

        Args:
            name: the sweep block's name.
            out: the output directory (``sweep.json``, ``cases/``, ``sweep.csv``); cases
                already finished there are not run again.
            jobs: worker threads (default: the machine's cores); the results are the same
                bits whatever the number.
            shard: ``"I/N"`` (this shard of N) or ``"env"`` (Slurm's array variables), as
                ``--shard``; merge shards with ``flexflight merge``.
            progress: ``True`` for a tqdm bar (when tqdm is installed), a tqdm bar, or a
                callable ``progress(done, total)`` in cases (called from worker threads with
                the GIL held, at most ten times a second; an exception it raises is raised
                when the sweep ends).

        Returns:
            The :class:`SweepResult`: ``summary`` (cases run, resumed, failed) and
            ``table`` (``sweep.csv`` as a DataFrame, or a dict of columns).

        Raises:
            Error: an unknown sweep, a project opened from several files, a bad shard, an
                output that cannot be written.
        """
        adapter = _ProgressAdapter(progress, f"sweep {name}", unit="case")
        try:
            summary, warnings = self._p.sweep(
                name, os.fspath(out), jobs, shard, adapter if adapter.active() else None
            )
        finally:
            adapter.close()
        return SweepResult(summary, os.fspath(out), list(warnings))

    def montecarlo(
        self,
        dispersion: str,
        out: PathLike,
        samples: Optional[int] = None,
        jobs: Optional[int] = None,
        shard: Optional[str] = None,
        flutter_margin: Optional[bool] = None,
        progress: Progress = None,
        full_outputs: bool = False,
        exact_boundaries: bool = False,
    ) -> "MonteCarloResult":
        """Runs a declared dispersion (``flexflight montecarlo FILE --dispersion NAME --out
        DIR``).

        Args:
            dispersion: the dispersion block's name.
            out: the output directory (``montecarlo.json``, ``samples/``, ``samples.csv``,
                ``statistics.json``, ``statistics.txt``, ``figures/``); samples already
                finished there are not run again.
            samples: how many samples (default: the block's ``samples``).
            jobs: worker threads (default: the machine's cores); the results are the same
                bits whatever the number.
            shard: ``"I/N"`` or ``"env"``, as ``--shard``; merge shards with ``flexflight
                merge``.
            flutter_margin: compute each sample's flutter margin (default: when the
                scenario launches from a rail).
            progress: ``True`` for a tqdm bar (when tqdm is installed), a tqdm bar, or a
                callable ``progress(done, total)`` in samples (from worker threads with the
                GIL held, at most ten times a second; an exception it raises is raised when
                the run ends).
            full_outputs: take each sample's outputs from the complete run summary
                (``--full-outputs``: slower, the same bits).
            exact_boundaries: solve every sample's flutter boundary at its own fin thickness
                instead of interpolating between compiled thicknesses
                (``--exact-boundaries``; ``montecarlo.json`` then has no
                ``boundary_nodes``).

        Returns:
            The :class:`MonteCarloResult`: ``summary`` (samples run, resumed, failed, time
            per stage), ``statistics`` (``statistics.json``), ``samples`` (``samples.csv``
            as a DataFrame) and ``text`` (the short summary).

        Raises:
            Error: an unknown dispersion, a project opened from several files, a bad shard,
                an output that cannot be written.
        """
        adapter = _ProgressAdapter(progress, f"montecarlo {dispersion}", unit="sample")
        try:
            summary, warnings = self._p.montecarlo(
                dispersion, os.fspath(out), samples, jobs, shard, flutter_margin,
                adapter if adapter.active() else None, bool(full_outputs), bool(exact_boundaries),
            )
        finally:
            adapter.close()
        return MonteCarloResult(summary, os.fspath(out), list(warnings))

    def linear(self, scenario: str, frozen_gravity: bool = False) -> Dict[str, Any]:
        """Trim and linearise a scenario's 3-D model (``flexflight analyze linear
        --format json``): a dict with ``scenario``, ``vehicle``, ``mode_names``,
        ``options`` and ``analysis`` (the trim, the roots and their classification).

        Args:
            scenario: the scenario's name.
            frozen_gravity: keep gravity at its reference direction in the body frame
                (``--frozen-gravity``).
        """
        out, warnings = self._p.linear(scenario, bool(frozen_gravity))
        out["warnings"] = list(warnings)
        return out


class Run:
    """A flown scenario.

    Attributes:
        summary: ``summary.json`` as a dict (stop reason, flight summary with apogee and
            events, extrema, energy balance, verdict, warnings, flutter margin).
        warnings: the cache's and the flutter margin's warnings (strings).
    """

    def __init__(self, native: Any, warnings: List[str]) -> None:
        self._r = native
        self.summary: Dict[str, Any] = native.summary()
        self.warnings: List[str] = warnings
        self._history: Optional[Any] = None

    def __repr__(self) -> str:
        s = self.summary
        return f"flexflight.Run(scenario={s.get('scenario')!r}, stop={s.get('stop_reason')!r}, t_end={s.get('t_end')!r})"

    @property
    def columns(self) -> Dict[str, Any]:
        """The history as a dict of numpy arrays, one per channel (``history.csv``'s
        columns, the same bits)."""
        channels, rows, data = self._r.history()
        return _columns(channels, rows, data)

    @property
    def history(self) -> Any:
        """The history: a pandas DataFrame (one column per channel, ``time`` first) when
        pandas is installed, else :attr:`columns`."""
        if self._history is None:
            self._history = _table(self.columns)
        return self._history

    @property
    def events(self) -> Dict[str, Any]:
        """The flight's events (``rail_exit``, ``burnout``, ``apogee``, ``landing``: each
        ``None`` or ``{"t", "position", "velocity"}`` with the inertial position, m, z
        down, and velocity, m/s; ``deployments``: a list of ``{"name", "trigger",
        "deployment"}``)."""
        return self._r.events()

    @property
    def flutter_margin(self) -> Optional[Any]:
        """The flutter margin over the flight (``flutter_margin.csv`` as a DataFrame, or a
        dict of columns without pandas); ``None`` when not computed. Its summary is
        ``summary["flutter_margin"]``."""
        text = self._r.flutter_margin_csv()
        if text is None:
            return None
        return _table(_csv_columns(text))

    def drag_curve(self) -> Optional[List[Tuple[float, float]]]:
        """The vehicle's zero-lift drag curve ``[(mach, cd)]`` on the coefficient tables'
        Mach grid at the scenario's initial altitude: body axial force plus every fin's at
        zero angle of attack, on the reference area ``pi d^2 / 4`` (RocketPy's ``pi r^2``);
        ``None`` without coefficient tables."""
        r = self._r.drag_curve()
        return None if r is None else list(r[1])

    def history_csv(self) -> str:
        """The text of ``history.csv``."""
        return self._r.history_csv()

    def write(self, out: PathLike) -> None:
        """Writes ``history.csv``, ``summary.json``, ``flutter_margin.csv`` (when computed)
        and ``aero_tables/`` (estimated tables) into directory ``out``, as ``flexflight run
        --out``: the same bytes; all files or none."""
        self._r.write(os.fspath(out))


class FlutterResult:
    """A solved flutter case.

    Attributes:
        summary: ``flutter.json`` as a dict (condition, modes, flutter points, divergence,
            TN-4197 estimates).
        warnings: the cache's warnings.
    """

    def __init__(self, summary: Dict[str, Any], vg_csv: str, warnings: List[str]) -> None:
        self.summary = summary
        self.vg_csv = vg_csv
        """The text of ``vg.csv``."""
        self.warnings = warnings

    def __repr__(self) -> str:
        return f"flexflight.FlutterResult(case={self.summary.get('case')!r}, flutter_speed_m_s={self.flutter_speed!r})"

    @property
    def table(self) -> Any:
        """The V-g / V-f table (``vg.csv``: ``speed_m_s, branch, name, g, frequency_hz, k,
        p_re, p_im``, one row per speed and branch), a DataFrame or a dict of columns."""
        return _table(_csv_columns(self.vg_csv))

    @property
    def flutter_points(self) -> List[Dict[str, Any]]:
        """Every flutter crossing (speed, frequency, dynamic pressure, reduced frequency,
        mode, partner), lowest speed first."""
        return list(self.summary.get("flutter") or [])

    @property
    def flutter_speed(self) -> Optional[float]:
        """The lowest flutter speed of the sweep, m/s (``None``: no flutter up to the
        largest speed)."""
        pts = [p["speed_m_s"] for p in self.flutter_points if p.get("speed_m_s") is not None]
        return min(pts) if pts else None


class SweepResult:
    """A sweep's outcome (``flexflight sweep``).

    Attributes:
        summary: ``sweep``, ``scenario``, ``shard``, ``cases``, ``ran``, ``resumed``,
            ``failed``, ``artifacts`` (structural variants compiled), ``wall_time_s``.
        out: the output directory.
        warnings: the warnings of the run.
    """

    def __init__(self, summary: Dict[str, Any], out: str, warnings: List[str]) -> None:
        self.summary = summary
        self.out = out
        self.warnings = warnings

    def __repr__(self) -> str:
        s = self.summary
        return f"<SweepResult {s['sweep']}: {s['cases']} cases, {s['failed']} failed, {self.out}>"

    @property
    def table(self) -> Any:
        """``sweep.csv``: one row per case, its parameters and its outputs (a pandas
        DataFrame when pandas is installed, else a dict of numpy arrays or lists)."""
        with builtins.open(os.path.join(self.out, "sweep.csv"), newline="") as f:
            return _table(_csv_columns(f.read()))


class MonteCarloResult:
    """A dispersion's outcome (``flexflight montecarlo``).

    Attributes:
        summary: ``dispersion``, ``scenario``, ``seed``, ``shard``, ``samples``, ``ran``,
            ``resumed``, ``failed``, ``incomplete`` (flown, but the integration failed
            before the flight reached a stop: out of the statistics), ``artifacts``,
            ``wall_time_s``, ``stage_seconds``.
        text: the short statistics summary (``statistics.txt``'s text for this run).
        out: the output directory.
        warnings: the warnings of the run.
    """

    def __init__(self, summary: Dict[str, Any], out: str, warnings: List[str]) -> None:
        self.text = summary.pop("text", "")
        self.summary = summary
        self.out = out
        self.warnings = warnings

    def __repr__(self) -> str:
        s = self.summary
        return f"<MonteCarloResult {s['dispersion']}: {s['samples']} samples, {s['failed']} failed, {self.out}>"

    @property
    def samples(self) -> Any:
        """``samples.csv``: every drawn input and every output per sample (a pandas
        DataFrame when pandas is installed, else a dict of numpy arrays or lists)."""
        with builtins.open(os.path.join(self.out, "samples.csv"), newline="") as f:
            return _table(_csv_columns(f.read()))

    @property
    def statistics(self) -> Dict[str, Any]:
        """``statistics.json``: percentiles with intervals, landing ellipses, the flutter
        margin's distribution, P(margin < 1.15) and P(flutter) with Wilson intervals, the
        Spearman sensitivities."""
        import json

        with builtins.open(os.path.join(self.out, "statistics.json")) as f:
            return json.load(f)


def write_rocketpy_drag_curve(curve: Iterable[Tuple[float, float]], path: PathLike) -> None:
    """Writes a drag curve ``[(mach, cd)]`` (e.g. :meth:`Run.drag_curve`) as RocketPy's
    drag-curve CSV: one ``mach,cd`` line per point, no header, Mach ascending (what
    ``Rocket(power_off_drag=path)`` reads). Values in shortest round-trip form."""
    pts = sorted((float(m), float(c)) for m, c in curve)
    if not pts:
        raise ValueError("an empty drag curve")
    with builtins.open(os.fspath(path), "w", newline="") as fh:
        for m, c in pts:
            fh.write(f"{m!r},{c!r}\n")

