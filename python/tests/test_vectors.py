"""volsample.vectors: the HDL reference vectors of `volsample vectors`, decoded here from the
hex files with the manifest's field layout and checked against the kernels' integer rules
recomputed in Python (exact integers), never against values taken from the output."""

import os
import shutil
import subprocess

import pytest

import volsample
from conftest import gil_free_ticks

ONE = 65280


def words(path):
    with open(path, encoding="ascii") as f:
        return [line.strip() for line in f if line.strip()]


def decode(out, manifest, which):
    """``{field name: [value per vector]}`` of ``inputs.hex`` or ``expected.hex``, from the
    manifest's offsets and widths (bit 0 the least significant bit of the word)."""
    layout = manifest[which]
    lines = words(os.path.join(out, layout["file"]))
    cols = {f["name"]: [] for f in layout["fields"]}
    for line in lines:
        assert len(line) == layout["hex_digits"]
        w = int(line, 16)
        for f in layout["fields"]:
            cols[f["name"]].append((w >> f["offset"]) & ((1 << f["width"]) - 1))
    return cols


def round_half_up(num, den):
    """⌊num/den + ½⌋ of the exact quotient (non-negative integers)."""
    return (2 * num + den) // (2 * den)


def test_manifest_states_the_request_and_the_layout(tmp_path):
    out = tmp_path / "comp"
    m = volsample.vectors("composite-front-to-back", str(out), count=200, seed=7)
    assert (m["kernel"], m["count"], m["seed"], m["frac_bits"]) == (
        "composite-front-to-back", 200, 7, 8)
    assert m["one"] == ONE
    with open(out / "manifest.json", encoding="utf-8") as f:
        import json
        assert json.load(f) == m  # the dict is the file
    for which in ("inputs", "expected"):
        layout = m[which]
        assert len(words(out / layout["file"])) == 200
        # Fields packed from bit 0 upwards without gaps, filling the word.
        end = 0
        for f in layout["fields"]:
            assert f["offset"] == end
            end += f["width"]
        assert end == layout["word_bits"] and layout["hex_digits"] == -(-end // 4)
    names = [f["name"] for f in m["inputs"]["fields"]]
    assert names == [p + c for p in ("acc_", "s_") for c in "rgba"]


def test_composite_outputs_follow_the_integer_rule(tmp_path):
    # One front-to-back step, recomputed: x = acc_x + ⌊(ONE − acc_a)·s_x/ONE + ½⌋.
    out = tmp_path / "comp"
    m = volsample.vectors("composite-front-to-back", str(out), count=300, seed=3)
    i, e = decode(out, m, "inputs"), decode(out, m, "expected")
    for k in range(300):
        t = ONE - i["acc_a"][k]
        for c in "rgba":
            want = i["acc_" + c][k] + round_half_up(t * i["s_" + c][k], ONE)
            assert e[c][k] == want, (k, c)
    # The sample is U8.8 associated: C̃ ≤ α ≤ ONE, in and out.
    for cols, pre in ((i, "acc_"), (i, "s_"), (e, "")):
        for k in range(300):
            assert max(cols[pre + c][k] for c in "rgb") <= cols[pre + "a"][k] <= ONE


def splitmix64(seed):
    state = seed
    mask = (1 << 64) - 1
    while True:
        state = (state + 0x9E3779B97F4A7C15) & mask
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
        yield z ^ (z >> 31)


def random_u88(draws):
    """A U8.8 sample as the module docs of ``volsample_host::vectors`` define the draws."""
    w = next(draws)
    k = w >> 61
    a = 0 if k == 0 else ONE if k == 1 else 256 * ((w >> 8) & 255) if k == 2 \
        else (w & 0xFFFFFFFF) % (ONE + 1)
    return [next(draws) % (a + 1) for _ in range(3)] + [a]


def test_the_seed_drives_splitmix64_after_the_corner_cases(tmp_path):
    out = tmp_path / "comp"
    m = volsample.vectors("composite-front-to-back", str(out), count=80, seed=12345)
    corners = m["corner_cases"]
    assert 0 < corners < 80
    i = decode(out, m, "inputs")
    draws = splitmix64(12345)
    for k in range(corners, 80):
        acc, s = random_u88(draws), random_u88(draws)
        assert [i["acc_" + c][k] for c in "rgba"] == acc, k
        assert [i["s_" + c][k] for c in "rgba"] == s, k


@pytest.mark.parametrize("filt", ["nearest", "trilinear"])
@pytest.mark.parametrize("frac_bits", [4, 8, 12])
def test_opacity_weighted_sampling_follows_the_integer_rule(tmp_path, filt, frac_bits):
    # Eight straight u8 voxels of a 2×2×2 volume (voxel i at (i&1, (i>>1)&1, i>>2)) sampled
    # at fractions (fx, fy, fz) of F bits: weights, then α = ⌊256·Σwα/2^s + ½⌋ and
    # C̃ = ⌊256·Σwα·C/(255·2^s) + ½⌋, recomputed with exact integers.
    out = tmp_path / filt
    n = 150
    m = volsample.vectors(f"opacity-weighted-{filt}", str(out), count=n, seed=9,
                          frac_bits=frac_bits)
    assert m["frac_bits"] == frac_bits
    i, e = decode(out, m, "inputs"), decode(out, m, "expected")
    u = 1 << frac_bits
    for k in range(n):
        f = [i["fx"][k], i["fy"][k], i["fz"][k]]
        assert all(0 <= x < u for x in f)
        if filt == "nearest":
            hi = [x >= u // 2 for x in f]
            w = [int(all(bool((j >> ax) & 1) == hi[ax] for ax in range(3))) for j in range(8)]
            s = 0
        else:
            w = []
            for j in range(8):
                p = 1
                for ax in range(3):
                    p *= f[ax] if (j >> ax) & 1 else u - f[ax]
                w.append(p)
            s = 3 * frac_bits
        assert sum(w) == 1 << s
        sa = sum(w[j] * i[f"v{j}_a"][k] for j in range(8))
        assert e["a"][k] == round_half_up(256 * sa, 1 << s), k
        for c in "rgb":
            sc = sum(w[j] * i[f"v{j}_a"][k] * i[f"v{j}_{c}"][k] for j in range(8))
            assert e[c][k] == round_half_up(256 * sc, 255 << s), (k, c)


def test_same_seed_same_bytes_other_seed_other_vectors(tmp_path):
    a, b, c = (tmp_path / x for x in "abc")
    kw = dict(count=120, frac_bits=6)
    ma = volsample.vectors("separate-trilinear", str(a), seed=5, **kw)
    mb = volsample.vectors("separate-trilinear", str(b), seed=5, **kw)
    mc = volsample.vectors("separate-trilinear", str(c), seed=6, **kw)
    assert ma == mb
    assert sorted(os.listdir(a)) == sorted(os.listdir(b)) == ["expected.hex", "inputs.hex",
                                                              "manifest.json"]
    for f in os.listdir(a):
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    corners = ma["corner_cases"]
    ia, ic = words(a / "inputs.hex"), words(c / "inputs.hex")
    assert ia[:corners] == ic[:corners]  # the corner cases draw nothing
    assert sum(x != y for x, y in zip(ia[corners:], ic[corners:])) > (120 - corners) // 2
    assert {k for k in ma if ma[k] != mc[k]} == {"seed"}


def test_tables_and_ray_march_counts(tmp_path):
    ext = tmp_path / "ext"
    m = volsample.vectors("extinction-weighted-trilinear", str(ext), count=40, table_size=17)
    assert m["table_size"] == 17
    for t in m["tables"]:
        lines = words(ext / t["file"])
        assert len(lines) == t["entries"] and all(len(x) == t["hex_digits"] for x in lines)
    ray = tmp_path / "ray"
    m = volsample.vectors("ray-march-opacity-weighted-nearest", str(ray), count=60, seed=2)
    names = [f["name"] for f in m["expected"]["fields"]]
    assert names[:4] == ["r", "g", "b", "a"] and len(names) == 5
    e = decode(ray, m, "expected")
    i = decode(ray, m, "inputs")
    assert names[4] == "samples"
    # A ray composites at most its n samples; one that stopped early had reached a_stop, and
    # compositing over the background only adds opacity.
    stopped = 0
    for k in range(60):
        assert e["samples"][k] <= i["n"][k] and e["a"][k] <= ONE
        if e["samples"][k] < i["n"][k]:
            stopped += 1
            assert e["a"][k] >= i["a_stop"][k], k
    assert stopped > 0  # the check above ran


def test_read_vectors_gives_the_decoded_words(tmp_path):
    out = tmp_path / "ray"
    m = volsample.vectors("ray-march-opacity-weighted-trilinear", str(out), count=30, seed=4)
    got = volsample.read_vectors(str(out))
    assert got["manifest"] == m
    assert got["input_fields"] == [f["name"] for f in m["inputs"]["fields"]]
    assert got["expected_fields"] == [f["name"] for f in m["expected"]["fields"]]
    assert got["inputs"].shape == (30, len(got["input_fields"]))
    assert got["expected"].shape == (30, 5)
    for which, fields in (("inputs", "input_fields"), ("expected", "expected_fields")):
        cols = decode(out, m, which)
        for j, name in enumerate(got[fields]):
            assert [int(x) for x in got[which][:, j]] == cols[name], name


def test_bad_requests_raise_value_error_naming_the_problem(tmp_path):
    out = str(tmp_path / "x")
    with pytest.raises(ValueError, match="unknown kernel 'mean'.*composite-front-to-back"):
        volsample.vectors("mean", out)
    with pytest.raises(ValueError, match="count must be at least 1"):
        volsample.vectors("composite-front-to-back", out, count=0)
    with pytest.raises(ValueError, match="frac-bits 13 is outside 4..=12"):
        volsample.vectors("opacity-weighted-nearest", out, count=1, frac_bits=13)
    with pytest.raises(ValueError, match="table-size applies only to the extinction"):
        volsample.vectors("composite-front-to-back", out, count=1, table_size=17)
    with pytest.raises(ValueError, match="table-size 300 is not supported"):
        volsample.vectors("extinction-weighted-nearest", out, count=1, table_size=300)
    assert not os.path.exists(out)  # nothing written for a rejected request
    with pytest.raises(OSError, match="manifest.json"):
        volsample.read_vectors(str(tmp_path))
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(OSError, match="cannot write"):
        volsample.vectors("composite-front-to-back", str(blocker / "sub"), count=1)


def test_a_damaged_file_is_a_value_error(tmp_path):
    out = tmp_path / "comp"
    volsample.vectors("composite-front-to-back", str(out), count=10)
    lines = words(out / "inputs.hex")
    (out / "inputs.hex").write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(ValueError, match="9 words, the manifest says 10"):
        volsample.read_vectors(str(out))


def test_the_gil_is_released(tmp_path):
    # Long enough to tell on any machine: the count doubles until a generation takes 0.2 s
    # (4000 vectors once took 0.041 s, too short for the check below).
    count = 4000
    for k in range(8):
        took, ticks = gil_free_ticks(lambda: volsample.vectors(
            "downsample-opacity-based", str(tmp_path / f"ds{k}"), count=count))
        if took > 0.2:
            break
        count *= 2
    assert took > 0.05, "generation too short to tell"
    assert ticks >= 5, (ticks, took, count)


CLI = os.environ.get("VOLSAMPLE_CLI") or shutil.which("volsample")


@pytest.mark.skipif(CLI is None, reason="no volsample CLI (set VOLSAMPLE_CLI to its path)")
def test_byte_identical_to_the_cli(tmp_path):
    py, cli = tmp_path / "py", tmp_path / "cli"
    volsample.vectors("extinction-weighted-nearest", str(py), count=500, seed=77, frac_bits=5,
                      table_size=65)
    subprocess.run([CLI, "vectors", "--kernel", "extinction-weighted-nearest", "--count", "500",
                    "--seed", "77", "--frac-bits", "5", "--table-size", "65", "--out", str(cli)],
                   check=True, capture_output=True)
    assert sorted(os.listdir(py)) == sorted(os.listdir(cli))
    for f in os.listdir(py):
        assert (py / f).read_bytes() == (cli / f).read_bytes(), f
