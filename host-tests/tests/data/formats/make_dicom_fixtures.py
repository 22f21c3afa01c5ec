"""Writes the DICOM series fixtures of host-tests/tests/load_dicom.rs: one folder per series
under dicom/, written by pydicom from numpy arrays, and beside each folder a JSON file of what
a correct loader must return, computed here and never with the Rust loader:

    {"dir": ..., "dims": [X, Y, Z],          # columns, rows, slices
     "type": "u8" | "i16" | "u16" | "i32" | "f32",
     "values": [...],                        # x (column) fastest, then y (row), then z (slice)
     "affine": [[4 numbers] x 4],            # index (i, j, k, 1) -> world, RAS+ millimetres
     "source": "dicom-patient", "rel_tol": 0.0}
or, for a folder that must be refused, {"dir": ..., "error": "substring", "names": "file"}
("names", optional: a file the error must name).

Each series is designed from its RAS+ affine: the script derives the DICOM attributes
(ImagePositionPatient, ImageOrientationPatient, PixelSpacing, all in LPS) from that affine, so
the JSON affine is the design, not a recomputation of the loader's formula. File names are
random, so that name order is not slice order. pydicom reads every file back and its
pixel_array is checked against the design.

Separate from make_fixtures.py so that regenerating these does not need (or rewrite the files
of) pynrrd, nibabel and tifffile. Run from anywhere (the files land in dicom/ beside this
script):
    python3 -m venv /tmp/v && /tmp/v/bin/pip install numpy pydicom
    /tmp/v/bin/python host-tests/tests/data/formats/make_dicom_fixtures.py
Tested with numpy 2.4.6, pydicom 3.0.2.
"""

import json
import os
import shutil

import numpy as np
import pydicom
from pydicom.dataset import Dataset, FileMetaDataset
from pydicom.encaps import encapsulate
from pydicom.uid import (
    CTImageStorage,
    DeflatedExplicitVRLittleEndian,
    ExplicitVRBigEndian,
    ExplicitVRLittleEndian,
    ImplicitVRLittleEndian,
    JPEGBaseline8Bit,
    generate_uid,
)

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dicom")
RNG = np.random.default_rng(20260501)
LPS = np.diag([-1.0, -1.0, 1.0, 1.0])  # RAS <-> LPS (its own inverse)


def uid(*parts):
    return generate_uid(entropy_srcs=["volsample"] + [str(p) for p in parts])


def rotation(axis, degrees):
    """A rotation matrix about `axis` (Rodrigues)."""
    a = np.asarray(axis, np.float64)
    a /= np.linalg.norm(a)
    t = np.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * k @ k


def design(rot, spacing, origin):
    """RAS+ affine with direction columns `rot` scaled by `spacing` = (col, row, slice) mm."""
    a = np.eye(4)
    a[:3, :3] = rot @ np.diag(spacing)
    a[:3, 3] = origin
    return a


def ds_str(x):
    """A DS value of at most 16 characters."""
    s = f"{x:.10g}"
    assert len(s) <= 16, s
    return s


def slice_dataset(name, series, k, affine, image, ts, bits, signed, **extra):
    """The dataset of slice `k` of a series with RAS+ `affine`; `image` is (rows, cols)."""
    lps = LPS @ affine
    r = lps[:3, 0] / np.linalg.norm(lps[:3, 0])
    c = lps[:3, 1] / np.linalg.norm(lps[:3, 1])
    pos = lps @ np.array([0.0, 0.0, k, 1.0])
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CTImageStorage
    meta.MediaStorageSOPInstanceUID = uid(name, series, k)
    meta.TransferSyntaxUID = ts
    ds = Dataset()
    ds.file_meta = meta
    ds.SOPClassUID = CTImageStorage
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.Modality = "OT"
    ds.StudyInstanceUID = uid(name, "study")
    ds.SeriesInstanceUID = series
    ds.InstanceNumber = k + 1
    ds.ImagePositionPatient = [ds_str(v) for v in pos[:3]]
    ds.ImageOrientationPatient = [ds_str(v) for v in np.concatenate([r, c])]
    ds.PixelSpacing = [ds_str(np.linalg.norm(lps[:3, 1])), ds_str(np.linalg.norm(lps[:3, 0]))]
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.Rows, ds.Columns = image.shape
    ds.BitsAllocated = bits
    ds.BitsStored = extra.pop("BitsStored", bits)
    ds.HighBit = ds.BitsStored - 1
    ds.PixelRepresentation = 1 if signed else 0
    for key, v in extra.items():
        setattr(ds, key, v)
    big = ts == ExplicitVRBigEndian
    dt = np.dtype(f"{'i' if signed else 'u'}{bits // 8}").newbyteorder(">" if big else "<")
    raw = image.astype(dt).tobytes()
    if ts == JPEGBaseline8Bit:
        ds.PixelData = encapsulate([raw])  # not real JPEG: the loader must refuse it unread
        ds["PixelData"].VR = "OB"
    else:
        ds.PixelData = raw + (b"\0" if len(raw) % 2 else b"")
        ds["PixelData"].VR = "OB" if bits == 8 else "OW"
    return ds


def save(ds, path):
    ts = ds.file_meta.TransferSyntaxUID
    if ts == ExplicitVRBigEndian:
        # pydicom 3 writes big-endian data sets only when asked explicitly.
        ds.save_as(path, enforce_file_format=True, implicit_vr=False, little_endian=False)
    else:
        ds.save_as(path, enforce_file_format=True)


def names(n):
    """`n` random file names whose sorted order is not 0, 1, 2, ..."""
    while True:
        out = [f"IM{RNG.integers(16**6):06X}.dcm" for _ in range(n)]
        if len(set(out)) == n and (n < 2 or sorted(out) != out):
            return out


def write_series(name, affine, volume, ts, bits, signed, stored=None, rescale=(1, 0),
                 extra_files=True, per_slice=None, **extra):
    """Writes volume[x, y, z] as slices; returns the folder. `stored` is the raw stored array
    (defaults to `volume`); `per_slice(k)` gives extra attributes of slice k. Returns the
    folder, the series UID and the file names of slices 0, 1, ..."""
    d = os.path.join(HERE, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    stored = volume if stored is None else stored
    # Slices are sorted along the normal (row direction x column direction), so the design's
    # slice axis must point that way for the JSON's index order to be the loader's.
    lps = LPS @ affine
    assert np.dot(np.cross(lps[:3, 0], lps[:3, 1]), lps[:3, 2]) > 0, name
    series = uid(name, "series")
    X, Y, Z = volume.shape
    files = names(Z)
    for k in range(Z):
        kw = dict(extra)
        if rescale != (1, 0):
            kw["RescaleSlope"] = ds_str(rescale[0])
            kw["RescaleIntercept"] = ds_str(rescale[1])
        if per_slice:
            kw.update(per_slice(k))
        image = stored[:, :, k].T  # (rows = y, cols = x)
        ds = slice_dataset(name, series, k, affine, image, ts, bits, signed, **kw)
        path = os.path.join(d, files[k])
        save(ds, path)
        back = pydicom.dcmread(path)
        assert back.file_meta.TransferSyntaxUID == ts
        if ts != JPEGBaseline8Bit and not name.startswith("err_"):
            # pydicom masks the stored values to BitsStored, as the loader must.
            assert np.array_equal(back.pixel_array, volume[:, :, k].T), (name, k)
    return d, series, files


def write_json(name, volume, ty, affine, rel_tol=0.0):
    X, Y, Z = volume.shape
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        json.dump({"dir": name, "dims": [X, Y, Z], "type": ty,
                   "values": [v.item() for v in volume.flatten(order="F")],
                   "affine": affine.tolist(), "source": "dicom-patient", "rel_tol": rel_tol}, f)
        f.write("\n")


def write_error(name, error, names=None):
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        e = {"dir": name, "error": error}
        if names:
            e["names"] = names
        json.dump(e, f)
        f.write("\n")


shutil.rmtree(HERE, ignore_errors=True)
os.makedirs(HERE)

# ---------------------------------------------------------------- series to load

# CT: 5 slices of 6x4, int16 with RescaleIntercept -1024 (Hounsfield units), oblique, 2.5 mm
# gaps; a text file and a DICOMDIR in the folder are skipped.
X, Y, Z = 6, 4, 5
stored = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 53 - 900).astype(np.int16)
aff = design(rotation([1, 2, 3], 25), [0.9, 0.7, 2.5], [-40.5, 12.25, 87.0])
d, _, _ = write_series("ct_i16_oblique", aff, stored + 0, ExplicitVRLittleEndian, 16, True,
                    rescale=(1, -1024))
with open(os.path.join(d, "NOTES.txt"), "w") as f:
    f.write("not a DICOM file: skipped\n")
meta = FileMetaDataset()
meta.MediaStorageSOPClassUID = "1.2.840.10008.1.3.10"  # Media Storage Directory Storage
meta.MediaStorageSOPInstanceUID = uid("dicomdir")
meta.TransferSyntaxUID = ExplicitVRLittleEndian
dd = Dataset()
dd.file_meta = meta
dd.FileSetID = "VOLSAMPLE"
dd.save_as(os.path.join(d, "DICOMDIR"), enforce_file_format=True)
write_json("ct_i16_oblique", stored.astype(np.int64) - 1024, "i16", aff)

# MR: 4 slices of 5x3, uint16 with 12 bits stored (the bits above hold junk the loader must
# mask off), axial LPS (RAS x and y flipped), Implicit VR Little Endian, no rescale.
X, Y, Z = 5, 3, 4
values = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 67 + 5).astype(np.uint16)
junk = (RNG.integers(0, 16, values.shape) << 12).astype(np.uint16)
aff = design(np.diag([-1.0, -1.0, 1.0]), [1.25, 1.5, 3.0], [100.0, 80.0, -20.0])
write_series("mr_u16_axial_implicit", aff, values, ImplicitVRLittleEndian, 16, False,
             stored=values | junk, BitsStored=12)
write_json("mr_u16_axial_implicit", values, "u16", aff)

# Sagittal, int16 big-endian (Explicit VR Big Endian) with slope 0.25 and intercept 10.5:
# float samples.
X, Y, Z = 4, 3, 3
stored = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 301 - 5000).astype(np.int16)
rot = np.array([[0.0, 0, -1], [1, 0, 0], [0, -1, 0]])  # columns: anterior, inferior, left
aff = design(rot, [0.5, 0.8, 1.2], [30.0, -10.0, 55.5])
write_series("sag_i16_be_scaled", aff, stored, ExplicitVRBigEndian, 16, True,
             rescale=(0.25, 10.5))
write_json("sag_i16_be_scaled", (stored * 0.25 + 10.5).astype(np.float32), "f32", aff)

# Coronal, uint8 with an odd pixel count (pixel data padded to even), 3 slices.
X, Y, Z = 5, 3, 3
values = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 5 + 7).astype(np.uint8)
rot = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # columns: right, inferior, anterior
aff = design(rot, [0.6, 0.6, 4.0], [-3.0, 20.0, 9.0])
write_series("cor_u8", aff, values, ExplicitVRLittleEndian, 8, False)
write_json("cor_u8", values, "u8", aff)

# 32-bit signed with a whole intercept past i16: i32 samples. 2 slices of 3x2.
X, Y, Z = 3, 2, 2
stored = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 250_000 - 1_000_000).astype(np.int32)
aff = design(np.eye(3), [1.0, 1.0, 1.0], [0.0, 0.0, 0.0])
write_series("i32_shifted", aff, stored, ExplicitVRLittleEndian, 32, True, rescale=(1, 7))
write_json("i32_shifted", stored.astype(np.int64) + 7, "i32", aff)

# ---------------------------------------------------------------- series to refuse

X, Y, Z = 3, 2, 3
vol = (np.arange(X * Y * Z).reshape((Z, Y, X)).transpose(2, 1, 0) * 11).astype(np.int16)
aff = design(np.eye(3), [1.0, 1.0, 2.0], [0.0, 0.0, 0.0])

# Two series in one folder (3 files and 1).
d, _, _ = write_series("err_two_series", aff, vol, ExplicitVRLittleEndian, 16, True)
d2, _, _ = write_series("err_two_series_b", aff, vol[:, :, :1], ExplicitVRLittleEndian, 16, True)
for f in os.listdir(d2):
    shutil.move(os.path.join(d2, f), os.path.join(d, "B" + f))
os.rmdir(d2)
write_error("err_two_series", "2 series in one folder")

# Uneven slice spacing: the last slice one millimetre too far.
_, _, files = write_series("err_uneven", aff, vol, ExplicitVRLittleEndian, 16, True,
                    per_slice=lambda k: {"ImagePositionPatient": ["0", "0", ds_str(2 * k + (k == 2))]})
write_error("err_uneven", "are 3.0000 mm apart along the slice normal, but the series' median gap "
            "is 2.0000 mm (uneven spacing or a missing slice)", names=files[2])

# A JPEG Baseline transfer syntax (encapsulated pixel data).
write_series("err_jpeg", aff, vol.astype(np.uint8), JPEGBaseline8Bit, 8, False)
write_error("err_jpeg", "JPEG Baseline (Process 1) (1.2.840.10008.1.2.4.50) is compressed")

# A deflated data set.
write_series("err_deflated", aff, vol, DeflatedExplicitVRLittleEndian, 16, True)
write_error("err_deflated", "(1.2.840.10008.1.2.1.99) is compressed")

# A header claiming 40 rows over pixel data for 2.
write_series("err_rows", aff, vol, ExplicitVRLittleEndian, 16, True,
             per_slice=lambda k: {"Rows": 40} if k == 2 else {})
write_error("err_rows", "pixel data hold 12 bytes, but 3×40 pixels of 16 bits need 240")

# Slices of two sizes in one series.
d, series, _ = write_series("err_sizes", aff, vol, ExplicitVRLittleEndian, 16, True)
odd = slice_dataset("err_sizes", series, 3, aff, np.zeros((3, 3), np.int16),
                    ExplicitVRLittleEndian, 16, True)
save(odd, os.path.join(d, "ZZ_ODD.dcm"))
write_error("err_sizes", "size 3×3 differs from 3×2", names="ZZ_ODD.dcm")

# Several frames in one file.
write_series("err_frames", aff, vol, ExplicitVRLittleEndian, 16, True,
             per_slice=lambda k: {"NumberOfFrames": 2} if k == 1 else {})
write_error("err_frames", "2 frames in one file")

total = sum(os.path.getsize(os.path.join(r, f)) for r, _, fs in os.walk(HERE) for f in fs)
print(f"wrote {HERE}: {total} bytes")
