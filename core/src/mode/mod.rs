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

    /// What one tap contributes to [`weighted8_f32`](Self::weighted8_f32): everything about
    /// the tap that does not depend on the sample position. The float ray marcher keeps the
    /// lanes of the taps a ray has already read ([`TapCache`](crate::TapCache)), so each voxel
    /// is converted about once per cell instead of once per sample.
    fn lanes(&self, tap: V) -> TapLanes;

    /// [`weighted`](Self::weighted) in `f32` for the 8 taps of a trilinear cell: the same
    /// operations in the same order, so bit-identical, computed from the taps'
    /// [`lanes`](Self::lanes) (four lanes per tap, the shape a SIMD kernel needs).
    #[inline(always)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        let [t0, t1, t2, t3, t4, t5, t6, t7] = *taps;
        combine_faces(
            &Face::new(self, [t0, t1, t2, t3]),
            &Face::new(self, [t4, t5, t6, t7]),
            w,
        )
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

/// One tap's part in the weighted sum `Σ (w_i·k_i)·u_i` of [`Mode::weighted8_f32`]: four lanes `u`
/// and a factor `k` on its weight.
///
/// For [`OpacityWeighted`] `u = (C_r, C_g, C_b, 1)` and `k = α`, so the sum is
/// `(Σ ω C, Σ ω)` with `ω = w·α`; for the modes that interpolate their channels linearly
/// `u` holds the channels and `k = 1` (`w·1 = w` exactly).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TapLanes {
    /// The four lanes `(c₀, c₁, c₂, a)` of [`Interp`].
    pub u: [f32; 4],
    /// The factor on the tap's weight.
    pub k: f32,
}

impl TapLanes {
    /// Lanes weighted by the tap's weight alone (`k = 1`).
    #[inline(always)]
    pub const fn linear(u: [f32; 4]) -> Self {
        Self { u, k: 1.0 }
    }
}

/// The [`TapLanes`] of 4 taps: one face of constant `z` of a trilinear cell, in tap order.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Face {
    pub(crate) u: [[f32; 4]; 4],
    pub(crate) k: [f32; 4],
}

impl Face {
    /// The lanes of 4 taps.
    #[inline(always)]
    pub(crate) fn new<V: Voxel, M: Mode<V> + ?Sized>(mode: &M, taps: [V; 4]) -> Self {
        let l = taps.map(|v| mode.lanes(v));
        Self {
            u: l.map(|l| l.u),
            k: l.map(|l| l.k),
        }
    }
}

/// `Σ (w_i·k_i)·u_i` over the lanes of the 8 taps of a cell (taps 0–3 in `lo`, 4–7 in `hi`),
/// summed from the last tap down like [`dot`]: lane `j` is bit-identical to
/// `dot(ω, u, |u| u[j])` with `ω_i = w_i·k_i`. The trilinear kernel of every mode in `f32`.
///
/// Not inlined: on its own the compiler keeps each tap's four lanes in one vector register
/// (x86-64: 8 multiplies and 7 adds of 4 lanes); inlined into a ray loop it fell back to
/// scalar code, 1.4× the instructions per sample.
#[inline(never)]
pub(crate) fn combine_faces(lo: &Face, hi: &Face, w: &[f32; 8]) -> Interp<f32> {
    let [w0, w1, w2, w3, w4, w5, w6, w7] = *w;
    let [k0, k1, k2, k3] = lo.k;
    let [k4, k5, k6, k7] = hi.k;
    let omega = [
        w0 * k0,
        w1 * k1,
        w2 * k2,
        w3 * k3,
        w4 * k4,
        w5 * k5,
        w6 * k6,
        w7 * k7,
    ];
    let [u0, u1, u2, u3] = lo.u;
    let [u4, u5, u6, u7] = hi.u;
    let [c0, c1, c2, a] = dot_lanes8(&omega, &[u0, u1, u2, u3, u4, u5, u6, u7]);
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
