#!/usr/bin/env bash
# The C API check: the header must be what cbindgen generates from src/lib.rs today, the
# staticlib must build, and the C test, compiled with `gcc -ffreestanding`, must pass.
# Called by ../run.sh (which installs cbindgen and gcc); uses $CARGO and $CARGO_TARGET_DIR.
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

gcc -std=c11 -ffreestanding -Wall -Wextra -Werror -pedantic -I include -c tests/test.c -o "$OUT/test.o"
gcc "$OUT/test.o" "$LIB" -o "$OUT/test"
"$OUT/test"
