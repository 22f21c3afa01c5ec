//! Extinction-based downsampling: filter `τ` and `C^τ`; the coarse voxel is twice as long.

use super::{sealed, Method};
use crate::each::Each;
use crate::lanes::clamp_to;
use crate::voxel::{ExtinctionF32, MAX_TAU};

/// Extinction-based downsampling (Kraus §4.1, fig. 2): filter the extinction `τ̄` and the
/// extinction-weighted color `C̄^τ`, which are linear in the material mix and need no
/// correction.
///
/// **Units.** `τ` is per unit length, and every level is a [`Volume`](crate::Volume) in its
/// own voxel units, so the coarse voxel's doubled length is folded into the stored values:
/// `τ′ = 2·τ̄` and `C^τ′ = 2·C̄^τ` per coarse voxel (exact in floating point). A level-`ℓ`
/// volume then samples like any other: an [`ExtinctionWeighted`](crate::ExtinctionWeighted)
/// step of `d` level voxels has opacity `1 − e^(−τ′·d)`, the same as a step of `2^ℓ·d` fine
/// voxels through the filtered `τ̄`. Values above [`MAX_TAU`] saturate there (a level that far
/// up is opaque at any step of at least `10⁻¹⁶` voxels).
///
/// The paper's 2×2×2 example (four voxels at `τ = 4`, four at 0, fine distance 1) gives
/// `τ̄ = 2`, stored as `τ′ = 4` per coarse voxel: opacity `1 − e^(−4) ≈ 0.9817` over one
/// coarse voxel, the same as the layers it replaces.
///
/// Error bound: one level's `τ′` and `C^τ′` are within `7.5ε·2·τ_max` (`ε = 2⁻²³`, `τ_max`
/// the input's largest `τ`) of the exact result for the stored input (the filter's `7.5ε`,
/// relative, then doubled exactly); level `ℓ` of a chain is within `7.5ε·ℓ·2^ℓ·τ_max` of
/// the exact chain, `τ_max` taken at level 0. `C^τ′ ≤ τ′` always holds (clamped at the ulp
/// level).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ExtinctionBased;

impl sealed::Sealed for ExtinctionBased {}

impl Method for ExtinctionBased {
    type Voxel = ExtinctionF32;

    #[inline(always)]
    fn channels(v: ExtinctionF32) -> [f32; 4] {
        let [r, g, b] = v.c_tau;
        [r, g, b, v.tau]
    }

    #[inline(always)]
    fn finish(f: [f32; 4]) -> ExtinctionF32 {
        let [r, g, b, tau] = f;
        let tau = clamp_to(2.0 * tau, MAX_TAU);
        ExtinctionF32 {
            c_tau: [r, g, b].each(|c| clamp_to(2.0 * c, tau)),
            tau,
        }
    }
}
