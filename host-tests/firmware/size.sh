#!/usr/bin/env bash
# Prints the size and stack table (markdown) of the images run.sh built into REPORT/elf:
# .text/.rodata of the minimal scene images against the full pipeline, and the stack
# high-water mark of one ray measured by the `stack` image (paint the stack, run one ray,
# find the lowest overwritten word) on each board.
# Usage: size.sh REPORT_DIR   (run.sh calls it; the ELFs must exist)
set -euo pipefail
REPORT=${1:?usage: size.sh REPORT_DIR}
sec() { size -A "$1" | awk -v s="$2" '$1 == s { print $2; f = 1 } END { if (!f) print 0 }'; }
qemu_run() {
    local board=$1 cpu=cortex-m3
    [ "$board" = mps2-an386 ] && cpu=cortex-m4
    timeout 300 qemu-system-arm -machine "$board" -cpu "$cpu" -nographic -monitor none \
        -semihosting-config enable=on,target=native -kernel "$2"
}
DIRS=(thumbv7em-none-eabihf-mps2-an386 thumbv7m-none-eabi-mps2-an385)
declare -A WHAT=(
    [baseline]="runtime only (vector table, reset, semihosting exit)"
    [min_int]="**minimal scene**: integer OpacityWeighted trilinear, front to back, one ray"
    [min_float]="minimal float scene: OpacityWeighted trilinear, front to back, d = d′"
    [full]="**full pipeline**: every float mode × filter × order with correction, termination, background and both cameras; every integer mode × filter with correction; the integer ray marcher; integer extinction"
    [suite]="the bit-identity suite: every kernel, fewer cast combinations than \`full\`, plus hex printing"
)
echo "### Image size (bytes; release, opt-level s, fat LTO, panic = abort)"
echo
echo "| image | what | Cortex-M4F .text | .rodata | Cortex-M3 .text | .rodata |"
echo "|---|---|---:|---:|---:|---:|"
for img in baseline min_int min_float full suite; do
    row="| \`$img\` | ${WHAT[$img]} |"
    for d in "${DIRS[@]}"; do
        elf="$REPORT/elf/$d/$img"
        row="$row $(sec "$elf" .text) | $(sec "$elf" .rodata) |"
    done
    echo "$row"
done
echo
echo "Cortex-M4F: thumbv7em-none-eabihf (hardware single precision); Cortex-M3: thumbv7m-none-eabi"
echo "(soft float from compiler-builtins). .data and .bss are 0 in every kernel image."
echo
echo "### Stack high-water mark of one ray (bytes, measured by painting)"
echo
declare -A STACK
for b in mps2-an386 mps2-an385 lm3s6965evb; do
    case $b in
        mps2-an386) elf="$REPORT/elf/thumbv7em-none-eabihf-mps2-an386/stack" ;;
        mps2-an385) elf="$REPORT/elf/thumbv7m-none-eabi-mps2-an385/stack" ;;
        lm3s6965evb) elf="$REPORT/elf/thumbv7m-none-eabi-lm3s6965evb/stack" ;;
    esac
    while read -r tag name bytes; do
        [ "$tag" = stack ] && STACK[$name,$b]=$bytes
    done < <(qemu_run "$b" "$elf")
done
echo "| ray | Cortex-M4F (mps2-an386) | Cortex-M3 (mps2-an385) | Cortex-M3 (lm3s6965evb) |"
echo "|---|---:|---:|---:|"
for name in int_ow_trilinear_f2b int_ow_trilinear_f2b_corrected float_ow_trilinear_f2b \
    float_ow_trilinear_f2b_corrected float_ext_bspline2_b2f; do
    echo "| \`$name\` | ${STACK[$name,mps2-an386]:-?} | ${STACK[$name,mps2-an385]:-?} | ${STACK[$name,lm3s6965evb]:-?} |"
done
echo
echo "One ray of 16 samples (integer) or one cast through the 4×4×4 scene (float), from the"
echo "stack pointer at the call; the volume, marcher and correction table live in the caller."
