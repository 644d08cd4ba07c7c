#!/usr/bin/env bash
# Reads m2rc's robot-frame outputs (--emit nav-path, waypoints, geojson, mcap) back with
# independent readers: PyYAML, the `mcap` package and `rosbags` (PyPI), installed here into a
# virtual environment. Run by `cargo test -p m2rc --test it robot_out` (and by hand):
#   scripts/robot-roundtrip.sh M2RC MAP PROGRAM OUTDIR
# Exits 77 when the readers cannot be installed (the test then says it skipped, loudly).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
VENV="${M2RC_ROBOT_VENV:-/tmp/m2rc-robot-venv}"
if ! "$VENV/bin/python" -c 'import yaml, mcap, rosbags' 2>/dev/null; then
  if ! { python3 -m venv "$VENV" && "$VENV/bin/pip" install -q "mcap>=1.1" "rosbags>=0.10" pyyaml; } >&2; then
    echo "cannot install the readers (python3 -m venv; pip install mcap rosbags pyyaml)" >&2
    exit 77
  fi
fi
exec "$VENV/bin/python" "$here/robot_roundtrip.py" "$@"
