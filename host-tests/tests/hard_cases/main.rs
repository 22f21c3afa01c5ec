//! The hard-case catalog (issue 8): every numerically hard
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
//! | 8 | [`int_downsampling`] | integer levels and chains: `α` at 0, full scale and one LSB from them, depths at and above the cap, `a = 0, ¼, ½` and arbitrary `a`, the widest accumulators |
//! | 9 | [`pre_passes`] | classification and shading: zero gradients, `1×1×1`, volume edges, scalars near `±f32::MAX` and subnormal, bad classifiers and lights |
//!
//! Group 3 also runs the integer ray marcher over `10⁶` faint samples at `F` = 4, 8, 12.
//!
//! Cases other test files already cover are not repeated; each module names them.
//!
//! **The summary table.** Every case hands its worst error to one table (`common`), which
//! [`zz_summary_table`] prints once all [`EXPECTED_CASES`] have reported: case, kernel,
//! worst error, bound and their ratio (`cargo test --release -p volsample-host --test
//! hard_cases -- --nocapture`).

mod common;
mod downsampling;
mod extinction;
mod geometry;
mod input;
mod int_downsampling;
mod integer;
mod long_rays;
mod opacity;
mod pre_passes;

use std::time::Duration;

/// The number of rows (distinct cases) the catalog reports. A case added without a row, or a
/// row whose case never ran, fails [`zz_summary_table`]; update this with the catalog.
const EXPECTED_CASES: usize = 54;

/// Prints the summary table once every case has reported (sorted last, so with one test
/// thread it runs after the others; with several it waits for them). It fails if a case is
/// missing or listed twice; after a failed test or in a filtered run it prints what it has.
#[test]
fn zz_summary_table() {
    let (rows, partial) = common::wait_and_print(EXPECTED_CASES, Duration::from_secs(600));
    if partial {
        return;
    }
    assert_eq!(
        rows.len(),
        EXPECTED_CASES,
        "cases reported: {:?}",
        rows.iter().map(|r| r.case).collect::<Vec<_>>()
    );
    for r in &rows {
        assert!(
            r.err.is_finite() && r.err <= r.bound,
            "{}: {} > {}",
            r.case,
            r.err,
            r.bound
        );
    }
}
