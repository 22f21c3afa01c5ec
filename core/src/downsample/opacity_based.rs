//! Opacity-based downsampling: filter `α` and `C̃`, then correct for the doubled distance.

use super::{sealed, Method};
use crate::each::Each;
use crate::lanes::clamp_to;
use crate::voxel::AssociatedF32;

/// Opacity-based downsampling (the common method, Kraus §4.1, fig. 3): filter the opacity `ᾱ`
/// and the associated color `C̄`, then correct both for the coarse voxel's doubled length:
/// `α′ = 1 − (1 − ᾱ)² = ᾱ·(2 − ᾱ)` and `C̃′ = C̄·α′/ᾱ = C̄·(2 − ᾱ)`.
///
/// The factored forms need no division and no special case at `ᾱ = 0`, and keep `C̃′ ≤ α′`
/// whenever `C̄ ≤ ᾱ`; the result is clamped into `0 ≤ C̃′ ≤ α′ ≤ 1` to absorb rounding at the
/// ulp level. Loses opacity: the paper's 2×2×2 example (four voxels at `α = 1 − e^(−4)`, four
/// at 0) gives `α′ = 1 − ((1 + e^(−4))/2)² ≈ 0.7408` where the layers it replaces have
/// `1 − e^(−4) ≈ 0.9817`.
///
/// Levels are [`AssociatedF32`] volumes whose opacities hold for the reference distance `d′`
/// measured in the level's own voxels (`2^ℓ·d′` fine voxels at level `ℓ`).
///
/// Error bound: one level's `α′` and `C̃′` are within 17ε (`ε = 2⁻²³`) of the exact
/// (real-number) result for the stored input: the filtered channels within `7.5ε`
/// ([`Filter4::combine`](super::Filter4::combine) three times), doubled by the correction,
/// whose slope is at most 2, plus two roundings. Over `ℓ` levels the bound is
/// `17ε·(2^ℓ − 1)`, the correction's slope compounding.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OpacityBased;

impl sealed::Sealed for OpacityBased {}

impl Method for OpacityBased {
    type Voxel = AssociatedF32;

    #[inline(always)]
    fn channels(v: AssociatedF32) -> [f32; 4] {
        let [r, g, b] = v.c;
        [r, g, b, v.a]
    }

    #[inline(always)]
    fn finish(f: [f32; 4]) -> AssociatedF32 {
        let [r, g, b, a] = f;
        // NaN cannot arise from valid input; `max`/`min` would map it to 0 anyway.
        let a = clamp_to(a, 1.0);
        let gain = 2.0 - a;
        let a2 = (a * gain).min(1.0);
        AssociatedF32 {
            c: [r, g, b].each(|c| (clamp_to(c, a) * gain).min(a2)),
            a: a2,
        }
    }
}
