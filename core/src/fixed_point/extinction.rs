//! Integer `ExtinctionWeighted` (Kraus, Bürger 2008, eqs. 18–23) over fixed-point `(τ, C^τ)`
//! voxels, with table-driven `e^(−x)` and `φ(x)` ([`exp_phi`](super::exp_phi)).
//!
//! # Storage: [`ExtinctionFx`]
//!
//! `τ` is stored as the optical depth of one reference distance, `D = τ·d′`, in U7.20
//! ([`DEPTH_FRAC_BITS`] `= 20`, `raw/2^20`), capped like the float path at
//! [`MAX_OPTICAL_DEPTH`] `= 64` (raw [`MAX_DEPTH_RAW`]
//! `= 2^26`), and `C^τ·d′ = D·C` in the same format, `≤ D`. Storing per `d′` makes the format
//! independent of the reference distance: the step enters only through `r = d/d′`
//! ([`IntRatio`]). From a straight voxel with opacity `α` (for `d′`):
//! `D = ⌊2^20·min(−ln(1 − α), 64) + ½⌋` and `D·C = ⌊D·C + ½⌋` (both **round half up**; the
//! second in exact integer arithmetic for `u8` colors, `D·255` bytes).
//!
//! # Kernel
//!
//! With integer weights `w_i` summing to `2^s` (`s = 3F ≤ 36`, or 0 for nearest):
//!
//! 1. `S_τ = Σ w_i·D_i`, `S_c = Σ w_i·(D·C)_i` (exact, `u64`: `≤ 2^26·2^36 = 2^62`);
//! 2. the step's optical depth `x = S_τ·r/2^(s+20)` to 28 fractional bits,
//!    `x_raw = ⌊S_τ·r_raw/2^(s+24) + ½⌋` (**round half up**, `u128`: `< 2^62·2^64`), then
//!    **saturated** at `16·2^28`; likewise `x_c` from `S_c` (so `x_c ≤ x`);
//! 3. for `x < 1` (the same split as the float kernel): `α = ⌊ONE·x·φ̂(x) + ½⌋` and
//!    `C̃ = ⌊ONE·x_c·φ̂(x) + ½⌋` (**round half up** of the exact products, `u128`:
//!    `ONE·x_raw·P < 2^16·2^28·2^58`), `φ̂` interpolated from the table;
//! 4. for `1 ≤ x < 16`: `α = ⌊ONE·(1 − ê(x)) + ½⌋` with `ê` the two-table product, then
//!    `C̃ = ⌊α·S_c/S_τ + ½⌋` (**round half up**; `S_τ > 0` as `x ≥ 1`; `u128`: `< 2^16·2^62`);
//! 5. for `x ≥ 16`: `α = ONE`, `C̃ = ⌊ONE·S_c/S_τ + ½⌋`.
//!
//! `C̃ ≤ α` by construction: `S_c ≤ S_τ` (each `(D·C)_i ≤ D_i`), so `x_c ≤ x` in step 3 and
//! `S_c/S_τ ≤ 1` in steps 4–5, and every rounding is monotone. `α ≤ ONE`: `x·φ̂(x) ≤ 1` and
//! `ê ≥ 0`.

use super::exp_phi::{
    round_half_up_div128, round_half_up_shift128, ExtinctionTables, IntRatio, ARG_FRAC_BITS,
    ARG_SATURATED, EXP_INT_FRAC_BITS, TABLE_FRAC_BITS,
};
use super::{sealed, IntMode, IntSample, IntWeights, ONE};
use crate::error::Error;
use crate::voxel::{StraightF32, StraightU8, Voxel, VoxelFault, MAX_OPTICAL_DEPTH};

/// Fractional bits of the stored optical depth `D = τ·d′` and of `D·C`.
pub const DEPTH_FRAC_BITS: u32 = 20;
/// The cap of the stored optical depth, [`MAX_OPTICAL_DEPTH`]`·2^20 = 2^26`.
pub const MAX_DEPTH_RAW: u32 = (MAX_OPTICAL_DEPTH as u32) << DEPTH_FRAC_BITS;

/// An extinction voxel in fixed point: optical depth per reference distance `D = τ·d′` and
/// `D·C = C^τ·d′`, both U7.20 (see the module docs).
///
/// Valid when `tau ≤ MAX_DEPTH_RAW` and every `c_tau[k] ≤ tau` (checked by
/// [`Volume::new`](crate::Volume::new); the kernel also clamps, so no input can overflow it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ExtinctionFx {
    /// `D = τ·d′`, raw U7.20, at most [`MAX_DEPTH_RAW`].
    pub tau: u32,
    /// `D·C = C^τ·d′` per channel, raw U7.20, each at most `tau`.
    pub c_tau: [u32; 3],
}

/// `⌊2^20·min(−ln1p(−α), 64) + ½⌋` for `α ∈ [0, 1]` (NaN and negatives read as 0).
fn depth_raw(a: f64) -> u32 {
    let a = if a > 0.0 { a.min(1.0) } else { 0.0 };
    // α = 1: ln1p(−1) = −∞, capped to 64 like the float path.
    let depth = (-libm::log1p(-a)).min(f64::from(MAX_OPTICAL_DEPTH));
    super::exp_phi::round_scaled(depth, DEPTH_FRAC_BITS as i32).min(u64::from(MAX_DEPTH_RAW)) as u32
}

impl ExtinctionFx {
    /// The optical depth `D = τ·d′` as a `fixed` U12.20 number (the same bits as
    /// [`tau`](Self::tau); values never exceed [`MAX_DEPTH_RAW`], i.e. 64). With the feature
    /// `fixed` (on by default).
    #[cfg(feature = "fixed")]
    pub fn depth(&self) -> fixed::types::U12F20 {
        fixed::types::U12F20::from_bits(self.tau)
    }

    /// `D·C` per channel as `fixed` U12.20 numbers (the same bits as
    /// [`c_tau`](Self::c_tau)). With the feature `fixed` (on by default).
    #[cfg(feature = "fixed")]
    pub fn depth_color(&self) -> [fixed::types::U12F20; 3] {
        self.c_tau.map(fixed::types::U12F20::from_bits)
    }

    /// The fixed-point extinction form of a straight `u8` voxel (opacity for `d′`).
    ///
    /// Error bound: `D` within `2^−21` of `min(−ln(1 − α/255), 64)` and each `D·C` within
    /// `2^−21` of `D_stored·C/255` (so within `2^−20` of the exact `D·C`).
    pub fn from_straight_u8(v: StraightU8) -> Self {
        let [r, g, b, a] = v.0;
        let tau = depth_raw(f64::from(a) / 255.0);
        // 2·2^26·255 + 255 < 2^36: exact in u64; the quotient is at most tau.
        let c = |c: u8| ((2 * u64::from(tau) * u64::from(c) + 255) / 510) as u32;
        Self {
            tau,
            c_tau: [c(r), c(g), c(b)],
        }
    }

    /// The fixed-point extinction form of a straight `f32` voxel (opacity for `d′`); values
    /// outside `[0, 1]` are clamped into it and NaN reads as 0.
    ///
    /// Error bound: as [`from_straight_u8`](Self::from_straight_u8) (`D·C` is rounded from
    /// the exact `f64` product of the stored `D` and the `f32` color).
    pub fn from_straight_f32(v: StraightF32) -> Self {
        let tau = depth_raw(f64::from(v.a));
        let c = |c: f32| {
            let c = if c > 0.0 { f64::from(c.min(1.0)) } else { 0.0 };
            // tau < 2^27 and c has 24 significant bits: the product is exact in f64.
            (super::exp_phi::round_scaled(f64::from(tau) * c, 0) as u32).min(tau)
        };
        Self {
            tau,
            c_tau: v.c.map(c),
        }
    }
}

impl Voxel for ExtinctionFx {
    const TRANSPARENT: Self = Self {
        tau: 0,
        c_tau: [0; 3],
    };
    fn check(&self) -> Result<(), VoxelFault> {
        if self.tau > MAX_DEPTH_RAW {
            return Err(VoxelFault::OutOfRange);
        }
        if self.c_tau.iter().any(|&c| c > self.tau) {
            return Err(VoxelFault::ColorExceedsOpacity);
        }
        Ok(())
    }
}

/// The integer `ExtinctionWeighted` mode: the step ratio `r = d/d′` and the `φ`/`e^(−x)`
/// tables of size `N` it reads (see the module docs for the arithmetic).
///
/// Error bound (against the exact `α = 1 − e^(−x)`, `C̃ = C^τ·α/τ` of the same stored voxels,
/// same weights, `x = D̄·r` with the given `f32` ratio), with `h = 1/(N − 1)`:
/// `α` within `½ + ONE·h²/(8e) + 0.01` U8.8 LSB and each `C̃` within
/// `1 + ONE·h²/(8e) + 0.01` (`extinction_int_a_lsb(N)`, `extinction_int_c_lsb(N)` in the
/// tolerance table): ½ for the final rounding, the table's chord error (`h²/24` for `φ`,
/// `h²/(8e)` for `e^(−x)` at `x ≥ 1`, the larger), `0.01` for the entries, `x` and `r`
/// quantization and the `e^(−16)` tail, and for `C̃` at `x ≥ 1` another ½ from reusing the
/// rounded `α`. At `N = 257` that is 0.56 / 1.06 LSB. Against the `f64` reference on the
/// straight voxels the stored `D` (`2^−21`) and `D·C` (`2^−20`) add
/// `ONE·r·2^−21` to `α` and `1.25·ONE·r·2^−20` to `C̃` (`extinction_int_storage_lsb`).
#[derive(Debug, Clone, Copy)]
pub struct IntExtinction<'t, const N: usize> {
    tables: &'t ExtinctionTables<N>,
    ratio: IntRatio,
}

impl<'t, const N: usize> IntExtinction<'t, N> {
    /// The mode for step ratio `ratio = d/d′` over `tables`.
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `ratio` is finite, positive and below `2^32`.
    pub fn new(tables: &'t ExtinctionTables<N>, ratio: f32) -> Result<Self, Error> {
        Ok(Self {
            tables,
            ratio: IntRatio::new(ratio)?,
        })
    }

    /// The quantized step ratio.
    pub const fn ratio(&self) -> IntRatio {
        self.ratio
    }

    /// The tables.
    pub const fn tables(&self) -> &'t ExtinctionTables<N> {
        self.tables
    }

    /// The step's optical depth to 28 fractional bits: `⌊s·r_raw/2^(shift+24) + ½⌋`,
    /// **saturated** at `16·2^28`.
    #[inline(always)]
    fn depth(&self, s: u64, shift: u32) -> u64 {
        // s ≤ 2^62, r_raw < 2^64: the product is below 2^126.
        let x = round_half_up_shift128(
            u128::from(s) * u128::from(self.ratio.raw()),
            shift + DEPTH_FRAC_BITS + super::exp_phi::RATIO_FRAC_BITS - ARG_FRAC_BITS,
        );
        if x >= u128::from(ARG_SATURATED) {
            ARG_SATURATED
        } else {
            x as u64
        }
    }

    /// One step of the emission–absorption integral from the interpolated sums (see the
    /// module docs, steps 2–5).
    #[inline(always)]
    fn integrate(&self, s_t: u64, s_c: [u64; 3], shift: u32) -> IntSample {
        let one = u128::from(ONE);
        let x = self.depth(s_t, shift);
        let k = self.tables.interp_bits();
        if x < 1 << ARG_FRAC_BITS {
            let p = u128::from(self.tables.phi_interp(x));
            let s = ARG_FRAC_BITS + TABLE_FRAC_BITS + k;
            // one·x·p < 2^16·2^28·2^(31+k) ≤ 2^102: exact in u128; each result ≤ ONE.
            let a = round_half_up_shift128(one * u128::from(x) * p, s) as u16;
            let c = s_c.map(|sc| {
                let xc = self.depth(sc, shift);
                round_half_up_shift128(one * u128::from(xc) * p, s) as u16
            });
            return IntSample::from_valid(c, a);
        }
        let s = EXP_INT_FRAC_BITS + TABLE_FRAC_BITS + k;
        let q = self.tables.exp_neg_interp(x);
        // q < 2^(62+k) ≤ 2^s, so 1 − ê ≥ 0; one·2^s ≤ 2^(16+63+26).
        let a = round_half_up_shift128(one * ((1u128 << s) - q.min(1u128 << s)), s) as u16;
        let st = u128::from(s_t);
        // α·S_c ≤ 2^16·2^62; S_c ≤ S_τ keeps each quotient ≤ α.
        let c = s_c.map(|sc| round_half_up_div128(u128::from(a) * u128::from(sc), st) as u16);
        IntSample::from_valid(c, a)
    }
}

impl<const N: usize> sealed::Sealed for IntExtinction<'_, N> {}

impl<const N: usize> IntMode<ExtinctionFx> for IntExtinction<'_, N> {
    const OPACITY_BASED: bool = false;

    #[inline]
    fn for_step_ratio(self, ratio: f32) -> Result<Self, Error> {
        Ok(Self {
            ratio: IntRatio::new(ratio)?,
            ..self
        })
    }

    #[inline(always)]
    fn combine<const K: usize>(&self, taps: &[ExtinctionFx; K], w: &IntWeights<K>) -> IntSample {
        let mut s_t = 0u64;
        let mut s_c = [0u64; 3];
        for (v, &w) in taps.iter().zip(w.weights().iter()) {
            // Clamps are no-ops for validated voxels; they bound every product by 2^62.
            let t = v.tau.min(MAX_DEPTH_RAW);
            s_t += w * u64::from(t);
            for (s, &c) in s_c.iter_mut().zip(v.c_tau.iter()) {
                *s += w * u64::from(c.min(t));
            }
        }
        self.integrate(s_t, s_c, w.shift())
    }
}
