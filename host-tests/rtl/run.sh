#!/usr/bin/env bash
# Generates reference vectors with `volsample vectors` for every kernel, runs the
# Verilog-2005 datapaths in this directory against them with Icarus Verilog (among them the
# resource-lean sequential vs_ow_ftb_lean, tb_ow_ftb_lean.v), checks that
# each bench really compares (mutation check), lints with Verilator and, when Verilator is
# installed, runs the pipelined datapath (vs_ow_ftb_pipe) in a Verilator C++ bench; checks
# the manifests with read_vectors.py (every expected word of the composite and sampling
# kernels recomputed from manifest.json alone, and a flipped word caught); when
# Yosys is installed it synthesizes every datapath (synth.sh). Exits non-zero on any
# mismatch, missing PASS line, failed mutation check, lint warning or datapath that stops
# synthesizing.
#
# Environment: VECTORS_COUNT (default 10000, at least 10000), VECTORS_SEED (default 1),
# VECTORS_OUT (default target/hdl-vectors), CARGO_TARGET_DIR as usual; VOLSAMPLE_BIN, a
# `volsample` binary already built (CI passes the test stage's), else it is built here;
# SYNTH=0 skips the synthesis step, SYNTH_JOBS (default 2) parallel Yosys runs.
set -euo pipefail
RTL="$(cd "$(dirname "$0")" && pwd)"
cd "$RTL/../.."
T_START=$(date +%s)

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
command -v python3 >/dev/null || { echo "run.sh: python3 not found (apt-get install -y python3)" >&2; exit 2; }

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
# The CLI, built once (`cargo run --release -q -- vectors ...` per kernel would re-check the
# build for every kernel), unless VOLSAMPLE_BIN names one.
if [ -n "${VOLSAMPLE_BIN:-}" ]; then
  BIN="$(cd "$(dirname "$VOLSAMPLE_BIN")" && pwd)/$(basename "$VOLSAMPLE_BIN")"
  [ -x "$BIN" ] || { echo "run.sh: VOLSAMPLE_BIN=$VOLSAMPLE_BIN is not an executable" >&2; exit 2; }
else
  cargo build --release -q -p volsample-host --bin volsample
  BIN="$(cd "${CARGO_TARGET_DIR:-target}" && pwd)/release/volsample"
fi
vectors() { "$BIN" vectors "$@"; }

echo "--- generating $COUNT vectors per kernel (seed $SEED) into $OUT"
# Every kernel the CLI has: its error message for an unknown kernel lists them.
KERNELS=$("$BIN" vectors --kernel '?' --out "$OUT" 2>&1 | sed -n 's/.*(one of: \(.*\))$/\1/p' | tr -d ,) || true
[ -n "$KERNELS" ] || { echo "run.sh: could not list the kernels of volsample vectors" >&2; exit 1; }
rm -rf "$OUT"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
nk=0
for k in $KERNELS; do
  vectors --kernel "$k" --count "$COUNT" --seed "$SEED" --out "$OUT/$k"
  nk=$(( nk + 1 ))
done
for f in 4 12; do
  vectors --kernel opacity-weighted-trilinear --frac-bits "$f" --count "$COUNT" --seed "$SEED" \
    --out "$OUT/opacity-weighted-trilinear-f$f"
done
# The extinction datapath at the smallest and largest F with a small and a large table.
vectors --kernel extinction-weighted-trilinear --frac-bits 12 --table-size 17 --count "$COUNT" \
  --seed "$SEED" --out "$OUT/extinction-weighted-trilinear-f12-n17"
vectors --kernel extinction-weighted-nearest --frac-bits 4 --table-size 4097 --count "$COUNT" \
  --seed "$SEED" --out "$OUT/extinction-weighted-nearest-f4-n4097"
for k in $KERNELS; do
  n=$(wc -l < "$OUT/$k/expected.hex")
  [ "$n" -eq "$COUNT" ] || { echo "run.sh: $OUT/$k/expected.hex has $n words, expected $COUNT" >&2; exit 1; }
done

SIM="$OUT/sim"
mkdir -p "$SIM"
RAY_MARCH_SRC="vs_ray_march.v vs_ow_trilinear.v vs_ow_nearest.v vs_nearest_tap.v
  vs_opacity_correction.v vs_composite_ftb.v vs_div255.v"
# sources TOP: the Verilog files of bench TOP.
sources() {
  local s
  case "$1" in
    tb_ow_trilinear) s="tb_ow_trilinear.v vs_ow_trilinear.v vs_div255.v" ;;
    tb_composite_ftb) s="tb_composite_ftb.v vs_composite_ftb.v vs_div255.v" ;;
    tb_sample) s="tb_sample.v vs_ow_nearest.v vs_separate_nearest.v vs_separate_trilinear.v
      vs_preweighted_nearest.v vs_preweighted_trilinear.v vs_nearest_tap.v
      vs_trilinear_weights.v vs_div255.v" ;;
    tb_downsample_ob) s="tb_downsample_ob.v vs_downsample_ob.v vs_div255.v" ;;
    tb_opacity_correction) s="tb_opacity_correction.v vs_opacity_correction.v" ;;
    tb_extinction) s="tb_extinction.v vs_extinction.v vs_trilinear_weights.v vs_nearest_tap.v" ;;
    tb_ray_march) s="tb_ray_march.v $RAY_MARCH_SRC" ;;
    tb_ow_ftb_lean) s="tb_ow_ftb_lean.v vs_ow_ftb_lean.v" ;;
  esac
  for f in $s; do printf '%s ' "$RTL/$f"; done
}
# compile NAME TOP PARAMS... : builds $SIM/NAME.vvp; fails on any iverilog warning.
compile() {
  local name="$1" top="$2"; shift 2
  local log="$SIM/$name.iverilog.log"
  # shellcheck disable=SC2046
  iverilog -g2005 -Wall -s "$top" "$@" -o "$SIM/$name.vvp" $(sources "$top") > "$log" 2>&1 || { cat "$log"; exit 1; }
  if [ -s "$log" ]; then cat "$log"; echo "run.sh: iverilog warnings for $name" >&2; exit 1; fi
}
# simulate NAME LOG DIR EXPECTED_FILE [INPUTS_FILE] : runs bench $SIM/NAME.vvp on
# INPUTS_FILE (default DIR/inputs.hex), log in LOG, in DIR (the benches whose datapaths read
# tables load DIR/table_*.hex).
simulate() {
  (cd "$3" && vvp -n "$SIM/$1.vvp" +INPUTS="${5:-$3/inputs.hex}" +EXPECTED="$4" > "$2" 2>&1) || true
}

TOTAL_SIM=0
FAILED=0
RUNS=0
# check NAME TOP DIR PARAMS... : compile, simulate, require the PASS line with COUNT vectors.
check() {
  local name="$1" top="$2" dir="$3"; shift 3
  compile "$name" "$top" -P"$top.N=$COUNT" "$@"
  local t0 t1
  t0=$(now)
  simulate "$name" "$SIM/$name.log" "$dir" "$dir/expected.hex"
  t1=$(now)
  TOTAL_SIM=$(awk -v a="$TOTAL_SIM" -v d="$(elapsed "$t0" "$t1")" 'BEGIN { print a + d }')
  RUNS=$(( RUNS + 1 ))
  grep -E '^(MISMATCH|PASS|FAIL)' "$SIM/$name.log" | head -25
  echo "    ($name: simulated in $(elapsed "$t0" "$t1") s)"
  if ! grep -qE "^PASS: .*: $COUNT vectors, 0 mismatches( \(.*\))?\$" "$SIM/$name.log" || grep -q '^FAIL:' "$SIM/$name.log"; then
    echo "run.sh: $name FAILED (log: $SIM/$name.log)" >&2
    FAILED=1
  fi
}

# name|bench|vector directory|parameters: every bench run, each also mutation-checked.
BENCHES="ow_f8|tb_ow_trilinear|opacity-weighted-trilinear|-Ptb_ow_trilinear.F=8
ow_f4|tb_ow_trilinear|opacity-weighted-trilinear-f4|-Ptb_ow_trilinear.F=4
ow_f12|tb_ow_trilinear|opacity-weighted-trilinear-f12|-Ptb_ow_trilinear.F=12
ow_nearest|tb_sample|opacity-weighted-nearest|-Ptb_sample.KIND=0
separate_nearest|tb_sample|separate-nearest|-Ptb_sample.KIND=1
separate_trilinear|tb_sample|separate-trilinear|-Ptb_sample.KIND=2
preweighted_nearest|tb_sample|preweighted-nearest|-Ptb_sample.KIND=3
preweighted_trilinear|tb_sample|preweighted-trilinear|-Ptb_sample.KIND=4
composite|tb_composite_ftb|composite-front-to-back|
correction|tb_opacity_correction|opacity-correction|
downsample|tb_downsample_ob|downsample-opacity-based|
extinction_trilinear|tb_extinction|extinction-weighted-trilinear|-Ptb_extinction.NEAREST=0
extinction_nearest|tb_extinction|extinction-weighted-nearest|-Ptb_extinction.NEAREST=1
extinction_trilinear_f12_n17|tb_extinction|extinction-weighted-trilinear-f12-n17|-Ptb_extinction.F=12 -Ptb_extinction.B=4
extinction_nearest_f4_n4097|tb_extinction|extinction-weighted-nearest-f4-n4097|-Ptb_extinction.F=4 -Ptb_extinction.B=12 -Ptb_extinction.NEAREST=1
ray_march_trilinear|tb_ray_march|ray-march-opacity-weighted-trilinear|-Ptb_ray_march.NEAREST=0
ray_march_nearest|tb_ray_march|ray-march-opacity-weighted-nearest|-Ptb_ray_march.NEAREST=1
ow_ftb_lean_f8|tb_ow_ftb_lean|opacity-weighted-trilinear|-Ptb_ow_ftb_lean.F=8
ow_ftb_lean_f4|tb_ow_ftb_lean|opacity-weighted-trilinear-f4|-Ptb_ow_ftb_lean.F=4
ow_ftb_lean_f12|tb_ow_ftb_lean|opacity-weighted-trilinear-f12|-Ptb_ow_ftb_lean.F=12"

echo "--- simulating (iverilog $(iverilog -V 2>/dev/null | head -1 | awk '{print $4}'))"
while IFS='|' read -r name top dir params; do
  # shellcheck disable=SC2086
  check "$name" "$top" "$OUT/$dir" $params
done <<< "$BENCHES"
[ "$FAILED" -eq 0 ] || exit 1
echo "    $RUNS bench runs x $COUNT vectors, 0 mismatches; total simulation time: ${TOTAL_SIM} s"

# The mutation check runs each bench again on its first MUT_N vectors (to keep the stage
# short; the full runs above compared all of them) with one expected bit flipped.
MUT_N=1000
echo "--- mutation check: one flipped bit in one expected word must make each bench fail (first $MUT_N vectors)"
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
LINE=$(( MUT_N / 2 + 1 ))
while IFS='|' read -r name top dir params; do
  dir="$OUT/$dir"
  # shellcheck disable=SC2086
  compile "$name.mut" "$top" -P"$top.N=$MUT_N" $params
  head -n "$MUT_N" "$dir/inputs.hex" > "$SIM/$name.mut.inputs.hex"
  head -n "$MUT_N" "$dir/expected.hex" > "$SIM/$name.mut.expected.hex"
  mutate "$SIM/$name.mut.expected.hex" "$SIM/$name.mutated.hex" "$LINE"
  simulate "$name.mut" "$SIM/$name.mutated.log" "$dir" "$SIM/$name.mutated.hex" "$SIM/$name.mut.inputs.hex"
  if grep -qE '^FAIL: .* 1 mismatches$' "$SIM/$name.mutated.log" \
     && grep -q "^MISMATCH vector $(( LINE - 1 )):" "$SIM/$name.mutated.log"; then
    echo "    $name: flipped bit 0 of expected word $(( LINE - 1 )) -> bench FAILS as it must: $(grep '^FAIL' "$SIM/$name.mutated.log")"
  else
    echo "run.sh: mutation check FAILED for $name: the bench did not report exactly that mismatch" >&2
    cat "$SIM/$name.mutated.log" >&2
    exit 1
  fi
done <<< "$BENCHES"

# The manifest reader: every expected word of the kernels it has an oracle for, recomputed
# from the inputs with nothing but the manifest; then the same mutation as the benches.
echo "--- manifest reader (read_vectors.py, $(python3 --version 2>&1)): expected words recomputed from manifest.json alone"
READER_DIRS="composite-front-to-back opacity-weighted-trilinear opacity-weighted-trilinear-f4
  opacity-weighted-trilinear-f12 separate-trilinear preweighted-trilinear
  opacity-weighted-nearest separate-nearest preweighted-nearest"
NREAD=0
for d in $READER_DIRS; do
  python3 "$RTL/read_vectors.py" --check "$OUT/$d" > "$SIM/read_$d.log" 2>&1 || true
  grep -E '^(MISMATCH|PASS|FAIL)' "$SIM/read_$d.log" | head -25
  grep -qE "^PASS: .*: $COUNT vectors, 0 mismatches\$" "$SIM/read_$d.log" \
    || { cat "$SIM/read_$d.log" >&2; echo "run.sh: read_vectors.py --check $d FAILED" >&2; exit 1; }
  NREAD=$(( NREAD + 1 ))
done
for d in composite-front-to-back opacity-weighted-trilinear; do
  mutate "$OUT/$d/expected.hex" "$SIM/read_$d.mutated.hex" "$LINE"
  python3 "$RTL/read_vectors.py" --check "$OUT/$d" --expected "$SIM/read_$d.mutated.hex" \
    > "$SIM/read_$d.mutated.log" 2>&1 || true
  if grep -qE '^FAIL: .* 1 mismatches$' "$SIM/read_$d.mutated.log" \
     && grep -q "^MISMATCH vector $(( LINE - 1 )):" "$SIM/read_$d.mutated.log"; then
    echo "    $d: flipped bit 0 of expected word $(( LINE - 1 )) -> the reader FAILS as it must: $(grep '^FAIL' "$SIM/read_$d.mutated.log")"
  else
    echo "run.sh: mutation check FAILED for read_vectors.py on $d" >&2
    cat "$SIM/read_$d.mutated.log" >&2
    exit 1
  fi
done

if command -v verilator >/dev/null; then
  echo "--- verilator --lint-only -Wall ($(verilator --version | awk '{print $2}'))"
  lint() { verilator --lint-only -Wall "$@"; }
  for f in 4 8 12; do
    lint -GF="$f" --top-module vs_ow_trilinear "$RTL/vs_ow_trilinear.v" "$RTL/vs_div255.v"
    lint -GF="$f" --top-module vs_ow_ftb_lean "$RTL/vs_ow_ftb_lean.v"
    for m in vs_separate_trilinear vs_preweighted_trilinear; do
      lint -GF="$f" --top-module "$m" "$RTL/$m.v" "$RTL/vs_trilinear_weights.v" "$RTL/vs_div255.v"
    done
    for m in vs_ow_nearest vs_separate_nearest vs_preweighted_nearest; do
      lint -GF="$f" --top-module "$m" "$RTL/$m.v" "$RTL/vs_nearest_tap.v" "$RTL/vs_div255.v"
    done
    for nr in 0 1; do
      lint -GF="$f" -GNEAREST="$nr" --top-module vs_extinction "$RTL/vs_extinction.v" \
        "$RTL/vs_trilinear_weights.v" "$RTL/vs_nearest_tap.v"
      # shellcheck disable=SC2046
      lint -GF="$f" -GNEAREST="$nr" --top-module vs_ray_march $(for s in $RAY_MARCH_SRC; do printf '%s ' "$RTL/$s"; done)
    done
  done
  lint --top-module vs_composite_ftb "$RTL/vs_composite_ftb.v" "$RTL/vs_div255.v"
  lint --top-module vs_downsample_ob "$RTL/vs_downsample_ob.v" "$RTL/vs_div255.v"
  lint --top-module vs_opacity_correction "$RTL/vs_opacity_correction.v"
  # The place-and-route tops of synth.sh (several modules in one file, hence DECLFILENAME).
  for top in pnr_ow_ftb_lean pnr_ow_nearest pnr_preweighted_nearest pnr_composite_ftb; do
    lint -Wno-DECLFILENAME --top-module "$top" "$RTL/pnr_top.v" "$RTL/vs_ow_ftb_lean.v" "$RTL/vs_ow_nearest.v" \
      "$RTL/vs_preweighted_nearest.v" "$RTL/vs_composite_ftb.v" "$RTL/vs_nearest_tap.v" "$RTL/vs_div255.v"
  done
  echo "    clean"
else
  echo "--- verilator not installed: lint skipped"
fi

PIPE_NOTE="pipelined datapath skipped (verilator not installed)"
if command -v verilator >/dev/null; then
  echo "--- pipelined OW trilinear + front-to-back (vs_ow_ftb_pipe.v), Verilator C++ bench"
  for f in 4 8 12; do
    case "$f" in 8) ow="$OUT/opacity-weighted-trilinear" ;; *) ow="$OUT/opacity-weighted-trilinear-f$f" ;; esac
    mdir="$SIM/pipe_f$f"
    verilator --cc --exe --build -j 1 -Wall -O2 -GF="$f" --Mdir "$mdir" --top-module vs_ow_ftb_pipe \
      "$RTL/vs_ow_ftb_pipe.v" "$RTL/vs_div255.v" "$RTL/tb_ow_ftb_pipe.cpp" -o tb_ow_ftb_pipe \
      > "$mdir.build.log" 2>&1 || { cat "$mdir.build.log"; echo "run.sh: verilator build of vs_ow_ftb_pipe F=$f failed" >&2; exit 1; }
    pipe() { "$mdir/tb_ow_ftb_pipe" "$f" "$2" "$ow/inputs.hex" "$1" "$OUT/composite-front-to-back/inputs.hex" || true; }
    pipe "$ow/expected.hex" "$COUNT" > "$SIM/pipe_f$f.log"
    grep -E '^(MISMATCH|PASS|FAIL)' "$SIM/pipe_f$f.log" | head -25
    grep -qE "^PASS: .*: $COUNT vectors, 0 mismatches" "$SIM/pipe_f$f.log" || { echo "run.sh: vs_ow_ftb_pipe F=$f FAILED" >&2; exit 1; }
    mutate "$ow/expected.hex" "$SIM/pipe_f$f.mutated.hex" "$LINE"
    pipe "$SIM/pipe_f$f.mutated.hex" "$MUT_N" > "$SIM/pipe_f$f.mutated.log"
    if grep -qE '^FAIL: .* 1 mismatches$' "$SIM/pipe_f$f.mutated.log" \
       && grep -q "^MISMATCH vector $(( LINE - 1 )):" "$SIM/pipe_f$f.mutated.log"; then
      echo "    mutation: flipped bit 0 of expected word $(( LINE - 1 )) -> $(grep '^FAIL' "$SIM/pipe_f$f.mutated.log")"
    else
      echo "run.sh: mutation check FAILED for vs_ow_ftb_pipe F=$f" >&2
      cat "$SIM/pipe_f$f.mutated.log" >&2
      exit 1
    fi
  done
  PIPE_NOTE="pipelined datapath at F = 4, 8, 12 passed in Verilator"
fi

SYNTH_NOTE="synthesis skipped (yosys not installed)"
if [ "${SYNTH:-1}" = 0 ]; then
  SYNTH_NOTE="synthesis skipped (SYNTH=0)"
elif command -v yosys >/dev/null; then
  echo "--- synthesis (synth.sh): Yosys synth_xilinx -family xc7 and synth_ice40 -dsp, per datapath"
  SYNTH_JOBS="${SYNTH_JOBS:-2}" SYNTH_OUT="$OUT/synth" "$RTL/synth.sh" "$OUT"
  SYNTH_NOTE="every datapath synthesized"
else
  echo "--- yosys not installed: synthesis skipped"
fi
echo "--- HDL vectors: PASS ($nk kernels x $COUNT vectors generated; $RUNS bench runs, 0 mismatches; $RUNS mutation checks caught; manifest reader on $NREAD vector sets, 2 mutations caught; $PIPE_NOTE; $SYNTH_NOTE; $(( $(date +%s) - T_START )) s)"
