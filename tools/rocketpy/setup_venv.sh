#!/usr/bin/env bash
# Creates tools/rocketpy/.venv with the pinned RocketPy (from PyPI) if it is not there yet.
# Kept out of `cargo test`: only the comparison scripts in this folder use it.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --upgrade pip
  "$venv/bin/pip" install --quiet -r "$here/requirements.txt"
fi
echo "$venv/bin/python"
