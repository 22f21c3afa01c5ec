#!/usr/bin/env bash
# Generates reference vectors with `volsample vectors`, runs the Verilog-2005 datapaths in
# this directory against them with Icarus Verilog, and checks that the benches really
# compare (mutation check). Exits non-zero on any mismatch, missing PASS line or failed
# mutation check. Optional: `verilator --lint-only -Wall` when verilator is installed.
#
# Environment: VECTORS_COUNT (default 10000, at least 10000), VECTORS_SEED (default 1),
# VECTORS_OUT (default target/hdl-vectors), CARGO_TARGET_DIR as usual.
set -euo pipefail
RTL="$(cd "$(dirname "$0")" && pwd)"
cd "$RTL/../.."

COUNT="${VECTORS_COUNT:-10000}"
SEED="${VECTORS_SEED:-1}"
OUT="${VECTORS_OUT:-target/hdl-vectors}"
if [ "$COUNT" -lt 10000 ]; then
  echo "run.sh: VECTORS_COUNT=$COUNT is below the required 10000" >&2
  exit 2
fi
for tool in iverilog vvp; do
  command -v "$tool" >/dev/null || { echo "run.sh: $tool not found (apt-get install -y iverilog)" >&2; exit 2; }
done

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
# The CLI, built once (`cargo run --release -q -- vectors ...` per kernel would re-check the
# build ten times).
cargo build --release -q -p volsample-host --bin volsample
BIN="${CARGO_TARGET_DIR:-target}/release/volsample"
vectors() { "$BIN" vectors "$@"; }

echo "--- generating $COUNT vectors per kernel (seed $SEED) into $OUT"
KERNELS="opacity-weighted-nearest opacity-weighted-trilinear separate-nearest separate-trilinear
preweighted-nearest preweighted-trilinear composite-front-to-back opacity-correction
downsample-opacity-based"
rm -rf "$OUT"
for k in $KERNELS; do
  vectors --kernel "$k" --count "$COUNT" --seed "$SEED" --out "$OUT/$k"
done
for f in 4 12; do
  vectors --kernel opacity-weighted-trilinear --frac-bits "$f" --count "$COUNT" --seed "$SEED" \
    --out "$OUT/opacity-weighted-trilinear-f$f"
done
for k in $KERNELS; do
  n=$(wc -l < "$OUT/$k/expected.hex")
  [ "$n" -eq "$COUNT" ] || { echo "run.sh: $OUT/$k/expected.hex has $n words, expected $COUNT" >&2; exit 1; }
done

SIM="$OUT/sim"
mkdir -p "$SIM"
# compile NAME TOP PARAMS... : builds $SIM/NAME.vvp; fails on any iverilog warning.
compile() {
  local name="$1" top="$2"; shift 2
  local log="$SIM/$name.iverilog.log"
  local src
  case "$top" in
    tb_ow_trilinear) src="$RTL/tb_ow_trilinear.v $RTL/vs_ow_trilinear.v $RTL/vs_div255.v" ;;
    tb_composite_ftb) src="$RTL/tb_composite_ftb.v $RTL/vs_composite_ftb.v $RTL/vs_div255.v" ;;
  esac
  # shellcheck disable=SC2086
  iverilog -g2005 -Wall -s "$top" "$@" -o "$SIM/$name.vvp" $src > "$log" 2>&1 || { cat "$log"; exit 1; }
  if [ -s "$log" ]; then cat "$log"; echo "run.sh: iverilog warnings for $name" >&2; exit 1; fi
}
# simulate NAME LOG DIR EXPECTED_FILE : runs bench $SIM/NAME.vvp on DIR/inputs.hex, log in LOG.
simulate() {
  vvp -n "$SIM/$1.vvp" +INPUTS="$3/inputs.hex" +EXPECTED="$4" > "$2" 2>&1 || true
}

TOTAL_SIM=0
FAILED=0
# check NAME TOP DIR PARAMS... : compile, simulate, require the PASS line.
check() {
  local name="$1" top="$2" dir="$3"; shift 3
  compile "$name" "$top" -P"$top.N=$COUNT" "$@"
  local t0 t1
  t0=$(now)
  simulate "$name" "$SIM/$name.log" "$dir" "$dir/expected.hex"
  t1=$(now)
  TOTAL_SIM=$(awk -v a="$TOTAL_SIM" -v d="$(elapsed "$t0" "$t1")" 'BEGIN { print a + d }')
  grep -E '^(MISMATCH|PASS|FAIL)' "$SIM/$name.log" | head -25
  echo "    ($name: simulated in $(elapsed "$t0" "$t1") s)"
  if ! grep -q '^PASS:' "$SIM/$name.log" || grep -q '^FAIL:' "$SIM/$name.log"; then
    echo "run.sh: $name FAILED (log: $SIM/$name.log)" >&2
    FAILED=1
  fi
}

echo "--- simulating (iverilog $(iverilog -V 2>/dev/null | head -1 | awk '{print $4}'))"
check ow_f8 tb_ow_trilinear "$OUT/opacity-weighted-trilinear" -Ptb_ow_trilinear.F=8
check ow_f4 tb_ow_trilinear "$OUT/opacity-weighted-trilinear-f4" -Ptb_ow_trilinear.F=4
check ow_f12 tb_ow_trilinear "$OUT/opacity-weighted-trilinear-f12" -Ptb_ow_trilinear.F=12
check composite tb_composite_ftb "$OUT/composite-front-to-back"
[ "$FAILED" -eq 0 ] || exit 1
echo "    total simulation time: ${TOTAL_SIM} s, 0 mismatches"

echo "--- mutation check: one flipped bit in one expected word must make each bench fail"
# mutate SRC DST LINE : copy SRC to DST with bit 0 of word LINE (1-based) flipped.
mutate() {
  awk -v n="$3" 'NR == n {
      d = substr($0, length($0), 1); h = index("0123456789abcdef", tolower(d)) - 1;
      x = (h % 2 == 0) ? h + 1 : h - 1;
      $0 = substr($0, 1, length($0) - 1) substr("0123456789abcdef", x + 1, 1)
    } { print }' "$1" > "$2"
  cmp -s "$1" "$2" && { echo "run.sh: mutation did not change $1" >&2; exit 1; }
  return 0
}
LINE=$(( COUNT / 2 + 1 ))
for pair in "ow_f8:$OUT/opacity-weighted-trilinear" "composite:$OUT/composite-front-to-back"; do
  name="${pair%%:*}"; dir="${pair#*:}"
  mutate "$dir/expected.hex" "$SIM/$name.mutated.hex" "$LINE"
  simulate "$name" "$SIM/$name.mutated.log" "$dir" "$SIM/$name.mutated.hex"
  if grep -qE '^FAIL: .* 1 mismatches$' "$SIM/$name.mutated.log" \
     && grep -q "^MISMATCH vector $(( LINE - 1 )):" "$SIM/$name.mutated.log"; then
    echo "    $name: flipped bit 0 of expected word $(( LINE - 1 )) -> bench FAILS as it must:"
    grep -E '^(MISMATCH|FAIL)' "$SIM/$name.mutated.log" | sed 's/^/      /'
  else
    echo "run.sh: mutation check FAILED for $name: the bench did not report exactly that mismatch" >&2
    cat "$SIM/$name.mutated.log" >&2
    exit 1
  fi
done

if command -v verilator >/dev/null; then
  echo "--- verilator --lint-only -Wall ($(verilator --version | awk '{print $2}'))"
  for f in 4 8 12; do
    verilator --lint-only -Wall -GF="$f" --top-module vs_ow_trilinear "$RTL/vs_ow_trilinear.v" "$RTL/vs_div255.v"
  done
  verilator --lint-only -Wall --top-module vs_composite_ftb "$RTL/vs_composite_ftb.v" "$RTL/vs_div255.v"
  echo "    clean"
else
  echo "--- verilator not installed: lint skipped"
fi
echo "--- HDL vectors: PASS (9 kernels x $COUNT vectors generated; 4 bench runs, 0 mismatches; mutation check passed)"
