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
//!   lanes ([`RayMarcher::cast_rays`]; eight in AVX2 lanes on a CPU with AVX2); bit-identical
//!   either way, and every one of these marchers an instance of one march loop
//!   (`core/src/march.rs`). The integer pipeline's marcher is [`render::IntRayMarcher`] (its `F = 8`
//!   alias [`IntRayMarcher`]).
//! * **In fixed point** — [`fixed_point`]: the bit-exact integer kernels of firmware and
//!   hardware (the integer `OpacityWeighted` trilinear kernel in SSE2 on x86-64;
//!   bit-identical).
//! * **In which instruction set** — [`arch`]: on x86-64 the AVX2 + FMA instances are in
//!   every build and run where the CPU has them ([`Isa::detect`], at a marcher's
//!   construction; `with_isa` forces one); elsewhere only the portable code is linked.
//!
//! Items marked `#[doc(hidden)]` (the lane kernels' trait methods and flags, `cast4`, the
//! `lanes` module) are internals shared with the host tests, not part of the API.
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
// `unsafe` only in `arch` (the AVX2 and SSE2 entries, loads and bit casts, each with its
// proof); every other module forbids it.
#![deny(unsafe_code)]
#![doc(test(attr(deny(warnings))))]

#[allow(unsafe_code)]
#[deny(clippy::undocumented_unsafe_blocks)]
pub mod arch;
#[forbid(unsafe_code)]
pub mod classify;
#[forbid(unsafe_code)]
pub mod composite;
#[forbid(unsafe_code)]
pub mod downsample;
#[forbid(unsafe_code)]
mod each;
#[forbid(unsafe_code)]
pub mod error;
#[forbid(unsafe_code)]
pub mod filter;
#[forbid(unsafe_code)]
pub mod fixed_point;
#[doc(hidden)]
#[forbid(unsafe_code)]
pub mod lanes;
#[forbid(unsafe_code)]
mod march;
#[forbid(unsafe_code)]
pub mod mode;
#[forbid(unsafe_code)]
pub mod num;
#[forbid(unsafe_code)]
pub mod opacity;
#[forbid(unsafe_code)]
pub mod ray;
#[forbid(unsafe_code)]
pub mod render;
#[forbid(unsafe_code)]
pub mod sample;
#[forbid(unsafe_code)]
pub mod shade;
#[forbid(unsafe_code)]
pub mod skip;
#[forbid(unsafe_code)]
pub mod transfer;
#[forbid(unsafe_code)]
pub mod volume;
#[forbid(unsafe_code)]
pub mod voxel;

#[cfg(test)]
#[forbid(unsafe_code)]
mod tests_portable;

pub use arch::Isa;
pub use composite::{BackToFront, FrontToBack, Never, Threshold};
pub use fixed_point::{IntSample, IntStop};

/// The integer ray marcher ([`render::IntRayMarcher`]) at the default `F = 8`
/// fractional position bits, so that `IntRayMarcher::new(…)` needs no turbofish; for another
/// `F`, `render::IntRayMarcher::<_, _, _, F>::new(…)`.
///
/// ```
/// use volsample::{IntRayMarcher, IntStop, OpacityWeighted, Ray, Step, StraightU8, Trilinear, Volume};
/// let voxels = [StraightU8([255, 128, 0, 200]); 8];
/// let vol = Volume::new(&voxels, [2, 2, 2])?;
/// let m = IntRayMarcher::new(vol, OpacityWeighted, Trilinear::new(), IntStop::NEVER, Step::new(0.5)?)?;
/// let s = m.cast(&Ray::new([0.5, 0.5, -1.0], [0.0, 0.0, 1.0])?);
/// assert!(s.a() > 0 && s.c()[2] == 0);
/// # Ok::<(), volsample::Error>(())
/// ```
pub type IntRayMarcher<'v, V, M, Fl> =
    render::IntRayMarcher<'v, V, M, Fl, { fixed_point::DEFAULT_FRAC_BITS }, skip::NoSkip>;
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
