#!/usr/bin/env bash
# Peers of the ray_march bench (issue 9): scipy.ndimage.map_coordinates(order=1) on float32
# arrays and, where the Debian package libnanovdb-dev is installed (or installable), NanoVDB's
# trilinear sampler, on the same volume and sample positions as volsample. Prints ns/sample and
# the ratios against the medians of the last `cargo bench --bench ray_march` run.
#
# Not part of .ci/run: it takes minutes and its timings are noisy on a shared machine.
#   host-tests/peers/run.sh            # uses the last criterion results
#   RUN_BENCH=1 host-tests/peers/run.sh  # runs the criterion bench first
# VENV (default /tmp/volsample-peers-venv) holds numpy and scipy from PyPI.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
VENV="${VENV:-/tmp/volsample-peers-venv}"
OUT="${OUT:-$(mktemp -d)}"

if [ "${RUN_BENCH:-0}" = 1 ]; then
  (cd "$ROOT" && cargo bench -p volsample-host --bench ray_march)
fi

if [ ! -x "$VENV/bin/python" ]; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q numpy scipy
fi

# Positions first (peers.py writes them), then NanoVDB on the same files, then the table.
NANO_RESULTS="$OUT/nanovdb.txt"
"$VENV/bin/python" -c "
import sys; sys.path.insert(0, '$HERE')
import peers
peers.coherent_positions(peers.N).tofile('$OUT/coherent.f32')
peers.random_positions(1 << 20).tofile('$OUT/random.f32')
"

if [ ! -f /usr/include/nanovdb/NanoVDB.h ] && [ "$(id -u)" = 0 ]; then
  apt-get install -y -qq libnanovdb-dev >/dev/null 2>&1 || true
fi
if [ -f /usr/include/nanovdb/NanoVDB.h ]; then
  # -O2 for the baseline x86-64 target, as cargo builds volsample.
  g++ -std=c++17 -O2 -o "$OUT/nanovdb_peer" "$HERE/nanovdb_peer.cpp"
  "$OUT/nanovdb_peer" "$OUT/coherent.f32" "$OUT/random.f32" > "$NANO_RESULTS"
else
  echo "NanoVDB: libnanovdb-dev not available, skipped" >&2
fi

"$VENV/bin/python" "$HERE/peers.py" "$TARGET/criterion" "$OUT" "$NANO_RESULTS"
lscpu | sed -n 's/^Model name: *//p'
