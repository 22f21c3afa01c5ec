//! Host side of volsample: the independent f64 reference model, the tolerance table, and the
//! pieces the `volsample` CLI and the tests share.

pub mod checks;
pub mod demo;
pub mod float_checks;
pub mod int_model;
pub mod pipeline;
pub mod reference;
pub mod scene;
pub mod strategies;
pub mod tolerance;

#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
mod readme_doctest {}
