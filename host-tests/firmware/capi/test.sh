#!/usr/bin/env bash
# The C API check: the header must be what cbindgen generates from src/lib.rs today and compile
# alone as C99 with -Wall -Wextra -pedantic; the staticlib must build for the host and for
# Cortex-M (thumbv7em-none-eabihf, thumbv7m-none-eabi); the C test must pass on the host and,
# linked with arm-none-eabi-gcc against the Cortex-M staticlib, under QEMU on both boards;
# and the smallest C images are built and measured.
# Called by ../run.sh (which installs cbindgen, gcc, gcc-arm-none-eabi and QEMU); uses $CARGO
# and $CARGO_TARGET_DIR. Set CAPI_CORTEX_M=0 to skip the Cortex-M part.
set -euo pipefail
cd "$(dirname "$0")"
CARGO=${CARGO:-/usr/bin/cargo}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$(pwd)/../target}
OUT="$CARGO_TARGET_DIR/capi"
mkdir -p "$OUT"

cbindgen --quiet --config cbindgen.toml --crate volsample-capi --output "$OUT/volsample.h" .
if ! diff -u include/volsample.h "$OUT/volsample.h"; then
    echo "include/volsample.h is stale: regenerate it with" >&2
    echo "  (cd host-tests/firmware/capi && cbindgen --config cbindgen.toml --crate volsample-capi --output include/volsample.h .)" >&2
    exit 1
fi

"$CARGO" build -q --release -p volsample-capi
LIB="$CARGO_TARGET_DIR/release/libvolsample_capi.a"
# What the Rust code of the staticlib needs from outside. The archive also carries
# compiler-builtins (with compiler-rt's C objects, some of which mention malloc or pthread), but
# a linker only pulls a member in for a symbol something refers to; so we check the crate's own
# object(s): whatever they leave undefined must be defined elsewhere in the archive or be one of
# the C library's memory functions. No allocator, no I/O, no unwinding.
rm -rf "$OUT/ar" && mkdir -p "$OUT/ar"
(cd "$OUT/ar" && ar x "$LIB")
own=$(find "$OUT/ar" -name 'volsample_capi-*.o')
[ -n "$own" ] || { echo "no volsample_capi object in $LIB" >&2; exit 1; }
nm --defined-only "$OUT"/ar/*.o 2>/dev/null | awk 'NF == 3 {print $3}' | sort -u > "$OUT/defined.txt"
und=$(nm -u $own | awk '{print $2}' | sort -u | comm -23 - "$OUT/defined.txt" \
    | grep -vE '^(memcpy|memmove|memset|memcmp|bcmp)$' || true)
[ -z "$und" ] || { echo "libvolsample_capi.a needs unexpected symbols: $und" >&2; exit 1; }
echo "staticlib: its Rust object needs only: $(nm -u $own | awk '{print $2}' | sort -u | comm -23 - "$OUT/defined.txt" | tr '\n' ' ')"

WARN=(-std=c99 -Wall -Wextra -Werror -pedantic)
# The header alone, as C99 and as C++ (its extern "C" guard).
echo '#include "volsample.h"' > "$OUT/header_only.c"
gcc "${WARN[@]}" -I include -c "$OUT/header_only.c" -o "$OUT/header_only.o"
g++ -std=c++11 -Wall -Wextra -Werror -pedantic -I include -x c++ -c "$OUT/header_only.c" -o "$OUT/header_only_cpp.o"
gcc "${WARN[@]}" -ffreestanding -I include -c tests/test.c -o "$OUT/test.o"
gcc "${WARN[@]}" -c tests/io_host.c -o "$OUT/io_host.o"
gcc "$OUT/test.o" "$OUT/io_host.o" "$LIB" -o "$OUT/test"
echo "C test on the host: $("$OUT/test")"

[ "${CAPI_CORTEX_M:-1}" = 1 ] || exit 0
# --- Cortex-M: the staticlib cross-built with Debian's toolchain (core from source, like the
# images of ../run.sh), the C test and the smallest images linked by arm-none-eabi-gcc with
# tests/cortex_m.c (start-up, semihosting) and tests/cortex_m.ld, run under QEMU.
declare -A CFLAGS_OF=(
    [thumbv7em-none-eabihf]="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16"
    [thumbv7m-none-eabi]="-mcpu=cortex-m3 -mthumb -mfloat-abi=soft"
)
declare -A BOARD_OF=([thumbv7em-none-eabihf]=mps2-an386 [thumbv7m-none-eabi]=mps2-an385)
declare -A CPU_OF=([thumbv7em-none-eabihf]=cortex-m4 [thumbv7m-none-eabi]=cortex-m3)
SIZES="$OUT/sizes.md"
{
    echo "| C image | what | Cortex-M4F .text | Cortex-M3 .text |"
    echo "|---|---|---:|---:|"
} > "$SIZES"
declare -A TEXT
for t in thumbv7em-none-eabihf thumbv7m-none-eabi; do
    RUSTC_BOOTSTRAP=1 "$CARGO" build -q -Zbuild-std=core --release --target "$t" -p volsample-capi
    ALIB="$CARGO_TARGET_DIR/$t/release/libvolsample_capi.a"
    [ -s "$ALIB" ] || { echo "no $ALIB" >&2; exit 1; }
    # shellcheck disable=SC2206
    flags=(${CFLAGS_OF[$t]} "${WARN[@]}" -ffreestanding -Os -ffunction-sections -fdata-sections -I include)
    link=(-nostdlib -nostartfiles -T tests/cortex_m.ld -Wl,--gc-sections -Wl,-z,noexecstack)
    o="$OUT/$t"
    mkdir -p "$o"
    arm-none-eabi-gcc "${flags[@]}" -c tests/cortex_m.c -o "$o/cortex_m.o"
    arm-none-eabi-gcc "${flags[@]}" -c tests/test.c -o "$o/test.o"
    arm-none-eabi-gcc "${flags[@]}" "${link[@]}" "$o/test.o" "$o/cortex_m.o" "$ALIB" -lgcc -o "$o/test.elf"
    und=$(arm-none-eabi-nm -u "$o/test.elf" || true)
    [ -z "$und" ] || { echo "$o/test.elf has undefined symbols: $und" >&2; exit 1; }
    board=${BOARD_OF[$t]}
    got=$(timeout 300 qemu-system-arm -machine "$board" -cpu "${CPU_OF[$t]}" -nographic -monitor none \
        -semihosting-config enable=on,target=native -kernel "$o/test.elf") \
        || { echo "$got"; echo "the C test failed on $t ($board)" >&2; exit 1; }
    echo "C test on $t ($board, QEMU): $got"
    case $got in *" passed, 0 failed"*) ;; *) echo "no pass line from the C test on $t" >&2; exit 1 ;; esac
    for v in int cast dispatch; do
        case $v in int) def=() ;; cast) def=(-DVS_MIN_CAST) ;; dispatch) def=(-DVS_MIN_DISPATCH) ;; esac
        arm-none-eabi-gcc "${flags[@]}" "${def[@]}" -c tests/min.c -o "$o/min_$v.o"
        arm-none-eabi-gcc "${flags[@]}" "${link[@]}" "$o/min_$v.o" "$o/cortex_m.o" "$ALIB" -lgcc -o "$o/min_$v.elf"
        timeout 60 qemu-system-arm -machine "$board" -cpu "${CPU_OF[$t]}" -nographic -monitor none \
            -semihosting-config enable=on,target=native -kernel "$o/min_$v.elf" \
            || { echo "min_$v failed on $t ($board)" >&2; exit 1; }
        TEXT[$t.$v]=$(arm-none-eabi-size -A "$o/min_$v.elf" | awk '$1 == ".text" {print $2}')
    done
    TEXT[$t.test]=$(arm-none-eabi-size -A "$o/test.elf" | awk '$1 == ".text" {print $2}')
done
what_int='`vs_int_sample_u8_opacity_weighted_trilinear`: one integer sample'
what_cast='`vs_cast_u8_opacity_weighted_trilinear`: one float ray, front to back'
what_dispatch='`vs_cast_u8`: the same ray through the dispatching entry point'
what_test='`tests/test.c`: every entry point'
for v in int cast dispatch test; do
    w="what_$v"
    f=min_$v.c; [ "$v" = test ] && f=test.c
    echo "| \`$f\` | ${!w} | ${TEXT[thumbv7em-none-eabihf.$v]} | ${TEXT[thumbv7m-none-eabi.$v]} |" >> "$SIZES"
done
sed -i 's/`min_int.c`/`min.c`/; s/`min_cast.c`/`min.c -DVS_MIN_CAST`/; s/`min_dispatch.c`/`min.c -DVS_MIN_DISPATCH`/' "$SIZES"
echo "C images on Cortex-M (release staticlib, opt-level s, fat LTO; gcc -Os, --gc-sections), bytes:"
cat "$SIZES"
# Per-mode entry points must keep an image small: the one-kernel images well below the
# dispatching one (which links every mode x filter).
for t in thumbv7em-none-eabihf thumbv7m-none-eabi; do
    [ "$(( ${TEXT[$t.cast]} * 4 ))" -lt "${TEXT[$t.dispatch]}" ] \
        || { echo "on $t the one-kernel cast image is not below a quarter of the dispatching one" >&2; exit 1; }
done
