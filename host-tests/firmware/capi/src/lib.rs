//! C ABI over the main volsample kernels, as a `no_std` static library.
//!
//! Its own crate so that the core stays `forbid(unsafe_code)`: the only `unsafe` here turns
//! the caller's pointers into slices and references, after checking them for null.
//!
//! Conventions: every function that can fail returns an `int32_t` status (`VS_OK` = 0, a
//! negative `VS_ERR_*` otherwise) and writes its result through an out pointer only on
//! success. Modes, filters and orders are `uint32_t` constants (`VS_MODE_*`, `VS_FILTER_*`,
//! `VS_ORDER_*`), so no C value can be an invalid Rust enum. Voxels are RGBA bytes, four per
//! voxel, `x` fastest: straight for `VS_MODE_SEPARATE` and `VS_MODE_OPACITY_WEIGHTED`,
//! premultiplied (`C̃ ≤ α`) for `VS_MODE_PREWEIGHTED`. The header `include/volsample.h` is
//! generated from this file by cbindgen (see `test.sh`, which fails if it is stale).
#![no_std]
#![deny(unsafe_op_in_unsafe_fn)]
#![allow(clippy::missing_safety_doc)]

use core::hint::black_box;

use volsample::composite::Order;
use volsample::fixed_point::{
    composite_front_to_back, premultiply, unpremultiply, IntFilter, IntMode, IntPos, IntSample,
    IntSampler, IntStop,
};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, BackToFront, Error, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack,
    Interp, Mode, Nearest, OpacityWeighted, Preweighted, Ray, RayMarcher, Sample, Separate, Step,
    StraightU8, Trilinear, TriquadraticBSpline, Volume,
};

/// Major version of this C API (semantic versioning: a change of the ABI or of a function's
/// results raises it once the API is 1.0).
pub const VOLSAMPLE_VERSION_MAJOR: u32 = 0;
/// Minor version of this C API.
pub const VOLSAMPLE_VERSION_MINOR: u32 = 1;
/// Patch version of this C API.
pub const VOLSAMPLE_VERSION_PATCH: u32 = 0;
/// The version as one number, `major·10000 + minor·100 + patch`; compare it with
/// `vs_version()` to catch a header that does not match the linked library.
pub const VOLSAMPLE_VERSION: u32 = 100;

/// `s` as a decimal number (a compile-time parser for the package version).
const fn parse_u32(s: &str) -> u32 {
    let b = s.as_bytes();
    let mut i = 0;
    let mut n = 0u32;
    while i < b.len() {
        n = n * 10 + (b[i] - b'0') as u32;
        i += 1;
    }
    n
}
const _: () = {
    assert!(VOLSAMPLE_VERSION_MAJOR == parse_u32(env!("CARGO_PKG_VERSION_MAJOR")));
    assert!(VOLSAMPLE_VERSION_MINOR == parse_u32(env!("CARGO_PKG_VERSION_MINOR")));
    assert!(VOLSAMPLE_VERSION_PATCH == parse_u32(env!("CARGO_PKG_VERSION_PATCH")));
    assert!(
        VOLSAMPLE_VERSION
            == VOLSAMPLE_VERSION_MAJOR * 10000
                + VOLSAMPLE_VERSION_MINOR * 100
                + VOLSAMPLE_VERSION_PATCH
    );
};

/// The linked library's version, `major·10000 + minor·100 + patch`: equal to the header's
/// `VOLSAMPLE_VERSION` when header and library match.
#[no_mangle]
pub extern "C" fn vs_version() -> u32 {
    VOLSAMPLE_VERSION
}

/// Success.
pub const VS_OK: i32 = 0;
/// A required pointer was null.
pub const VS_ERR_NULL: i32 = -1;
/// An unknown mode, filter or order constant, or a combination the kernels do not offer.
pub const VS_ERR_ARG: i32 = -2;
/// The voxel count does not match the dimensions, a dimension is 0 or too large, or a
/// premultiplied voxel has a color above its opacity.
pub const VS_ERR_VOLUME: i32 = -3;
/// The step is not finite and positive, or so small that a ray would take too many samples.
pub const VS_ERR_STEP: i32 = -4;
/// The ray origin is not finite or its direction is zero or not finite.
pub const VS_ERR_RAY: i32 = -5;
/// The early-termination threshold is outside `(0, 1]` (float) or `(0, 65280]` (integer).
pub const VS_ERR_THRESHOLD: i32 = -6;
/// Another input error.
pub const VS_ERR_OTHER: i32 = -99;

/// Interpolate color and opacity separately (the flawed baseline; straight voxels).
pub const VS_MODE_SEPARATE: u32 = 0;
/// Opacity-weighted color interpolation (Wittenbrink 1998; straight voxels).
pub const VS_MODE_OPACITY_WEIGHTED: u32 = 1;
/// Interpolate stored premultiplied colors (Drebin 1988; premultiplied voxels).
pub const VS_MODE_PREWEIGHTED: u32 = 2;

/// Nearest neighbour.
pub const VS_FILTER_NEAREST: u32 = 0;
/// Trilinear, as a sum of 8 weighted products.
pub const VS_FILTER_TRILINEAR: u32 = 1;
/// Trilinear, as a binary tree of lerps (float kernels only).
pub const VS_FILTER_TRILINEAR_TREE: u32 = 2;
/// Triquadratic B-spline, 27 taps (float kernels only).
pub const VS_FILTER_TRIQUADRATIC: u32 = 3;

/// Composite front to back.
pub const VS_ORDER_FRONT_TO_BACK: u32 = 0;
/// Composite back to front.
pub const VS_ORDER_BACK_TO_FRONT: u32 = 1;

/// Opacity 1 of a U8.8 integer sample (`255·256`).
pub const VS_INT_ONE: u16 = 65280;
const _: () = assert!(VS_INT_ONE == volsample::fixed_point::ONE);

/// A float associated sample: color `c` (premultiplied) and opacity `a`, `0 ≤ c ≤ a ≤ 1`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct VsSample {
    /// Associated color.
    pub c: [f32; 3],
    /// Opacity.
    pub a: f32,
}

/// An integer associated sample in U8.8 (`raw/256` u8 levels; opacity 1 is `VS_INT_ONE`).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct VsIntSample {
    /// Associated color.
    pub c: [u16; 3],
    /// Opacity.
    pub a: u16,
}

/// A volume of RGBA byte voxels: `count` voxels of 4 bytes at `rgba`, which must be
/// `nx·ny·nz` (else `VS_ERR_VOLUME`).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct VsVolumeU8 {
    /// The voxel bytes, `4·count` of them.
    pub rgba: *const u8,
    /// Voxels at `rgba` (the buffer's size in voxels).
    pub count: usize,
    /// Voxels along x.
    pub nx: usize,
    /// Voxels along y.
    pub ny: usize,
    /// Voxels along z.
    pub nz: usize,
}

/// How a float ray is marched.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct VsMarch {
    /// `VS_MODE_*`.
    pub mode: u32,
    /// `VS_FILTER_*`.
    pub filter: u32,
    /// `VS_ORDER_*`.
    pub order: u32,
    /// Step `d` in voxels (the voxel opacities hold for one voxel; `d ≠ 1` corrects them).
    pub step: f32,
    /// Start phase in `[0, 1)`.
    pub phase: f32,
    /// Front to back: stop once the opacity reaches this (`1` never stops early).
    pub a_stop: f32,
}

// The voxel types are one-field tuple structs over `[u8; 4]`. With size 4 and alignment 1 the
// field fills the struct at offset 0, and every byte pattern is a valid voxel, so a slice of
// 4-byte groups may be viewed as a slice of them. (`#[repr(transparent)]` on them in the core
// would make this a documented guarantee.)
const _: () = {
    assert!(core::mem::size_of::<StraightU8>() == 4 && core::mem::align_of::<StraightU8>() == 1);
    assert!(
        core::mem::size_of::<AssociatedU8>() == 4 && core::mem::align_of::<AssociatedU8>() == 1
    );
};

fn status(e: Error) -> i32 {
    match e {
        Error::LengthMismatch { .. }
        | Error::ZeroDimension { .. }
        | Error::DimensionTooLarge
        | Error::ColorExceedsOpacity { .. } => VS_ERR_VOLUME,
        Error::InvalidStep | Error::InvalidPhase | Error::TooManySamples => VS_ERR_STEP,
        Error::InvalidRay => VS_ERR_RAY,
        Error::InvalidThreshold => VS_ERR_THRESHOLD,
        _ => VS_ERR_OTHER,
    }
}

/// The voxels of `v` as a slice of `V` (one of the 4-byte voxel types).
///
/// # Safety
/// `v.rgba` must be null or point to `4·count` readable bytes that stay unchanged for `'a`.
unsafe fn voxels<'a, V>(v: &VsVolumeU8) -> Result<&'a [V], i32> {
    const { assert!(core::mem::size_of::<V>() == 4 && core::mem::align_of::<V>() == 1) };
    if v.rgba.is_null() {
        return Err(VS_ERR_NULL);
    }
    let n = v.count;
    if n > isize::MAX as usize / 4 {
        return Err(VS_ERR_VOLUME);
    }
    // SAFETY: non-null, `n` voxels of 4 bytes readable by the caller's contract, alignment 1,
    // every byte pattern valid (see the layout assertion above).
    Ok(unsafe { core::slice::from_raw_parts(v.rgba.cast::<V>(), n) })
}

fn volume<'a, V: Voxel>(data: &'a [V], v: &VsVolumeU8) -> Result<Volume<'a, V>, i32> {
    Volume::new(data, [v.nx, v.ny, v.nz]).map_err(status)
}

/// Writes `x` through `out` (checked for null).
///
/// # Safety
/// `out` must be null or valid for a write of `T`.
unsafe fn put<T>(out: *mut T, x: Result<T, i32>) -> i32 {
    if out.is_null() {
        return VS_ERR_NULL;
    }
    match x {
        Ok(x) => {
            // SAFETY: non-null and valid for writes by the caller's contract.
            unsafe { out.write(x) };
            VS_OK
        }
        Err(e) => e,
    }
}

/// Three consecutive values at `p`, or `None` for null.
///
/// # Safety
/// `p` must be null or point to 3 readable, initialised values.
unsafe fn vec3<T: Copy>(p: *const T) -> Option<&'static [T; 3]> {
    // SAFETY: non-null pointers point to 3 values by the caller's contract; `[T; 3]` has the
    // alignment of `T`. The 'static lifetime does not escape the calling function.
    unsafe { p.cast::<[T; 3]>().as_ref() }
}

fn to_c(s: Sample) -> VsSample {
    VsSample { c: s.c, a: s.a }
}

fn to_c_int(s: IntSample) -> VsIntSample {
    VsIntSample { c: s.c(), a: s.a() }
}

/// Casts one ray with mode `M` and filter `F` over voxels `V`, dispatching the order.
fn cast_with<V: Voxel, M: Mode<V> + Copy, F: Filter>(
    vol: Volume<'_, V>,
    mode: M,
    f: F,
    m: &VsMarch,
    ray: &Ray,
) -> Result<Sample, i32> {
    fn go<V: Voxel, M: Mode<V> + Copy, F: Filter, O: Order>(
        vol: Volume<'_, V>,
        mode: M,
        f: F,
        o: O,
        m: &VsMarch,
        ray: &Ray,
    ) -> Result<Sample, i32> {
        let step = Step::new(m.step)
            .and_then(|s| s.with_phase(m.phase))
            .map_err(status)?;
        let marcher = RayMarcher::new(vol, mode, f, o, step).map_err(status)?;
        Ok(marcher.cast(ray))
    }
    match m.order {
        VS_ORDER_FRONT_TO_BACK if m.a_stop == 1.0 => go(vol, mode, f, FrontToBack::new(), m, ray),
        VS_ORDER_FRONT_TO_BACK => {
            let o = FrontToBack::with_threshold(m.a_stop).map_err(status)?;
            go(vol, mode, f, o, m, ray)
        }
        VS_ORDER_BACK_TO_FRONT => go(vol, mode, f, BackToFront, m, ray),
        _ => Err(VS_ERR_ARG),
    }
}

/// What every cast entry point does: check the pointers and that `march` names this entry
/// point's mode and filter (`ids`), view the voxels as `V`, cast, write `out` on success.
///
/// # Safety
/// As `vs_cast_u8`.
unsafe fn cast_entry<V: Voxel, M: Mode<V> + Copy, F: Filter>(
    (vol, march, origin, dir, out): CastArgs,
    mode: M,
    f: F,
    ids: (u32, u32),
) -> i32 {
    // SAFETY: each pointer is null (rejected) or valid by the caller's contract.
    let (Some(v), Some(m), Some(o), Some(d)) = (
        unsafe { vol.as_ref() },
        unsafe { march.as_ref() },
        unsafe { vec3(origin) },
        unsafe { vec3(dir) },
    ) else {
        return VS_ERR_NULL;
    };
    let r = (|| {
        if (m.mode, m.filter) != ids {
            return Err(VS_ERR_ARG);
        }
        let ray = Ray::new(*o, *d).map_err(status)?;
        // SAFETY: the caller's contract on `vol->rgba`.
        let data = unsafe { voxels::<V>(v) }?;
        cast_with(volume(data, v)?, mode, f, m, &ray)
    })();
    // SAFETY: the caller's contract on `out`.
    unsafe { put(out, r.map(to_c)) }
}

/// The arguments of a cast: volume, march, origin, direction, out.
type CastArgs = (
    *const VsVolumeU8,
    *const VsMarch,
    *const f32,
    *const f32,
    *mut VsSample,
);

/// Integrates one ray through a volume of RGBA bytes and composites it over transparent black,
/// with the mode and filter `march` names (`march->mode`, `march->filter`).
///
/// This entry point links every mode × filter (about 126 KB of Cortex-M4F code); a firmware
/// image that needs one calls its own entry point (`vs_cast_u8_opacity_weighted_trilinear`
/// and the others below), which links only that kernel.
///
/// Returns `VS_OK` and writes `*out`, or a `VS_ERR_*` status (`*out` untouched).
///
/// # Safety
/// `vol` and `march` must be valid pointers (or null: `VS_ERR_NULL`), `vol->rgba` must point to
/// `4·count` bytes, `origin` and `dir` to 3 floats each (x, y, z), `out` to a writable `VsSample`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    // SAFETY: null (rejected) or valid by the caller's contract.
    let Some(m) = (unsafe { march.as_ref() }) else {
        return VS_ERR_NULL;
    };
    let entry = match (m.mode, m.filter) {
        (VS_MODE_SEPARATE, VS_FILTER_NEAREST) => vs_cast_u8_separate_nearest,
        (VS_MODE_SEPARATE, VS_FILTER_TRILINEAR) => vs_cast_u8_separate_trilinear,
        (VS_MODE_SEPARATE, VS_FILTER_TRILINEAR_TREE) => vs_cast_u8_separate_trilinear_tree,
        (VS_MODE_SEPARATE, VS_FILTER_TRIQUADRATIC) => vs_cast_u8_separate_triquadratic,
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_NEAREST) => vs_cast_u8_opacity_weighted_nearest,
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR) => vs_cast_u8_opacity_weighted_trilinear,
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR_TREE) => {
            vs_cast_u8_opacity_weighted_trilinear_tree
        }
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRIQUADRATIC) => {
            vs_cast_u8_opacity_weighted_triquadratic
        }
        (VS_MODE_PREWEIGHTED, VS_FILTER_NEAREST) => vs_cast_u8_preweighted_nearest,
        (VS_MODE_PREWEIGHTED, VS_FILTER_TRILINEAR) => vs_cast_u8_preweighted_trilinear,
        (VS_MODE_PREWEIGHTED, VS_FILTER_TRILINEAR_TREE) => vs_cast_u8_preweighted_trilinear_tree,
        (VS_MODE_PREWEIGHTED, VS_FILTER_TRIQUADRATIC) => vs_cast_u8_preweighted_triquadratic,
        _ => return VS_ERR_ARG,
    };
    // SAFETY: forwarded unchanged; same contract.
    unsafe { entry(vol, march, origin, dir, out) }
}

/// `vs_cast_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_NEAREST` only (straight voxels); any
/// other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_separate_nearest(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_SEPARATE, VS_FILTER_NEAREST);
    // SAFETY: the caller's contract.
    unsafe {
        cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), Separate, Nearest, ids)
    }
}

/// `vs_cast_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_TRILINEAR` only (straight voxels); any
/// other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_separate_trilinear(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_SEPARATE, VS_FILTER_TRILINEAR);
    let f = Trilinear::new();
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), Separate, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_TRILINEAR_TREE` only (straight voxels);
/// any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_separate_trilinear_tree(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_SEPARATE, VS_FILTER_TRILINEAR_TREE);
    let f = Trilinear::tree();
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), Separate, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_TRIQUADRATIC` only (straight voxels);
/// any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_separate_triquadratic(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_SEPARATE, VS_FILTER_TRIQUADRATIC);
    let f = TriquadraticBSpline;
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), Separate, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_NEAREST` only (straight
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_opacity_weighted_nearest(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_NEAREST);
    let (m, f) = (OpacityWeighted, Nearest);
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_TRILINEAR` only (straight
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_opacity_weighted_trilinear(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR);
    let (m, f) = (OpacityWeighted, Trilinear::new());
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_TRILINEAR_TREE` only (straight
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_opacity_weighted_trilinear_tree(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR_TREE);
    let (m, f) = (OpacityWeighted, Trilinear::tree());
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_TRIQUADRATIC` only (straight
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_opacity_weighted_triquadratic(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRIQUADRATIC);
    let (m, f) = (OpacityWeighted, TriquadraticBSpline);
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<StraightU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_NEAREST` only (premultiplied
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_preweighted_nearest(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_PREWEIGHTED, VS_FILTER_NEAREST);
    let (m, f) = (Preweighted, Nearest);
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<AssociatedU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_TRILINEAR` only (premultiplied
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_preweighted_trilinear(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_PREWEIGHTED, VS_FILTER_TRILINEAR);
    let (m, f) = (Preweighted, Trilinear::new());
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<AssociatedU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_TRILINEAR_TREE` only (premultiplied
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_preweighted_trilinear_tree(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_PREWEIGHTED, VS_FILTER_TRILINEAR_TREE);
    let (m, f) = (Preweighted, Trilinear::tree());
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<AssociatedU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// `vs_cast_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_TRIQUADRATIC` only (premultiplied
/// voxels); any other `march->mode` or `march->filter` is `VS_ERR_ARG`.
///
/// # Safety
/// As `vs_cast_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_cast_u8_preweighted_triquadratic(
    vol: *const VsVolumeU8,
    march: *const VsMarch,
    origin: *const f32,
    dir: *const f32,
    out: *mut VsSample,
) -> i32 {
    let ids = (VS_MODE_PREWEIGHTED, VS_FILTER_TRIQUADRATIC);
    let (m, f) = (Preweighted, TriquadraticBSpline);
    // SAFETY: the caller's contract.
    unsafe { cast_entry::<AssociatedU8, _, _>((vol, march, origin, dir, out), m, f, ids) }
}

/// What every integer sample entry point does: check the pointers, view the voxels as `V`,
/// sample, write `out` on success.
///
/// # Safety
/// As `vs_int_sample_u8`.
unsafe fn int_entry<V: Voxel, M: IntMode<V>, F: IntFilter>(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
    mode: M,
    f: F,
) -> i32 {
    // SAFETY: null (rejected) or valid by the caller's contract.
    let (Some(v), Some(p)) = (unsafe { vol.as_ref() }, unsafe { vec3(pos_raw) }) else {
        return VS_ERR_NULL;
    };
    let pos = IntPos::<8>::from_raw(*p);
    // SAFETY: the caller's contract on `vol->rgba`.
    let r = unsafe { voxels::<V>(v) }
        .and_then(|data| volume(data, v))
        .map(|vol| IntSampler::new(vol, mode, f).sample(pos));
    // SAFETY: the caller's contract on `out`.
    unsafe { put(out, r.map(to_c_int)) }
}

/// One integer sample at `pos_raw` (voxel units with 8 fractional bits, so `128` is half a
/// voxel), bit-exact with the Rust kernels. Filters: `VS_FILTER_NEAREST`, `VS_FILTER_TRILINEAR`.
///
/// Links every integer mode × filter; `vs_int_sample_u8_opacity_weighted_trilinear` and the
/// others below link only their own.
///
/// # Safety
/// As `vs_cast_u8`: `vol` valid with its bytes, `pos_raw` 3 readable `uint32_t` (x, y, z), `out`
/// writable.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8(
    vol: *const VsVolumeU8,
    mode: u32,
    filter: u32,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    let entry = match (mode, filter) {
        (VS_MODE_SEPARATE, VS_FILTER_NEAREST) => vs_int_sample_u8_separate_nearest,
        (VS_MODE_SEPARATE, VS_FILTER_TRILINEAR) => vs_int_sample_u8_separate_trilinear,
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_NEAREST) => vs_int_sample_u8_opacity_weighted_nearest,
        (VS_MODE_OPACITY_WEIGHTED, VS_FILTER_TRILINEAR) => {
            vs_int_sample_u8_opacity_weighted_trilinear
        }
        (VS_MODE_PREWEIGHTED, VS_FILTER_NEAREST) => vs_int_sample_u8_preweighted_nearest,
        (VS_MODE_PREWEIGHTED, VS_FILTER_TRILINEAR) => vs_int_sample_u8_preweighted_trilinear,
        _ if vol.is_null() || pos_raw.is_null() || out.is_null() => return VS_ERR_NULL,
        _ => return VS_ERR_ARG,
    };
    // SAFETY: forwarded unchanged; same contract.
    unsafe { entry(vol, pos_raw, out) }
}

/// `vs_int_sample_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_NEAREST` (straight voxels).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_separate_nearest(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { int_entry::<StraightU8, _, _>(vol, pos_raw, out, Separate, Nearest) }
}

/// `vs_int_sample_u8` with `VS_MODE_SEPARATE` and `VS_FILTER_TRILINEAR` (straight voxels).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_separate_trilinear(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    let f = Trilinear::new();
    // SAFETY: the caller's contract.
    unsafe { int_entry::<StraightU8, _, _>(vol, pos_raw, out, Separate, f) }
}

/// `vs_int_sample_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_NEAREST` (straight
/// voxels).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_opacity_weighted_nearest(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { int_entry::<StraightU8, _, _>(vol, pos_raw, out, OpacityWeighted, Nearest) }
}

/// `vs_int_sample_u8` with `VS_MODE_OPACITY_WEIGHTED` and `VS_FILTER_TRILINEAR` (straight
/// voxels): the smallest entry point (see the firmware README for its size).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_opacity_weighted_trilinear(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    let f = Trilinear::new();
    // SAFETY: the caller's contract.
    unsafe { int_entry::<StraightU8, _, _>(vol, pos_raw, out, OpacityWeighted, f) }
}

/// `vs_int_sample_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_NEAREST` (premultiplied
/// voxels).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_preweighted_nearest(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    // SAFETY: the caller's contract.
    unsafe { int_entry::<AssociatedU8, _, _>(vol, pos_raw, out, Preweighted, Nearest) }
}

/// `vs_int_sample_u8` with `VS_MODE_PREWEIGHTED` and `VS_FILTER_TRILINEAR` (premultiplied
/// voxels).
///
/// # Safety
/// As `vs_int_sample_u8`.
#[no_mangle]
pub unsafe extern "C" fn vs_int_sample_u8_preweighted_trilinear(
    vol: *const VsVolumeU8,
    pos_raw: *const u32,
    out: *mut VsIntSample,
) -> i32 {
    let f = Trilinear::new();
    // SAFETY: the caller's contract.
    unsafe { int_entry::<AssociatedU8, _, _>(vol, pos_raw, out, Preweighted, f) }
}

/// Composites `n` integer samples front to back, stopping once the opacity reaches `a_stop`
/// (`VS_INT_ONE` never stops early); writes the composite and, if `used` is not null, the
/// number of samples used.
///
/// # Safety
/// `samples` must point to `n` valid `VsIntSample`s (or be null with `n = 0`), `out` writable,
/// `used` null or writable.
#[no_mangle]
pub unsafe extern "C" fn vs_int_composite_f2b(
    samples: *const VsIntSample,
    n: usize,
    a_stop: u16,
    out: *mut VsIntSample,
    used: *mut usize,
) -> i32 {
    let s: &[VsIntSample] = if n == 0 {
        &[]
    } else if samples.is_null() {
        return VS_ERR_NULL;
    } else {
        // SAFETY: `n` samples readable by the caller's contract; `VsIntSample` is plain data.
        unsafe { core::slice::from_raw_parts(samples, n) }
    };
    let r = IntStop::new(a_stop).map_err(status).and_then(|stop| {
        let mut bad = false;
        let it = s.iter().map(|x| {
            IntSample::new(x.c, x.a).unwrap_or_else(|_| {
                bad = true;
                IntSample::TRANSPARENT
            })
        });
        let (acc, k) = composite_front_to_back(it, stop);
        if bad {
            Err(VS_ERR_OTHER)
        } else {
            Ok((acc, k))
        }
    });
    if let (Ok((_, k)), false) = (&r, used.is_null()) {
        // SAFETY: non-null and writable by the caller's contract.
        unsafe { used.write(*k) };
    }
    // SAFETY: the caller's contract on `out`.
    unsafe { put(out, r.map(|(acc, _)| to_c_int(acc))) }
}

/// Opacity correction of one sample to the step ratio `d/d′`:
/// `α_d = 1 − (1 − α)^ratio`, `C̃_d = C̃·α_d/α`.
#[no_mangle]
pub extern "C" fn vs_correct(s: VsSample, ratio: f32) -> VsSample {
    to_c(volsample::opacity::correct(
        Sample { c: s.c, a: s.a },
        ratio,
    ))
}

/// One extinction step over length `d`: `α = 1 − e^(−τd)`, `C̃ = C^τ·α/τ`.
#[no_mangle]
pub extern "C" fn vs_integrate_step(
    c_tau_r: f32,
    c_tau_g: f32,
    c_tau_b: f32,
    tau: f32,
    d: f32,
) -> VsSample {
    let i = Interp {
        c: [c_tau_r, c_tau_g, c_tau_b],
        a: tau,
    };
    to_c(<ExtinctionWeighted as Mode<ExtinctionF32>>::finish(
        &ExtinctionWeighted,
        i,
        d,
    ))
}

/// `⌊C·α/255 + ½⌋`: a straight color byte premultiplied by an opacity byte.
#[no_mangle]
pub extern "C" fn vs_premultiply(c: u8, a: u8) -> u8 {
    premultiply(c, a)
}

/// `⌊255·C̃/α + ½⌋` (saturated; 0 when `α = 0`): the straight color of a premultiplied byte.
#[no_mangle]
pub extern "C" fn vs_unpremultiply(c: u8, a: u8) -> u8 {
    unpremultiply(c, a)
}

#[cfg(not(test))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // No kernel can panic (the firmware stage checks it); should one ever, do not unwind into C.
    loop {
        black_box(());
    }
}
