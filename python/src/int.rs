//! The integer pipeline: `sample_int` and `render_int` (the core's `IntRayMarcher` at `F`
//! fractional position bits, every integer mode: `Separate`, `OpacityWeighted`,
//! `Preweighted`, `IntExtinction` with `ExtinctionTables` of `N` nodes), `to_extinction_fx`
//! (the `ExtinctionFx` voxels `IntExtinction` reads) and `downsample_level_int` (one level of
//! the integer opacity- or extinction-based downsampling). Samples and pixels are U8.8
//! `uint16` (`65280` = 1).

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArray4, PyReadonlyArray2};
use pyo3::prelude::*;
use volsample::downsample::integer::{
    downsample_level_int as ds_level_int, IntExtinctionBased, IntFilter4, IntMethod,
    IntOpacityBased,
};
use volsample::downsample::{level_dims, Filter4};
use volsample::fixed_point::{ExtinctionFx, ExtinctionTables, IntExtinction, IntFilter, IntMode};
use volsample::render::IntRayMarcher;
use volsample::skip::{Emptiness, Occupancy, Skipping};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Error, IntSample, IntStop, Nearest, OpacityWeighted, Preweighted, Separate, Step,
    StraightU8, Trilinear, Volume,
};

use crate::{
    core_err, parse_filter, parse_method, parse_mode, pixels, read_positions, read_rgba,
    read_volume, render_bands, straight_of, to_array2, to_array4, value_err, Camera, CameraKind,
    Channels, FilterName, MethodName, ModeName, Params, SKIP_BRICK_LOG2,
};

/// The node counts of the `φ` and `e^(−x)` tables `table_nodes` may name (`2^B + 1`).
const TABLE_NODES: [usize; 5] = [17, 65, 257, 1025, 4097];

/// Voxels in the format an integer mode reads, with the volume's `[x, y, z]` dims.
enum IntJob {
    Separate(Vec<StraightU8>),
    OpacityWeighted(Vec<StraightU8>),
    Preweighted(Vec<AssociatedU8>),
    Extinction(Vec<ExtinctionFx>),
}

/// Reads the volume an integer mode needs: straight `uint8` (`separate`,
/// `opacity_weighted`), associated `uint8` (`preweighted`) or `uint32` `ExtinctionFx`
/// (`extinction`).
fn int_job(volume: &Bound<'_, PyAny>, mode: ModeName) -> PyResult<(IntJob, [usize; 3])> {
    if matches!(mode, ModeName::Extinction) {
        return match read_rgba::<u32>(volume) {
            Some(r) => {
                let (d, dims) = r?;
                Ok((IntJob::Extinction(d.into_iter().map(fx).collect()), dims))
            }
            None => Err(value_err(
                "the integer mode 'extinction' reads uint32 ExtinctionFx voxels (z, y, x, 4): convert a straight volume with to_extinction_fx()",
            )),
        };
    }
    if !matches!(
        mode,
        ModeName::Separate | ModeName::OpacityWeighted | ModeName::Preweighted
    ) {
        return Err(value_err(
            "the integer kernels offer the modes 'separate', 'opacity_weighted', 'preweighted' and 'extinction'",
        ));
    }
    let vol = read_volume(volume)?;
    let Channels::U8(raw) = vol.channels else {
        return Err(value_err(
            "the integer modes 'separate', 'opacity_weighted' and 'preweighted' read uint8 volumes",
        ));
    };
    let job = match mode {
        ModeName::Preweighted => IntJob::Preweighted(raw.into_iter().map(AssociatedU8).collect()),
        ModeName::Separate => IntJob::Separate(raw.into_iter().map(StraightU8).collect()),
        _ => IntJob::OpacityWeighted(raw.into_iter().map(StraightU8).collect()),
    };
    Ok((job, vol.dims))
}

/// `[D·C r, g, b, D]` channels as an `ExtinctionFx` voxel.
fn fx(c: [u32; 4]) -> ExtinctionFx {
    ExtinctionFx {
        tau: c[3],
        c_tau: [c[0], c[1], c[2]],
    }
}

/// A kernel generic over the integer pipeline's voxel, mode, filter and `F`: the one
/// dispatch below instantiates it for every combination a call can name.
trait IntKernel: Sized {
    type Out;
    fn run<V, M, Fl, const F: u32>(
        self,
        data: &[V],
        mode: M,
        filter: Fl,
    ) -> Result<Self::Out, Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Sync,
        Fl: IntFilter + Sync;

    /// [`run`](Self::run) for the modes that have empty voxels ([`Emptiness`]: the
    /// opacity-based integer modes), where a kernel can skip empty space; `run` unless a
    /// kernel says otherwise.
    fn run_empty<V, M, Fl, const F: u32>(
        self,
        data: &[V],
        mode: M,
        filter: Fl,
    ) -> Result<Self::Out, Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Emptiness<V> + Sync,
        Fl: IntFilter + Sync,
    {
        self.run::<V, M, Fl, F>(data, mode, filter)
    }
}

/// The call's integer options, checked before any work.
#[derive(Clone, Copy)]
struct IntOptions {
    nearest: bool,
    frac_bits: u32,
    table_nodes: usize,
}

fn int_options(filter: &str, frac_bits: u32, table_nodes: usize) -> PyResult<IntOptions> {
    let nearest = match parse_filter(filter)? {
        FilterName::Nearest => true,
        FilterName::Trilinear => false,
        _ => {
            return Err(value_err(
                "the integer kernels offer the filters 'nearest' and 'trilinear'",
            ))
        }
    };
    if !(4..=12).contains(&frac_bits) {
        return Err(value_err("frac_bits must lie in 4..=12"));
    }
    if !TABLE_NODES.contains(&table_nodes) {
        return Err(value_err(format!(
            "table_nodes must be one of {TABLE_NODES:?}"
        )));
    }
    Ok(IntOptions {
        nearest,
        frac_bits,
        table_nodes,
    })
}

/// Runs `k` on `job` with the options' filter, `F` and table size (checked by
/// [`int_options`]; anything else reads as the defaults, never reached).
fn dispatch<K: IntKernel>(k: K, job: &IntJob, o: IntOptions) -> Result<K::Out, Error> {
    match o.frac_bits {
        4 => by_filter::<K, 4>(k, job, o),
        5 => by_filter::<K, 5>(k, job, o),
        6 => by_filter::<K, 6>(k, job, o),
        7 => by_filter::<K, 7>(k, job, o),
        9 => by_filter::<K, 9>(k, job, o),
        10 => by_filter::<K, 10>(k, job, o),
        11 => by_filter::<K, 11>(k, job, o),
        12 => by_filter::<K, 12>(k, job, o),
        _ => by_filter::<K, 8>(k, job, o),
    }
}

fn by_filter<K: IntKernel, const F: u32>(
    k: K,
    job: &IntJob,
    o: IntOptions,
) -> Result<K::Out, Error> {
    if o.nearest {
        by_mode::<K, Nearest, F>(k, job, Nearest, o.table_nodes)
    } else {
        by_mode::<K, Trilinear, F>(k, job, Trilinear::new(), o.table_nodes)
    }
}

fn by_mode<K: IntKernel, Fl: IntFilter + Sync, const F: u32>(
    k: K,
    job: &IntJob,
    fl: Fl,
    nodes: usize,
) -> Result<K::Out, Error> {
    match job {
        IntJob::Separate(d) => k.run_empty::<_, _, _, F>(d, Separate, fl),
        IntJob::OpacityWeighted(d) => k.run_empty::<_, _, _, F>(d, OpacityWeighted, fl),
        IntJob::Preweighted(d) => k.run_empty::<_, _, _, F>(d, Preweighted, fl),
        IntJob::Extinction(d) => match nodes {
            17 => with_tables::<K, Fl, F, 17>(k, d, fl),
            65 => with_tables::<K, Fl, F, 65>(k, d, fl),
            1025 => with_tables::<K, Fl, F, 1025>(k, d, fl),
            4097 => with_tables::<K, Fl, F, 4097>(k, d, fl),
            _ => with_tables::<K, Fl, F, 257>(k, d, fl),
        },
    }
}

fn with_tables<K: IntKernel, Fl: IntFilter + Sync, const F: u32, const N: usize>(
    k: K,
    d: &[ExtinctionFx],
    fl: Fl,
) -> Result<K::Out, Error> {
    let tables = ExtinctionTables::<N>::new();
    // The marcher sets the step ratio d/d′ (`IntMode::for_step_ratio`).
    let mode = IntExtinction::new(&tables, 1.0)?;
    k.run::<_, _, _, F>(d, mode, fl)
}

/// The marcher of a call: the volume at `d′`, the step, no early termination unless asked.
fn int_marcher<V, M, Fl, const F: u32>(
    data: &[V],
    mode: M,
    filter: Fl,
    p: Params,
    stop: IntStop,
) -> Result<IntRayMarcher<'_, V, M, Fl, F>, Error>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
{
    let vol = Volume::new(data, p.dims)?.with_reference_distance(p.d_ref)?;
    IntRayMarcher::<V, M, Fl, F>::new(vol, mode, filter, stop, Step::new(p.step)?)
}

/// `IntRayMarcher::sample` at every position.
struct SampleAt<'a> {
    p: Params,
    pos: &'a [[f32; 3]],
}

impl IntKernel for SampleAt<'_> {
    type Out = Vec<[u16; 4]>;
    fn run<V, M, Fl, const F: u32>(
        self,
        data: &[V],
        mode: M,
        filter: Fl,
    ) -> Result<Self::Out, Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Sync,
        Fl: IntFilter + Sync,
    {
        let m = int_marcher::<V, M, Fl, F>(data, mode, filter, self.p, IntStop::NEVER)?;
        let mut out = vec![IntSample::TRANSPARENT; self.pos.len()];
        m.sample_into(self.pos, &mut out)?;
        Ok(out
            .iter()
            .map(|s| {
                let c = s.c();
                [c[0], c[1], c[2], s.a()]
            })
            .collect())
    }
}

/// `IntRayMarcher::render_rows_into` in bands of rows, over the background, skipping empty
/// space where asked (`with_skipping`, 8³-voxel bricks; only the modes with [`Emptiness`]).
struct RenderInto<'a> {
    p: Params,
    stop: IntStop,
    background: IntSample,
    skip: bool,
    cam: CameraKind,
    size: (usize, usize),
    threads: usize,
    img: &'a mut [IntSample],
}

impl RenderInto<'_> {
    /// Renders the image with a configured marcher, in bands of rows.
    fn draw<V, M, Fl, const F: u32, S>(
        self,
        m: &IntRayMarcher<'_, V, M, Fl, F, S>,
    ) -> Result<(), Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Sync,
        Fl: IntFilter + Sync,
        S: Skipping + Sync,
    {
        let (cam, size) = (self.cam, self.size);
        render_bands(self.img, size, self.threads, |first, band| {
            m.render_rows_into(&cam, size, first, band)
        })
    }
}

impl IntKernel for RenderInto<'_> {
    type Out = ();
    fn run<V, M, Fl, const F: u32>(self, data: &[V], mode: M, filter: Fl) -> Result<(), Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Sync,
        Fl: IntFilter + Sync,
    {
        let m = int_marcher::<V, M, Fl, F>(data, mode, filter, self.p, self.stop)?
            .with_background(self.background);
        self.draw(&m)
    }

    fn run_empty<V, M, Fl, const F: u32>(self, data: &[V], mode: M, filter: Fl) -> Result<(), Error>
    where
        V: Voxel + Sync,
        M: IntMode<V> + Emptiness<V> + Sync,
        Fl: IntFilter + Sync,
    {
        if !self.skip {
            return self.run::<V, M, Fl, F>(data, mode, filter);
        }
        let mut grid = vec![0u8; Occupancy::buffer_len(self.p.dims, SKIP_BRICK_LOG2)];
        let m = int_marcher::<V, M, Fl, F>(data, mode, filter, self.p, self.stop)?
            .with_background(self.background)
            .with_skipping(&mut grid, SKIP_BRICK_LOG2)?;
        self.draw(&m)
    }
}

/// The background of `render_int`: U8.8 associated `(C̃r, C̃g, C̃b, α)`, `C̃ ≤ α ≤ 65280`
/// (`IntSample::new`); transparent when not given.
fn int_background(background: Option<[i64; 4]>) -> PyResult<IntSample> {
    let Some(bg) = background else {
        return Ok(IntSample::TRANSPARENT);
    };
    let s = match bg.map(u16::try_from) {
        [Ok(r), Ok(g), Ok(b), Ok(a)] => IntSample::new([r, g, b], a),
        _ => Err(Error::InvalidIntSample),
    };
    s.map_err(|e| {
        value_err(format!(
            "background must be U8.8 associated (C̃r, C̃g, C̃b, α) with 0 <= C̃ <= α <= 65280: {e}"
        ))
    })
}

/// Samples a volume with the bit-exact integer pipeline (`IntRayMarcher::sample`: the position
/// clamped into the grid and quantized to `frac_bits` fractional bits, round half up; the
/// integer kernel; `IntCorrection` from `reference_distance` to `step` for the opacity-based
/// modes, the step ratio for `extinction`): U8.8 associated samples (`65280` = opacity 1) as
/// `uint16` `(n, 4)`.
#[pyfunction]
#[pyo3(signature = (volume, positions, mode = "opacity_weighted", filter = "trilinear", step = 1.0, reference_distance = 1.0, frac_bits = 8, table_nodes = 257))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn sample_int<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    positions: PyReadonlyArray2<'py, f32>,
    mode: &str,
    filter: &str,
    step: f32,
    reference_distance: f32,
    frac_bits: u32,
    table_nodes: usize,
) -> PyResult<Bound<'py, PyArray2<u16>>> {
    let pos = read_positions(positions)?;
    let o = int_options(filter, frac_bits, table_nodes)?;
    let (job, dims) = int_job(volume, parse_mode(mode)?)?;
    let p = Params {
        dims,
        step,
        d_ref: reference_distance,
    };
    let out = py.allow_threads(|| dispatch(SampleAt { p, pos: &pos }, &job, o));
    Ok(to_array2(out.map_err(core_err)?)?.into_pyarray(py))
}

/// Renders a volume with the integer pipeline (`IntRayMarcher::render_into`, front to back,
/// integer compositing, early termination once the opacity reaches `a_stop`): a
/// `(height, width, 4)` `uint16` image of U8.8 associated pixels over `background`
/// (`with_background`: U8.8 associated, composited behind every ray with the same integer
/// step; transparent by default). `skip` (`with_skipping`, 8³-voxel bricks, the modes but
/// `extinction`) steps over empty space: the same image bit for bit. `threads` bands of rows
/// give the same image bit for bit.
#[pyfunction]
#[pyo3(signature = (volume, camera, width, height, mode = "opacity_weighted", filter = "trilinear", step = 0.5, reference_distance = 1.0, frac_bits = 8, table_nodes = 257, a_stop = 65280, threads = 1, background = None, skip = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_int<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    camera: &Camera,
    width: usize,
    height: usize,
    mode: &str,
    filter: &str,
    step: f32,
    reference_distance: f32,
    frac_bits: u32,
    table_nodes: usize,
    a_stop: i64,
    threads: usize,
    background: Option<[i64; 4]>,
    skip: bool,
) -> PyResult<Bound<'py, PyArray3<u16>>> {
    let o = int_options(filter, frac_bits, table_nodes)?;
    let stop = u16::try_from(a_stop)
        .map_err(|_| Error::InvalidThreshold)
        .and_then(IntStop::new)
        .map_err(core_err)?;
    let background = int_background(background)?;
    let mode = parse_mode(mode)?;
    if skip && matches!(mode, ModeName::Extinction) {
        return Err(value_err(
            "skip is not available for the integer mode 'extinction' (the core's IntRayMarcher skips for the opacity-based modes only)",
        ));
    }
    let (job, dims) = int_job(volume, mode)?;
    let size = (width, height);
    let mut img = pixels(size, IntSample::TRANSPARENT)?;
    let k = RenderInto {
        p: Params {
            dims,
            step,
            d_ref: reference_distance,
        },
        stop,
        background,
        skip,
        cam: camera.kind,
        size,
        threads,
        img: &mut img,
    };
    py.allow_threads(|| dispatch(k, &job, o))
        .map_err(core_err)?;
    let flat: Vec<u16> = img
        .iter()
        .flat_map(|s| {
            let c = s.c();
            [c[0], c[1], c[2], s.a()]
        })
        .collect();
    Array3::from_shape_vec((height, width, 4), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| value_err(format!("internal shape error: {e}")))
}

/// The fixed-point extinction voxels `(D·C r, g, b, D)` (`uint32`, U7.20: `raw/2^20`) of a
/// straight `uint8` or `float32` volume whose opacities hold for the reference distance:
/// `D = ⌊2^20·min(−ln(1 − α), 64) + ½⌋`, `D·C` rounded half up (`ExtinctionFx`).
#[pyfunction]
pub(crate) fn to_extinction_fx<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray4<u32>>> {
    let vol = read_volume(volume)?;
    let dims = vol.dims;
    let out = py.allow_threads(|| {
        let v: Vec<ExtinctionFx> = match &vol.channels {
            Channels::U8(d) => d
                .iter()
                .map(|&c| ExtinctionFx::from_straight_u8(StraightU8(c)))
                .collect(),
            Channels::F32(_) => {
                let s = straight_of(&vol.channels);
                Volume::new(&s, dims)?;
                s.into_iter().map(ExtinctionFx::from_straight_f32).collect()
            }
        };
        Volume::new(&v, dims)?;
        Ok::<_, Error>(
            v.into_iter()
                .map(|e| [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau])
                .collect::<Vec<_>>(),
        )
    });
    Ok(to_array4(out.map_err(core_err)?, dims)?.into_pyarray(py))
}

/// One integer level of `src` (validated by the caller) with `method` and `filter`.
fn int_level<V: Copy, M: IntMethod<V>>(
    method: M,
    filter: IntFilter4,
    src: &[V],
    dims: [usize; 3],
    zero: V,
) -> Result<(Vec<V>, [usize; 3]), Error> {
    let od = level_dims(dims, 1);
    let mut dst = vec![zero; od[0] * od[1] * od[2]];
    ds_level_int(method, filter, src, dims, &mut dst)?;
    Ok((dst, od))
}

/// One level of the bit-exact integer downsampling (`downsample::integer`), `a` quantized to
/// Q0.16 (round half up). `method="opacity"`: associated `uint8` or U8.8 `uint16` voxels,
/// `α′ = ᾱ(2 − ᾱ)`, `C̃′ = C̄(2 − ᾱ)`; `method="extinction"`: `uint32` `ExtinctionFx` voxels,
/// `D′ = 2·D̄` (saturated at 64). The output has the input's dtype.
#[pyfunction]
#[pyo3(signature = (volume, method, a = 0.25))]
pub(crate) fn downsample_level_int<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    method: &str,
    a: f32,
) -> PyResult<Bound<'py, PyAny>> {
    let method = parse_method(method)?;
    let filter = IntFilter4::from_filter(Filter4::new(a).map_err(core_err)?);
    let dtype_err = || {
        value_err(match method {
            MethodName::Opacity => "method 'opacity' reads associated uint8 or U8.8 uint16 voxels (z, y, x, 4)",
            MethodName::Extinction => "method 'extinction' reads uint32 ExtinctionFx voxels (z, y, x, 4) (see to_extinction_fx())",
        })
    };
    match method {
        MethodName::Opacity => {
            if let Some(r) = read_rgba::<u8>(volume) {
                let (d, dims) = r?;
                let out = py.allow_threads(|| {
                    let src: Vec<AssociatedU8> = d.into_iter().map(AssociatedU8).collect();
                    Volume::new(&src, dims)?;
                    let (l, od) =
                        int_level(IntOpacityBased, filter, &src, dims, AssociatedU8::default())?;
                    Ok::<_, Error>((l.into_iter().map(|v| v.0).collect::<Vec<_>>(), od))
                });
                let (l, od) = out.map_err(core_err)?;
                return Ok(to_array4(l, od)?.into_pyarray(py).into_any());
            }
            if let Some(r) = read_rgba::<u16>(volume) {
                let (d, dims) = r?;
                let out = py.allow_threads(|| {
                    let src = d
                        .iter()
                        .enumerate()
                        .map(|(i, c)| {
                            IntSample::new([c[0], c[1], c[2]], c[3])
                                .map_err(|e| format!("voxel {i}: {e}"))
                        })
                        .collect::<Result<Vec<_>, _>>()?;
                    let (l, od) =
                        int_level(IntOpacityBased, filter, &src, dims, IntSample::TRANSPARENT)
                            .map_err(|e| e.to_string())?;
                    let l: Vec<[u16; 4]> = l
                        .into_iter()
                        .map(|s| {
                            let c = s.c();
                            [c[0], c[1], c[2], s.a()]
                        })
                        .collect();
                    Ok::<_, String>((l, od))
                });
                let (l, od) = out.map_err(value_err)?;
                return Ok(to_array4(l, od)?.into_pyarray(py).into_any());
            }
            Err(dtype_err())
        }
        MethodName::Extinction => {
            let Some(r) = read_rgba::<u32>(volume) else {
                return Err(dtype_err());
            };
            let (d, dims) = r?;
            let out = py.allow_threads(|| {
                let src: Vec<ExtinctionFx> = d.into_iter().map(fx).collect();
                Volume::new(&src, dims)?;
                let (l, od) = int_level(
                    IntExtinctionBased,
                    filter,
                    &src,
                    dims,
                    ExtinctionFx::default(),
                )?;
                let l: Vec<[u32; 4]> = l
                    .into_iter()
                    .map(|e| [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau])
                    .collect();
                Ok::<_, Error>((l, od))
            });
            let (l, od) = out.map_err(core_err)?;
            Ok(to_array4(l, od)?.into_pyarray(py).into_any())
        }
    }
}
