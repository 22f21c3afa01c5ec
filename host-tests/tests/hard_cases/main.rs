//! The hard-case catalog (issue 8, DESIGN.md "Proof obligations"): every numerically hard
//! situation named once, every affected kernel — float and integer, every mode, filter,
//! compositor, correction and downsampling — driven through it, and each result held finite
//! and within a bound of `tolerance::hard_cases` (or the kernel's own bound in the tolerance
//! table). Each case prints its worst error against its bound (`--nocapture`).
//!
//! | group | module | what is hard |
//! |---|---|---|
//! | 1 | [`opacity`] | `α → 0` (ratios `α_d/α`, un-premultiplying, `C^τ·α/τ`), `α = 1` (`τ = ∞`, `ln 0`), one LSB from 0 and 1 |
//! | 2 | [`extinction`] | `τ = 0`, subnormal `τ`, `τd` at the `φ` switch-over, huge and capped `τ`, `d/d′ = 10^±6`, `d′ → 0` |
//! | 3 | [`long_rays`] | `10⁶` samples of tiny opacity against `1 − e^(−Στd)`; no drift past 1 |
//! | 4 | [`geometry`] | grazing rays, samples on centres / faces / the last plane, rays touching the box, tiny volumes, steps larger than the volume |
//! | 5 | [`input`] | NaN, ±∞, negative, > 1, subnormal in every constructor: the matching error or a valid value |
//! | 6 | [`integer`] | all-255 at every `F`, accumulator worst cases, one LSB from 0 and 1, premultiplied storage at `α_F = 1` |
//! | 7 | [`downsampling`] | the same edges through one level and whole chains |
//!
//! Cases other test files already cover are not repeated; each module names them.

mod common;
mod downsampling;
mod extinction;
mod geometry;
mod input;
mod integer;
mod long_rays;
mod opacity;
