#!/usr/bin/env python3
"""Reads the vector files of `volsample vectors` from their manifest.json alone.

Decoding is generic: each line of inputs.hex / expected.hex is one word, most significant
hex digit first; every field is taken from the word by the manifest's offset, width and
signedness (two's complement) and named by the manifest. Nothing about a kernel is assumed.

The check (--check) recomputes every expected word of the kernels whose arithmetic this
file re-implements, exactly as their manifest writes it out (the formulas of its "rounding"
entry, which the check first compares with the text the oracle was written from, so a
changed rule is reported instead of silently checked against old arithmetic):
composite-front-to-back and the six sampling kernels
({opacity-weighted,separate,preweighted}-{nearest,trilinear}), at any F.

Usage:
  read_vectors.py DIR                  summary of the manifest and the first words, decoded
  read_vectors.py --dump N DIR         the first N words as JSON lines (inputs and expected)
  read_vectors.py --check DIR [--expected FILE]
                                       recompute every expected word (FILE instead of the
                                       directory's expected.hex); prints each mismatch (the
                                       first 20 in full) and one final PASS:/FAIL: line; exit
                                       status 1 on a mismatch or an undecodable file

Python 3 standard library only.
"""

import json
import os
import sys


class VectorError(Exception):
    """A vector file that does not match its manifest."""


def load_manifest(directory):
    """The manifest of a vector directory, as a dict."""
    with open(os.path.join(directory, "manifest.json"), encoding="utf-8") as f:
        return json.load(f)


def check_layout(layout):
    """Checks that a word layout is consistent: fields inside the word, no overlap."""
    bits = layout["word_bits"]
    if layout["hex_digits"] != (bits + 3) // 4:
        raise VectorError("hex_digits %d does not hold %d bits" % (layout["hex_digits"], bits))
    used = 0
    for field in layout["fields"]:
        off, width = field["offset"], field["width"]
        if width < 1 or off < 0 or off + width > bits:
            raise VectorError("field %s (offset %d, width %d) is outside the %d-bit word"
                              % (field["name"], off, width, bits))
        mask = ((1 << width) - 1) << off
        if used & mask:
            raise VectorError("field %s overlaps another field" % field["name"])
        used |= mask


def decode_word(text, layout):
    """One word (a line of hex digits) as a dict field name -> int."""
    if len(text) != layout["hex_digits"]:
        raise VectorError("%d hex digits, the manifest says %d" % (len(text), layout["hex_digits"]))
    word = int(text, 16)
    if word >> layout["word_bits"]:
        raise VectorError("bits set above bit %d" % (layout["word_bits"] - 1))
    values = {}
    for field in layout["fields"]:
        width = field["width"]
        v = (word >> field["offset"]) & ((1 << width) - 1)
        if field["signed"] and v >> (width - 1):
            v -= 1 << width
        values[field["name"]] = v
    return values


def read_words(directory, layout, path=None):
    """Every word of a vector file (default: the layout's file in directory), decoded."""
    check_layout(layout)
    path = path or os.path.join(directory, layout["file"])
    words = []
    with open(path, encoding="ascii") as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            try:
                words.append(decode_word(line, layout))
            except ValueError as e:
                raise VectorError("%s line %d: %s" % (path, n, e)) from e
            except VectorError as e:
                raise VectorError("%s line %d: %s" % (path, n, e)) from e
    return words


def read_vectors(directory, expected_path=None):
    """(manifest, inputs, expected) of a vector directory; the counts must match the manifest."""
    m = load_manifest(directory)
    inputs = read_words(directory, m["inputs"])
    expected = read_words(directory, m["expected"], expected_path)
    for name, words in (("inputs", inputs), ("expected", expected)):
        if len(words) != m["count"]:
            raise VectorError("%s: %d words, the manifest says %d" % (name, len(words), m["count"]))
    return m, inputs, expected


# ---------------------------------------------------------------------------------------
# Oracles: the integer arithmetic of the manifests' "rounding" entries, written again.


def round_half_up(num, den):
    """The manifest's "round half up": floor(num/den + 1/2), exactly."""
    return (2 * num + den) // (2 * den)


def field_frac_bits(m, key, name):
    for field in m[key]["fields"]:
        if field["name"] == name:
            return field["frac_bits"]
    raise VectorError("no field %s in %s" % (name, key))


# The formulas each oracle implements, as the manifests write them ({s}: 3F).
COMPOSITE_RULES = [
    ("r, g, b, a", "round half up",
     "T = 65280 − acc_a; x = acc_x + ⌊T·s_x/65280 + ½⌋ = acc_x + (T·s_x + 32640) div 65280"),
]
WEIGHT_RULES = {
    "nearest": ("round half up",
                "nearest voxel per axis: ⌊(index·2^F + f)/2^F + ½⌋, i.e. corner bit = (f ≥ "
                "2^(F−1)); weight 1, shift s = 0"),
    "trilinear": ("exact",
                  "w_i = wx·wy·wz, per axis the factor of the low corner 2^F − f and of the high "
                  "corner f (wx from fx, wy from fy, wz from fz; corner i at (i&1, (i>>1)&1, "
                  "i>>2), so w_0 = (2^F − fx)·(2^F − fy)·(2^F − fz)); exact, each ≤ 2^s; Σ w_i "
                  "= 2^s, s = 3F = {s}"),
}
OUTPUT_RULES = {
    "opacity-weighted": [
        ("a", "round half up", "S_α = Σ w_i·α_i; a = ⌊256·S_α/2^s + ½⌋"),
        ("r, g, b", "round half up", "S_c = Σ (w_i·α_i)·C_i; c = ⌊256·S_c/(255·2^s) + ½⌋"),
    ],
    "separate": [
        ("a", "round half up", "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"),
        ("(straight C, internal)", "round half up", "C = ⌊256·Σ w_i·C_i/2^s + ½⌋"),
        ("r, g, b", "round half up", "c = ⌊a·C/65280 + ½⌋ = (a·C + 32640) div 65280"),
    ],
    "preweighted": [
        ("a", "round half up", "a = ⌊256·Σ w_i·α_i/2^s + ½⌋"),
        ("r, g, b", "round half up", "c = ⌊256·Σ w_i·min(C̃_i, α_i)/2^s + ½⌋"),
    ],
}


def same_rules(got, want, what):
    """The manifest's rules (a list of {output, rule, formula}) must be the oracle's."""
    got = [(o.get("output"), o.get("rule"), o.get("formula")) for o in got]
    if got != want:
        raise VectorError("%s: the manifest's rules are not the ones this oracle implements:\n"
                          "  manifest: %r\n  oracle:   %r" % (what, got, want))


def composite_oracle(m):
    same_rules(m["rounding"]["outputs"], COMPOSITE_RULES, m["kernel"])
    one = m["one"]

    def step(w):
        t = one - w["acc_a"]
        return {x: w["acc_" + x] + (t * w["s_" + x] + one // 2) // one for x in "rgba"}
    return step


def sample_oracle(m):
    mode, _, filt = m["kernel"].rpartition("-")
    f = field_frac_bits(m, "inputs", "fx")
    s = 3 * f if filt == "trilinear" else 0
    rule, formula = WEIGHT_RULES[filt]
    weights = m["rounding"]["weights"]
    if (weights["rule"], weights["formula"]) != (rule, formula.format(s=s)):
        raise VectorError("%s: the manifest's weight rule is not the one this oracle implements:"
                          "\n  manifest: %r" % (m["kernel"], weights))
    same_rules(m["rounding"]["outputs"], OUTPUT_RULES[mode], m["kernel"])
    one = m["one"]

    def weights_of(w):
        if filt == "trilinear":
            axes = [(2 ** f - w[a], w[a]) for a in ("fx", "fy", "fz")]
            return [axes[0][i & 1] * axes[1][(i >> 1) & 1] * axes[2][i >> 2] for i in range(8)]
        corner = sum((w[a] >= 2 ** (f - 1)) << k for k, a in enumerate(("fx", "fy", "fz")))
        return [int(i == corner) for i in range(8)]

    def sample(w):
        wi = weights_of(w)
        if sum(wi) != 2 ** s:
            raise VectorError("weights do not sum to 2^s")
        alpha = [w["v%d_a" % i] for i in range(8)]
        out = {"a": round_half_up(256 * sum(x * y for x, y in zip(wi, alpha)), 2 ** s)}
        for ch in "rgb":
            c = [w["v%d_%s" % (i, ch)] for i in range(8)]
            if mode == "opacity-weighted":
                s_c = sum(x * a * y for x, a, y in zip(wi, alpha, c))
                out[ch] = round_half_up(256 * s_c, 255 * 2 ** s)
            elif mode == "separate":
                straight = round_half_up(256 * sum(x * y for x, y in zip(wi, c)), 2 ** s)
                out[ch] = (out["a"] * straight + one // 2) // one
            else:
                out[ch] = round_half_up(256 * sum(x * min(y, a) for x, y, a in zip(wi, c, alpha)),
                                        2 ** s)
        return out
    return sample


def oracle(m):
    """The recomputation of a kernel's expected word from its input word, or None."""
    kernel = m["kernel"]
    if kernel == "composite-front-to-back":
        return composite_oracle(m)
    mode, _, filt = kernel.rpartition("-")
    if mode in OUTPUT_RULES and filt in WEIGHT_RULES:
        return sample_oracle(m)
    return None


def check(directory, expected_path=None):
    """Recomputes every expected word; prints mismatches and a PASS:/FAIL: line. 0 if all match."""
    m, inputs, expected = read_vectors(directory, expected_path)
    fn = oracle(m)
    if fn is None:
        print("FAIL: read_vectors: no oracle for kernel %s" % m["kernel"])
        return 1
    errors = 0
    for i, (w, e) in enumerate(zip(inputs, expected)):
        got = fn(w)
        if any(got[k] != e[k] for k in got) or set(got) != set(e):
            errors += 1
            if errors <= 20:
                print("MISMATCH vector %d: recomputed %s, expected.hex %s" % (i, got, e))
    what = "read_vectors %s F=%s" % (m["kernel"], m.get("frac_bits"))
    if errors:
        print("FAIL: %s: %d vectors, %d mismatches" % (what, len(expected), errors))
        return 1
    print("PASS: %s: %d vectors, 0 mismatches" % (what, len(expected)))
    return 0


def main(argv):
    args = list(argv)
    mode, limit, expected_path = "summary", 4, None
    if args[:1] == ["--check"]:
        mode = "check"
        args = args[1:]
    elif args[:1] == ["--dump"] and len(args) >= 2:
        mode, limit = "dump", int(args[1])
        args = args[2:]
    if len(args) >= 3 and args[1] == "--expected":
        expected_path = args[2]
        args = args[:1] + args[3:]
    if len(args) != 1:
        print(__doc__.split("Usage:")[1].split("Python 3")[0], file=sys.stderr)
        return 2
    directory = args[0]
    try:
        if mode == "check":
            return check(directory, expected_path)
        m, inputs, expected = read_vectors(directory, expected_path)
        if mode == "summary":
            print("%s: %s" % (m["kernel"], m["description"]))
            for key in ("inputs", "expected"):
                names = [f["name"] for f in m[key]["fields"]]
                print("  %s: %d words of %d bits, fields %s" % (m[key]["file"], m["count"],
                                                                 m[key]["word_bits"], " ".join(names)))
        for i in range(min(limit, len(inputs))):
            print(json.dumps({"vector": i, "inputs": inputs[i], "expected": expected[i]}))
        return 0
    except (VectorError, OSError, KeyError) as e:
        print("FAIL: read_vectors: %s: %s" % (directory, e))
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
