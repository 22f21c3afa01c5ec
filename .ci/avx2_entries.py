#!/usr/bin/env python3
"""Checks that the AVX2 entries of a binary hold AVX2 code.

The core runs a kernel in AVX2 by calling it inside `run_avx2`, a function compiled for AVX2
and FMA into which the kernel is inlined (`core/src/arch/avx2/mod.rs`). If LLVM keeps the
kernel as a function of its own instead (a closure it did not inline), that function is
compiled for the baseline and `run_avx2` only jumps to it: the AVX2 instance then runs
baseline code, with identical results, so no test of results can see it.

Usage: avx2_entries.py BINARY. Reads `objdump -d` of BINARY and fails if any instance of
`run_avx2` is a bare jump or call to another function, or contains no VEX-encoded
instruction; prints how many instances it checked.
"""
import re
import subprocess
import sys

# A VEX-encoded instruction: what only a function compiled for AVX (and up) contains.
VEX = re.compile(r"\tv[a-z0-9]+\s")
FUNCTION = re.compile(r"^[0-9a-f]+ <(.*)>:$")
TRANSFER = re.compile(r"\t(jmp|call)\s+[0-9a-f]+ <([^>]*)>")


def functions(binary):
    """(name, instructions) of every function in the disassembly, padding left out."""
    out = subprocess.run(
        ["objdump", "-d", "--no-show-raw-insn", binary],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    name, body = None, []
    for line in out.splitlines():
        m = FUNCTION.match(line)
        if m:
            if name is not None:
                yield name, body
            name, body = m.group(1), []
        elif name is not None and "\t" in line:
            if not re.search(r"\t(int3|nop)", line):
                body.append(line)
    if name is not None:
        yield name, body


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: avx2_entries.py BINARY")
    checked, bad = 0, []
    for name, body in functions(sys.argv[1]):
        if "run_avx2" not in name:
            continue
        checked += 1
        first = TRANSFER.search(body[0]) if body else None
        if len(body) <= 2 and first:
            bad.append(f"{name}: only a {first.group(1)} to {first.group(2)}")
        elif not any(VEX.search(line) for line in body):
            bad.append(f"{name}: no VEX-encoded instruction in {len(body)}")
    print(f"AVX2 entries (run_avx2 instances) in {sys.argv[1]}: {checked}, without AVX2 code: {len(bad)}")
    for b in bad[:20]:
        print("  " + b)
    if checked == 0 or bad:
        sys.exit(1)


if __name__ == "__main__":
    main()
