//! Reconstruction filters: *where* the taps come from and with which weights.
//!
//! All filters clamp to the edge: a tap outside the grid reads the nearest edge voxel, so a
//! sample exactly on the last voxel plane (`x = n − 1`) or anywhere outside is well defined.
//!
//! | filter | taps | weights |
//! |---|---|---|
//! | [`Nearest`] | 1 | voxel `⌊x + ½⌋` |
//! | [`Trilinear`] | 8 | `(1 − f, f)` per axis, `f = x − ⌊x⌋`; two evaluation orders |
//! | [`TriquadraticBSpline`] | 27 | `((½ − t)²/2, ¾ − t², (½ + t)²/2)` per axis, `t = x − ⌊x + ½⌋` |
//!
//! The weights of every filter add up to exactly 1 in floating point (weight 0 is computed as
//! 1 minus the others, in the order the kernels sum them), so constant data, in particular an
//! opaque region, is reproduced exactly.

use crate::each::Each;
use crate::lanes::{pack, unpack, F32x4};
use crate::mode::{lane_taps, linear_weighted8_f32, pack_interp, tap_columns, LaneVisitor, Mode};
use crate::num::Num;
use crate::sample::Interp;
use crate::volume::Volume;
use crate::voxel::{ExtinctionF32, Voxel};

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Nearest {}
    impl<O: super::TrilinearOrder> Sealed for super::Trilinear<O> {}
    impl Sealed for super::TriquadraticBSpline {}
    impl Sealed for super::Tree {}
    impl Sealed for super::WeightedSum {}
}

/// A reconstruction filter.
pub trait Filter: sealed::Sealed + Copy + Default + core::fmt::Debug {
    /// Number of voxels read per sample.
    const TAPS: usize;

    /// Whether the lane kernels run with this filter (`true`): [`RayMarcher::cast4`]
    /// marching four rays in lanes, and [`RayMarcher::cast`] computing four consecutive
    /// samples in lanes; with `false` rays and samples go one by one (the results are the same
    /// bit for bit either way). One tap per sample leaves [`Nearest`] too little arithmetic
    /// to share among the lanes: in packets it ran 1.2–1.9× slower in `volsample report`.
    ///
    /// [`RayMarcher::cast4`]: crate::RayMarcher::cast4
    /// [`RayMarcher::cast`]: crate::RayMarcher::cast
    #[doc(hidden)]
    const PACKETS: bool = true;

    /// Runs `visitor` for the eight-lane kernel (the AVX2 instance of
    /// [`RayMarcher::cast_rays`](crate::RayMarcher::cast_rays) and `cast`) of `mode` with
    /// this filter, where there is one: [`Trilinear`]`<`[`WeightedSum`]`>` passes it on to
    /// the mode ([`Mode::lanes8`]); the filter's and the mode's types pick the kernel.
    /// `Err(visitor)` for the other filters.
    #[doc(hidden)]
    #[inline(always)]
    fn lanes8<V: Voxel, M: Mode<V>, X: LaneVisitor>(mode: &M, visitor: X) -> Result<X::Out, X> {
        let _ = mode;
        Err(visitor)
    }

    /// Reconstructs the quantities `mode` interpolates at `pos` (voxel units).
    fn interpolate<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [f32; 3],
    ) -> Interp<f32>;

    /// [`interpolate`](Self::interpolate) at four positions, lane `l` at `pos[l]` and
    /// bit-identical to `interpolate` there (the packet kernels of
    /// [`RayMarcher::cast4`](crate::RayMarcher::cast4)). The default runs `interpolate` per
    /// lane; [`Trilinear`] gathers per lane and computes weights and sums in lanes.
    #[inline(always)]
    #[doc(hidden)]
    fn interpolate_x4<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [[f32; 3]; 4],
    ) -> Interp<F32x4> {
        pack_interp(pos.each(|p| Self::interpolate(mode, vol, p)))
    }
}

/// `⌊x⌋`, bit for bit `libm::floorf` for every `f32` (a test checks all 2³²). On x86-64:
/// below 2²³ in magnitude by truncation to `i32`, one less where that rounded up, with the
/// sign of `x` (so `⌊−0⌋ = −0`); from 2²³ on every `f32` is an integer, and infinities and
/// NaN pass through. There libm's portable `floorf` branches on the exponent (it uses
/// `roundss` only in a build for SSE4.1 or later, which a default build is not), and with it
/// `RayMarcher::sample` inlined into a caller's loop was slower than with this one (by 5–13 %
/// in the bench's random-access row; the performance log, 2026-12-07 (evening)). Elsewhere
/// `libm::floorf` itself, so that the Cortex-M images keep their code.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn floor(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let t = (x as i32) as f32;
        let f = if t > x { t - 1.0 } else { t };
        f.copysign(x)
    } else {
        x
    }
}

/// `⌊x⌋`: `libm::floorf` (see the x86-64 form above).
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
pub(crate) fn floor(x: f32) -> f32 {
    libm::floorf(x)
}

/// Splits a coordinate into `⌊x⌋` and the fraction `x − ⌊x⌋`.
#[inline(always)]
fn split(x: f32) -> (isize, f32) {
    let fl = floor(x);
    // `as` saturates (and maps NaN to 0), so no coordinate can overflow.
    (fl as isize, x - fl)
}

/// `⌊x + ½⌋` (round half up), exactly: `x − ⌊x⌋` is exact in `f32`, `x + ½` is not — for
/// the `x` one ulp below a half-integer it rounds up to the integer (`0.49999997 + 0.5 = 1`),
/// which made [`Nearest`] read the wrong voxel.
#[inline(always)]
fn round_half_up(x: f32) -> isize {
    let (i, f) = split(x);
    if f >= 0.5 {
        i.saturating_add(1)
    } else {
        i
    }
}

/// Nearest neighbour: the voxel at `⌊x + ½⌋` per axis (round half up).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Nearest;

impl Filter for Nearest {
    const TAPS: usize = 1;
    const PACKETS: bool = false;

    #[inline(always)]
    fn interpolate<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [f32; 3],
    ) -> Interp<f32> {
        let [x, y, z] = pos.each(round_half_up);
        mode.weighted(&[vol.fetch_clamped(x, y, z)], &[1.0f32])
    }
}

/// The evaluation order of trilinear interpolation (Wittenbrink Table 1).
pub trait TrilinearOrder: sealed::Sealed + Copy + Default + core::fmt::Debug {
    /// [`Filter::lanes8`] of [`Trilinear`] in this order: `Err(visitor)` but for
    /// [`WeightedSum`], the order of the eight-lane kernels.
    #[doc(hidden)]
    #[inline(always)]
    fn lanes8<V: Voxel, M: Mode<V>, X: LaneVisitor>(mode: &M, visitor: X) -> Result<X::Out, X> {
        let _ = mode;
        Err(visitor)
    }

    /// `vol` as [`ExtinctionF32`] voxels where `M` is `ExtinctionWeighted` over them and
    /// this order reads such taps in place ([`WeightedSum`] in builds where
    /// `EXTINCTION_F32_IN_PLACE`), else `None`.
    #[doc(hidden)]
    #[inline(always)]
    fn extinction_in_place<'a, V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'a, V>,
    ) -> Option<Volume<'a, ExtinctionF32>> {
        let _ = (mode, vol);
        None
    }

    /// Interpolates the 8 taps of a cell (tap `i` at corner `(i & 1, (i >> 1) & 1, i >> 2)`)
    /// at fractions `f`.
    fn interpolate<T: Num, V: Voxel, M: Mode<V>>(mode: &M, taps: &[V; 8], f: [T; 3]) -> Interp<T>;

    /// [`interpolate`](Self::interpolate) in `f32`: the same arithmetic in the same order
    /// (bit-identical), by the mode's four-lane [`Mode::weighted8_f32`] where the order uses
    /// weights.
    #[inline(always)]
    fn interpolate_f32<V: Voxel, M: Mode<V>>(mode: &M, taps: &[V; 8], f: [f32; 3]) -> Interp<f32> {
        Self::interpolate(mode, taps, f)
    }

    /// [`interpolate_f32`](Self::interpolate_f32) for four cells in lanes (tap `k` of cell
    /// `l` is `taps[k][l]`, its fractions lane `l` of `f`), lane by lane bit-identical. The
    /// default runs `interpolate_f32` per lane.
    #[inline(always)]
    fn interpolate_x4<V: Voxel, M: Mode<V>>(
        mode: &M,
        taps: &[[V; 4]; 8],
        f: [F32x4; 3],
    ) -> Interp<F32x4> {
        let cells = lane_taps(taps);
        let mut out = [Interp::default(); 4];
        for ((o, cell), f) in out.iter_mut().zip(cells.iter()).zip(unpack(f)) {
            *o = Self::interpolate_f32(mode, cell, f);
        }
        pack_interp(out)
    }
}

/// A binary tree of 7 lerps per interpolated channel.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tree;

/// A sum of 8 weighted products per channel, with the weights from [`trilinear_weights`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WeightedSum;

impl TrilinearOrder for Tree {
    #[inline(always)]
    fn interpolate<T: Num, V: Voxel, M: Mode<V>>(mode: &M, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        mode.tree8(taps, f)
    }
}

impl TrilinearOrder for WeightedSum {
    #[inline(always)]
    fn lanes8<V: Voxel, M: Mode<V>, X: LaneVisitor>(mode: &M, visitor: X) -> Result<X::Out, X> {
        mode.lanes8(visitor)
    }

    #[inline(always)]
    fn extinction_in_place<'a, V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'a, V>,
    ) -> Option<Volume<'a, ExtinctionF32>> {
        if EXTINCTION_F32_IN_PLACE {
            mode.extinction_f32(vol)
        } else {
            None
        }
    }

    #[inline(always)]
    fn interpolate<T: Num, V: Voxel, M: Mode<V>>(mode: &M, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        mode.weighted(taps, &trilinear_weights(f))
    }

    #[inline(always)]
    fn interpolate_f32<V: Voxel, M: Mode<V>>(mode: &M, taps: &[V; 8], f: [f32; 3]) -> Interp<f32> {
        mode.weighted8_f32(taps, &trilinear_weights(f))
    }

    #[inline(always)]
    fn interpolate_x4<V: Voxel, M: Mode<V>>(
        mode: &M,
        taps: &[[V; 4]; 8],
        f: [F32x4; 3],
    ) -> Interp<F32x4> {
        mode.weighted8_x4(taps, &trilinear_weights(f))
    }
}

/// The 8 trilinear weights from fractions `[x, y, z]`, indexed like the taps
/// (`w[i]` for corner `(i & 1, (i >> 1) & 1, i >> 2)`).
///
/// Computed as the paper counts them, 4M 19A: the products `xy, xz, yz, xyz` (4M), then
/// `w111 = xyz`, `w110 = xy − xyz`, …, `w001 = z − xz − yz + xyz` (12A), and
/// `w000 = 1 − (w111 + w011 + w101 + w001 + w110 + w010 + w100)` (7A) — the paper's
/// `1 − x − y − z + xy + xz + yz − xyz` in exact arithmetic, but summed in the order the
/// kernels sum, so that the weights add up to exactly 1 in floating point and a constant
/// region is reproduced exactly (see the mode module's `weighted_sums`).
///
/// Error bound: each weight within `4ε` of its exact value (`ε = 2⁻²³` in `f32`); `w000` may
/// be `−4ε` where its exact value is 0 (`TRILINEAR_WEIGHT_ABS` in the tests).
#[inline(always)]
pub fn trilinear_weights<T: Num>(f: [T; 3]) -> [T; 8] {
    let [x, y, z] = f;
    let xy = x * y;
    let xz = x * z;
    let yz = y * z;
    let xyz = xy * z;
    let w110 = xy - xyz;
    let w101 = xz - xyz;
    let w011 = yz - xyz;
    let w100 = x - xy - xz + xyz;
    let w010 = y - xy - yz + xyz;
    let w001 = z - xz - yz + xyz;
    let rest = xyz + w011 + w101 + w001 + w110 + w010 + w100;
    let w000 = T::ONE - rest;
    [w000, w100, w010, w110, w001, w101, w011, xyz]
}

/// Trilinear interpolation, evaluated in the order `O` ([`WeightedSum`] by default, the
/// faster one; [`Tree`] for the paper's comparison).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Trilinear<O: TrilinearOrder = WeightedSum>(pub O);

impl Trilinear<WeightedSum> {
    /// Trilinear as a sum of weighted products (the default order).
    pub const fn new() -> Self {
        Self(WeightedSum)
    }
}

impl Trilinear<Tree> {
    /// Trilinear as a binary tree of lerps.
    pub const fn tree() -> Self {
        Self(Tree)
    }
}

impl<O: TrilinearOrder> Trilinear<O> {
    /// Interpolates the 8 given taps at fractions `f` in this order, with any [`Num`]
    /// (the operation-counting tests run this with a counting type).
    #[inline(always)]
    pub fn interpolate_taps<T: Num, V: Voxel, M: Mode<V>>(
        mode: &M,
        taps: &[V; 8],
        f: [T; 3],
    ) -> Interp<T> {
        O::interpolate(mode, taps, f)
    }

    /// The 8 taps of the cell containing `pos` (clamped to the edge) and the fractions.
    ///
    /// Bit-identical to [`gather_clamped`](Self::gather_clamped), faster where the whole
    /// cell lies inside the grid: there `⌊x⌋` is a truncation, the interior test is one
    /// unsigned compare per axis, and the taps come from [`Volume::cell`] without clamps.
    #[inline(always)]
    pub fn gather<V: Voxel>(vol: &Volume<'_, V>, pos: [f32; 3]) -> ([V; 8], [f32; 3]) {
        match Self::gather_interior(vol, pos, |v| *v) {
            Some(g) => g,
            None => Self::gather_clamped(vol, pos),
        }
    }

    /// The fast path of [`gather`](Self::gather), with `f` applied to each tap in place:
    /// `f` of the taps and the fractions where the whole cell lies inside the grid, else
    /// `None` (then [`gather_clamped`](Self::gather_clamped) applies).
    #[inline(always)]
    fn gather_interior<V: Voxel, R>(
        vol: &Volume<'_, V>,
        pos: [f32; 3],
        f: impl Fn(&V) -> R,
    ) -> Option<([R; 8], [f32; 3])> {
        let [nx, ny, nz] = vol.dims();
        let [x, y, z] = pos;
        // For `x ≥ +0` the bits of an f32 order like its value, while −0, negatives and NaN
        // have bits above every positive bound; so this is `+0 ≤ x < n − 1` (every
        // coordinate below 2²⁴ is exact). −0 takes the clamped path, where its fraction is
        // `−0 − ⌊−0⌋ = +0`.
        let inside = |x: f32, n: usize| x.to_bits() < ((n - 1) as f32).to_bits();
        if inside(x, nx) && inside(y, ny) && inside(z, nz) {
            // `x as i32` truncates, which is `⌊x⌋` for `0 ≤ x < 2²⁴` (and is cheaper than a
            // saturating cast to `usize`); the fraction is then exactly `x − ⌊x⌋`.
            let (xi, yi, zi) = (x as i32, y as i32, z as i32);
            if let Some(taps) = vol.cell_map(xi as usize, yi as usize, zi as usize, f) {
                return Some((taps, [x - xi as f32, y - yi as f32, z - zi as f32]));
            }
        }
        None
    }

    /// One sample of `ExtinctionWeighted` over [`ExtinctionF32`] in the weighted-sum order:
    /// each tap read in place as its four lanes `[C^τ, τ]`, then the mode's sums with the
    /// channels in lanes (what [`gather`](Self::gather) then the mode's `weighted8_f32`
    /// compute from copies of the taps, bit for bit).
    #[inline(always)]
    fn extinction_f32(vol: &Volume<'_, ExtinctionF32>, pos: [f32; 3]) -> Interp<f32> {
        let (u, f) = Self::gather_lanes(vol, pos);
        linear_weighted8_f32(&u, &trilinear_weights(f))
    }

    /// [`gather`](Self::gather) of [`ExtinctionF32`] taps as their lanes `[C^τ, τ]`, the
    /// interior ones read in place.
    #[inline(always)]
    fn gather_lanes(vol: &Volume<'_, ExtinctionF32>, pos: [f32; 3]) -> ([[f32; 4]; 8], [f32; 3]) {
        match Self::gather_interior(vol, pos, ExtinctionF32::lanes) {
            Some(g) => g,
            None => {
                let (taps, f) = Self::gather_clamped(vol, pos);
                (taps.each(|v| v.lanes()), f)
            }
        }
    }

    /// `vol` as [`ExtinctionF32`] voxels where the order reads the taps of `ExtinctionWeighted`
    /// over them in place ([`TrilinearOrder::extinction_in_place`]; the case of
    /// [`extinction_f32`](Self::extinction_f32)), else `None`.
    #[inline(always)]
    fn as_extinction_f32<'a, V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'a, V>,
    ) -> Option<Volume<'a, ExtinctionF32>> {
        O::extinction_in_place(mode, vol)
    }

    /// [`gather`](Self::gather) by the plain path: `⌊x⌋` exactly (`floor`), every tap clamped to
    /// the edge (the reference the fast path is tested against).
    #[inline(always)]
    pub fn gather_clamped<V: Voxel>(vol: &Volume<'_, V>, pos: [f32; 3]) -> ([V; 8], [f32; 3]) {
        let (x, fx) = split(pos[0]);
        let (y, fy) = split(pos[1]);
        let (z, fz) = split(pos[2]);
        (vol.cell_clamped(x, y, z), [fx, fy, fz])
    }
}

impl<O: TrilinearOrder> Filter for Trilinear<O> {
    const TAPS: usize = 8;

    #[inline(always)]
    fn lanes8<V: Voxel, M: Mode<V>, X: LaneVisitor>(mode: &M, visitor: X) -> Result<X::Out, X> {
        O::lanes8(mode, visitor)
    }

    #[inline(always)]
    fn interpolate<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [f32; 3],
    ) -> Interp<f32> {
        if let Some(vol) = Self::as_extinction_f32(mode, vol) {
            return Self::extinction_f32(&vol, pos);
        }
        let (taps, f) = Self::gather(vol, pos);
        O::interpolate_f32(mode, &taps, f)
    }

    #[inline(always)]
    fn interpolate_x4<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [[f32; 3]; 4],
    ) -> Interp<F32x4> {
        let [p0, p1, p2, p3] = pos;
        if let Some(vol) = Self::as_extinction_f32(mode, vol) {
            let e = |p| Self::extinction_f32(&vol, p);
            return pack_interp([e(p0), e(p1), e(p2), e(p3)]);
        }
        let (t0, f0) = Self::gather(vol, p0);
        let (t1, f1) = Self::gather(vol, p1);
        let (t2, f2) = Self::gather(vol, p2);
        let (t3, f3) = Self::gather(vol, p3);
        O::interpolate_x4(mode, &tap_columns([t0, t1, t2, t3]), pack([f0, f1, f2, f3]))
    }
}

/// Whether [`Trilinear`] reads the taps of `ExtinctionWeighted` over [`ExtinctionF32`] in
/// place and sums each sample with its four channels in lanes (`extinction_f32`, also in
/// `cast`'s four-sample lanes), or copies them as for every other mode and format (with the
/// four samples in lanes after a transposition of the taps). Both are bit-identical to one
/// sample at a time.
///
/// In place in builds for CPUs with AVX: there the copies and the transposition left the
/// taps on the stack in pieces of 4, 8 and 12 bytes, and the `ray_march` bench's 16-byte
/// `cast` took 1.86 of `OpacityWeighted`'s time (1.20–1.23 in place). In the baseline x86-64
/// build the copies are faster: 1.08 of `OpacityWeighted`'s `cast`, and the four-ray packets
/// 0.84 (in place with the transposition, 1.10 and 1.03).
const EXTINCTION_F32_IN_PLACE: bool = cfg!(target_feature = "avx");

/// Triquadratic B-spline approximation (27 taps), the filter Kraus pairs with the `a = ⅕`
/// downsampling mask. Not interpolating: it smooths even at voxel centres.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriquadraticBSpline;

/// The quadratic B-spline weights for offset `t = x − ⌊x + ½⌋ ∈ [−½, ½)`, for taps
/// `−1, 0, +1`.
#[inline(always)]
pub fn bspline2_weights(t: f32) -> [f32; 3] {
    let l = 0.5 - t;
    let r = 0.5 + t;
    [0.5 * l * l, 0.75 - t * t, 0.5 * r * r]
}

impl Filter for TriquadraticBSpline {
    const TAPS: usize = 27;

    #[inline(always)]
    fn interpolate<V: Voxel, M: Mode<V>>(
        mode: &M,
        vol: &Volume<'_, V>,
        pos: [f32; 3],
    ) -> Interp<f32> {
        let mut base = [0isize; 3];
        let mut w = [[0.0f32; 3]; 3];
        for ((b, w), p) in base.iter_mut().zip(w.iter_mut()).zip(pos) {
            let i = round_half_up(p);
            *b = i;
            *w = bspline2_weights(p - i as f32);
        }
        let [bx, by, bz] = base;
        let [wx, wy, wz] = w;
        let taps: [V; 27] = crate::each::build(|k| {
            let (dx, dy, dz) = (k % 3, (k / 3) % 3, k / 9);
            vol.fetch_clamped(
                bx.saturating_add(dx as isize - 1),
                by.saturating_add(dy as isize - 1),
                bz.saturating_add(dz as isize - 1),
            )
        });
        let mut weights: [f32; 27] = crate::each::build(|k| {
            let at = |w: &[f32; 3], i: usize| w.get(i).copied().unwrap_or(0.0);
            at(&wx, k % 3) * at(&wy, (k / 3) % 3) * at(&wz, k / 9)
        });
        // Partition of unity in floating point: weight 0 is 1 minus the others, summed in the
        // kernels' order (last to first), so constant data is reproduced exactly.
        let rest = weights.iter().skip(1).rev().fold(0.0f32, |acc, w| acc + w);
        if let Some(w0) = weights.first_mut() {
            *w0 = 1.0 - rest;
        }
        mode.weighted(&taps, &weights)
    }
}
