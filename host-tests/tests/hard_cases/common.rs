//! Shared helpers of the catalog: the worst-error record every case prints and asserts.

use volsample::Sample;
use volsample_host::reference::RefAssoc;

/// The worst error a case observed, against its bound.
#[derive(Debug)]
pub struct Worst {
    name: &'static str,
    unit: &'static str,
    err: f64,
    bound: f64,
    at: String,
}

impl Worst {
    /// A case whose errors are compared with `bound` (errors in `unit`).
    pub fn new(name: &'static str, unit: &'static str) -> Self {
        Self {
            name,
            unit,
            err: 0.0,
            bound: 0.0,
            at: String::new(),
        }
    }

    /// Records one error against its bound; fails the test at once if it is exceeded or
    /// not finite.
    #[track_caller]
    pub fn check(&mut self, err: f64, bound: f64, at: impl FnOnce() -> String) {
        assert!(
            err.is_finite() && err <= bound,
            "{}: error {err:e} {} > bound {bound:e} at {}",
            self.name,
            self.unit,
            at()
        );
        // Keep the case with the largest error relative to its own bound.
        let ratio = |e: f64, b: f64| {
            if b > 0.0 {
                e / b
            } else if e > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        };
        if self.at.is_empty() || ratio(err, bound) > ratio(self.err, self.bound) {
            self.err = err;
            self.bound = bound;
            self.at = at();
        }
    }

    /// Prints the row of the closing table: case, worst error, its bound, where.
    pub fn report(&self) {
        println!(
            "HARD-CASE | {} | {:.3e} {} | {:.3e} | {:.3} | {}",
            self.name,
            self.err,
            self.unit,
            self.bound,
            if self.bound > 0.0 {
                self.err / self.bound
            } else {
                0.0
            },
            self.at
        );
    }
}

/// `true` when every field is finite and `0 ≤ C̃ ≤ α ≤ 1`.
#[track_caller]
pub fn assert_valid(s: Sample, what: impl FnOnce() -> String) {
    assert!(s.is_valid(), "invalid sample {s:?} at {}", what());
}

/// Largest absolute difference over `α` and `C̃`.
pub fn abs_err(core: Sample, want: RefAssoc) -> f64 {
    volsample_host::float_checks::max_abs_diff(core, want)
}

/// Largest error of `core` against `want` relative to `scale` per channel, with an absolute
/// floor `floor` for results in the subnormal range: `max |core − want| / (rel·scale + floor)`
/// is what the callers bound; this returns `max |core − want|` and the per-channel budget
/// ratio.
pub fn rel_excess(core: Sample, want: RefAssoc, rel: f64, floor: f64) -> f64 {
    let one = |c: f32, w: f64| (f64::from(c) - w).abs() / (rel * w.abs() + floor);
    (0..3)
        .map(|k| one(core.c[k], want.color[k]))
        .fold(one(core.a, want.alpha), f64::max)
}
