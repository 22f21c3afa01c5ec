"""Orientation peer of `volsample render`: one asymmetric object stored three ways (RAS, LPS
with x and y reversed, and with permuted axes), each an NRRD with its `space`, `space
directions` and `space origin`, rendered by volsample and by VTK's CPU ray caster given the
file's index-to-RAS matrix as the volume's user matrix (how 3D Slicer places a volume in
VTK). Both use the anterior view (eye anterior, superior up, the patient's right on the
image's left), post-classification with one transfer function, step 0.5 and the same
framing. Prints, per storage, how far volsample's image is from VTK's, and how far the
images would be with the storage read wrongly (the VTK image of the RAS file mirrored left to
right, and rendered from behind), so the numbers show they could fail.

The object (RAS, mm, voxel centres 0..n-1): a blue body (scalar 100) with two red nodules
(255), one right-anterior-superior, in front of the body, one left-posterior-inferior,
behind it; every edge a one-voxel linear ramp.

Usage: python vtk_orient.py VOLSAMPLE_BIN OUT_DIR [--n 64] [--size 256]
(`vtk_ct.sh` sets up the venv with vtk and numpy and the offscreen window; ORIENT=1 runs this.)
"""

import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vtk_ct  # noqa: E402  (sets the offscreen window before importing vtk)
import vtk  # noqa: E402
from vtk.util import numpy_support  # noqa: E402

TF = [
    (0.0, 0.0, 0.0, 0.0, 0.0),
    (50.0, 0.2, 0.4, 1.0, 0.0),
    (100.0, 0.2, 0.4, 1.0, 0.04),
    (180.0, 1.0, 0.3, 0.2, 0.1),
    (255.0, 1.0, 0.2, 0.1, 0.5),
]


def ras_object(n):
    """The object as an array indexed [z, y, x] (RAS voxel centres 0..n-1, spacing 1)."""
    c = (n - 1) / 2.0
    z, y, x = np.meshgrid(*(np.arange(n, dtype=np.float64),) * 3, indexing="ij")

    def ball(cx, cy, cz, r):
        d = np.sqrt((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2)
        return np.clip(r - d + 0.5, 0.0, 1.0)

    body = ball(c, c, c, 0.36 * n)
    front = ball(c + 0.2 * n, c + 0.2 * n, c + 0.2 * n, 0.12 * n)  # right, anterior, superior
    back = ball(c - 0.22 * n, c - 0.22 * n, c - 0.18 * n, 0.1 * n)  # left, posterior, inferior
    v = np.maximum(100.0 * body, 255.0 * np.maximum(front, back))
    return np.round(v).astype(np.uint8)


def storages(ras):
    """(name, stored array [k, j, i], space, index-to-space 3x3 (columns: directions), origin)."""
    n = ras.shape[0]
    eye = np.eye(3)
    lps = ras[:, ::-1, ::-1]  # index i runs to the left, j posterior: L = i - (n-1), P = j - (n-1)
    perm = np.ascontiguousarray(np.moveaxis(ras, (0, 1, 2), (2, 0, 1)))  # [k,j,i] = ras[i,k,j]
    d_perm = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])  # i->z, j->x, k->y
    return [
        ("ras", np.ascontiguousarray(ras), "right-anterior-superior", eye, np.zeros(3)),
        ("lps", np.ascontiguousarray(lps), "left-posterior-superior", eye,
         np.array([-(n - 1.0), -(n - 1.0), 0.0])),
        ("permuted", perm, "right-anterior-superior", d_perm, np.zeros(3)),
    ]


def write_nrrd(path, arr, space, dirs, origin):
    nk, nj, ni = arr.shape
    vec = lambda v: "(" + ",".join(f"{float(x):g}" for x in v) + ")"  # noqa: E731
    head = (
        "NRRD0004\ntype: uint8\ndimension: 3\n"
        f"space: {space}\nsizes: {ni} {nj} {nk}\n"
        f"space directions: {vec(dirs[:, 0])} {vec(dirs[:, 1])} {vec(dirs[:, 2])}\n"
        "kinds: domain domain domain\nencoding: raw\n"
        f"space origin: {vec(origin)}\n\n"
    )
    with open(path, "wb") as f:
        f.write(head.encode("ascii"))
        f.write(arr.tobytes())


def index_to_ras(space, dirs, origin):
    """4x4 matrix from (i, j, k, 1) to RAS."""
    m = np.eye(4)
    m[:3, :3] = dirs
    m[:3, 3] = origin
    if space.startswith("left-posterior"):
        m = np.diag([-1.0, -1.0, 1.0, 1.0]) @ m
    return m


def render_vtk(arr, m, n, size, png, azimuth=0.0):
    nk, nj, ni = arr.shape
    img = vtk.vtkImageData()
    img.SetDimensions(ni, nj, nk)
    img.SetSpacing(1.0, 1.0, 1.0)
    img.SetOrigin(0.0, 0.0, 0.0)
    a = numpy_support.numpy_to_vtk(arr.ravel(), deep=1)
    a.SetName("density")
    img.GetPointData().SetScalars(a)
    volume = vtk.vtkVolume()
    volume.SetMapper(vtk_ct.ray_cast_mapper(img, 0.5))
    volume.SetProperty(vtk_ct.volume_property(TF))
    um = vtk.vtkMatrix4x4()
    for r in range(4):
        for c in range(4):
            um.SetElement(r, c, float(m[r, c]))
    volume.SetUserMatrix(um)
    ren = vtk.vtkRenderer()
    ren.SetBackground(0.0, 0.0, 0.0)
    ren.AddVolume(volume)
    win = vtk_ct.offscreen_window(ren, size)
    cam = ren.GetActiveCamera()
    vtk_ct.anterior_camera(cam, [n, n, n], [1.0, 1.0, 1.0], size, size)
    if azimuth:
        cam.Azimuth(azimuth)
    win.Render()
    vtk_ct.write_png(win, png)


def mirror_png(src, dst):
    r = vtk.vtkPNGReader()
    r.SetFileName(src)
    f = vtk.vtkImageFlip()
    f.SetFilteredAxis(0)
    f.SetInputConnection(r.GetOutputPort())
    vtk_ct.write_png_of(f.GetOutputPort(), dst)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("volsample")
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=64)
    ap.add_argument("--size", type=int, default=256)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    tf = os.path.join(args.out, "orient.tf.txt")
    with open(tf, "w") as f:
        for p in TF:
            f.write(" ".join(f"{x:g}" for x in p) + "\n")
    ras = ras_object(args.n)
    print(f"vtk {vtk.vtkVersion.GetVTKVersion()}: {args.n}^3 asymmetric object, "
          f"{args.size}x{args.size}, anterior view, post-classified, step 0.5", flush=True)
    ras_vtk = None
    for name, arr, space, dirs, origin in storages(ras):
        nrrd = os.path.join(args.out, f"orient-{name}.nrrd")
        write_nrrd(nrrd, arr, space, dirs, origin)
        ours = os.path.join(args.out, f"volsample-{name}.png")
        subprocess.run([args.volsample, "render", "--nrrd", nrrd, "--tf", tf, "--modes",
                        "post-classified", "--size", str(args.size), "--a-stop", "1",
                        "--quiet", "--out", ours], check=True, stdout=subprocess.DEVNULL)
        theirs = os.path.join(args.out, f"vtk-{name}.png")
        render_vtk(arr, index_to_ras(space, dirs, origin), args.n, args.size, theirs)
        ras_vtk = ras_vtk or theirs
        print(f"{name:9} ({space}): " + vtk_ct.compare(ours, theirs), flush=True)
    mirrored = os.path.join(args.out, "vtk-ras-mirrored.png")
    mirror_png(ras_vtk, mirrored)
    behind = os.path.join(args.out, "vtk-ras-from-behind.png")
    render_vtk(ras, index_to_ras("right", np.eye(3), np.zeros(3)), args.n, args.size, behind,
               azimuth=180.0)
    ours = os.path.join(args.out, "volsample-ras.png")
    print("wrong    (mirrored):    " + vtk_ct.compare(ours, mirrored), flush=True)
    print("wrong    (from behind): " + vtk_ct.compare(ours, behind), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
