#!/usr/bin/env bash
# The firmware suite's committed reference (`suite-reference.txt`): one line per suite case
# (its line count and the SHA-256 of its lines) and the suite's summary line (line count,
# value count and the FNV-1a-64 of every value). It is written from the host runner's output,
# so it does not depend on QEMU; run.sh checks the host's and every board's output against it.
# That catches what the host-versus-QEMU comparison cannot: a change shared by every target
# (say, a rounding turned into a truncation in the core), which moves host and QEMU together.
#
# Usage: reference.sh digest SUITE_OUTPUT     print the per-case lines and the summary
#        reference.sh check SUITE_OUTPUT      compare with suite-reference.txt; names the
#                                             cases that differ, fails on any difference and
#                                             on fewer values than the reference holds
#        reference.sh write SUITE_OUTPUT      rewrite suite-reference.txt (after a deliberate
#                                             change of a kernel's results: say so in the commit)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
REF="$HERE/suite-reference.txt"

# Case of a line: the entry of the suite's CASES list its name starts with (`int.<x>` for the
# integer cases, else the first dot- or slash-separated part).
digest() {
    local out=$1 tmp
    tmp=$(mktemp -d)
    awk -v dir="$tmp" '
        /^#/ { next }
        { n = split($1, a, /[.\/]/); key = (a[1] == "int" && n > 2) ? a[1] "." a[2] : a[1]
          if (!(key in seen)) { seen[key] = 1; order[++k] = key }
          print > (dir "/" key) }
        END { for (i = 1; i <= k; i++) print order[i] > (dir "/.order") }' "$out"
    while read -r key; do
        printf '%s lines=%s sha256=%s\n' "$key" "$(wc -l < "$tmp/$key")" \
            "$(sha256sum < "$tmp/$key" | cut -d' ' -f1)"
    done < "$tmp/.order"
    rm -rf "$tmp"
    local summary
    summary=$(tail -n 1 "$out")
    case $summary in "# suite lines="*" values="*" fnv64="*) echo "$summary" ;;
        *) echo "no summary line at the end of $out: $summary" >&2; return 1 ;;
    esac
}

values() { sed -n 's/^# suite .*values=\([0-9]*\).*/\1/p' "$1" | tail -n 1; }

case ${1:-} in
digest) digest "$2" ;;
write)
    {
        echo "# The firmware suite's reference, written by host-tests/firmware/reference.sh from the"
        echo "# host runner (volsample-fw-host). run.sh fails if the host or a board differs from it."
        digest "$2"
    } > "$REF"
    echo "wrote $REF: $(tail -n 1 "$REF")"
    ;;
check)
    got=$(digest "$2") || exit 1
    want=$(grep -v '^# The\|^# host' "$REF")
    want_n=$(values "$REF")
    got_n=$(echo "$got" | sed -n 's/^# suite .*values=\([0-9]*\).*/\1/p')
    if [ "$got_n" -lt "$want_n" ]; then
        echo "$2: $got_n values, fewer than the reference's $want_n" >&2
    fi
    if [ "$got" != "$want" ]; then
        echo "$2 differs from suite-reference.txt:" >&2
        diff <(echo "$want") <(echo "$got") | grep '^[<>]' | head -40 >&2
        exit 1
    fi
    [ "$got_n" -ge "$want_n" ] || exit 1
    echo "$2: matches the reference ($(echo "$got" | tail -n 1))"
    ;;
*) echo "usage: $0 digest|check|write SUITE_OUTPUT" >&2; exit 2 ;;
esac
