#!/usr/bin/env bash
# The firmware stage of CI (issue 6), whole: install the toolchain, cross-build the core for
# Cortex-M, run the kernel suite under QEMU and compare it bit for bit with the host and with
# the committed reference (suite-reference.txt, written from the host), check
# the images for heap use, undefined symbols and reachable panics, link the `defmt` feature
# with a logger, print the size/stack table, and build and test the C API.
#
# Usage: host-tests/firmware/run.sh        (as root on Debian 12; installs what it needs)
# Env:   FW_TARGET_DIR  cargo target dir   (default host-tests/firmware/target, git-ignored)
#        FW_SKIP_INSTALL=1                  skip apt-get (when everything is installed)
# Outputs (hex dumps, size table) go to $FW_TARGET_DIR/report/.
set -euo pipefail
cd "$(dirname "$0")"
FW_DIR=$(pwd)
T0=$(date +%s)
step() { echo; echo "--- [fw $(( $(date +%s) - T0 ))s] $*"; }
fail() { echo "FIRMWARE CHECK FAILED: $*" >&2; exit 1; }

export CARGO_TARGET_DIR="${FW_TARGET_DIR:-$FW_DIR/target}"
export CARGO_TERM_COLOR=never
unset RUSTFLAGS CARGO_BUILD_RUSTFLAGS CARGO_ENCODED_RUSTFLAGS RUSTUP_TOOLCHAIN
REPORT="$CARGO_TARGET_DIR/report"
mkdir -p "$REPORT"

# ---------------------------------------------------------------------------------------------
step "install: Debian's Rust (with its core sources, for -Zbuild-std), lld, QEMU, cbindgen"
# rustup's toolchain cannot add targets here, so the Cortex-M `core` is built from Debian's
# rust-web-src. /usr/bin/rust-lld dangles unless lld-22 is installed. Installing
# qemu-system-arm replaces the newer qemu-utils; nothing in this project needs them.
PKGS=(rustc-web cargo-web rust-web-src rust-web-llvm lld-22 qemu-system-arm cbindgen gcc g++ binutils gcc-arm-none-eabi)
missing=()
for p in "${PKGS[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ] && [ "${FW_SKIP_INSTALL:-0}" != 1 ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# rustup's cargo comes first in PATH: always call Debian's by path, with its rustc.
CARGO=/usr/bin/cargo
export RUSTC=/usr/bin/rustc
"$RUSTC" --version
"$CARGO" --version
qemu-system-arm --version | head -1
[ -e /usr/bin/rust-lld ] || fail "/usr/bin/rust-lld dangles (lld-22 missing)"

xbuild() { # xbuild TARGET ARGS...: cross-build with core from source
    local target=$1; shift
    RUSTC_BOOTSTRAP=1 "$CARGO" build -q -Zbuild-std=core --release --target "$target" "$@"
}
qemu() { # qemu BOARD ELF: run to the semihosting exit; a fault would spin, hence timeout
    local board=$1 elf=$2 cpu
    case $board in
        mps2-an386) cpu=cortex-m4 ;;
        mps2-an385|lm3s6965evb) cpu=cortex-m3 ;;
        *) fail "unknown board $board" ;;
    esac
    # (lm3s6965evb's QEMU model prints "Timer with period zero, disabling" on stderr: harmless.)
    timeout 300 qemu-system-arm -machine "$board" -cpu "$cpu" -nographic -monitor none \
        -semihosting-config enable=on,target=native -kernel "$elf"
}

# target → QEMU board of the suite. thumbv7m runs the suite on mps2-an385 (Cortex-M3,
# 4 MiB): the suite (~320 KB) and the every-kernel image (~500 KB) do not fit the
# lm3s6965evb's 256 KiB of flash, which gets the small images below.
TARGETS=(thumbv7em-none-eabihf thumbv7m-none-eabi)
declare -A BOARD=([thumbv7em-none-eabihf]=mps2-an386 [thumbv7m-none-eabi]=mps2-an385)
BINS=(suite stack baseline min_int min_float full panic_canary)
SMALL_BINS=(stack baseline min_int min_float)

# ---------------------------------------------------------------------------------------------
step "build: host suite runner (debug and release) and the Cortex-M images"
"$CARGO" build -q -p volsample-fw-host
"$CARGO" build -q --release -p volsample-fw-host
for t in "${TARGETS[@]}"; do
    unset VOLSAMPLE_FW_BOARD
    xbuild "$t" $(printf -- '--bin %s ' "${BINS[@]}")
    mkdir -p "$REPORT/elf/$t-${BOARD[$t]}"
    for b in "${BINS[@]}"; do cp "$CARGO_TARGET_DIR/$t/release/$b" "$REPORT/elf/$t-${BOARD[$t]}/"; done
done
# The same small images for the lm3s6965evb's real memory map (256 KiB flash, 64 KiB RAM).
VOLSAMPLE_FW_BOARD=lm3s6965evb xbuild thumbv7m-none-eabi $(printf -- '--bin %s ' "${SMALL_BINS[@]}")
mkdir -p "$REPORT/elf/thumbv7m-none-eabi-lm3s6965evb"
for b in "${SMALL_BINS[@]}"; do
    cp "$CARGO_TARGET_DIR/thumbv7m-none-eabi/release/$b" "$REPORT/elf/thumbv7m-none-eabi-lm3s6965evb/"
done

# ---------------------------------------------------------------------------------------------
step "bit identity: the suite on the host (debug, release) and under QEMU, byte for byte"
"$CARGO_TARGET_DIR/debug/volsample-fw-host" > "$REPORT/suite-host-debug.txt"
"$CARGO_TARGET_DIR/release/volsample-fw-host" > "$REPORT/suite-host-release.txt"
cmp "$REPORT/suite-host-debug.txt" "$REPORT/suite-host-release.txt" \
    || fail "host debug and release suite outputs differ"
summary=$(tail -n 1 "$REPORT/suite-host-release.txt")
case $summary in "# suite lines="*" values="*) ;; *) fail "host suite summary missing: $summary" ;; esac
for t in "${TARGETS[@]}"; do
    b=${BOARD[$t]}
    qemu "$b" "$REPORT/elf/$t-$b/suite" > "$REPORT/suite-$t-$b.txt" || fail "suite on $b exited with $?"
    if ! cmp -s "$REPORT/suite-host-release.txt" "$REPORT/suite-$t-$b.txt"; then
        diff "$REPORT/suite-host-release.txt" "$REPORT/suite-$t-$b.txt" | head -40
        fail "suite on $t ($b) differs from the host: $(diff "$REPORT/suite-host-release.txt" \
            "$REPORT/suite-$t-$b.txt" | grep -c '^<') lines"
    fi
    echo "$t on $b: identical to the host: $summary"
done

# ---------------------------------------------------------------------------------------------
step "reference: the host's and every board's output against the committed suite-reference.txt"
# The comparison above cannot see a change that moves every target alike (a rounding made a
# truncation in the core moves the host and QEMU together); the committed reference, written
# from the host runner, can. First the check itself must fail on a changed value.
# (The last hex digit of the first integer compositing result, 0 ↔ 1 or made 0.)
awk '!done && /^int\.composite\.f2b\/0 / { c = substr($0, length($0)); done = 1
        $0 = substr($0, 1, length($0) - 1) (c == "0" ? "1" : "0") } { print }' \
    "$REPORT/suite-host-release.txt" > "$REPORT/suite-altered.txt"
cmp -s "$REPORT/suite-host-release.txt" "$REPORT/suite-altered.txt" && fail "the altered copy is unaltered"
if "$FW_DIR/reference.sh" check "$REPORT/suite-altered.txt" 2>/dev/null; then
    fail "reference.sh accepted a suite output with one altered value: the check is broken"
fi
echo "reference.sh rejects an output with one altered value"
"$FW_DIR/reference.sh" check "$REPORT/suite-host-release.txt" \
    || fail "the host's suite output differs from suite-reference.txt (if a kernel's results changed on purpose, rewrite it: host-tests/firmware/reference.sh write OUTPUT)"
for t in "${TARGETS[@]}"; do
    b=${BOARD[$t]}
    "$FW_DIR/reference.sh" check "$REPORT/suite-$t-$b.txt" || fail "the suite on $b differs from suite-reference.txt"
done

# ---------------------------------------------------------------------------------------------
step "images: no heap, no undefined symbols, no reachable panic"
# Panic reachability. Each kernel image (baseline, min_int, min_float, full) calls the
# kernels on inputs hidden behind `black_box`, so the optimiser cannot prove a bounds check
# or an overflow away by constant folding, only by what the code itself guarantees. Its
# panic handler calls `volsample_firmware::panic_trap`, a distinct `#[inline(never)]`
# function. The image is linked with fat LTO, one codegen unit and --gc-sections, so a
# function nobody calls is dropped: if any panic site were reachable from the kernels, the
# chain site → core::panicking::* → rust_begin_unwind → panic_trap would keep all of those
# symbols. We require that none of them is in the symbol table. `panic_canary` has one
# deliberate reachable panic and must show the symbols, which proves the check can fail.
PANIC_RE='panic_trap|rust_begin_unwind|core::panicking|panic_bounds_check|unwrap_failed|expect_failed|slice_(start_|end_)?index_.*fail|panic_const'
HEAP_RE='^(malloc|free|calloc|realloc|aligned_alloc|posix_memalign|__rust_alloc|__rust_dealloc|__rust_realloc|__rust_alloc_zeroed|__rg_alloc|__rdl_alloc|__rust_alloc_error_handler)$'
for dir in "$REPORT"/elf/*/; do
    for elf in "$dir"*; do
        name=$(basename "$elf")
        [ "$name" = panic_canary ] && continue
        und=$(nm -u "$elf" | awk '{print $2}' | grep -v '^$' || true)
        [ -z "$und" ] || fail "$elf has undefined symbols: $und"
        heap=$(nm "$elf" | awk '{print $NF}' | grep -E "$HEAP_RE" || true)
        [ -z "$heap" ] || fail "$elf links allocator symbols: $heap"
        case $name in
            baseline|min_int|min_float|full)
                p=$(nm -C "$elf" | grep -E "$PANIC_RE" || true)
                [ -z "$p" ] || fail "$elf keeps a panic path: $p" ;;
        esac
    done
    canary="no canary here"
    if [ -e "$dir/panic_canary" ]; then
        nm -C "$dir/panic_canary" | grep -qE "$PANIC_RE" \
            || fail "the panic check does not see the canary's panic in $dir: the check is broken"
        canary="canary's panic detected"
    fi
    echo "$(basename "$dir"): no heap, no undefined symbols in $(ls "$dir" | tr '\n' ' ');" \
        "panic-free: $(cd "$dir" && ls -d baseline min_int min_float full 2>/dev/null | tr '\n' ' ')($canary)"
done
# Each image must also run to its semihosting exit (a HardFault would hang until timeout).
for t in "${TARGETS[@]}"; do
    b=${BOARD[$t]}
    for img in baseline min_int min_float full; do
        qemu "$b" "$REPORT/elf/$t-$b/$img" || fail "$img on $b exited with $?"
    done
done
for img in baseline min_int min_float; do
    qemu lm3s6965evb "$REPORT/elf/thumbv7m-none-eabi-lm3s6965evb/$img" || fail "$img on lm3s6965evb failed"
done

# ---------------------------------------------------------------------------------------------
step "defmt: the core's defmt feature linked with a logger (defmt-rtt)"
xbuild thumbv7em-none-eabihf --features defmt --bin defmt_link
DEFMT_ELF="$CARGO_TARGET_DIR/thumbv7em-none-eabihf/release/defmt_link"
n=$(nm "$DEFMT_ELF" | grep -c '{"package":"volsample' || true)
[ "$n" -gt 0 ] || fail "no volsample format strings in the .defmt section of defmt_link"
qemu mps2-an386 "$DEFMT_ELF" || fail "defmt_link did not run to its exit"
echo "defmt_link: links and runs; $n interned volsample format strings"

# ---------------------------------------------------------------------------------------------
step "size and stack"
"$FW_DIR/size.sh" "$REPORT" | tee "$REPORT/size-stack.md"

# ---------------------------------------------------------------------------------------------
step "C API: header from cbindgen (C99, C++), staticlib for the host and Cortex-M, the C test on the host and under QEMU, the smallest C images"
"$FW_DIR/capi/test.sh"

step "firmware stage done in $(( $(date +%s) - T0 ))s"
