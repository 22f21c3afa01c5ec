//! Independent `f64` reference model of every float kernel in `volsample`.
//!
//! This module is written from the papers and the math alone; it does not use the `volsample` crate and
//! favours plain loops and textbook formulas over speed. Tests compare the core against it.
//!
//! # Conventions (shared with the core)
//!
//! - **Volume.** Dimensions `[nx, ny, nz]`; voxel `(x, y, z)` is stored at linear index
//!   `x + nx·(y + ny·z)` ([`linear_index`]). Voxel centres sit at integer coordinates and every
//!   position is in voxel units. Each volume carries its reference distance `d_ref` (the opacity
//!   unit distance `d′`, usually `1.0`).
//! - **Voxels.** A straight voxel ([`RefVoxel`]) has color `c ∈ [0,1]³` and opacity `a ∈ [0,1]`.
//!   Its associated (premultiplied) form ([`RefAssoc`]) is `(a·c, a)`. Its extinction form
//!   ([`RefExtinction`]) is `τ = −ln(1 − a)/d_ref` and `C^τ = τ·c`, where the optical depth
//!   `−ln(1 − a)` is capped at [`MAX_OPTICAL_DEPTH`] (so `a = 1` gives `τ = 64/d_ref`).
//! - **Filters** ([`RefFilter`], [`taps`]), clamp to edge (every tap index is clamped into
//!   `[0, n − 1]` per axis; positions outside the volume are allowed):
//!   nearest `i = ⌊x + ½⌋`, weight 1; trilinear `i0 = ⌊x⌋`, `f = x − i0`, taps `i0, i0 + 1` with
//!   weights `1 − f, f`; triquadratic B-spline `i = ⌊x + ½⌋`, `t = x − i`, taps `i − 1, i, i + 1`
//!   with weights `(½ − t)²/2, ¾ − t², (½ + t)²/2`. The 3D weight is the product of the axes.
//! - **Modes** ([`RefMode`], [`sample`]) return an associated sample valid for the step `d`:
//!   `Separate` (`α = Σwα_i`, `C̃ = α·Σwc_i`), `OpacityWeighted` (`ω_i = w_iα_i`, `α = Σω_i`,
//!   `C̃ = Σω_ic_i`), `Preweighted` (from stored associated voxels: `α = Σwα_i`, `C̃ = ΣwC̃_i`),
//!   `ExtinctionWeighted` (`τ = Στ_iw_i`, `C^τ = ΣwC^τ_i`, `α = 1 − e^(−τd)`,
//!   `C̃ = C^τ·d·φ(τd)`, `φ(x) = −expm1(−x)/x`, `φ(0) = 1`) and `PostClassified`
//!   (`(C, α) = TF(Σws_i)`, `C̃ = α·C`). The opacity-based modes (all but `ExtinctionWeighted`)
//!   apply the opacity correction `α_d = 1 − (1 − α)^(d/d_ref)`, `C̃_d = C̃·α_d/α` when
//!   `d ≠ d_ref` ([`opacity_correct`]).
//! - **Transfer function** ([`RefTransferFunction`]): sorted control points `(s, rgb, a)`,
//!   piecewise linear between them, clamped to the end values outside.
//! - **Compositing** associated samples ([`composite_front_to_back`],
//!   [`composite_back_to_front`], [`over_background`]): front to back `C += (1 − A)·C̃_s`,
//!   `A += (1 − A)·α_s`, stopping before the next sample once `A ≥ a_stop`; back to front
//!   `C = C̃_s + (1 − α_s)·C`, `A = α_s + (1 − α_s)·A`; over a background `B`:
//!   `(C + (1 − A)·B_c, A + (1 − A)·B_a)`.
//! - **Rays** ([`RefRay`], [`clip_ray`], [`sample_times`]): the direction is normalized by the
//!   caller. The volume box is `[−½, n − ½]` per axis, clipped by the slab method to `[t0, t1]`
//!   with `t0` raised to `0`. Samples lie at `t_k = (k + phase)·d` for every integer `k` with
//!   `t0 ≤ t_k < t1`.
//! - **Cameras** ([`RefCamera`], [`camera_ray`]): pixel `(i, j)` of a `w × h` image, `j = 0` the
//!   top row; images are stored row-major (`j·w + i`).
//! - **Ground truth** ([`integrate_ray_exact`], [`integrate_ray_exact_scalar`]): the
//!   emission–absorption integral of the extinction-weighted reconstruction, by midpoint
//!   substeps composited exactly.
//! - **Classification** ([`RefIsosurface`], [`levoy_opacities`]): Levoy's isosurface opacity
//!   with the gradient by central differences (one-sided at the edges).
//!
//! Inputs are assumed valid (finite, colors and opacities in `[0, 1]`, `d > 0`, `d_ref > 0`);
//! the reference does not validate them. Functions that index a volume panic when a dimension
//! is zero or the data length does not match the dimensions.

pub mod camera;
pub mod classify;
pub mod composite;
pub mod downsample;
pub mod filter;
pub mod mode;
pub mod opacity;
pub mod ray;
pub mod render;
pub mod tf;
pub mod truth;
mod vec3;
pub mod volume;

pub use camera::{camera_ray, RefCamera};
pub use classify::{
    central_gradient, levoy_classify, levoy_opacities, shade_factor, RefIsosurface,
};
pub use composite::{
    composite_back_to_front, composite_front_to_back, front_to_back_used, over, over_background,
};
pub use filter::{axis_taps, interpolate, taps, RefFilter};
pub use mode::{
    sample, sample_extinction_weighted, sample_opacity_weighted, sample_post_classified,
    sample_preweighted, sample_separate, RefMode, RefSource,
};
pub use opacity::{alpha_over_tau, extinction_sample, opacity_correct, phi};
pub use ray::{clip_ray, sample_positions, sample_times, RefRay};
pub use render::{render_exact, render_pixel, render_reference, RefRenderParams};
pub use tf::{RefControlPoint, RefTransferFunction};
pub use truth::{
    extinction_at, integrate_ray_exact, integrate_ray_exact_scalar, integrate_segment,
    integrate_source_exact,
};
pub use volume::{
    linear_index, optical_depth, RefAssoc, RefAssocVolume, RefExtinction, RefScalarVolume,
    RefVolume, RefVoxel,
};

/// Cap on the optical depth `−ln(1 − α)` of one voxel over `d_ref`: an opaque voxel (`α = 1`)
/// gets `τ = MAX_OPTICAL_DEPTH / d_ref` instead of infinity. `e^(−64) ≈ 1.6·10⁻²⁸`, far below
/// any tolerance.
pub const MAX_OPTICAL_DEPTH: f64 = 64.0;
