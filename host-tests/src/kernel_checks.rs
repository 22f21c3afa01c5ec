//! Check functions of the kernel-family fuzz targets (`int_marcher`, `downsample`, `filters`,
//! `classify`), one module each: each
//! decodes its input from bytes with `arbitrary` (exactly as the fuzz target does, through
//! [`checks::run`](crate::checks::run)), reduces every decoded value into the range the API
//! accepts (never panicking on any input), runs the kernel and its independent model, and
//! returns `Err` with a description when they disagree or a stated bound is broken.
//!
//! - `int_marcher`: the integer ray marcher (`IntRayMarcher`: `cast_counted`, `cast_rays`,
//!   `march_positions`) on small random `u8` volumes, rays, steps, reference distances, stop
//!   thresholds and backgrounds, nearest and trilinear, every integer mode, `F ∈ {4, 8, 12}`,
//!   against the bit-exact integer model (`int_model`: sample, correction, extinction and
//!   compositing models), bit for bit, sample count included. Built with the feature
//!   `marcher-checks` only (as `marcher_checks`), like its fuzz target (the fuzz crate's
//!   feature `marcher`); its corpus replays in every `cargo test`.
//! - `downsample`: one level and whole chains of the float (`OpacityBased`, `ExtinctionBased`)
//!   and integer (`AssociatedU8`, U8.8 `IntSample`, `ExtinctionFx`) downsampling for any filter
//!   `a` the API accepts, against the f64 reference (`reference::downsample`, within
//!   `tolerance::downsample`) and the bit-exact integer model (`int_model::downsample`).
//! - `filters`: the float nearest and triquadratic B-spline filters, every float mode, at
//!   random positions (one voxel past every face and beyond), against the f64 reference
//!   (`float_checks`, within `tolerance::sample_bound`, as `tests/float_vs_reference.rs`).
//! - `vectors` (with the feature `loaders`, which the fuzz crate builds): any request of
//!   `volsample vectors`, written to files and read back by the code's layouts and by the
//!   manifest's field tables, each decoded case run through the kernel again.
//! - `classify`: the pre-passes (`classify_isosurface`, `shade_in_place`,
//!   `classify_transfer`) on fields of any finite `f32` scalars, against the f64 reference
//!   (`reference::levoy_opacities`, `central_gradient`, `RefTransferFunction::eval`) within
//!   `tolerance::hard_cases` and `tolerance::TF_EVAL_*`, as `tests/hard_cases/pre_passes.rs`.

use arbitrary::{Arbitrary, Unstructured};
use volsample::fixed_point::IntSample;

use crate::int_model::composite as cm;

mod classify;
mod downsample;
mod filters;
#[cfg(feature = "marcher-checks")]
mod int_marcher;
#[cfg(feature = "loaders")]
mod vectors;

pub use classify::{classify, ClassifyInput};
pub use downsample::{downsample, DownsampleInput};
pub use filters::{filters, FilterInput};
#[cfg(feature = "marcher-checks")]
pub use int_marcher::{int_marcher, MarchMode, MarcherInput, RayInput};
#[cfg(feature = "loaders")]
pub use vectors::{vectors, VectorsInput, MAX_FUZZ_COUNT};

/// The kernel-family fuzz targets, by name (`fuzz/fuzz_targets/<name>.rs`, corpus in
/// `fuzz/corpus/<name>/`); [`checks::TARGETS`](crate::checks::TARGETS) lists them too.
pub const TARGETS: [&str; 5] = [
    "int_marcher",
    "downsample",
    "filters",
    "classify",
    "vectors",
];

/// Decodes `data` as the fuzz target `target` does and runs its check.
///
/// # Errors
/// The check's description of a broken oracle, or an unknown target name.
pub fn run(target: &str, data: &[u8]) -> Result<(), String> {
    match target {
        #[cfg(feature = "marcher-checks")]
        "int_marcher" => int_marcher(&decode(data)).map(|_| ()),
        #[cfg(not(feature = "marcher-checks"))]
        "int_marcher" => Err("int_marcher: built without the feature marcher-checks".into()),
        "downsample" => downsample(&decode(data)).map(|_| ()),
        "filters" => filters(&decode(data)).map(|_| ()),
        "classify" => classify(&decode(data)).map(|_| ()),
        #[cfg(feature = "loaders")]
        "vectors" => vectors(&decode(data)),
        #[cfg(not(feature = "loaders"))]
        "vectors" => Err("vectors: built without the feature loaders".into()),
        _ => Err(format!("unknown kernel fuzz target {target}")),
    }
}

/// Input that does not decode is not a failure (libFuzzer skips it the same way).
fn decode<'a, T: Arbitrary<'a> + Default>(data: &'a [u8]) -> T {
    T::arbitrary_take_rest(Unstructured::new(data)).unwrap_or_default()
}

/// The voxel bytes of a volume of `n` voxels: `bytes`, then past them the fixed pattern
/// [`fill`], so that a short input is not a constant (or empty) volume.
fn filled(bytes: &[[u8; 4]], n: usize) -> Vec<[u8; 4]> {
    (0..n)
        .map(|i| bytes.get(i).copied().unwrap_or_else(|| fill(i)))
        .collect()
}

/// Voxel `i` of the pattern that fills a volume past an input's voxels: a hash of `i`, one
/// byte per channel (full range, not smooth).
pub fn fill(i: usize) -> [u8; 4] {
    let h = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    [8, 24, 40, 56].map(|s| (h >> s) as u8)
}

fn raw(s: &IntSample) -> cm::Raw {
    let [r, g, b] = s.c();
    [r, g, b, s.a()]
}
