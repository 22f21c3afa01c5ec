#!/usr/bin/env python3
"""Writes the seed corpora of the parser fuzz targets (fuzz/corpus/load_*) from the loaders'
test fixtures (host-tests/tests/data/formats), in the input layouts that
volsample_host::parser_checks decodes. Run from the repository root; `cargo fuzz cmin`
afterwards keeps the seeds that add coverage."""
import gzip, hashlib, json, os, struct

FIX = "host-tests/tests/data/formats"
TYPES = ["u8", "i8", "u16", "i16", "u32", "i32", "f32", "f64"]


def put(target, data):
    d = f"fuzz/corpus/{target}"
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, hashlib.sha1(data).hexdigest()), "wb") as f:
        f.write(data)


def fix(name):
    with open(os.path.join(FIX, name), "rb") as f:
        return f.read()


# load_raw: dims (3 x u16 LE), type selector, big-endian flag, no spacing / a spacing, bytes.
for name in ["raw_f64_le.raw", "raw_i16_be.raw", "raw_u32_be.raw"]:
    meta = json.loads(fix(name + ".json"))
    head = struct.pack("<3H", *meta["dims"]) + bytes(
        [TYPES.index(meta["raw"]["type"]), int(meta["raw"]["big_endian"])])
    put("load_raw", head + b"\0" + fix(name))
    put("load_raw", head + b"\1" + struct.pack("<3d", 0.5, 1.0, 2.0) + fix(name))
    put("load_raw", head + b"\0" + fix(name)[:-1])  # a byte short: refused
put("load_raw", struct.pack("<3H", 1, 1, 1) + bytes([6, 0, 0]) + struct.pack("<f", float("nan")))

# load_nrrd: mode 0 (attached), 1 (detached: u16 LE header length, header, data), 2 (written).
for name in sorted(os.listdir(FIX)):
    if name.endswith(".nrrd"):
        put("load_nrrd", b"\0" + fix(name))
    elif name.endswith(".nhdr"):
        lines = [l for l in fix(name).split(b"\n") if not l.startswith(b"data file:")]
        data_name = [l for l in fix(name).split(b"\n") if l.startswith(b"data file:")][0]
        header = b"\n".join(lines).rstrip(b"\n") + b"\ndata file: data.bin\n"
        put("load_nrrd", b"\1" + struct.pack("<H", len(header)) + header
            + fix(data_name.split(b":", 1)[1].strip().decode()))
for enc in range(5):
    for ty in range(8):
        put("load_nrrd", bytes([2, 3, 2, 1, ty, enc, ty % 2, enc % 2]) + bytes(range(17, 60, 3)))

# load_nifti: the plain files (the target gzips every input itself).
for name in sorted(os.listdir(FIX)):
    if name.endswith(".nii"):
        put("load_nifti", fix(name))
    elif name.endswith(".nii.gz"):
        put("load_nifti", gzip.decompress(fix(name)))
put("load_nifti", fix("nifti1_u8.nii")[:-1])  # a byte short: refused

# load_tiff: every TIFF fixture, the refused ones included.
for name in sorted(os.listdir(FIX)):
    if name.endswith(".tif"):
        put("load_tiff", fix(name))

# load_tf: text and JSON transfer functions.
put("load_tf", b"# s r g b a\n0 0 0 0 0\n80 0.8 0.5 0.4 0.05\n230 1 1 0.9 0.9\n")
put("load_tf", b'{"points": [[0, 0, 0, 0, 0], [0.5, 1, 0.5, 0.25, 0.5], [1, 1, 1, 1, 1]]}')
put("load_tf", b"[[-1000, 0, 0, 0, 0], [3000, 1, 1, 1, 1e-3]]")
put("load_tf", b"0 0 0 0 0\n0 1 1 1 1\n")  # not increasing: refused
