//! Host side of volsample: the independent f64 reference model, the tolerance table, and the
//! pieces the `volsample` CLI and the tests share.

pub mod demo;
pub mod float_checks;
pub mod reference;
pub mod strategies;
pub mod tolerance;
pub mod int_model;
pub mod checks;

#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
mod readme_doctest {}
