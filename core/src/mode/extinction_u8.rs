//! `ExtinctionWeightedU8`: extinction-based sampling read straight from 8-bit straight RGBA.

use super::{
    channels_x4, integrate_step, linear_tree, linear_weighted, linear_weighted8_f32, sealed,
    weighted_sums, LaneMode, LaneVisitor, Linear, Mode, TauOfAlpha8,
};
use crate::each::Each;
use crate::error::Error;
use crate::lanes::{F32x4, Lanes};
use crate::num::Num;
use crate::sample::{Interp, Sample};
use crate::voxel::{unorm8, ExtinctionF32, StraightF32, StraightU8};

/// The extinction `τ = −ln(1 − α)/d′` of every opacity byte (`α = n/255`) for a reference
/// distance `d′`, with the optical depth capped as [`ExtinctionF32::from_straight`] caps it:
/// 256 `f32` (1 KiB), built once per volume.
///
/// ```
/// use volsample::mode::TauTable;
/// let t = TauTable::new(0.5)?;
/// assert_eq!(t.tau(0), 0.0);
/// assert!((t.tau(128) - (-(1.0f32 - 128.0 / 255.0).ln() / 0.5)).abs() < 1e-6);
/// assert!(TauTable::new(0.0).is_err());
/// # Ok::<(), volsample::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TauTable {
    d_ref: f32,
    tau: [f32; 256],
}

impl TauTable {
    /// The table for opacities that hold for distance `d_ref`.
    ///
    /// Entry `n` is exactly the `τ` that [`ExtinctionF32::from_straight`] computes for
    /// `α = n/255` (that byte's value as `f32`), so a volume read through the table samples bit
    /// for bit like the same volume converted to [`ExtinctionF32`] first.
    ///
    /// Error bound: each entry within relative `2ε` (`ε = 2⁻²³`) of `−ln(1 − n/255)/d′` below
    /// the optical-depth cap, `from_straight`'s bound (`FROM_STRAIGHT_TAU_REL` in the tests,
    /// which check all 256 entries against f64).
    ///
    /// # Errors
    /// [`Error::InvalidReferenceDistance`] unless `d_ref` is finite and positive.
    pub fn new(d_ref: f32) -> Result<Self, Error> {
        if !(d_ref.is_finite() && d_ref > 0.0) {
            return Err(Error::InvalidReferenceDistance);
        }
        let mut tau = [0.0f32; 256];
        for (t, n) in tau.iter_mut().zip(0..=u8::MAX) {
            let straight = StraightF32 {
                c: [0.0; 3],
                a: unorm8(n),
            };
            *t = ExtinctionF32::from_straight(straight, d_ref).tau;
        }
        Ok(Self { d_ref, tau })
    }

    /// The reference distance the table was built for.
    pub fn d_ref(&self) -> f32 {
        self.d_ref
    }

    /// `τ` of every opacity byte (the eight-ray lane kernel's lookups).
    #[inline(always)]
    pub(crate) fn taus(&self) -> &[f32; 256] {
        &self.tau
    }

    /// `τ` of opacity byte `n`.
    #[inline(always)]
    pub fn tau(&self, n: u8) -> f32 {
        // 256 entries: the lookup cannot miss; `get` keeps the crate panic-free.
        self.tau.get(usize::from(n)).copied().unwrap_or(0.0)
    }

    /// The extinction form of a straight voxel: `τ` from the table, `C^τ = min(τ·C, τ)` with
    /// `C = n/255`, the same operations as [`ExtinctionF32::from_straight`], so bit-identical
    /// to it.
    #[inline(always)]
    pub fn extinction(&self, v: StraightU8) -> ExtinctionF32 {
        let [r, g, b, a] = v.0;
        let tau = self.tau(a);
        ExtinctionF32 {
            // `from_straight` caps `C^τ` at `τ`; here the cap is never needed: `τ` is finite
            // and `n/255 ≤ 1`, and the rounded product of `τ` and a value in `[0, 1]` is at
            // most `τ` (rounding is monotone and `τ` is representable), so leaving it out
            // changes no bit (checked for every byte pair in the host tests) and saves
            // three `min`s a tap.
            c_tau: [r, g, b].each(|c| tau * unorm8(c)),
            tau,
        }
    }
}

/// [`ExtinctionWeighted`](super::ExtinctionWeighted) over straight 8-bit RGBA voxels, their
/// opacities read as extinction through a [`TauTable`] per tap: 4 bytes a voxel instead of the
/// 16 of [`ExtinctionF32`], so a large volume costs what `OpacityWeighted` costs in memory
/// traffic. Results are bit-identical to `ExtinctionWeighted` over the volume converted with
/// [`TauTable::extinction`] (equivalently [`ExtinctionF32::from_straight`] of `n/255`), so
/// its error bound is `ExtinctionWeighted`'s, on those values.
///
/// The table's `d′` is the distance the stored opacities hold for; an extinction mode never
/// corrects opacity, so the volume's own reference distance is not used.
///
/// It saves memory (4 bytes a voxel against 16); whether it saves time depends on the
/// machine and the volume: each tap costs a table lookup and three products, against reads a
/// quarter as wide. Where the volume is large and its rows of 16-byte voxels would be a
/// multiple of 4 KiB (256 voxels wide, say), the narrower voxels also spare the caches the
/// set conflicts of such rows. The README's performance section has the measurements.
///
/// ```
/// use volsample::mode::{ExtinctionWeightedU8, TauTable};
/// use volsample::{FrontToBack, RayMarcher, Step, StraightU8, Trilinear, Volume};
/// let voxels = [StraightU8([200, 100, 50, 128]); 8];
/// let vol = Volume::new(&voxels, [2, 2, 2])?;
/// let tau = TauTable::new(1.0)?;
/// let m = RayMarcher::new(
///     vol, ExtinctionWeightedU8::new(&tau), Trilinear::new(), FrontToBack::new(), Step::new(1.0)?,
/// )?;
/// // One step of length d = d′ through a uniform medium gives back the stored opacity.
/// assert!((m.sample([0.5, 0.5, 0.5]).a - 128.0 / 255.0).abs() < 1e-6);
/// # Ok::<(), volsample::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtinctionWeightedU8<'t> {
    table: &'t TauTable,
}

impl<'t> ExtinctionWeightedU8<'t> {
    /// The mode reading opacities through `table`.
    pub fn new(table: &'t TauTable) -> Self {
        Self { table }
    }

    /// The table.
    pub fn table(&self) -> &'t TauTable {
        self.table
    }

    #[inline(always)]
    fn channels<T: Num>(&self, v: StraightU8) -> ([T; 3], T) {
        let e = self.table.extinction(v);
        (e.c_tau.each(T::from_f32), T::from_f32(e.tau))
    }
}

impl sealed::Sealed for ExtinctionWeightedU8<'_> {}

impl Mode<StraightU8> for ExtinctionWeightedU8<'_> {
    const OPACITY_BASED: bool = false;

    #[inline(always)]
    fn lanes8<X: LaneVisitor>(&self, visitor: X) -> Result<X::Out, X> {
        Ok(visitor.visit(self))
    }

    #[inline(always)]
    fn weighted<T: Num, const K: usize>(&self, taps: &[StraightU8; K], w: &[T; K]) -> Interp<T> {
        linear_weighted(&taps.each(|v| self.channels::<T>(v)), w)
    }

    #[inline(always)]
    fn weighted8_f32(&self, taps: &[StraightU8; 8], w: &[f32; 8]) -> Interp<f32> {
        let u = taps.each(|v| {
            let e = self.table.extinction(v);
            [e.c_tau[0], e.c_tau[1], e.c_tau[2], e.tau]
        });
        linear_weighted8_f32(&u, w)
    }

    #[inline(always)]
    fn tree8<T: Num>(&self, taps: &[StraightU8; 8], f: [T; 3]) -> Interp<T> {
        linear_tree(&taps.each(|v| self.channels::<T>(v)), f)
    }

    #[inline(always)]
    fn finish(&self, i: Interp<f32>, d: f32) -> Sample {
        integrate_step(i.c, i.a, d)
    }

    #[inline(always)]
    fn weighted8_x4(&self, taps: &[[StraightU8; 4]; 8], w: &[F32x4; 8]) -> Interp<F32x4> {
        weighted_sums::<F32x4, Linear, _, 8>(w, taps, |col| {
            channels_x4(*col, |v| self.channels::<f32>(v))
        })
    }

    #[inline(always)]
    fn finish_in<T: Lanes>(&self, i: Interp<T>, d: f32) -> Interp<T> {
        super::extinction::integrate_in(i, d)
    }
}

impl LaneMode for ExtinctionWeightedU8<'_> {
    type Voxel = StraightU8;
    type Taps = TauOfAlpha8;
    type W = Linear;
    const LAG: u32 = 1;
    type Correction = crate::opacity::Uncorrected;
    #[inline(always)]
    fn taus(&self) -> &[f32; 256] {
        self.table.taus()
    }
    #[inline(always)]
    fn finish_lanes<T: Lanes>(i: Interp<T>, d: f32) -> Interp<T> {
        super::extinction::integrate_in(i, d)
    }
}
