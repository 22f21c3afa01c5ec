"""Writes the format fixtures of host-tests/tests/load_formats.rs and, for each, a JSON file of
what a correct loader must return, computed here with numpy / nibabel / pynrrd / tifffile and
never with the Rust loader:

    {"file": ..., "reader": "nrrd" | "nifti" | "tiff" | "raw", "dims": [X, Y, Z],
     "type": "u8" | "i8" | "u16" | "i16" | "u32" | "i32" | "f32" | "f64",
     "values": [...],            # x fastest, then y, then z
     "affine": [[4 numbers] x 4],  # index (i, j, k, 1) -> world, RAS+ millimetres
     "source": "sform" | "qform" | "pixdim" | "nrrd-space" | "nrrd-spacings" | "identity",
     "rel_tol": 0.0,             # relative tolerance of the values (0: exact)
     "raw": {"type": ..., "big_endian": ...}}    # raw files only
or, for files that must be refused, {"file": ..., "reader": ..., "error": "substring"}.

Run from anywhere (the files land beside this script):
    python3 -m venv /tmp/v && /tmp/v/bin/pip install numpy pynrrd nibabel tifffile
    /tmp/v/bin/python host-tests/tests/data/formats/make_fixtures.py
Tested with numpy 2.4.6, pynrrd 1.1.3, nibabel 5.4.2, tifffile 2026.3.3.
The DICOM series (dicom/) come from make_dicom_fixtures.py beside this script (pydicom).
"""

import json
import math
import os

import nibabel as nib
import nrrd
import numpy as np
import tifffile

HERE = os.path.dirname(os.path.abspath(__file__))
X, Y, Z = 5, 4, 3

# Distinct values: index v = x + 5y + 20z, mapped into each type's range (negative values for
# the signed types, values past 2^31 for uint32, non-f32 values for float64).
V = np.arange(X * Y * Z, dtype=np.float64).reshape((Z, Y, X)).transpose(2, 1, 0)  # [x, y, z]
assert V[1, 0, 0] == 1 and V[0, 1, 0] == 5 and V[0, 0, 1] == 20
TYPES = {
    "u8": (np.uint8, V * 4 + 3),
    "i8": (np.int8, V * 2 - 60),
    "u16": (np.uint16, V * 1000 + 7),
    "i16": (np.int16, V * 37 - 1024),
    "u32": (np.uint32, V * 70_000_000 + 1),
    "i32": (np.int32, V * -30_000_000 + 900_000_000),
    "f32": (np.float32, V * 0.25 - 3.5),
    "f64": (np.float64, (V - 30) / 7),
}


def arr(ty, order=None):
    """The (X, Y, Z) array of `ty`, optionally in another byte order ('>' or '<')."""
    dt, vals = TYPES[ty]
    a = vals.astype(dt)
    assert np.array_equal(a.astype(np.float64), vals), ty  # no value was changed by the cast
    if order:
        a = a.astype(np.dtype(dt).newbyteorder(order))
    return a


def flat(a):
    """Values x fastest, as plain Python numbers."""
    return [v.item() for v in np.asarray(a).flatten(order="F")]


def write_json(name, reader, a, ty, affine, source, rel_tol=0.0, **extra):
    d = {
        "file": name,
        "reader": reader,
        "dims": list(a.shape),
        "type": ty,
        "values": flat(a),
        "affine": np.asarray(affine, dtype=np.float64).tolist(),
        "source": source,
        "rel_tol": rel_tol,
    }
    d.update(extra)
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        json.dump(d, f)


def write_error(name, reader, error):
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        json.dump({"file": name, "reader": reader, "error": error}, f)


def p(name):
    return os.path.join(HERE, name)


# An LPS-ish affine: x and y flipped, a 20 degree turn about z, anisotropic voxels, an origin.
t = math.radians(20)
ROT = np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])
LPSISH = np.eye(4)
LPSISH[:3, :3] = np.diag([-1, -1, 1]) @ ROT @ np.diag([0.8, 1.2, 2.5])
LPSISH[:3, 3] = [12.5, -30.25, 7.0]
SHEAR = np.array([[0.9, 0.1, 0.0, -4.0], [0.0, -1.1, 0.2, 5.5], [0.05, 0.0, 3.0, -6.25], [0, 0, 0, 1]])

# ---------------------------------------------------------------- NIfTI (nibabel)


def nifti(name, ty, cls=nib.Nifti1Image, big=False, scale=None, codes=None, affine=LPSISH):
    a = arr(ty)
    hdr = cls.header_class(endianness=">" if big else "<")
    hdr.set_data_dtype(a.dtype)
    img = cls(a, affine, header=hdr)
    h = img.header
    if codes == "qform":  # qform only
        h.set_sform(None, code=0)
        h.set_qform(affine, code=1)
    elif codes == "both":  # a sheared sform (code 2) and a different qform (code 1)
        h.set_sform(SHEAR, code=2)
        h.set_qform(LPSISH, code=1)
    elif codes == "none":
        h.set_sform(None, code=0)
        h.set_qform(None, code=0)
        h.set_zooms((0.8, 1.2, 2.5))
    if scale:
        h.set_slope_inter(*scale)
    img.to_filename(p(name))
    back = nib.load(p(name))
    hb = back.header
    assert (hb.endianness == ">") == big
    data = np.asanyarray(back.dataobj)  # scaled by nibabel when the header says so
    if scale:
        data = back.get_fdata()  # float64
        out_ty, rel = ("f64" if ty in ("i32", "u32", "f64") else "f32"), 1e-6
    else:
        assert data.dtype.newbyteorder("=") == np.dtype(TYPES[ty][0]), (name, data.dtype)
        out_ty, rel = ty, 0.0
    sc, qc = int(hb["sform_code"]), int(hb["qform_code"])
    if sc > 0:
        aff, src = hb.get_sform(), "sform"
    elif qc > 0:
        aff, src = hb.get_qform(), "qform"
    else:
        # NIfTI "method 1": pixdim on the diagonal, origin 0 (nibabel's img.affine differs).
        aff, src = np.diag(list(hb.get_zooms()[:3]) + [1.0]), "pixdim"
    if src != "pixdim":
        assert np.allclose(aff, back.affine)
    if name == "nifti1_i16_qform_flip.nii":
        assert hb["pixdim"][0] == -1 and np.allclose(aff, affine)
    write_json(name, "nifti", data, out_ty, aff, src, rel)


nifti("nifti1_u8.nii", "u8")
nifti("nifti1_i8.nii", "i8")
nifti("nifti1_i16_scaled.nii.gz", "i16", scale=(0.5, -1024.0))
nifti("nifti1_u16_be.nii", "u16", big=True)
nifti("nifti1_i32_qform.nii", "i32", codes="qform")
nifti("nifti1_u32_both.nii", "u32", codes="both")
nifti("nifti1_f32_pixdim.nii", "f32", codes="none")
# One flip (a negative determinant): the qform needs qfac = pixdim[0] = -1.
FLIP = LPSISH.copy()
FLIP[:3, :3] = np.diag([1, -1, 1]) @ LPSISH[:3, :3]
nifti("nifti1_i16_qform_flip.nii", "i16", codes="qform", affine=FLIP)
nifti("nifti1_f64.nii.gz", "f64")
nifti("nifti2_i16.nii", "i16", cls=nib.Nifti2Image)
nifti("nifti2_u16_be_qform.nii", "u16", cls=nib.Nifti2Image, big=True, codes="qform")
nifti("nifti2_f64.nii.gz", "f64", cls=nib.Nifti2Image, codes="both")

# ---------------------------------------------------------------- NRRD (pynrrd)


def nrrd_file(name, ty, order=None, **header):
    a = arr(ty, order)
    nrrd.write(p(name), a, header, index_order="F")
    data, hb = nrrd.read(p(name), index_order="F")
    assert np.array_equal(data, a)
    sizes = list(hb["sizes"])
    keep = [k for k in range(len(sizes)) if not (len(sizes) == 4 and sizes[k] == 1)]
    if "space directions" in hb:
        dirs = np.asarray(hb["space directions"], dtype=np.float64)
        aff = np.eye(4)
        aff[:3, :3] = dirs[keep].T  # each axis's vector is a column
        aff[:3, 3] = hb.get("space origin", np.zeros(3))
        flip = {"left-posterior-superior": [-1, -1, 1], "left-anterior-superior": [-1, 1, 1]}
        aff[:3] = np.diag(flip.get(hb.get("space"), [1, 1, 1])) @ aff[:3]
        src = "nrrd-space"
    elif "spacings" in hb:
        aff, src = np.diag([hb["spacings"][k] for k in keep] + [1.0]), "nrrd-spacings"
    else:
        aff, src = np.eye(4), "identity"
    write_json(name, "nrrd", data.reshape([sizes[k] for k in keep], order="F"), ty, aff, src)


DIRS = LPSISH[:3, :3].T  # rows: the world vector of one step along each axis
nrrd_file("nrrd_u8_raw.nrrd", "u8", encoding="raw", space="right-anterior-superior",
          **{"space directions": np.diag([0.5, 0.5, 1.5]), "space origin": np.array([1.0, 2.0, 3.0])})
nrrd_file("nrrd_i16_gzip.nrrd", "i16", space="left-posterior-superior",  # pynrrd's default gzip
          **{"space directions": DIRS, "space origin": np.array([-10.0, 20.5, 3.25])})
nrrd_file("nrrd_u16_be.nrrd", "u16", order=">", encoding="raw")
nrrd_file("nrrd_i8_ascii.nrrd", "i8", encoding="ascii", spacings=[0.5, 0.75, 2.0])
nrrd_file("nrrd_u32_bzip2.nrrd", "u32", encoding="bzip2", space="left-anterior-superior",
          **{"space directions": DIRS, "space origin": np.array([0.0, 0.0, 0.0])})
nrrd_file("nrrd_f32_detached.nhdr", "f32", encoding="raw", spacings=[0.25, 0.5, 4.0])
nrrd_file("nrrd_f64_detached_gz.nhdr", "f64", order=">", encoding="gzip")
# A leading axis of size 1 (one channel): pynrrd writes 'none' for its space direction.
a4 = arr("i32").reshape((1, X, Y, Z), order="F")
nrrd.write(p("nrrd_i32_4d.nrrd"), a4, {"space": "left-posterior-superior",
                                       "space directions": np.vstack([[np.nan] * 3, DIRS]),
                                       "kinds": ["list", "domain", "domain", "domain"]},
           index_order="F")
_, h4 = nrrd.read(p("nrrd_i32_4d.nrrd"), index_order="F")
aff = np.eye(4)
aff[:3, :3] = np.asarray(h4["space directions"][1:], dtype=np.float64).T
aff[:3] = np.diag([-1, -1, 1]) @ aff[:3]
write_json("nrrd_i32_4d.nrrd", "nrrd", arr("i32"), "i32", aff, "nrrd-space")

# ---------------------------------------------------------------- raw (numpy tofile)


def raw_file(name, ty, order):
    a = arr(ty, order)
    a.flatten(order="F").tofile(p(name))
    write_json(name, "raw", a, ty, np.eye(4), "identity",
               raw={"type": ty, "big_endian": order == ">"})


raw_file("raw_i16_be.raw", "i16", ">")
raw_file("raw_f64_le.raw", "f64", "<")
raw_file("raw_u32_be.raw", "u32", ">")

# ---------------------------------------------------------------- TIFF stacks (tifffile)


def tiff_file(name, ty, order=None, **kw):
    a = arr(ty, order)
    tifffile.imwrite(p(name), a.transpose(2, 1, 0), photometric="minisblack", **kw)  # (Z, Y, X)
    back = tifffile.imread(p(name))
    assert back.shape == (Z, Y, X) and np.array_equal(back, a.transpose(2, 1, 0))
    with tifffile.TiffFile(p(name)) as tf:
        assert len(tf.pages) == Z  # one page per slice
    write_json(name, "tiff", back.transpose(2, 1, 0), ty, np.eye(4), "identity")


tiff_file("tiff_u8.tif", "u8")
tiff_file("tiff_u16_deflate.tif", "u16", compression="zlib")
tiff_file("tiff_i16_be.tif", "i16", byteorder=">")
tiff_file("tiff_f32.tif", "f32")
tiff_file("tiff_i32.tif", "i32")
tiff_file("tiff_f64.tif", "f64")

# Files to refuse.
with tifffile.TiffWriter(p("tiff_bad_sizes.tif")) as tw:
    tw.write(np.zeros((4, 5), np.uint8), photometric="minisblack")
    tw.write(np.zeros((4, 6), np.uint8), photometric="minisblack")
write_error("tiff_bad_sizes.tif", "tiff", "page 2 is 6×4 but page 1 is 5×4")
tifffile.imwrite(p("tiff_rgb.tif"), np.zeros((2, 4, 5, 3), np.uint8), photometric="rgb")
write_error("tiff_rgb.tif", "tiff", "grayscale")
