//! Sampling modes: *what* is interpolated between voxels.
//!
//! | mode | interpolates | sample `(C̃, α)` |
//! |---|---|---|
//! | [`Separate`] | `C_i`, `α_i` separately | `α = Σ wα`, `C̃ = α·Σ wC` (the flawed baseline) |
//! | [`OpacityWeighted`] | `ω_i = w_i·α_i` | `α = Σ ω`, `C̃ = Σ ω C` (Wittenbrink 1998) |
//! | [`Preweighted`] | stored `C̃_i` | `α = Σ wα`, `C̃ = Σ wC̃` (Drebin 1988) |
//! | [`ExtinctionWeighted`] | `τ_i`, `C^τ_i` | `α = 1 − e^(−τd)`, `C̃ = C^τ·α/τ` (Kraus 2008) |
//! | [`ExtinctionWeightedU8`] | the same, `τ_i` of 8-bit opacities from a [`TauTable`] | as `ExtinctionWeighted` |
//! | [`PostClassified`] | scalar `s_i` | `(C, α) = TF(Σ ws)`, `C̃ = α·C` |
//!
//! A mode is a type implementing [`Mode<V>`] for the voxel formats it can read; the kernels are
//! generic over it, so the choice costs nothing at run time. Every mode offers both trilinear
//! evaluation orders the paper costs (Table 1): a sum of weighted products
//! ([`Mode::weighted`], for any tap count) and a binary tree of 7 lerps per channel
//! ([`Mode::tree8`]).

mod extinction;
mod extinction_u8;
mod lanes8;
mod opacity_weighted;
mod post_classified;
mod preweighted;
mod separate;

pub use extinction::{integrate_step, ExtinctionWeighted};
pub use extinction_u8::{ExtinctionWeightedU8, TauTable};
pub use opacity_weighted::OpacityWeighted;
pub use post_classified::PostClassified;
pub use preweighted::Preweighted;
pub use separate::Separate;

use crate::each::Each;
pub(crate) use lanes8::{
    ByOpacity, LaneMode, LaneVisitor, LaneVoxel, Linear, StoredF32x4, TauOfAlpha8, Unorm8,
    Weighting,
};
// (The AVX2 kernel's stage takes the correction in lanes, x86-64 only.)
#[cfg(target_arch = "x86_64")]
pub(crate) use lanes8::LaneCorrection;
// (The integer lane kernel's visitors, x86-64 only, pass the empty `τ` table.)
#[cfg(target_arch = "x86_64")]
pub(crate) use lanes8::NO_TAUS;

use crate::lanes::{pack, unpack, F32x4, Lanes};
use crate::num::Num;
use crate::sample::{Interp, Sample};
use crate::voxel::Voxel;

pub(crate) mod sealed {
    pub trait Sealed {}
}

/// A sampling mode over voxels of format `V`.
///
/// Sealed: the five modes of this module are the only implementations.
pub trait Mode<V: Voxel>: sealed::Sealed + core::fmt::Debug {
    /// `true` for the modes whose voxel opacities are defined for the reference distance and
    /// need opacity correction when the step differs from it; `false` for
    /// [`ExtinctionWeighted`], which integrates over the step itself.
    const OPACITY_BASED: bool;

    /// Runs `visitor` for the mode's eight-lane kernel, where it has one (`OpacityWeighted`,
    /// `Separate`, `ExtinctionWeightedU8`, `ExtinctionWeighted`): the mode's type picks the
    /// kernel's instance. `Err(visitor)` for the modes without one.
    #[doc(hidden)]
    #[inline(always)]
    fn lanes8<X: LaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Err(visitor)
    }

    /// `vol` as [`ExtinctionF32`](crate::voxel::ExtinctionF32) voxels where the mode is
    /// [`ExtinctionWeighted`] over them, whose trilinear sums are the plain weighted sums of
    /// each tap's stored `[C^τ, τ]` (`linear_weighted8_f32`), so that a filter may read the
    /// taps in place; `None` for every other mode and format.
    #[doc(hidden)]
    #[inline(always)]
    fn extinction_f32<'a>(
        &self,
        vol: &crate::volume::Volume<'a, V>,
    ) -> Option<crate::volume::Volume<'a, crate::voxel::ExtinctionF32>> {
        let _ = vol;
        None
    }

    /// Interpolates `K` taps as a sum of weighted products (weights `w`, summing to 1).
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T>;

    /// [`weighted`](Self::weighted) in `f32` for the 8 taps of a trilinear cell: the same
    /// operations in the same order, so bit-identical, written over four lanes
    /// `(c₀, c₁, c₂, a)` per tap, the shape a SIMD kernel needs (the float ray marcher's hot
    /// path; on baseline x86-64 the compiler still emits scalar code for it). The default is
    /// `weighted` itself.
    #[inline(always)]
    #[doc(hidden)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        self.weighted(taps, w)
    }

    /// Interpolates the 8 taps of a trilinear cell as a binary tree of lerps with fractions
    /// `f = [fx, fy, fz]`; tap `i` is the corner `(i & 1, (i >> 1) & 1, i >> 2)`.
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T>;

    /// Turns the interpolated quantities into an associated sample for a step of length `d`
    /// (used by [`ExtinctionWeighted`] only; the opacity-based modes return opacities for `d′`
    /// and leave correction to the [`Correction`](crate::opacity::Correction) stage).
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample;

    /// [`weighted8_f32`](Self::weighted8_f32) for four cells at once (the packet kernels of
    /// [`RayMarcher::cast4`](crate::RayMarcher::cast4)): tap `k` of cell `l` is `taps[k][l]`,
    /// its weight lane `l` of `w[k]`. Lane `l` of the result is bit-identical to
    /// `weighted8_f32` of cell `l`. The default runs `weighted8_f32` lane by lane; the modes
    /// with a sum of weighted products run the same generic sums on [`F32x4`].
    #[inline(always)]
    #[doc(hidden)]
    fn weighted8_x4(&self, taps: &[[V; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        let weights = unpack(*w);
        let cells = lane_taps(taps);
        let mut out = [Interp::default(); 4];
        for ((o, cell), wl) in out.iter_mut().zip(cells.iter()).zip(weights.iter()) {
            *o = self.weighted8_f32(cell, wl);
        }
        pack_interp(out)
    }

    /// [`finish`](Self::finish) in any [`Lanes`] (`f32`, four or eight lanes): lane `l` of
    /// the result (`c` the associated color, `a` the opacity) is bit-identical to `finish` of
    /// lane `l` (up to the sign of a zero, see [`Lanes::clamp_to`]). The default runs `finish`
    /// lane by lane.
    #[inline(always)]
    #[doc(hidden)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, d: f32) -> Interp<T> {
        crate::sample::per_lane(i, |x| self.finish(x, d).into())
    }
}

/// The four cells of a packet, per lane: `out[l][k] = taps[k][l]`.
#[inline(always)]
pub(crate) fn lane_taps<V: Copy>(taps: &[[V; 4]; 8]) -> [[V; 8]; 4] {
    let [first, ..] = *taps;
    let [v, ..] = first;
    let mut out = [[v; 8]; 4];
    for (k, col) in taps.iter().enumerate() {
        for (cell, x) in out.iter_mut().zip(col) {
            if let Some(slot) = cell.get_mut(k) {
                *slot = *x;
            }
        }
    }
    out
}

/// Four cells as tap columns (the inverse of [`lane_taps`]): `out[k][l] = cells[l][k]`.
#[inline(always)]
pub(crate) fn tap_columns<V: Copy>(cells: [[V; 8]; 4]) -> [[V; 4]; 8] {
    let [c0, c1, c2, c3] = cells;
    let [v, ..] = c0;
    let mut out = [[v; 4]; 8];
    for ((((o, a), b), c), d) in out.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
        *o = [a, b, c, d];
    }
    out
}

/// Four `Interp<f32>` packed into lanes.
#[inline(always)]
pub(crate) fn pack_interp(lanes: [Interp<f32>; 4]) -> Interp<F32x4> {
    let [c0, c1, c2, a] = pack(lanes.each(|x| [x.c[0], x.c[1], x.c[2], x.a]));
    Interp { c: [c0, c1, c2], a }
}

/// The inverse of [`pack_interp`].
#[inline(always)]
pub(crate) fn unpack_interp(i: Interp<F32x4>) -> [Interp<f32>; 4] {
    let [c0, c1, c2] = i.c;
    unpack([c0, c1, c2, i.a]).each(|[c0, c1, c2, a]| Interp { c: [c0, c1, c2], a })
}

/// One tap column of a packet as lanes: `f` of each lane's voxel, `(c, a)` packed.
#[inline(always)]
pub(crate) fn channels_x4<V: Copy>(
    col: [V; 4],
    f: impl Fn(V) -> ([f32; 3], f32),
) -> ([F32x4; 3], F32x4) {
    // Written out: `array::map` here is not always inlined, and this runs 8 times a sample.
    let [v0, v1, v2, v3] = col;
    let ([r0, g0, b0], a0) = f(v0);
    let ([r1, g1, b1], a1) = f(v1);
    let ([r2, g2, b2], a2) = f(v2);
    let ([r3, g3, b3], a3) = f(v3);
    (
        [
            F32x4::from_array([r0, r1, r2, r3]),
            F32x4::from_array([g0, g1, g2, g3]),
            F32x4::from_array([b0, b1, b2, b3]),
        ],
        F32x4::from_array([a0, a1, a2, a3]),
    )
}

/// The sums of weighted products of every mode, written once for every number type (`f32`,
/// `f64`, the lanes): over the `K` taps from the *last* down to tap 0, with `(c, a) =
/// f(tap)` and the weights `W::tap(w_k, a)`, `Σ w_c·c` per color and `Σ` of the `a` terms
/// (`K`M `K−1`A each, and `K`M for `ω` by [`ByOpacity`]). Each tap is converted when its turn
/// comes, so the accumulators and one tap's channels are live at a time (in registers, in
/// the lane kernels).
///
/// The order is part of the contract with the filters: they compute weight 0 as `1 − S`, with
/// `S` the sum of the other weights in exactly this order, so that for `x_i = 1` the sum is
/// exactly 1 (`fl(S + fl(1 − S)) = 1` for every `S ∈ [0, 2]`). A constant opaque region then
/// interpolates to `α = 1` exactly, which opacity correction (ill-conditioned at 1) needs.
#[inline(always)]
pub(crate) fn weighted_sums<T: Num, W: Weighting, X, const K: usize>(
    w: &[T; K],
    taps: &[X; K],
    mut f: impl FnMut(&X) -> ([T; 3], T),
) -> Interp<T> {
    // One loop body, `f` called at one place: with the eight taps written out instead, the
    // AVX2 instance of the skipping marcher (four-lane packets) took 1.15–1.27 of its former
    // time; with this loop, 0.96 in a quick pass.
    let mut acc = Interp {
        c: [T::ZERO; 3],
        a: T::ZERO,
    };
    for (k, (wk, x)) in w.iter().zip(taps.iter()).rev().enumerate() {
        let ([r, g, b], a) = f(x);
        let (wc, wa) = W::tap(*wk, a);
        let [cr, cg, cb] = acc.c;
        acc = if k == 0 {
            Interp {
                c: [wc * r, wc * g, wc * b],
                a: wa,
            }
        } else {
            Interp {
                c: [cr + wc * r, cg + wc * g, cb + wc * b],
                a: acc.a + wa,
            }
        };
    }
    acc
}

/// `Σ w_i·u_i` over four lanes per tap, summed from the last tap down: lane `k` of the result
/// is bit-identical to the [`Linear`] sum of channel `k`. The one sum outside
/// [`weighted_sums`]: the scalar hot path's form, a tap's four channels in the lanes of an
/// array, which the compiler vectorises over channels (written as `weighted_sums` of one
/// [`F32x4`] per tap, it added 588 bytes to the Cortex-M4F `min_float` image).
#[inline(always)]
pub(crate) fn dot_lanes8(w: &[f32; 8], u: &[[f32; 4]; 8]) -> [f32; 4] {
    let mut it = w.iter().zip(u.iter()).rev();
    let mut acc = [0.0f32; 4];
    if let Some((w7, u7)) = it.next() {
        acc = u7.each(|x| *w7 * x);
    }
    for (w, u) in it {
        for (a, x) in acc.iter_mut().zip(u.iter()) {
            *a += *w * *x;
        }
    }
    acc
}

/// [`linear_weighted`] in `f32` over lanes `(c₀, c₁, c₂, a)`: bit-identical.
#[inline(always)]
pub(crate) fn linear_weighted8_f32(u: &[[f32; 4]; 8], w: &[f32; 8]) -> Interp<f32> {
    let [c0, c1, c2, a] = dot_lanes8(w, u);
    Interp { c: [c0, c1, c2], a }
}

/// `a + t·(b − a)`: 1M 2A.
#[inline(always)]
pub(crate) fn lerp<T: Num>(a: T, b: T, t: T) -> T {
    a + t * (b - a)
}

/// Trilinear interpolation of one channel as a binary tree of 7 lerps (7M 14A).
#[inline(always)]
pub(crate) fn lerp8<T: Num>(v: [T; 8], f: [T; 3]) -> T {
    let [v0, v1, v2, v3, v4, v5, v6, v7] = v;
    let [fx, fy, fz] = f;
    let x0 = lerp(v0, v1, fx);
    let x1 = lerp(v2, v3, fx);
    let x2 = lerp(v4, v5, fx);
    let x3 = lerp(v6, v7, fx);
    let y0 = lerp(x0, x1, fy);
    let y1 = lerp(x2, x3, fy);
    lerp(y0, y1, fz)
}

/// Interpolates four linear channels `(c, a)` as sums of weighted products (`K`M `K−1`A each).
#[inline(always)]
pub(crate) fn linear_weighted<T: Num, const K: usize>(
    ch: &[([T; 3], T); K],
    w: &[T; K],
) -> Interp<T> {
    weighted_sums::<T, Linear, _, K>(w, ch, |v| *v)
}

/// Interpolates four linear channels `(c, a)` as lerp trees (28M 56A).
#[inline(always)]
pub(crate) fn linear_tree<T: Num>(ch: &[([T; 3], T); 8], f: [T; 3]) -> Interp<T> {
    Interp {
        c: [
            lerp8(ch.each(|v| v.0[0]), f),
            lerp8(ch.each(|v| v.0[1]), f),
            lerp8(ch.each(|v| v.0[2]), f),
        ],
        a: lerp8(ch.each(|v| v.1), f),
    }
}
