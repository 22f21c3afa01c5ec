//! `ExtinctionWeighted`: extinction-based sampling (Kraus, Bürger 2008, eqs. 18–23).

use super::{
    channels_x4, linear_tree, linear_weighted, linear_weighted8_f32, sealed, weighted_sums,
    LaneMode, LaneVisitor, Linear, Mode, StoredF32x4,
};
use crate::each::Each;
use crate::lanes::{F32x4, Lanes};
use crate::num::Num;
use crate::opacity::{phi_poly_in, PHI_POLY_BELOW};
use crate::sample::{clamped, Interp, Sample};
use crate::volume::Volume;
use crate::voxel::{ExtinctionF32, ExtinctionVoxel};

/// Interpolates extinction `τ` and extinction-weighted color `C^τ`, then integrates over the
/// step: `α = 1 − e^(−τd)`, `C̃ = C^τ·α/τ`.
///
/// Stable forms: for `τd < 1`, `C̃ = C^τ·d·φ(τd)` (finite as `τ → 0`, where it tends to
/// `C^τ·d`) and `α = τd·φ(τd)`, with `φ` by a polynomial
/// ([`phi_poly`](crate::opacity::phi_poly)); for `τd ≥ 1`, `α = −expm1(−τd)` and
/// `C̃ = (C^τ/τ)·α` (no `∞·0` when `τd` overflows). No opacity correction is ever needed:
/// the step enters here.
///
/// Error bound (f32 against the f64 reference on the same stored values, any step `d`): `α`
/// and each `C̃` within `(1 + taps·(1 + d·τ_max))·ε`, `ε = 2⁻²³`, `τ_max` the largest stored
/// `τ` among the taps (the interpolated `τ` is within `taps·ε·τ_max`, and `|∂α/∂τ| ≤ d`;
/// `tolerance::sample_bound` in the tests).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ExtinctionWeighted;

impl sealed::Sealed for ExtinctionWeighted {}

impl<V: ExtinctionVoxel> Mode<V> for ExtinctionWeighted {
    const OPACITY_BASED: bool = false;

    #[inline(always)]
    fn lanes8<X: LaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Ok(visitor.visit(self))
    }

    #[inline(always)]
    fn extinction_f32<'a>(&self, vol: &Volume<'a, V>) -> Option<Volume<'a, ExtinctionF32>> {
        V::as_extinction_f32(vol.data()).map(|d| vol.with_data(d))
    }

    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[V; K], w: &[T; K]) -> Interp<T> {
        linear_weighted(&taps.each(|v| v.extinction::<T>()), w)
    }

    #[inline(always)]
    fn weighted8_f32(&self, taps: &[V; 8], w: &[f32; 8]) -> Interp<f32> {
        let u = taps.each(|v| {
            let ([r, g, b], a) = v.extinction::<f32>();
            [r, g, b, a]
        });
        linear_weighted8_f32(&u, w)
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[V; 8], f: [T; 3]) -> Interp<T> {
        linear_tree(&taps.each(|v| v.extinction::<T>()), f)
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample {
        integrate_step(i.c, i.a, d)
    }

    #[inline(always)]
    fn weighted8_x4(&self, taps: &[[V; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        weighted_sums::<F32x4, Linear, _, 8>(w, taps, |col| {
            channels_x4(*col, |v| v.extinction::<f32>())
        })
    }

    #[inline(always)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, d: f32) -> Interp<T> {
        integrate_in(i, d)
    }
}

/// [`integrate_step`] in any [`Lanes`] (the one extinction step of every kernel), lane by
/// lane bit-identical to it. Where every lane has `x = τd < 1` (the common case), in lanes:
/// `φ` by [`phi_poly`](crate::opacity::phi_poly), `α = x·φ` and `C̃ = C^τ·(d·φ)`, with no
/// branch, so that the lanes vectorise; otherwise `integrate_step` per lane, out of line
/// (with it inlined, `cast` of `ExtinctionWeightedU8` took 28.0–29.0 ns/sample in a probe of
/// the four-lane path, out of line 21.8; in the eight-lane kernel, inlining the lanes' path
/// took the packets from 7.1 to 6.4).
#[inline(always)]
pub(crate) fn integrate_in<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
    let x = i.a.max0() * T::from_f32(d);
    if T::all(x.lt(T::from_f32(PHI_POLY_BELOW))) {
        below_one(i.c, x, d)
    } else {
        integrate_per_lane(i, d)
    }
}

/// The step for `x = τd < 1`: `φ = phi_poly(x)`, `α = x·φ`, `C̃ = C^τ·(d·φ)`, clamped.
#[inline(always)]
fn below_one<T: Lanes>(c_tau: [T; 3], x: T, d: f32) -> Interp<T> {
    let phi = phi_poly_in(x);
    let g = T::from_f32(d) * phi;
    let [r, gr, b] = c_tau;
    clamped(Interp {
        c: [r * g, gr * g, b * g],
        a: x * phi,
    })
}

/// [`integrate_step`] of each lane ([`integrate_in`] where some lane's `τd` is not below 1).
#[cold]
#[inline(never)]
fn integrate_per_lane<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
    crate::sample::per_lane(i, |l| integrate_step(l.c, l.a, d).into())
}

/// One step of the emission–absorption integral with constant `C^τ` and `τ` over length `d`:
/// `α = 1 − e^(−τd)`, `C̃ = C^τ·α/τ` in the stable forms of [`ExtinctionWeighted`]: for
/// `x = τd < 1`, `φ = phi_poly(x)`, `α = x·φ` and `C̃ = C^τ·(d·φ)` (no division, no
/// `expm1f`); from 1 on, `α = −expm1f(−x)` and `C̃ = (C^τ/τ)·α`.
///
/// Error bound: `α` and each `C̃` within `6ε` (`ε = 2⁻²³`) of the exact value for the given
/// `f32` input (`INTEGRATE_STEP_ABS` in the tests). Negative or NaN `τ` is read as 0.
#[inline]
pub fn integrate_step(c_tau: [f32; 3], tau: f32, d: f32) -> Sample {
    let tau = tau.max(0.0);
    let x = tau * d;
    if x < PHI_POLY_BELOW {
        below_one(c_tau, x, d).into()
    } else {
        let a = -libm::expm1f(-x);
        Sample::clamped(c_tau.each(|c| (c / tau) * a), a)
    }
}

impl LaneMode for ExtinctionWeighted {
    type Voxel = ExtinctionF32;
    type Taps = StoredF32x4;
    type W = Linear;
    const LAG: u32 = 1;
    type Correction = crate::opacity::Uncorrected;
    #[inline(always)]
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
        integrate_in(i, d)
    }
}
