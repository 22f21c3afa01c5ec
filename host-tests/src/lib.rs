//! Host side of volsample: the independent f64 reference model, the tolerance table, and the
//! pieces the `volsample` CLI and the tests share.

// reference: added with the f64 model
pub mod demo;
pub mod tolerance;

#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
mod readme_doctest {}
