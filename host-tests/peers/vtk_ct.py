"""Peer of `volsample render` on the CT phantom: VTK's CPU ray caster on the same volume,
transfer function, camera, image size and step.

Reads the phantom's attached raw NRRD (`NRRD0004`, header lines up to a blank line, then the
voxels, x fastest) and its transfer function (`s r g b a` lines: straight colour and opacity
per unit length of one voxel), and renders them offscreen with vtkFixedPointVolumeRayCastMapper:
sample distance 0.5 (AutoAdjustSampleDistances off, image sample distance 1), trilinear
interpolation, shading off, scalar opacity unit distance 1 (so VTK corrects opacities for the
step as volsample does: a' = 1 - (1 - a)^(0.5 / 1)), orthographic anterior view (eye on +y
looking along -y, +z up, image right = -x) framing the box [-1/2, n - 1/2]^3 with volsample's
5 % margin, 512 x 512, black background.

For each thread count: sets vtkMultiThreader's global maximum and the mapper's NumberOfThreads,
renders a warm-up frame (VTK builds its min/max space-leaping volume and tables there), then
times N frames of `renWin.Render()` (wall clock) and prints the median; also prints the
mapper's own GetTimeToDraw() (the ray cast alone). Writes the last frame as a PNG.

Usage: python vtk_ct.py NRRD TF_TXT [--size 512] [--threads 1,2] [--frames 5]
                        [--out PREFIX] [--compare VOLSAMPLE_PNG]
Prints one line per thread count: `vtk threads=N median_ms=M ...` for vtk_ct.sh to read.
"""

import argparse
import os
import statistics
import sys
import time

import numpy as np

# Ask VTK for its EGL window when there is no X display (the PyPI wheel picks one at run
# time: X, then EGL, then OSMesa); vtk_ct.sh sets this too.
if not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import vtk  # noqa: E402
from vtk.util import numpy_support  # noqa: E402

FRAME_MARGIN = 1.05  # volsample's host-tests/src/view/mod.rs


def read_nrrd(path):
    """(array z,y,x of the voxels, sizes (x, y, z), spacings (x, y, z)) of an attached raw
    uint8/uint16/float NRRD."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"\n\n")
    if not data.startswith(b"NRRD") or end < 0:
        raise SystemExit(f"{path}: not an attached NRRD")
    fields = {}
    for line in data[:end].decode("ascii").splitlines()[1:]:
        if line.startswith("#") or ":" not in line:
            continue
        key, _, value = line.partition(":")
        fields[key.strip().lower()] = value.lstrip("=").strip()
    if fields.get("encoding") != "raw":
        raise SystemExit(f"{path}: encoding {fields.get('encoding')}, only raw is read here")
    types = {"uint8": np.uint8, "unsigned char": np.uint8, "uchar": np.uint8,
             "uint16": np.uint16, "unsigned short": np.uint16, "ushort": np.uint16,
             "float": np.float32}
    ty = types.get(fields.get("type", ""))
    if ty is None or int(fields.get("dimension", 0)) != 3:
        raise SystemExit(f"{path}: type {fields.get('type')} / dimension not handled")
    sizes = [int(v) for v in fields["sizes"].split()]
    spacings = [float(v) for v in fields.get("spacings", "1 1 1").split()]
    dtype = np.dtype(ty)
    if dtype.itemsize > 1:
        dtype = dtype.newbyteorder("<" if fields.get("endian", "little") == "little" else ">")
    count = sizes[0] * sizes[1] * sizes[2]
    vox = np.frombuffer(data, dtype=dtype, count=count, offset=end + 2)
    return vox.reshape(sizes[2], sizes[1], sizes[0]), sizes, spacings


def read_tf(path):
    points = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                s, r, g, b, a = (float(v) for v in line.split())
                points.append((s, r, g, b, a))
    if not points:
        raise SystemExit(f"{path}: no transfer function points")
    return points


def image_data(vox, sizes, spacings):
    img = vtk.vtkImageData()
    img.SetDimensions(*sizes)
    img.SetSpacing(*spacings)
    img.SetOrigin(0.0, 0.0, 0.0)
    arr = numpy_support.numpy_to_vtk(vox.ravel(), deep=1)
    arr.SetName("density")
    img.GetPointData().SetScalars(arr)
    return img


def volume_property(points):
    color = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    for s, r, g, b, a in points:
        color.AddRGBPoint(s, r, g, b)
        opacity.AddPoint(s, a)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(1.0)  # opacities hold per voxel length, as ours
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def anterior_camera(cam, sizes, spacings, width, height):
    """volsample's default view: orthographic, eye on +y looking along -y, +z up; the box of
    voxel centres extended by half a voxel, its projection times 1.05 filling the image."""
    lo = [-0.5 * s for s in spacings]
    hi = [(n - 0.5) * s for n, s in zip(sizes, spacings)]
    centre = [(n - 1) * 0.5 * s for n, s in zip(sizes, spacings)]
    half_w = max(abs(lo[0] - centre[0]), abs(hi[0] - centre[0]))  # image right = -x
    half_h = max(abs(lo[2] - centre[2]), abs(hi[2] - centre[2]))  # image up = +z
    aspect = width / height
    half_extent = max(half_w, half_h * aspect) * FRAME_MARGIN  # half the image width
    radius = 0.5 * float(np.linalg.norm(np.subtract(hi, lo)))
    cam.ParallelProjectionOn()
    cam.SetFocalPoint(*centre)
    cam.SetPosition(centre[0], centre[1] + 2.0 * radius, centre[2])
    cam.SetViewUp(0.0, 0.0, 1.0)
    cam.SetParallelScale(half_extent / aspect)  # VTK's parallel scale: half the height
    cam.SetClippingRange(radius * 0.5, radius * 3.5)
    return half_extent


def read_png(path):
    r = vtk.vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    a = numpy_support.vtk_to_numpy(img.GetPointData().GetScalars())
    a = a.reshape(h, w, -1)[::-1]  # VTK's rows run bottom-up
    return a[..., :3].astype(np.int16)


def compare(ours_path, vtk_path):
    ours, theirs = read_png(ours_path), read_png(vtk_path)
    if ours.shape[0] > theirs.shape[0]:
        ours = ours[ours.shape[0] - theirs.shape[0]:]  # volsample's label strip on top
    if ours.shape != theirs.shape:
        return f"compare: shapes differ {ours.shape} vs {theirs.shape}"
    d = np.abs(ours - theirs)
    lum = d.max(axis=2)
    return (f"compare vs {os.path.basename(ours_path)}: mean |diff| per channel "
            f"{d.mean(axis=(0, 1)).round(2).tolist()} of 255, max {int(d.max())}, "
            f"pixels off by >8: {100.0 * (lum > 8).mean():.2f} %, by >32: "
            f"{100.0 * (lum > 32).mean():.2f} %")


def ray_cast_mapper(img, step):
    """vtkFixedPointVolumeRayCastMapper on `img`: composite blend, sample distance `step` (no
    automatic adjustment), one ray per pixel."""
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(img)
    mapper.SetBlendModeToComposite()
    mapper.AutoAdjustSampleDistancesOff()
    mapper.LockSampleDistanceToInputSpacingOff()
    mapper.SetSampleDistance(step)
    mapper.SetImageSampleDistance(1.0)
    return mapper


def offscreen_window(ren, size):
    """An offscreen `size` x `size` window showing `ren`, no multisampling."""
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(size, size)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)
    return win


def write_png(win, png):
    """The window's last frame as an RGB PNG."""
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    write_png_of(grab.GetOutputPort(), png)


def write_png_of(port, png):
    """The image of a VTK pipeline's output `port` as a PNG."""
    w = vtk.vtkPNGWriter()
    w.SetFileName(png)
    w.SetInputConnection(port)
    w.Write()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("nrrd")
    ap.add_argument("tf")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--step", type=float, default=0.5)
    ap.add_argument("--out", default="vtk-ct", help="PNG prefix: PREFIX-tN.png")
    ap.add_argument("--compare", help="volsample's PNG of the same view")
    args = ap.parse_args()

    vox, sizes, spacings = read_nrrd(args.nrrd)
    img = image_data(vox, sizes, spacings)
    prop = volume_property(read_tf(args.tf))

    mapper = ray_cast_mapper(img, args.step)
    # No opaque geometry in the scene: skip reading back the depth buffer each frame.
    mapper.IntermixIntersectingGeometryOff()

    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtk.vtkRenderer()
    ren.SetBackground(0.0, 0.0, 0.0)
    ren.AddVolume(volume)
    win = offscreen_window(ren, args.size)
    anterior_camera(ren.GetActiveCamera(), sizes, spacings, args.size, args.size)

    print(f"vtk {vtk.vtkVersion.GetVTKVersion()}, window {win.GetClassName()}, "
          f"mapper {mapper.GetClassName()}, volume {sizes} {vox.dtype}, "
          f"image {args.size}x{args.size}, step {mapper.GetSampleDistance()}", flush=True)

    win.Render()
    gl = [l.strip() for l in (win.ReportCapabilities() or "").splitlines()
          if "renderer string" in l.lower()]
    if gl:
        print(f"  ({gl[0]}; OpenGL only draws the finished image)", flush=True)

    for n in [int(t) for t in args.threads.split(",")]:
        vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(n)
        vtk.vtkMultiThreader.SetGlobalDefaultNumberOfThreads(n)
        mapper.SetNumberOfThreads(n)
        win.Render()  # warm-up with this thread count
        walls, draws = [], []
        for _ in range(args.frames):
            t0 = time.perf_counter()
            win.Render()
            walls.append((time.perf_counter() - t0) * 1e3)
            draws.append(mapper.GetTimeToDraw() * 1e3)
        med = statistics.median(walls)
        print(f"vtk threads={n} median_ms={med:.1f} cast_median_ms="
              f"{statistics.median(draws):.1f} threads_used={mapper.GetNumberOfThreads()} "
              f"frames_ms={','.join(f'{w:.0f}' for w in walls)}", flush=True)

        png = f"{args.out}-t{n}.png"
        write_png(win, png)
        print(f"  -> {png}", flush=True)
        if args.compare:
            print("  " + compare(args.compare, png), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
