#!/usr/bin/env bash
# Synthesizes the datapaths in this directory with Yosys for a Xilinx 7-series part
# (`synth_xilinx -family xc7 -noiopad`) and for iCE40 (`synth_ice40 -dsp`, the UltraPlus
# SB_MAC16 multipliers), and prints one table row per datapath and target: cells, DSP
# blocks, LUTs (on xc7 with the SRL shift registers), flip-flops (registers the tools move
# into DSP blocks are not counted) and carry cells. Exits non-zero if any datapath fails to
# synthesize (or maps to no cells at all).
#
# With nextpnr-ice40 installed it also places and routes the datapaths that fit an iCE40
# UP5K (8 SB_MAC16, 5 280 LUT4; package sg48) in the register-wrapped tops of pnr_top.v
# (fixed seed) and prints the logic cells, DSP blocks and the Fmax nextpnr reports; it fails
# if one of them no longer places and routes.
#
# The datapaths with ROM tables and 64-bit-ratio products (opacity correction, extinction,
# ray march) take minutes each to map; by default they are only elaborated and coarsely
# synthesized (`synth -run :fine`, then `check -assert`: they must still synthesize, in
# seconds; row "coarse", word-level cells), and mapped with --all (figures in README.md).
# (With Yosys 0.23, --all stops on vs_ray_march for iCE40: an internal assertion in its
# DSP inference; README.md gives those two rows as mapped by Yosys 0.70 and how.)
#
# Usage: synth.sh [--all] [VECTORS_DIR]. VECTORS_DIR is run.sh's vector directory: the
# datapaths with ROM tables read them ($readmemh) from its opacity-correction and
# extinction-weighted-trilinear subdirectories (as `volsample vectors` writes them); without
# it those datapaths are skipped. Environment: SYNTH_OUT (default target/hdl-synth) for the
# logs and statistics, SYNTH_JOBS (default 1) parallel Yosys runs, SYNTH_ONLY (a regular
# expression) to synthesize only the datapaths whose name matches.
set -euo pipefail
RTL="$(cd "$(dirname "$0")" && pwd)"
cd "$RTL/../.."
command -v yosys >/dev/null || { echo "synth.sh: yosys not found (apt-get install -y yosys)" >&2; exit 2; }
ALL=0
if [ "${1:-}" = --all ]; then ALL=1; shift; fi
VEC="${1:-}"
[ -z "$VEC" ] || VEC="$(cd "$VEC" && pwd)"
OUT="$(mkdir -p "${SYNTH_OUT:-target/hdl-synth}" && cd "${SYNTH_OUT:-target/hdl-synth}" && pwd)"
JOBS="${SYNTH_JOBS:-1}"

# name|top|parameters|sources (relative to RTL)|table directory (a subdirectory of VEC) or -
# (the datapaths with tables are the heavy ones, mapped only with --all)
DESIGNS="ow_trilinear_f4|vs_ow_trilinear|F=4|vs_ow_trilinear.v vs_div255.v|-
ow_trilinear_f8|vs_ow_trilinear|F=8|vs_ow_trilinear.v vs_div255.v|-
ow_trilinear_f12|vs_ow_trilinear|F=12|vs_ow_trilinear.v vs_div255.v|-
separate_trilinear_f8|vs_separate_trilinear|F=8|vs_separate_trilinear.v vs_trilinear_weights.v vs_div255.v|-
preweighted_trilinear_f8|vs_preweighted_trilinear|F=8|vs_preweighted_trilinear.v vs_trilinear_weights.v|-
ow_nearest_f8|vs_ow_nearest|F=8|vs_ow_nearest.v vs_nearest_tap.v vs_div255.v|-
separate_nearest_f8|vs_separate_nearest|F=8|vs_separate_nearest.v vs_nearest_tap.v vs_div255.v|-
preweighted_nearest_f8|vs_preweighted_nearest|F=8|vs_preweighted_nearest.v vs_nearest_tap.v|-
composite_ftb|vs_composite_ftb||vs_composite_ftb.v vs_div255.v|-
downsample_ob|vs_downsample_ob||vs_downsample_ob.v vs_div255.v|-
ow_ftb_pipe_f8|vs_ow_ftb_pipe|F=8|vs_ow_ftb_pipe.v vs_div255.v|-
ow_ftb_lean_f8|vs_ow_ftb_lean|F=8|vs_ow_ftb_lean.v|-"
if [ -n "$VEC" ]; then
  DESIGNS="$DESIGNS
opacity_correction|vs_opacity_correction||vs_opacity_correction.v|opacity-correction
extinction_trilinear_f8|vs_extinction|F=8 NEAREST=0|vs_extinction.v vs_trilinear_weights.v vs_nearest_tap.v|extinction-weighted-trilinear
extinction_nearest_f8|vs_extinction|F=8 NEAREST=1|vs_extinction.v vs_trilinear_weights.v vs_nearest_tap.v|extinction-weighted-trilinear
ray_march_trilinear_f8|vs_ray_march|F=8 NEAREST=0|vs_ray_march.v vs_ow_trilinear.v vs_ow_nearest.v vs_nearest_tap.v vs_opacity_correction.v vs_composite_ftb.v vs_div255.v|opacity-correction
ray_march_nearest_f8|vs_ray_march|F=8 NEAREST=1|vs_ray_march.v vs_ow_trilinear.v vs_ow_nearest.v vs_nearest_tap.v vs_opacity_correction.v vs_composite_ftb.v vs_div255.v|opacity-correction"
fi

# Place and route on an iCE40 UP5K (nextpnr-ice40 --up5k --package sg48, fixed seed, target
# PNR_FREQ MHz, default 48; the reported Fmax is that of the placed and routed design): the
# datapaths that fit one, each in its top of pnr_top.v (ports behind shift registers, so the
# timing is register to register). name (top pnr_NAME)|synth_ice40 options|sources|all: with
# --all only (vs_composite_ftb: its four 16x16 products and four /255 multiply-shifts need
# 20 SB_MAC16, so it is mapped without -dsp, in LUTs, and nextpnr takes over a minute).
PNR="ow_ftb_lean|-dsp|vs_ow_ftb_lean.v|
preweighted_nearest|-dsp|vs_preweighted_nearest.v vs_nearest_tap.v|
ow_nearest||vs_ow_nearest.v vs_nearest_tap.v vs_div255.v|
composite_ftb||vs_composite_ftb.v vs_div255.v|all"
PNR_FREQ="${PNR_FREQ:-48}"
PNR_SEED=1
# pnr NAME OPTIONS SOURCES: Yosys then nextpnr; log in $OUT/NAME.pnr.log.
pnr() {
  local name="$1" opts="$2" src="$3" files=" $RTL/pnr_top.v" s
  for s in $src; do files="$files $RTL/$s"; done
  if ! yosys -q -l "$OUT/pnr_$name.yosys.log" \
        -p "read_verilog$files; synth_ice40 $opts -flatten -top pnr_$name -json $OUT/pnr_$name.json" \
        > /dev/null 2>&1; then
    echo "synth.sh: pnr_$name failed to synthesize (log: $OUT/pnr_$name.yosys.log)" >&2
    return 1
  fi
  local t0
  t0=$(date +%s.%N)
  if ! nextpnr-ice40 --up5k --package sg48 --pcf-allow-unconstrained --seed "$PNR_SEED" \
        --freq "$PNR_FREQ" --timing-allow-fail --json "$OUT/pnr_$name.json" \
        -l "$OUT/pnr_$name.pnr.log" > /dev/null 2>&1; then
    echo "synth.sh: pnr_$name failed to place and route on an UP5K (log: $OUT/pnr_$name.pnr.log)" >&2
    return 1
  fi
  awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.0f\n", b - a }' > "$OUT/pnr_$name.secs"
}

# run NAME TOP PARAMS SOURCES TABLES TARGET: one Yosys run, statistics in $OUT/NAME.TARGET.stat.
run() {
  local name="$1" top="$2" params="$3" src="$4" tables="$5" target="$6" files="" s kv chparam="" synth dir="$RTL"
  for s in $src; do files="$files $RTL/$s"; done
  for kv in $params; do chparam="$chparam -chparam ${kv%%=*} ${kv#*=}"; done
  case "$target" in
    xc7) synth="synth_xilinx -family xc7 -noiopad -flatten -top $top" ;;
    ice40) synth="synth_ice40 -dsp -flatten -top $top" ;;
    coarse) synth="synth -flatten -top $top -run :fine; check -assert" ;;
  esac
  # The ROM tables are read ($readmemh) relative to the working directory.
  [ "$tables" = "-" ] || dir="$VEC/$tables"
  if ! (cd "$dir" && yosys -q -l "$OUT/$name.$target.log" \
        -p "read_verilog$files; hierarchy -top $top $chparam; $synth; tee -q -o $OUT/$name.$target.stat stat" \
        > /dev/null 2>&1); then
    echo "synth.sh: $name failed to synthesize for $target (log: $OUT/$name.$target.log)" >&2
    return 1
  fi
}

# count STAT REGEX: sum of the cell counts whose type matches REGEX.
count() {
  awk -v re="$2" '$1 ~ re && $2 ~ /^[0-9]+$/ { n += $2 } END { print n + 0 }' "$1"
}

# targets TABLES: the runs of a datapath (the heavy ones only coarse without --all).
targets() {
  if [ "$1" = "-" ] || [ "$ALL" = 1 ]; then echo "xc7 ice40"; else echo coarse; fi
}
if [ -n "${SYNTH_ONLY:-}" ]; then
  DESIGNS=$(grep -E "^(${SYNTH_ONLY})\|" <<< "$DESIGNS" || true)
  [ -n "$DESIGNS" ] || { echo "synth.sh: no datapath matches SYNTH_ONLY=$SYNTH_ONLY" >&2; exit 2; }
fi

t0=$(date +%s)
pids=()
while IFS='|' read -r name top params src tables; do
  for target in $(targets "$tables"); do
    run "$name" "$top" "$params" "$src" "$tables" "$target" &
    pids+=("$!")
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
  done
done <<< "$DESIGNS"
HAVE_PNR=0
if command -v nextpnr-ice40 >/dev/null; then
  HAVE_PNR=1
  [ "$ALL" = 1 ] || PNR=$(grep -v '|all$' <<< "$PNR")
  if [ -n "${SYNTH_ONLY:-}" ]; then PNR=$(grep -E "^(${SYNTH_ONLY})\|" <<< "$PNR" || true); fi
  while IFS='|' read -r name opts src _; do
    [ -n "$name" ] || continue
    pnr "$name" "$opts" "$src" &
    pids+=("$!")
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
  done <<< "$PNR"
fi
failed=0
for p in "${pids[@]}"; do wait "$p" || failed=1; done

printf '%-26s %-6s %7s %5s %7s %5s %6s\n' datapath target cells DSP LUT FF carry
while IFS='|' read -r name top params src tables; do
  for target in $(targets "$tables"); do
    st="$OUT/$name.$target.stat"
    [ -s "$st" ] || { failed=1; continue; }
    cells=$(awk '/Number of cells:/ { n = $4 } END { print n + 0 }' "$st")
    case "$target" in
      xc7) dsp=$(count "$st" '^DSP48'); lut=$(count "$st" '^(LUT[1-6]|SRL16E|SRLC32E)$'); ff=$(count "$st" '^FD'); carry=$(count "$st" '^CARRY') ;;
      ice40) dsp=$(count "$st" '^SB_MAC16$'); lut=$(count "$st" '^SB_LUT4$'); ff=$(count "$st" '^SB_DFF'); carry=$(count "$st" '^SB_CARRY$') ;;
      coarse) dsp=-; lut=-; ff=$(count "$st" 'dff'); carry=- ;;
    esac
    if [ "$cells" -eq 0 ]; then
      echo "synth.sh: $name mapped to no cells for $target" >&2
      failed=1
    fi
    printf '%-26s %-6s %7s %5s %7s %5s %6s\n' "$name" "$target" "$cells" "$dsp" "$lut" "$ff" "$carry"
  done
done <<< "$DESIGNS"
if [ "$HAVE_PNR" = 1 ]; then
  echo "place and route, iCE40 UP5K sg48 (nextpnr-ice40 --seed $PNR_SEED --freq $PNR_FREQ; ports registered, see pnr_top.v):"
  printf '%-26s %-5s %10s %8s %10s %6s\n' top synth LC DSP Fmax/MHz "pnr s"
  while IFS='|' read -r name opts src _; do
    [ -n "$name" ] || continue
    log="$OUT/pnr_$name.pnr.log" fmax="" lc=- dsp=- secs=-
    if [ -s "$OUT/pnr_$name.secs" ]; then
      # The last Fmax line is the routed design's; LC and DSP from the utilisation report.
      fmax=$(sed -n "s/.*Max frequency for clock '[^']*': \([0-9.]*\) MHz.*/\1/p" "$log" | tail -1)
      lc=$(sed -n 's/.*ICESTORM_LC: *\([0-9]*\)\/ *\([0-9]*\).*/\1\/\2/p' "$log" | tail -1)
      dsp=$(sed -n 's/.*ICESTORM_DSP: *\([0-9]*\)\/ *\([0-9]*\).*/\1\/\2/p' "$log" | tail -1)
      secs=$(cat "$OUT/pnr_$name.secs")
    fi
    if [ -z "$fmax" ]; then failed=1; fmax=FAILED; fi
    printf '%-26s %-5s %10s %8s %10s %6s\n' "pnr_$name" "${opts:-lut}" "$lc" "$dsp" "$fmax" "$secs"
  done <<< "$PNR"
else
  echo "(nextpnr-ice40 not installed: no place and route, no Fmax)"
fi
echo "($(yosys -V | awk '{print $1, $2}'); $(command -v nextpnr-ice40 >/dev/null && nextpnr-ice40 --version 2>&1 | sed -n 's/.*(Version \(.*\))/nextpnr-ice40 \1/p'); $(( $(date +%s) - t0 )) s; logs in $OUT)"
exit "$failed"
