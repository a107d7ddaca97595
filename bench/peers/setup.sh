#!/usr/bin/env bash
# Installs the peers of the benchmark into the project's .venv when they are missing:
# the bpy wheel (Blender 4.5 LTS, headless), Newton (with NVIDIA Warp) and matplotlib.
# Tailor itself is built by `make develop`.
set -euo pipefail
cd "$(dirname "$0")/../.."
PY=.venv/bin/python
need=()
$PY -c 'import bpy' 2>/dev/null || need+=("bpy==4.5.*")
$PY -c 'import newton' 2>/dev/null || need+=(newton)
$PY -c 'import matplotlib' 2>/dev/null || need+=(matplotlib)
if [ ${#need[@]} -gt 0 ]; then
  echo "bench-peers: installing ${need[*]} into .venv"
  # A peer that cannot install is recorded by the benchmark as not run, not a failure here.
  $PY -m pip install -q "${need[@]}" || echo "bench-peers: pip could not install ${need[*]}; those peers will be skipped"
fi
