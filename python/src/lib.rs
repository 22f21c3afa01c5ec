//! Python bindings of `volsample` (module `volsample._volsample`; the Python package
//! `volsample` re-exports it and adds `volsample.dask`).
//!
//! Conventions shared by every function:
//! * a volume is a C-ordered numpy array of shape `(z, y, x, 4)` (the core's voxel order,
//!   `x + nx·(y + ny·z)`), `uint8` (`n/255`) or `float32`; it is copied into the core's voxel
//!   type, validated by the core (`Volume::new`) and the copy is freed on return;
//! * positions are `(n, 3)` `float32` arrays of `(x, y, z)` in voxel units (voxel centres at
//!   integer coordinates);
//! * every kernel call runs with the GIL released (`Python::allow_threads`);
//! * the core's errors become `ValueError` carrying the core's message.

use numpy::ndarray::{Array2, Array3, Array4};
use numpy::PyUntypedArrayMethods;
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArray4, PyReadonlyArray2, PyReadonlyArray4};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use volsample::composite::{Order, Threshold};
use volsample::downsample::integer::{downsample_level_int, IntFilter4, IntOpacityBased};
use volsample::downsample::{downsample_level as ds_level, level_dims, ExtinctionBased};
use volsample::downsample::{Filter4, Method, OpacityBased};
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::skip::{Emptiness, Occupancy, Skipping};
use volsample::{
    AssociatedF32, AssociatedU8, BackToFront, Error, ExtinctionF32, ExtinctionWeighted, Filter,
    FrontToBack, Mode, Nearest, OpacityWeighted, Preweighted, RayMarcher, Sample, Separate, Step,
    StraightF32, StraightU8, Trilinear, TriquadraticBSpline, Volume,
};

mod camera;
use camera::{Camera, CameraKind};
use post::TransferFunction;

/// The core's error as a `ValueError` with its message.
fn core_err(e: Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn value_err(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

/// A volume array read into owned voxels: `uint8` or `float32` channels, with its dims
/// `[nx, ny, nz]`.
enum Channels {
    U8(Vec<[u8; 4]>),
    F32(Vec<[f32; 4]>),
}

struct VolumeArg {
    channels: Channels,
    dims: [usize; 3],
}

/// Voxels of four channels and their `[x, y, z]` dimensions.
type Rgba<T> = (Vec<[T; 4]>, [usize; 3]);

/// The voxels and `[x, y, z]` dimensions of a `(z, y, x, 4)` array of element type `T`, or
/// `None` when `obj` is not such an array of `T`.
fn read_rgba<T: numpy::Element + Copy>(obj: &Bound<'_, PyAny>) -> Option<PyResult<Rgba<T>>> {
    let shape_err = || value_err("volume must have shape (z, y, x, 4)");
    let a = obj.extract::<PyReadonlyArray4<'_, T>>().ok()?;
    let s = a.shape();
    if s[3] != 4 {
        return Some(Err(shape_err()));
    }
    let dims = [s[2], s[1], s[0]];
    let v = a.as_array();
    let data = v
        .as_standard_layout()
        .as_slice()
        .ok_or_else(shape_err)
        .map(|d| {
            d.chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect()
        });
    Some(data.map(|d| (d, dims)))
}

/// Reads a `(z, y, x, 4)` `uint8` or `float32` array.
fn read_volume(obj: &Bound<'_, PyAny>) -> PyResult<VolumeArg> {
    if let Some(r) = read_rgba::<u8>(obj) {
        let (data, dims) = r?;
        return Ok(VolumeArg {
            channels: Channels::U8(data),
            dims,
        });
    }
    if let Some(r) = read_rgba::<f32>(obj) {
        let (data, dims) = r?;
        return Ok(VolumeArg {
            channels: Channels::F32(data),
            dims,
        });
    }
    Err(value_err(
        "volume must be a numpy array of shape (z, y, x, 4) and dtype uint8 or float32",
    ))
}

/// Reads `(n, 3)` float32 positions as `[x, y, z]`.
fn read_positions(positions: PyReadonlyArray2<'_, f32>) -> PyResult<Vec<[f32; 3]>> {
    if positions.shape()[1] != 3 {
        return Err(value_err("positions must have shape (n, 3): x, y, z"));
    }
    Ok(positions
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect())
}

fn straight_f32(c: [f32; 4]) -> StraightF32 {
    StraightF32 {
        c: [c[0], c[1], c[2]],
        a: c[3],
    }
}

fn straight_u8_to_f32(c: [u8; 4]) -> StraightF32 {
    let [r, g, b, a] = StraightU8(c).0.map(volsample::voxel::unorm8);
    StraightF32 { c: [r, g, b], a }
}

/// The reconstruction filters by name.
#[derive(Clone, Copy)]
enum FilterName {
    Nearest,
    Trilinear,
    TrilinearTree,
    BSpline,
}

fn parse_filter(name: &str) -> PyResult<FilterName> {
    Ok(match name {
        "nearest" => FilterName::Nearest,
        "trilinear" => FilterName::Trilinear,
        "trilinear_tree" => FilterName::TrilinearTree,
        "bspline" | "triquadratic_bspline" => FilterName::BSpline,
        other => {
            return Err(value_err(format!(
                "unknown filter {other:?}: expected 'nearest', 'trilinear', 'trilinear_tree' or 'bspline'"
            )))
        }
    })
}

/// The sampling modes by name.
#[derive(Clone, Copy)]
enum ModeName {
    Separate,
    OpacityWeighted,
    Preweighted,
    Extinction,
    ExtinctionU8,
    PostClassified,
}

fn parse_mode(name: &str) -> PyResult<ModeName> {
    Ok(match name {
        "separate" => ModeName::Separate,
        "opacity_weighted" => ModeName::OpacityWeighted,
        "preweighted" => ModeName::Preweighted,
        "extinction" => ModeName::Extinction,
        "extinction_u8" => ModeName::ExtinctionU8,
        "post_classified" => ModeName::PostClassified,
        other => {
            return Err(value_err(format!(
                "unknown mode {other:?}: expected 'separate', 'opacity_weighted', 'preweighted', 'extinction', 'extinction_u8' or 'post_classified'"
            )))
        }
    })
}

/// Runs `$body` with `$f` bound to the named filter (one monomorphized kernel per filter).
macro_rules! with_filter {
    ($name:expr, $f:ident => $body:expr) => {
        match $name {
            FilterName::Nearest => {
                let $f = Nearest;
                $body
            }
            FilterName::Trilinear => {
                let $f = Trilinear::new();
                $body
            }
            FilterName::TrilinearTree => {
                let $f = Trilinear::tree();
                $body
            }
            FilterName::BSpline => {
                let $f = TriquadraticBSpline;
                $body
            }
        }
    };
}

// After the macros they use (textual scope).
mod int;
mod post;
mod prepass;
mod vectors;

/// What a float pipeline needs besides mode, filter and voxels.
#[derive(Clone, Copy)]
struct Params {
    dims: [usize; 3],
    step: f32,
    d_ref: f32,
}

fn marcher<'v, V, M, F>(
    data: &'v [V],
    p: Params,
    mode: M,
    filter: F,
) -> Result<RayMarcher<'v, V, M, F, FrontToBack>, Error>
where
    V: volsample::voxel::Voxel,
    M: Mode<V>,
    F: Filter,
{
    let vol = Volume::new(data, p.dims)?.with_reference_distance(p.d_ref)?;
    RayMarcher::new(vol, mode, filter, FrontToBack::new(), Step::new(p.step)?)
}

fn sample_all<V, M, F>(
    data: &[V],
    p: Params,
    mode: M,
    filter: F,
    pos: &[[f32; 3]],
) -> Result<Vec<[f32; 4]>, Error>
where
    V: volsample::voxel::Voxel,
    M: Mode<V>,
    F: Filter,
{
    let m = marcher(data, p, mode, filter)?;
    let mut out = vec![Sample::TRANSPARENT; pos.len()];
    m.sample_into(pos, &mut out)?;
    Ok(out.iter().map(|s| [s.c[0], s.c[1], s.c[2], s.a]).collect())
}

/// The voxels a mode reads from the given channels, or why it cannot; `d_ref` is the distance
/// the stored opacities hold for (the `τ` table of `extinction_u8`).
fn dispatch_float<R>(
    channels: &Channels,
    mode: ModeName,
    d_ref: f32,
    run: impl FnOnce(FloatJob) -> Result<R, Error>,
) -> PyResult<Result<R, Error>> {
    let job = match (mode, channels) {
        (ModeName::Separate | ModeName::OpacityWeighted, Channels::U8(d)) => {
            FloatJob::StraightU8(d.iter().map(|&c| StraightU8(c)).collect())
        }
        (ModeName::Separate | ModeName::OpacityWeighted, Channels::F32(d)) => {
            FloatJob::StraightF32(d.iter().map(|&c| straight_f32(c)).collect())
        }
        (ModeName::Preweighted, Channels::U8(d)) => {
            FloatJob::AssociatedU8(d.iter().map(|&c| AssociatedU8(c)).collect())
        }
        (ModeName::Preweighted, Channels::F32(d)) => FloatJob::AssociatedF32(
            d.iter()
                .map(|&c| AssociatedF32 {
                    c: [c[0], c[1], c[2]],
                    a: c[3],
                })
                .collect(),
        ),
        (ModeName::Extinction, Channels::F32(d)) => FloatJob::ExtinctionF32(
            d.iter()
                .map(|&c| ExtinctionF32 {
                    c_tau: [c[0], c[1], c[2]],
                    tau: c[3],
                })
                .collect(),
        ),
        (ModeName::Extinction, Channels::U8(_)) => {
            return Err(value_err(
                "mode 'extinction' reads float32 (C^tau r, g, b, tau) voxels: convert a straight volume with to_extinction()",
            ))
        }
        (ModeName::ExtinctionU8, Channels::U8(d)) => match TauTable::new(d_ref) {
            Ok(t) => FloatJob::ExtinctionU8(d.iter().map(|&c| StraightU8(c)).collect(), Box::new(t)),
            Err(e) => return Ok(Err(e)),
        },
        (ModeName::ExtinctionU8, Channels::F32(_)) => {
            return Err(value_err(
                "mode 'extinction_u8' reads straight uint8 RGBA: for float32 use to_extinction() and mode 'extinction'",
            ))
        }
        (ModeName::PostClassified, _) => {
            return Err(value_err(
                "mode 'post_classified' needs a scalar volume and tf=TransferFunction(...)",
            ))
        }
    };
    Ok(run(job))
}

/// Owned voxels in the format a mode reads.
enum FloatJob {
    StraightU8(Vec<StraightU8>),
    StraightF32(Vec<StraightF32>),
    AssociatedU8(Vec<AssociatedU8>),
    AssociatedF32(Vec<AssociatedF32>),
    ExtinctionF32(Vec<ExtinctionF32>),
    /// Straight bytes and the `τ` table of their opacities.
    ExtinctionU8(Vec<StraightU8>, Box<TauTable>),
}

/// Runs a generic float kernel `$k(data, mode, filter)` for every (mode, voxel, filter).
macro_rules! run_float {
    ($job:expr, $mode:expr, $filter:expr, $k:ident ( $($arg:expr),* )) => {
        match ($job, $mode) {
            (FloatJob::StraightU8(d), ModeName::Separate) => with_filter!($filter, f => $k(&d, Separate, f, $($arg),*)),
            (FloatJob::StraightU8(d), _) => with_filter!($filter, f => $k(&d, OpacityWeighted, f, $($arg),*)),
            (FloatJob::StraightF32(d), ModeName::Separate) => with_filter!($filter, f => $k(&d, Separate, f, $($arg),*)),
            (FloatJob::StraightF32(d), _) => with_filter!($filter, f => $k(&d, OpacityWeighted, f, $($arg),*)),
            (FloatJob::AssociatedU8(d), _) => with_filter!($filter, f => $k(&d, Preweighted, f, $($arg),*)),
            (FloatJob::AssociatedF32(d), _) => with_filter!($filter, f => $k(&d, Preweighted, f, $($arg),*)),
            (FloatJob::ExtinctionF32(d), _) => with_filter!($filter, f => $k(&d, ExtinctionWeighted, f, $($arg),*)),
            (FloatJob::ExtinctionU8(d, t), _) => with_filter!($filter, f => $k(&d, ExtinctionWeightedU8::new(&t), f, $($arg),*)),
        }
    };
}

fn sample_kernel<V, M, F>(
    data: &[V],
    mode: M,
    filter: F,
    p: Params,
    pos: &[[f32; 3]],
) -> Result<Vec<[f32; 4]>, Error>
where
    V: volsample::voxel::Voxel,
    M: Mode<V>,
    F: Filter,
{
    sample_all(data, p, mode, filter, pos)
}

/// The transfer function of mode `post_classified`, `None` for the other modes; an error
/// where one is given without the other.
fn check_tf(mode: ModeName, tf: Option<&TransferFunction>) -> PyResult<Option<&TransferFunction>> {
    match (mode, tf) {
        (ModeName::PostClassified, Some(tf)) => Ok(Some(tf)),
        (ModeName::PostClassified, None) => Err(value_err(
            "mode 'post_classified' needs tf=TransferFunction(...)",
        )),
        (_, None) => Ok(None),
        (_, Some(_)) => Err(value_err("tf is read by mode 'post_classified' only")),
    }
}

fn to_array2<T: Copy + numpy::Element>(rows: Vec<[T; 4]>) -> PyResult<Array2<T>> {
    let n = rows.len();
    let flat: Vec<T> = rows.into_iter().flatten().collect();
    Array2::from_shape_vec((n, 4), flat)
        .map_err(|e| value_err(format!("internal shape error: {e}")))
}

fn to_array4<T: Copy + numpy::Element>(
    voxels: Vec<[T; 4]>,
    dims: [usize; 3],
) -> PyResult<Array4<T>> {
    let flat: Vec<T> = voxels.into_iter().flatten().collect();
    Array4::from_shape_vec((dims[2], dims[1], dims[0], 4), flat)
        .map_err(|e| value_err(format!("internal shape error: {e}")))
}

/// Samples a volume at positions: the associated color and opacity `(C̃r, C̃g, C̃b, α)` of a
/// segment of length `step` at each position, as `RayMarcher::sample` computes it
/// (opacity-corrected from `reference_distance` to `step` for the opacity-based modes).
#[pyfunction]
#[pyo3(signature = (volume, positions, mode = "opacity_weighted", filter = "trilinear", step = 1.0, reference_distance = 1.0, tf = None))]
#[allow(clippy::too_many_arguments)]
fn sample<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    positions: PyReadonlyArray2<'py, f32>,
    mode: &str,
    filter: &str,
    step: f32,
    reference_distance: f32,
    tf: Option<PyRef<'py, TransferFunction>>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let pos = read_positions(positions)?;
    let (mode, filter) = (parse_mode(mode)?, parse_filter(filter)?);
    if let Some(tf) = check_tf(mode, tf.as_deref())? {
        let out = post::sample_post(py, volume, &pos, tf, filter, step, reference_distance)?;
        return Ok(to_array2(out)?.into_pyarray(py));
    }
    let vol = read_volume(volume)?;
    let p = Params {
        dims: vol.dims,
        step,
        d_ref: reference_distance,
    };
    let out = py.allow_threads(|| {
        dispatch_float(&vol.channels, mode, reference_distance, |job| {
            run_float!(job, mode, filter, sample_kernel(p, &pos))
        })
    })?;
    Ok(to_array2(out.map_err(core_err)?)?.into_pyarray(py))
}

/// Opacity correction of associated samples `(n, 4)` from the reference distance to a step
/// of `ratio = d/d′` of it: `α_d = 1 − (1 − α)^ratio`, `C̃_d = C̃·α_d/α` (`opacity::correct`).
#[pyfunction]
fn correct_opacity<'py>(
    py: Python<'py>,
    samples: PyReadonlyArray2<'py, f32>,
    ratio: f32,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    if !(ratio.is_finite() && ratio > 0.0) {
        return Err(value_err("ratio must be finite and positive"));
    }
    if samples.shape()[1] != 4 {
        return Err(value_err("samples must have shape (n, 4): C̃r, C̃g, C̃b, α"));
    }
    let rows: Vec<Sample> = samples
        .as_array()
        .rows()
        .into_iter()
        .map(|r| Sample {
            c: [r[0], r[1], r[2]],
            a: r[3],
        })
        .collect();
    if let Some(i) = rows.iter().position(|s| !s.is_valid()) {
        return Err(value_err(format!(
            "sample {i} is not a valid associated sample (0 ≤ C̃ ≤ α ≤ 1, finite)"
        )));
    }
    let out = py.allow_threads(|| {
        rows.into_iter()
            .map(|s| {
                let t = volsample::opacity::correct(s, ratio);
                [t.c[0], t.c[1], t.c[2], t.a]
            })
            .collect::<Vec<_>>()
    });
    Ok(to_array2(out)?.into_pyarray(py))
}

/// Straight channels as `StraightF32`, from `uint8` (`n/255`) or `float32`.
fn straight_of(channels: &Channels) -> Vec<StraightF32> {
    match channels {
        Channels::U8(d) => d.iter().map(|&c| straight_u8_to_f32(c)).collect(),
        Channels::F32(d) => d.iter().map(|&c| straight_f32(c)).collect(),
    }
}

fn check_straight(v: &[StraightF32], dims: [usize; 3]) -> PyResult<()> {
    Volume::new(v, dims).map(|_| ()).map_err(core_err)
}

/// Associated (premultiplied) `float32` voxels `(C̃, α)` of a straight volume.
#[pyfunction]
fn to_associated<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let vol = read_volume(volume)?;
    let out = py.allow_threads(|| {
        let s = straight_of(&vol.channels);
        check_straight(&s, vol.dims)?;
        Ok::<_, PyErr>(
            s.into_iter()
                .map(|v| {
                    let a = AssociatedF32::from_straight(v);
                    [a.c[0], a.c[1], a.c[2], a.a]
                })
                .collect::<Vec<_>>(),
        )
    })?;
    Ok(to_array4(out, vol.dims)?.into_pyarray(py))
}

/// Extinction voxels `(C^τ, τ)` of a straight volume whose opacities hold for
/// `reference_distance` voxels (`ExtinctionF32::from_straight`).
#[pyfunction]
#[pyo3(signature = (volume, reference_distance = 1.0))]
fn to_extinction<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    reference_distance: f32,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    if !(reference_distance.is_finite() && reference_distance > 0.0) {
        return Err(core_err(Error::InvalidReferenceDistance));
    }
    let vol = read_volume(volume)?;
    let out = py.allow_threads(|| {
        let s = straight_of(&vol.channels);
        check_straight(&s, vol.dims)?;
        Ok::<_, PyErr>(
            s.into_iter()
                .map(|v| {
                    let e = ExtinctionF32::from_straight(v, reference_distance);
                    [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau]
                })
                .collect::<Vec<_>>(),
        )
    })?;
    Ok(to_array4(out, vol.dims)?.into_pyarray(py))
}

/// The two downsampling methods by name.
#[derive(Clone, Copy)]
enum MethodName {
    Opacity,
    Extinction,
}

fn parse_method(name: &str) -> PyResult<MethodName> {
    match name {
        "opacity" => Ok(MethodName::Opacity),
        "extinction" => Ok(MethodName::Extinction),
        other => Err(value_err(format!(
            "unknown method {other:?}: expected 'opacity' or 'extinction'"
        ))),
    }
}

fn level_of<M: Method>(
    method: M,
    filter: Filter4,
    data: &[M::Voxel],
    dims: [usize; 3],
) -> Result<(Vec<M::Voxel>, [usize; 3]), Error> {
    let od = level_dims(dims, 1);
    let mut out = vec![<M::Voxel as volsample::voxel::Voxel>::TRANSPARENT; od[0] * od[1] * od[2]];
    let vol = Volume::new(data, dims)?;
    ds_level(method, filter, &vol, &mut out)?;
    Ok((out, od))
}

/// A level's voxels as four channels, and its dims `[nx, ny, nz]`.
type Level = (Vec<[f32; 4]>, [usize; 3]);

/// `levels` successive levels (each `downsample_level` of the one before) of method-format
/// channels; returns every level after the input, as channels and dims.
fn levels_of(
    method: MethodName,
    filter: Filter4,
    channels: Vec<[f32; 4]>,
    dims: [usize; 3],
    levels: u32,
) -> Result<Vec<Level>, Error> {
    let mut out = Vec::new();
    match method {
        MethodName::Opacity => {
            let mut cur: Vec<AssociatedF32> = channels
                .iter()
                .map(|c| AssociatedF32 {
                    c: [c[0], c[1], c[2]],
                    a: c[3],
                })
                .collect();
            let mut d = dims;
            for _ in 0..levels {
                let (next, nd) = level_of(OpacityBased, filter, &cur, d)?;
                out.push((
                    next.iter().map(|v| [v.c[0], v.c[1], v.c[2], v.a]).collect(),
                    nd,
                ));
                cur = next;
                d = nd;
            }
        }
        MethodName::Extinction => {
            let mut cur: Vec<ExtinctionF32> = channels
                .iter()
                .map(|c| ExtinctionF32 {
                    c_tau: [c[0], c[1], c[2]],
                    tau: c[3],
                })
                .collect();
            let mut d = dims;
            for _ in 0..levels {
                let (next, nd) = level_of(ExtinctionBased, filter, &cur, d)?;
                out.push((
                    next.iter()
                        .map(|v| [v.c_tau[0], v.c_tau[1], v.c_tau[2], v.tau])
                        .collect(),
                    nd,
                ));
                cur = next;
                d = nd;
            }
        }
    }
    Ok(out)
}

/// One pyramid level of method-format `float32` voxels: `(C̃, α)` for `method="opacity"`,
/// `(C^τ, τ)` for `method="extinction"`, filtered with the 4-tap `(a, b, b, a)` filter.
#[pyfunction]
#[pyo3(signature = (volume, method = "extinction", a = 0.25))]
fn downsample_level<'py>(
    py: Python<'py>,
    volume: PyReadonlyArray4<'py, f32>,
    method: &str,
    a: f32,
) -> PyResult<Bound<'py, PyArray4<f32>>> {
    let method = parse_method(method)?;
    let filter = Filter4::new(a).map_err(core_err)?;
    let vol = read_volume(volume.as_any())?;
    let Channels::F32(ch) = vol.channels else {
        return Err(value_err("downsample_level reads float32 volumes"));
    };
    let mut levels = py
        .allow_threads(|| levels_of(method, filter, ch, vol.dims, 1))
        .map_err(core_err)?;
    let (data, dims) = levels
        .pop()
        .ok_or_else(|| value_err("internal: no level"))?;
    Ok(to_array4(data, dims)?.into_pyarray(py))
}

/// Level 0 in the method's format and `levels` coarser levels of a straight volume.
#[pyfunction]
#[pyo3(signature = (volume, levels, method = "extinction", a = 0.25, reference_distance = 1.0))]
fn pyramid<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    levels: u32,
    method: &str,
    a: f32,
    reference_distance: f32,
) -> PyResult<Vec<Bound<'py, PyArray4<f32>>>> {
    let method = parse_method(method)?;
    let filter = Filter4::new(a).map_err(core_err)?;
    if !(reference_distance.is_finite() && reference_distance > 0.0) {
        return Err(core_err(Error::InvalidReferenceDistance));
    }
    if levels > 24 {
        return Err(value_err("levels must be at most 24"));
    }
    let vol = read_volume(volume)?;
    let dims = vol.dims;
    let all = py.allow_threads(|| {
        let s = straight_of(&vol.channels);
        Volume::new(&s, dims)?;
        let base: Vec<[f32; 4]> = match method {
            MethodName::Opacity => s
                .into_iter()
                .map(|v| {
                    let a = AssociatedF32::from_straight(v);
                    [a.c[0], a.c[1], a.c[2], a.a]
                })
                .collect(),
            MethodName::Extinction => s
                .into_iter()
                .map(|v| {
                    let e = ExtinctionF32::from_straight(v, reference_distance);
                    [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau]
                })
                .collect(),
        };
        let rest = levels_of(method, filter, base.clone(), dims, levels)?;
        let mut all = vec![(base, dims)];
        all.extend(rest);
        Ok::<_, Error>(all)
    });
    all.map_err(core_err)?
        .into_iter()
        .map(|(d, dims)| Ok(to_array4(d, dims)?.into_pyarray(py)))
        .collect()
}

/// One level of the bit-exact integer opacity-based downsampling of associated `uint8`
/// voxels, the 4-tap filter's `a` quantized to Q0.16 (round half up).
#[pyfunction]
#[pyo3(signature = (volume, a = 0.25))]
fn downsample_level_u8<'py>(
    py: Python<'py>,
    volume: PyReadonlyArray4<'py, u8>,
    a: f32,
) -> PyResult<Bound<'py, PyArray4<u8>>> {
    let filter = IntFilter4::from_filter(Filter4::new(a).map_err(core_err)?);
    let vol = read_volume(volume.as_any())?;
    let Channels::U8(ch) = vol.channels else {
        return Err(value_err("downsample_level_u8 reads uint8 volumes"));
    };
    let dims = vol.dims;
    let out = py.allow_threads(|| {
        let src: Vec<AssociatedU8> = ch.into_iter().map(AssociatedU8).collect();
        Volume::new(&src, dims)?;
        let od = level_dims(dims, 1);
        let mut dst = vec![AssociatedU8::default(); od[0] * od[1] * od[2]];
        downsample_level_int(IntOpacityBased, filter, &src, dims, &mut dst)?;
        Ok::<_, Error>((dst.into_iter().map(|v| v.0).collect::<Vec<_>>(), od))
    });
    let (data, od) = out.map_err(core_err)?;
    Ok(to_array4(data, od)?.into_pyarray(py))
}

/// A `width × height` image of `fill`: the core's error for a zero width or height, and
/// `MemoryError` (not an abort) where it cannot be allocated.
fn pixels<P: Clone>((w, h): (usize, usize), fill: P) -> PyResult<Vec<P>> {
    if w == 0 || h == 0 {
        return Err(core_err(Error::EmptyImage));
    }
    let too_big =
        || PyMemoryError::new_err(format!("an image of {w}×{h} pixels does not fit in memory"));
    let n = w.checked_mul(h).ok_or_else(too_big)?;
    let mut img = Vec::new();
    img.try_reserve_exact(n).map_err(|_| too_big())?;
    img.resize(n, fill);
    Ok(img)
}

/// Renders `img` (`width·height` pixels, row-major, not empty) in `threads` bands of whole
/// rows on scoped threads, `band(first_row, rows)` each: a band's pixels are rendered as the
/// whole image renders them, so the image is the same for any thread count.
fn render_bands<P: Send>(
    img: &mut [P],
    (w, h): (usize, usize),
    threads: usize,
    band: impl Fn(usize, &mut [P]) -> Result<(), Error> + Sync,
) -> Result<(), Error> {
    if w == 0 || h == 0 {
        return Err(Error::EmptyImage);
    }
    let threads = threads.clamp(1, h);
    if threads == 1 {
        return band(0, img);
    }
    let rows_per = h.div_ceil(threads);
    let results: Vec<Result<(), Error>> = std::thread::scope(|s| {
        let handles: Vec<_> = img
            .chunks_mut(rows_per * w)
            .enumerate()
            .map(|(i, rows)| {
                let band = &band;
                s.spawn(move || band(i * rows_per, rows))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or(Err(Error::EmptyImage)))
            .collect()
    });
    results.into_iter().collect()
}

/// The float marcher's rendering options besides mode, filter and step.
#[derive(Clone, Copy)]
pub(crate) struct RenderOpts {
    /// Early termination (`FrontToBack<Threshold>`); `None` never stops (`a_stop = 1`).
    stop: Option<Threshold>,
    /// `BackToFront` instead of `FrontToBack`.
    back_to_front: bool,
    /// The associated background, composited behind every ray by the marcher.
    background: Sample,
    /// Empty-space skipping (`with_skipping`, bricks of `2^SKIP_BRICK_LOG2` voxels).
    skip: bool,
}

/// The brick size exponent of `skip=True`: 8³ voxels, as the CLI's `--skip`.
const SKIP_BRICK_LOG2: u32 = 3;

/// Runs `$body` with `$m` the marcher of `$vol` in the compositing order of `$o`.
macro_rules! with_order {
    ($o:expr, $vol:expr, $mode:expr, $filter:expr, $step:expr, $m:ident => $body:expr) => {
        match ($o.back_to_front, $o.stop) {
            (true, _) => {
                let $m = RayMarcher::new($vol, $mode, $filter, BackToFront, $step)?;
                $body
            }
            (false, Some(t)) => {
                let $m = RayMarcher::new($vol, $mode, $filter, FrontToBack(t), $step)?;
                $body
            }
            (false, None) => {
                let $m = RayMarcher::new($vol, $mode, $filter, FrontToBack::new(), $step)?;
                $body
            }
        }
    };
}

/// Renders the image with a configured marcher, over the background, in bands of rows.
fn draw<V, M, F, O, S>(
    m: RayMarcher<'_, V, M, F, O, S>,
    background: Sample,
    cam: CameraKind,
    size: (usize, usize),
    threads: usize,
    img: &mut [Sample],
) -> Result<(), Error>
where
    V: volsample::voxel::Voxel + Sync,
    M: Mode<V> + Sync,
    F: Filter + Sync,
    O: Order + Sync,
    S: Skipping + Sync,
{
    let m = m.with_background(background)?;
    render_bands(img, size, threads, |first, band| {
        m.render_rows_into(&cam, size, first, band)
    })
}

/// The volume of a call at its reference distance, and the step.
fn volume_of<V: volsample::voxel::Voxel>(
    data: &[V],
    p: Params,
) -> Result<(Volume<'_, V>, Step), Error> {
    let vol = Volume::new(data, p.dims)?.with_reference_distance(p.d_ref)?;
    Ok((vol, Step::new(p.step)?))
}

/// Renders without empty-space skipping (every mode, `post_classified` included).
#[allow(clippy::too_many_arguments)]
fn render_kernel<V, M, F>(
    data: &[V],
    mode: M,
    filter: F,
    p: Params,
    cam: CameraKind,
    size: (usize, usize),
    threads: usize,
    o: RenderOpts,
    img: &mut [Sample],
) -> Result<(), Error>
where
    V: volsample::voxel::Voxel + Sync,
    M: Mode<V> + Sync,
    F: Filter + Sync,
{
    let (vol, step) = volume_of(data, p)?;
    with_order!(o, vol, mode, filter, step, m => draw(m, o.background, cam, size, threads, img))
}

/// Renders the modes that have empty voxels ([`Emptiness`]), skipping empty space where the
/// options ask (bit-identical to not skipping, as the core promises).
#[allow(clippy::too_many_arguments)]
fn render_kernel_skip<V, M, F>(
    data: &[V],
    mode: M,
    filter: F,
    p: Params,
    cam: CameraKind,
    size: (usize, usize),
    threads: usize,
    o: RenderOpts,
    img: &mut [Sample],
) -> Result<(), Error>
where
    V: volsample::voxel::Voxel + Sync,
    M: Mode<V> + Emptiness<V> + Sync,
    F: Filter + Sync,
{
    if !o.skip {
        return render_kernel(data, mode, filter, p, cam, size, threads, o, img);
    }
    let (vol, step) = volume_of(data, p)?;
    let mut grid = vec![0u8; Occupancy::buffer_len(p.dims, SKIP_BRICK_LOG2)];
    with_order!(o, vol, mode, filter, step, m => {
        let m = m.with_skipping(&mut grid, SKIP_BRICK_LOG2)?;
        draw(m, o.background, cam, size, threads, img)
    })
}

/// The options of `render` checked: `a_stop` in `(0, 1]` (1: never stop), an order name, a
/// background of four floats, no skipping for `post_classified` (it has no empty voxels: two
/// scalars that classify as transparent can interpolate to one that does not).
fn render_opts(
    a_stop: f32,
    order: &str,
    background: Option<[f32; 4]>,
    skip: bool,
    mode: ModeName,
) -> PyResult<RenderOpts> {
    let stop = Threshold::new(a_stop).map_err(core_err)?;
    let stop = (a_stop < 1.0).then_some(stop);
    let back_to_front = match order {
        "front_to_back" => false,
        "back_to_front" => true,
        other => {
            return Err(value_err(format!(
                "unknown order {other:?}: expected 'front_to_back' or 'back_to_front'"
            )))
        }
    };
    if back_to_front && stop.is_some() {
        return Err(value_err(
            "a_stop applies to order 'front_to_back' only (back to front cannot stop early)",
        ));
    }
    if skip && matches!(mode, ModeName::PostClassified) {
        return Err(value_err(
            "skip is not available for mode 'post_classified' (interpolated scalars of transparent voxels may classify as visible)",
        ));
    }
    let background = match background {
        None => Sample::TRANSPARENT,
        Some([r, g, b, a]) => {
            let bg = Sample { c: [r, g, b], a };
            if !bg.is_valid() {
                return Err(core_err(Error::InvalidBackground));
            }
            bg
        }
    };
    Ok(RenderOpts {
        stop,
        back_to_front,
        background,
        skip,
    })
}

/// Renders a volume with a camera through the library's fast path
/// (`RayMarcher::render_rows_into`): a `(height, width, 4)` `float32` image of associated
/// `(C̃, α)` pixels. Front to back without early termination over a transparent background
/// unless asked: `a_stop` (`FrontToBack::with_threshold`: a ray stops once its opacity
/// reaches it; 1 never stops), `order="back_to_front"` (`BackToFront`), `background`
/// (associated `(C̃r, C̃g, C̃b, α)`, composited behind every ray by the marcher) and `skip`
/// (empty-space skipping, `with_skipping` with 8³-voxel bricks: the same image bit for bit).
#[pyfunction]
#[pyo3(signature = (volume, camera, width, height, mode = "opacity_weighted", filter = "trilinear", step = 0.5, reference_distance = 1.0, threads = 1, tf = None, a_stop = 1.0, order = "front_to_back", background = None, skip = false))]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    camera: &Camera,
    width: usize,
    height: usize,
    mode: &str,
    filter: &str,
    step: f32,
    reference_distance: f32,
    threads: usize,
    tf: Option<PyRef<'py, TransferFunction>>,
    a_stop: f32,
    order: &str,
    background: Option<[f32; 4]>,
    skip: bool,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (mode, filter) = (parse_mode(mode)?, parse_filter(filter)?);
    let o = render_opts(a_stop, order, background, skip, mode)?;
    let cam = camera.kind;
    let size = (width, height);
    let mut img = pixels(size, Sample::TRANSPARENT)?;
    if let Some(tf) = check_tf(mode, tf.as_deref())? {
        let (r, s) = (reference_distance, step);
        post::render_post(
            py,
            volume,
            tf,
            filter,
            (s, r),
            cam,
            size,
            threads,
            o,
            &mut img,
        )?;
    } else {
        let vol = read_volume(volume)?;
        let p = Params {
            dims: vol.dims,
            step,
            d_ref: reference_distance,
        };
        let out = py.allow_threads(|| {
            dispatch_float(&vol.channels, mode, reference_distance, |job| {
                run_float!(
                    job,
                    mode,
                    filter,
                    render_kernel_skip(p, cam, size, threads, o, &mut img)
                )
            })
        })?;
        out.map_err(core_err)?;
    }
    let flat: Vec<f32> = img
        .into_iter()
        .flat_map(|s| [s.c[0], s.c[1], s.c[2], s.a])
        .collect();
    let img = Array3::from_shape_vec((height, width, 4), flat)
        .map_err(|e| value_err(format!("internal shape error: {e}")))?;
    Ok(img.into_pyarray(py))
}

/// The native part of the `volsample` package.
#[pymodule]
fn _volsample(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sample, m)?)?;
    m.add_function(wrap_pyfunction!(int::sample_int, m)?)?;
    m.add_function(wrap_pyfunction!(int::render_int, m)?)?;
    m.add_function(wrap_pyfunction!(int::to_extinction_fx, m)?)?;
    m.add_function(wrap_pyfunction!(int::downsample_level_int, m)?)?;
    m.add_function(wrap_pyfunction!(correct_opacity, m)?)?;
    m.add_function(wrap_pyfunction!(to_associated, m)?)?;
    m.add_function(wrap_pyfunction!(to_extinction, m)?)?;
    m.add_function(wrap_pyfunction!(downsample_level, m)?)?;
    m.add_function(wrap_pyfunction!(pyramid, m)?)?;
    m.add_function(wrap_pyfunction!(downsample_level_u8, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(prepass::classify_transfer, m)?)?;
    m.add_function(wrap_pyfunction!(prepass::classify_isosurface, m)?)?;
    m.add_function(wrap_pyfunction!(prepass::gradient, m)?)?;
    m.add_function(wrap_pyfunction!(prepass::shade, m)?)?;
    m.add_function(wrap_pyfunction!(vectors::vectors, m)?)?;
    m.add_function(wrap_pyfunction!(vectors::read_vectors, m)?)?;
    m.add_class::<Camera>()?;
    m.add_class::<TransferFunction>()?;
    m.add_class::<prepass::Light>()?;
    Ok(())
}
