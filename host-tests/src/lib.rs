//! Host side of volsample: the independent f64 reference model, the tolerance table, and the
//! pieces the `volsample` CLI and the tests share.
//!
//! Without the default feature `app` only the models remain (`reference`, `int_model`,
//! `tolerance`, `float_checks`) and the allocator `memory`, with no dependency beyond the core,
//! std and (on Linux, for `memory`) `libc`. The feature `checks` adds the fuzz targets'
//! oracles (`checks`, `kernel_checks`, and `FloatCase`'s render comparisons), with
//! `arbitrary`; the fuzz targets build it so, the CLI does not. The feature
//! `loaders` (part of `app`) adds the scenes, the file loaders and `vectors` (with `checks`,
//! also `parser_checks`), for the parser and `vectors` fuzz targets; `marcher-checks` the
//! marcher checks (`marcher_checks`, the `int_marcher` check); `testing` (the tests and
//! benches, never the CLI) those and the proptest strategies and edge cases.

#[cfg(feature = "checks")]
pub mod checks;
#[cfg(feature = "app")]
pub mod demo;
#[cfg(feature = "testing")]
pub mod edge_cases;
#[cfg(feature = "app")]
pub mod filters;
pub mod float_checks;
#[cfg(feature = "app")]
pub mod images;
pub mod int_model;
#[cfg(feature = "app")]
pub mod isa;
#[cfg(feature = "checks")]
pub mod kernel_checks;
#[cfg(feature = "app")]
pub mod kraus;
#[cfg(feature = "marcher-checks")]
pub mod marcher_checks;
pub mod memory;
#[cfg(feature = "app")]
pub mod out;
#[cfg(all(feature = "loaders", feature = "checks"))]
pub mod parser_checks;
#[cfg(feature = "app")]
pub mod pipeline;
#[cfg(feature = "app")]
pub mod plot;
pub mod reference;
#[cfg(feature = "app")]
pub mod report;
#[cfg(feature = "loaders")]
pub mod scene;
#[cfg(feature = "testing")]
pub mod strategies;
#[cfg(feature = "app")]
pub mod texture_unit;
pub mod tolerance;
#[cfg(feature = "loaders")]
pub mod vectors;
#[cfg(feature = "app")]
pub mod view;
#[cfg(feature = "app")]
pub mod yardstick;

#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
mod readme_doctest {}
