#!/usr/bin/env bash
# Peer of `volsample render` on the 256^3 CT phantom: VTK's CPU ray caster
# (vtkFixedPointVolumeRayCastMapper, from the `vtk` wheel on PyPI, offscreen) against
# volsample's opacity-weighted trilinear renderer, same volume, transfer function, view,
# 512 x 512 image and step 0.5 voxel, with 1 and 2 threads. Prints the median wall time of a
# frame per renderer and thread count, and how much the two images differ. Then the orientation
# check of vtk_orient.py (ORIENT=0 skips it).
#
# Not part of .ci/run: it takes a minute or two and its timings are noisy on a shared machine.
#   host-tests/peers/vtk_ct.sh
#   FRAMES=9 SIZE=512 THREADS="1 2" OUT=/tmp/vtk-ct host-tests/peers/vtk_ct.sh
# Needs the release CLI (cargo build --release -p volsample-host; VOLSAMPLE=path overrides).
# VENV (default target/peers-venv) holds vtk and numpy from PyPI. Offscreen rendering: the
# wheel's EGL window on Mesa (llvmpipe) with no X display; if that fails, the script installs
# Mesa's EGL with apt-get, and failing that runs VTK under Xvfb.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
VENV="${VENV:-$TARGET/peers-venv}"
BIN="${VOLSAMPLE:-$TARGET/release/volsample}"
OUT="${OUT:-$(mktemp -d)}"
FRAMES="${FRAMES:-5}"
SIZE="${SIZE:-512}"
THREADS="${THREADS:-1 2}"
mkdir -p "$OUT"

if [ ! -x "$BIN" ]; then
  echo "no volsample binary at $BIN: cargo build --release -p volsample-host" >&2
  exit 1
fi

if ! "$VENV/bin/python" -c 'import vtk, numpy' 2>/dev/null; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q vtk numpy
fi
PY="$VENV/bin/python"

# --- Offscreen: EGL first (no X needed), then Mesa's EGL from Debian, then Xvfb. ---
probe() {
  timeout 120 "$@" "$PY" -c '
import vtk
w = vtk.vtkRenderWindow(); w.SetOffScreenRendering(1); w.SetSize(8, 8)
w.AddRenderer(vtk.vtkRenderer()); w.Render()
print(w.GetClassName())' 2>/dev/null | tail -n 1
}
WRAP=()
if [ -z "${DISPLAY:-}" ]; then
  export VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow
fi
WINDOW="$(probe || true)"
if [ -z "$WINDOW" ] && [ "$(id -u)" = 0 ]; then
  echo "VTK cannot render offscreen yet: installing Mesa's EGL (apt-get)" >&2
  apt-get update -qq >/dev/null 2>&1 || true
  apt-get install -y -qq libegl1 libegl-mesa0 libgl1-mesa-dri >/dev/null 2>&1 || true
  WINDOW="$(probe || true)"
fi
if [ -z "$WINDOW" ]; then
  if ! command -v xvfb-run >/dev/null && [ "$(id -u)" = 0 ]; then
    echo "EGL offscreen failed: installing xvfb (apt-get)" >&2
    apt-get install -y -qq xvfb xauth >/dev/null 2>&1 || true
  fi
  if command -v xvfb-run >/dev/null; then
    unset VTK_DEFAULT_OPENGL_WINDOW
    WRAP=(xvfb-run -a -s "-screen 0 1024x768x24")
    WINDOW="$(probe "${WRAP[@]}" || true)"
  fi
fi
if [ -z "$WINDOW" ]; then
  echo "VTK's wheel cannot render offscreen here (no EGL, no Xvfb): no VTK figures" >&2
  exit 1
fi
echo "VTK offscreen window: $WINDOW${WRAP:+ (under Xvfb)}"

# --- Inputs ---
"$BIN" phantom --size 256 --out "$OUT/ct-head.nrrd" >/dev/null
TF="$OUT/ct-head.tf.txt"

median() { sort -n | awk '{a[NR]=$1} END {if (NR % 2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }

# --- volsample: one process per frame (it prints the ray-marching time of the frame); a first
# untimed run warms the page cache. ---
declare -A VS
for t in $THREADS; do
  args=(render --nrrd "$OUT/ct-head.nrrd" --tf "$TF" --modes opacity-weighted
        --size "$SIZE" --threads "$t" --quiet --out "$OUT/volsample-t$t.png")
  "$BIN" "${args[@]}" >/dev/null
  ms=()
  for _ in $(seq "$FRAMES"); do
    line="$("$BIN" "${args[@]}")"
    ms+=("$(sed -n 's/.*; \([0-9.]*\) ms;.*/\1/p' <<<"$line")")
  done
  VS[$t]="$(printf '%s\n' "${ms[@]}" | median)"
  echo "volsample threads=$t median_ms=${VS[$t]} frames_ms=$(IFS=,; echo "${ms[*]}")"
done

# --- VTK ---
first="${THREADS%% *}"
VTK_LOG="$OUT/vtk.txt"
"${WRAP[@]}" "$PY" "$HERE/vtk_ct.py" "$OUT/ct-head.nrrd" "$TF" --size "$SIZE" \
  --threads "$(tr ' ' ',' <<<"$THREADS")" --frames "$FRAMES" --out "$OUT/vtk" \
  --compare "$OUT/volsample-t$first.png" 2>&1 | grep -v 'bad X server connection' | tee "$VTK_LOG"

# --- Table ---
echo
echo "256^3 uint8 CT phantom, ${SIZE}x${SIZE}, step 0.5 voxel, median of $FRAMES frames (ms)"
printf '%-8s %14s %10s %14s\n' threads "VTK fixed-pt" volsample "VTK/volsample"
for t in $THREADS; do
  v="$(sed -n "s/^vtk threads=$t median_ms=\([0-9.]*\).*/\1/p" "$VTK_LOG")"
  printf '%-8s %14s %10s %14s\n' "$t" "${v:-?}" "${VS[$t]}" \
    "$(awk -v a="${v:-0}" -v b="${VS[$t]}" 'BEGIN {if (b > 0 && a > 0) printf "%.2f", a / b; else print "?"}')"
done
lscpu | sed -n 's/^Model name: *//p'
echo "images: $OUT"

# --- Orientation: an asymmetric object stored as RAS, LPS and with permuted axes, rendered by
# volsample and by VTK given each file's index-to-RAS matrix (vtk_orient.py); ORIENT=0 skips. ---
if [ "${ORIENT:-1}" != 0 ]; then
  echo
  "${WRAP[@]}" "$PY" "$HERE/vtk_orient.py" "$BIN" "$OUT/orient" 2>&1 | grep -v 'bad X server connection'
fi
