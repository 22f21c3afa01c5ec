//! Host side of volsample: the independent f64 reference model, the tolerance table, and the
//! pieces the `volsample` CLI and the tests share.

pub mod checks;
pub mod demo;
pub mod edge_cases;
pub mod filters;
pub mod float_checks;
pub mod images;
pub mod int_model;
pub mod isa;
pub mod kraus;
pub mod out;
pub mod pipeline;
pub mod plot;
pub mod reference;
pub mod report;
pub mod scene;
pub mod strategies;
pub mod tolerance;
pub mod vectors;
pub mod view;
pub mod yardstick;

#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
mod readme_doctest {}
