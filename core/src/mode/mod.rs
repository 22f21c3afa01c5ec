//! Sampling modes: *what* is interpolated between voxels (DESIGN.md, "Sampling modes").
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

    /// Interpolates `K` taps as a sum of weighted products (weights `w`, summing to 1).
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T>;

    /// [`weighted`](Self::weighted) in `f32` for the 8 taps of a trilinear cell: the same
    /// operations in the same order, so bit-identical, written over four lanes
    /// `(c₀, c₁, c₂, a)` per tap, the shape a SIMD kernel needs (the float ray marcher's hot
    /// path; on baseline x86-64 the compiler still emits scalar code for it). The default is
    /// `weighted` itself.
    #[inline(always)]
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
}

/// `Σ w_i·x_i`, summed from the *last* tap down to tap 0 (8M 7A for 8 taps).
///
/// The order is part of the contract with the filters: they compute weight 0 as `1 − S`, with
/// `S` the sum of the other weights in exactly this order, so that for `x_i = 1` the result is
/// exactly 1 (`fl(S + fl(1 − S)) = 1` for every `S ∈ [0, 2]`). A constant opaque region then
/// interpolates to `α = 1` exactly, which opacity correction (ill-conditioned at 1) needs.
#[inline(always)]
pub(crate) fn dot<T: Num, X, const K: usize>(w: &[T; K], xs: &[X; K], f: impl Fn(&X) -> T) -> T {
    let mut it = w.iter().zip(xs.iter()).rev();
    match it.next() {
        Some((w0, x0)) => it.fold(*w0 * f(x0), |acc, (w, x)| acc + *w * f(x)),
        None => T::ZERO,
    }
}

/// `Σ x_i` in the order of [`dot`] (last to first).
#[inline(always)]
pub(crate) fn sum<T: Num, const K: usize>(xs: &[T; K]) -> T {
    let mut it = xs.iter().rev();
    match it.next() {
        Some(x0) => it.fold(*x0, |acc, x| acc + *x),
        None => T::ZERO,
    }
}

/// `Σ w_i·u_i` over four lanes per tap, summed from the last tap down like [`dot`]: lane `k`
/// of the result is bit-identical to `dot(w, u, |u| u[k])`.
#[inline(always)]
pub(crate) fn dot_lanes8(w: &[f32; 8], u: &[[f32; 4]; 8]) -> [f32; 4] {
    let mut it = w.iter().zip(u.iter()).rev();
    let mut acc = [0.0f32; 4];
    if let Some((w7, u7)) = it.next() {
        acc = u7.map(|x| *w7 * x);
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
    Interp {
        c: [
            dot(w, ch, |v| v.0[0]),
            dot(w, ch, |v| v.0[1]),
            dot(w, ch, |v| v.0[2]),
        ],
        a: dot(w, ch, |v| v.1),
    }
}

/// Interpolates four linear channels `(c, a)` as lerp trees (28M 56A).
#[inline(always)]
pub(crate) fn linear_tree<T: Num>(ch: &[([T; 3], T); 8], f: [T; 3]) -> Interp<T> {
    Interp {
        c: [
            lerp8(ch.map(|v| v.0[0]), f),
            lerp8(ch.map(|v| v.0[1]), f),
            lerp8(ch.map(|v| v.0[2]), f),
        ],
        a: lerp8(ch.map(|v| v.1), f),
    }
}
