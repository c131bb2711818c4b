"""Shared fixtures: the repository root, a private artifact cache, the `flexflight` binary."""

import os
import shutil
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cache_dir(tmp_path_factory):
    """One artifact cache for the session (the binary and the package share it, so their
    `artifact` paths in summary.json are the same)."""
    return str(tmp_path_factory.mktemp("cache"))


@pytest.fixture(scope="session")
def binary():
    """The `flexflight` binary of this checkout: `$FLEXFLIGHT_BIN`, else the release build
    under `$CARGO_TARGET_DIR` or `target/` (`.ci/run` builds it first). Missing is a failure,
    not a skip: the same-bits test must run."""
    cands = []
    if os.environ.get("FLEXFLIGHT_BIN"):
        cands.append(os.environ["FLEXFLIGHT_BIN"])
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    cands.append(os.path.join(target, "release", "flexflight"))
    for c in cands:
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    if shutil.which("cargo"):
        subprocess.run(["cargo", "build", "--release", "--locked"], cwd=ROOT, check=True)
        c = os.path.join(target, "release", "flexflight")
        if os.path.isfile(c):
            return c
    pytest.fail(f"no flexflight binary (tried {cands}); set FLEXFLIGHT_BIN or run `cargo build --release`")
