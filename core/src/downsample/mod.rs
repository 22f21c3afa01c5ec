//! RGBA downsampling and mipmap chains (Kraus, Bürger 2008, §4).
//!
//! One pyramid level halves each axis (odd sizes round up: `n ↦ ⌈n/2⌉`; an axis of 1 stays 1)
//! with a separable symmetric 4-tap [`Filter4`] `(a, b, b, a)`, `a + b = ½`; taps outside the
//! grid read the nearest edge voxel (clamp to edge, as the samplers do). What is filtered is
//! chosen by type:
//!
//! | [`Method`] | level voxels | filters | then |
//! |---|---|---|---|
//! | [`OpacityBased`] | [`AssociatedF32`](crate::AssociatedF32) | `α`, `C̃` | `α′ = 1 − (1 − ᾱ)²`, `C̃′ = C̄·α′/ᾱ` (loses opacity) |
//! | [`ExtinctionBased`] | [`ExtinctionF32`](crate::ExtinctionF32) | `τ`, `C^τ` | `τ′ = 2τ̄`, `C^τ′ = 2C̄^τ` per coarse voxel |
//!
//! # Geometry and units
//!
//! Every level is a [`Volume`](crate::Volume) in its own voxel units. Coarse voxel `j` of level `ℓ` covers the
//! fine voxels `2^ℓ·j … 2^ℓ·(j + 1) − 1`, so a level-0 position `p` is the level-`ℓ` position
//! `(p + ½)/2^ℓ − ½` ([`MipLevel::to_level`]) and a step of `d` fine voxels is `d/2^ℓ` level
//! voxels. Each level's reference distance is the base volume's `d′` *in its own voxels*, that
//! is `2^ℓ·d′` fine voxels ([`MipLevel::reference_distance_fine`]): opacity-based levels hold
//! opacities for that doubled (then quadrupled, …) distance, and extinction-based levels hold
//! `τ` per level voxel. [`MipLevel::sample`] does the conversions and samples a level with any
//! mode and filter (trilinear, triquadratic B-spline, …) for a step given in fine voxels.
//!
//! # Sizes
//!
//! [`level_dims`], [`level_count`], [`chain_len`] and [`level_offset`] are `const fn`, so a
//! firmware image can size a static chain buffer at compile time:
//!
//! ```
//! use volsample::downsample::{chain_len, level_dims, level_count, level_offset};
//! assert_eq!(level_dims([5, 4, 1], 1), [3, 2, 1]);
//! assert_eq!(level_count([5, 4, 1]), 4); // 5×4×1, 3×2×1, 2×1×1, 1×1×1
//! const N: usize = chain_len([5, 4, 1]);
//! assert_eq!(N, 6 + 2 + 1);
//! assert_eq!(level_offset([5, 4, 1], 3), 8);
//! ```
//!
//! # Example: the paper's 2×2×2 voxels
//!
//! ```
//! use volsample::downsample::{downsample_level, ExtinctionBased, Filter4, OpacityBased};
//! use volsample::{AssociatedF32, ExtinctionF32, Volume};
//! // Four voxels at τ = 4 (the x = 0 layer), four at τ = 0; fine distance d′ = 1.
//! let tau = |x: usize| if x == 0 { 4.0f32 } else { 0.0 };
//! let ext: [ExtinctionF32; 8] = core::array::from_fn(|i| ExtinctionF32 { c_tau: [tau(i % 2); 3], tau: tau(i % 2) });
//! let mut coarse = [ExtinctionF32::default(); 1];
//! let level = downsample_level(ExtinctionBased, Filter4::box2(), &Volume::new(&ext, [2, 2, 2])?, &mut coarse)?;
//! let alpha = -libm::expm1f(-level.data()[0].tau); // one coarse voxel: τ′ = 4 per coarse voxel
//! assert!((alpha - 0.98168).abs() < 1e-5);
//!
//! let a = |x: usize| if x == 0 { -libm::expm1f(-4.0) } else { 0.0 };
//! let op: [AssociatedF32; 8] = core::array::from_fn(|i| AssociatedF32 { c: [a(i % 2); 3], a: a(i % 2) });
//! let mut coarse = [AssociatedF32::default(); 1];
//! let level = downsample_level(OpacityBased, Filter4::box2(), &Volume::new(&op, [2, 2, 2])?, &mut coarse)?;
//! assert!((level.data()[0].a - 0.740758).abs() < 1e-5); // opacity lost
//! # Ok::<(), volsample::Error>(())
//! ```

mod chain;
mod extinction_based;
mod filter4;
pub mod integer;
mod level;
mod mip;
mod opacity_based;

pub use chain::{build_chain, MipChain};
pub use extinction_based::ExtinctionBased;
pub use filter4::Filter4;
pub use level::downsample_level;
pub use mip::MipLevel;
pub use opacity_based::OpacityBased;

use crate::voxel::Voxel;

/// Most levels a chain can have, level 0 included: an axis of
/// [`MAX_DIM`](crate::volume::MAX_DIM) `= 2²⁴` voxels takes 24 halvings to reach 1.
pub const MAX_LEVELS: usize = 25;

pub(crate) mod sealed {
    pub trait Sealed {}
}

/// What a downsampling filter is applied to, and how the filtered channels become a coarse
/// voxel: [`OpacityBased`] or [`ExtinctionBased`].
///
/// Sealed: the two methods of this module are the only implementations.
pub trait Method: sealed::Sealed + Copy + Default + core::fmt::Debug {
    /// The voxel format of the input level and of every coarse level.
    type Voxel: Voxel;

    /// The four filtered channels of a voxel: three color-like channels, then `α` or `τ`.
    fn channels(v: Self::Voxel) -> [f32; 4];

    /// The coarse voxel from the filtered channels.
    fn finish(filtered: [f32; 4]) -> Self::Voxel;
}

/// `⌈n/2^level⌉` for `n ≥ 1` (an axis of 0 is read as 1).
const fn halve(n: usize, level: u32) -> usize {
    let n = if n == 0 { 1 } else { n };
    if level >= usize::BITS {
        return 1;
    }
    let q = n >> level;
    let rem = n & ((1usize << level) - 1);
    if rem != 0 {
        q + 1
    } else {
        q
    }
}

/// The dimensions of level `level` of a chain whose level 0 has `dims`: `⌈n/2^level⌉` per axis
/// (level 0 is `dims` itself; halving `⌈n/2⌉` level after level gives the same result).
/// An axis of 0 is read as 1.
pub const fn level_dims(dims: [usize; 3], level: u32) -> [usize; 3] {
    [
        halve(dims[0], level),
        halve(dims[1], level),
        halve(dims[2], level),
    ]
}

/// `⌈log₂ n⌉` for `n ≥ 1` (0 for `n ≤ 1`).
const fn ceil_log2(n: usize) -> u32 {
    if n <= 1 {
        0
    } else {
        usize::BITS - (n - 1).leading_zeros()
    }
}

/// The number of levels of a full chain, level 0 included: `1 + ⌈log₂ max(nx, ny, nz)⌉`, the
/// last level being `1 × 1 × 1`. At most [`MAX_LEVELS`] for valid volume dimensions.
pub const fn level_count(dims: [usize; 3]) -> u32 {
    let mut m = ceil_log2(dims[0]);
    let y = ceil_log2(dims[1]);
    let z = ceil_log2(dims[2]);
    if y > m {
        m = y;
    }
    if z > m {
        m = z;
    }
    m + 1
}

/// Voxels in one level of `dims`, saturating at `usize::MAX` (which no buffer can match).
const fn voxel_count(dims: [usize; 3]) -> usize {
    dims[0].saturating_mul(dims[1]).saturating_mul(dims[2])
}

/// The index in a chain buffer ([`build_chain`]) where level `level ≥ 1` starts: the voxels of
/// levels `1 … level − 1`. Level 0 is the caller's volume and not in the buffer; `level = 0`
/// gives 0, and a level past the last gives [`chain_len`]. Saturates at `usize::MAX`.
pub const fn level_offset(dims: [usize; 3], level: u32) -> usize {
    let count = level_count(dims);
    let end = if level < count { level } else { count };
    let mut total = 0usize;
    let mut l = 1;
    while l < end {
        total = total.saturating_add(voxel_count(level_dims(dims, l)));
        l += 1;
    }
    total
}

/// Voxels in a whole chain buffer: every level after level 0, down to `1 × 1 × 1`.
/// Saturates at `usize::MAX` (which no buffer can match). About `n/7` for a cube of `n`
/// voxels (each level about an eighth of the one before), up to about `n` for a volume that
/// is long along one axis only.
pub const fn chain_len(dims: [usize; 3]) -> usize {
    level_offset(dims, level_count(dims))
}
