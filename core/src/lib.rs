//! # volsample
//!
//! Allocation-free sampling and compositing of RGBA volume data, for firmware, hardware golden
//! models and renderers that care what each sampling choice costs.
//!
//! * **What is interpolated** — the [`mode`]: [`Separate`] (the flawed common method),
//!   [`OpacityWeighted`] (Wittenbrink, Malzbender, Goss 1998), [`Preweighted`] (Drebin),
//!   [`ExtinctionWeighted`] (Kraus, Bürger 2008), [`PostClassified`].
//! * **From where** — the [`filter`]: [`Nearest`], [`Trilinear`] (two evaluation orders),
//!   [`TriquadraticBSpline`].
//! * **How opacity follows the step** — [`opacity`] correction, or extinction integration.
//! * **How samples combine** — [`composite`]: front to back (with optional early
//!   termination) or back to front, over a background.
//! * **Along which rays** — [`ray`] clipping and cameras, [`render`] for whole images, one
//!   ray at a time (four consecutive samples in [`lanes`] on SIMD targets) or four rays in
//!   lanes ([`RayMarcher::cast_rays`]; eight in AVX2 lanes with the feature `avx2` in a build
//!   for an AVX2 CPU, see [`render::AVX2_PACKETS`]); bit-identical either way.
//! * **In fixed point** — [`fixed_point`]: the bit-exact integer kernels of firmware and
//!   hardware (the integer `OpacityWeighted` trilinear kernel in SSE2 with the feature `sse2`
//!   on x86-64, see [`fixed_point::SSE2_KERNEL`]; bit-identical).
//!
//! Every choice is a type, so a pipeline contains only the stages its scene uses. Inputs are
//! validated once, at construction, into [`Error`] values; the kernels cannot panic, allocate
//! or touch global state.
//!
//! ```
//! use volsample::{FrontToBack, OpacityWeighted, RayMarcher, Separate, Step, StraightU8, Trilinear, Volume};
//! // Wittenbrink fig. 4: an opaque white voxel next to a transparent red one.
//! let voxels = [StraightU8([255, 255, 255, 255]), StraightU8([255, 0, 0, 0])];
//! let vol = Volume::new(&voxels, [2, 1, 1])?;
//! let step = Step::new(1.0)?; // d = d′: no opacity correction
//! let ow = RayMarcher::new(vol, OpacityWeighted, Trilinear::new(), FrontToBack::new(), step)?;
//! let sep = RayMarcher::new(vol, Separate, Trilinear::new(), FrontToBack::new(), step)?;
//! let mid = [0.5, 0.0, 0.0];
//! assert_eq!(ow.sample(mid).straight_color(), [1.0, 1.0, 1.0]); // stays white
//! assert_eq!(sep.sample(mid).straight_color(), [1.0, 0.5, 0.5]); // red bleeds in
//! # Ok::<(), volsample::Error>(())
//! ```
#![no_std]
// No `unsafe` anywhere, except in the AVX2 kernel (`lanes8`: its two entries, float and
// integer, two bit casts and the voxel loads after their bounds tests) in builds with the opt-in feature `avx2`, and the
// entry of the SSE2 integer kernel (`fixed_point::sse2`) with the feature `sse2`, where the
// crate denies it everywhere else.
#![cfg_attr(not(any(feature = "avx2", feature = "sse2")), forbid(unsafe_code))]
#![cfg_attr(any(feature = "avx2", feature = "sse2"), deny(unsafe_code))]
#![doc(test(attr(deny(warnings))))]

pub mod classify;
pub mod composite;
pub mod downsample;
pub mod error;
pub mod filter;
pub mod fixed_point;
pub mod lanes;
#[cfg(all(
    feature = "avx2",
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
))]
mod lanes8;
pub mod mode;
pub mod num;
pub mod opacity;
pub mod ray;
pub mod render;
pub mod sample;
pub mod shade;
pub mod skip;
pub mod transfer;
pub mod volume;
pub mod voxel;

pub use composite::{BackToFront, FrontToBack, Never, Threshold};
pub use error::Error;
pub use filter::{Filter, Nearest, Tree, Trilinear, TriquadraticBSpline, WeightedSum};
pub use mode::{ExtinctionWeighted, Mode, OpacityWeighted, PostClassified, Preweighted, Separate};
pub use num::Num;
pub use ray::{Camera, Orthographic, Perspective, Ray};
pub use render::{RayMarcher, Step};
pub use sample::{Interp, Sample};
pub use transfer::{ControlPoint, TransferFunction};
pub use volume::Volume;
pub use voxel::{AssociatedF32, AssociatedU8, ExtinctionF32, StraightF32, StraightU8};
