//! Shared helpers of the catalog: the worst-error record every case asserts, and the one
//! summary table the catalog prints (`zz_summary_table` in `main.rs`, `--nocapture`).
//!
//! Each [`Worst`] checks every error against its bound at once (the test fails at the first
//! error beyond it) and, when its case is done, [`Worst::report`]s its worst error into a
//! process-wide table. Rows of the same case (a proptest case reports once per run of its
//! body) merge into the worst of them. The summary test waits until every case has reported
//! (or a test has failed) and prints the table: case, kernel, worst error, bound, ratio.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once};
use std::time::{Duration, Instant};

use volsample::Sample;
use volsample_host::reference::RefAssoc;

/// One row of the summary table.
#[derive(Debug, Clone)]
pub struct Row {
    /// The case (its group number first, so the table sorts by group).
    pub case: &'static str,
    /// The kernel(s) driven through it.
    pub kernel: &'static str,
    /// The unit of `err` and `bound`.
    pub unit: &'static str,
    /// The worst error observed.
    pub err: f64,
    /// Its bound.
    pub bound: f64,
    /// Where the worst error was observed.
    pub at: String,
}

impl Row {
    /// `err/bound`, `0` for `0/0` and `∞` for an error above a zero bound.
    pub fn ratio(&self) -> f64 {
        ratio(self.err, self.bound)
    }
}

fn ratio(e: f64, b: f64) -> f64 {
    if b > 0.0 {
        e / b
    } else if e > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}

static ROWS: Mutex<Vec<Row>> = Mutex::new(Vec::new());
static PANICS: AtomicUsize = AtomicUsize::new(0);
static HOOK: Once = Once::new();

/// Counts panics (failed assertions) in every test thread, so that the summary stops waiting
/// for cases that will never report. The previous hook still prints the message.
fn install_panic_counter() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            PANICS.fetch_add(1, Ordering::SeqCst);
            previous(info);
        }));
    });
}

/// The worst error a case observed, against its bound.
#[derive(Debug)]
pub struct Worst {
    row: Row,
    seen: bool,
}

impl Worst {
    /// A case `case` driving `kernel`, whose errors are compared with their bounds (errors in
    /// `unit`).
    pub fn new(case: &'static str, kernel: &'static str, unit: &'static str) -> Self {
        install_panic_counter();
        Self {
            row: Row {
                case,
                kernel,
                unit,
                err: 0.0,
                bound: 0.0,
                at: String::new(),
            },
            seen: false,
        }
    }

    /// Records one error against its bound; fails the test at once if it is exceeded or
    /// not finite.
    #[track_caller]
    pub fn check(&mut self, err: f64, bound: f64, at: impl FnOnce() -> String) {
        assert!(
            err.is_finite() && err <= bound,
            "{}: error {err:e} {} > bound {bound:e} at {}",
            self.row.case,
            self.row.unit,
            at()
        );
        // Keep the case with the largest error relative to its own bound.
        if !self.seen || ratio(err, bound) > ratio(self.row.err, self.row.bound) {
            self.row.err = err;
            self.row.bound = bound;
            self.row.at = at();
            self.seen = true;
        }
    }

    /// Runs `f`, whose assertions demand exact results (the matching error, an exact
    /// value), and records it as 0 mismatches, or fails the case with 1 at `at`.
    #[track_caller]
    pub fn exact(&mut self, at: impl FnOnce() -> String, f: impl FnOnce()) {
        let failed = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).is_err();
        self.check(f64::from(u8::from(failed)), 0.0, at);
    }

    /// [`report`](Self::report) if anything was checked: for a fuzzed case whose one run may
    /// not reach every row (the summary still requires each row from some run).
    pub fn report_if_checked(self) {
        if self.seen {
            self.report();
        }
    }

    /// Hands the worst error to the summary table. A case that checked nothing fails here:
    /// a row without a single check would state a bound nothing was held to.
    #[track_caller]
    pub fn report(self) {
        assert!(self.seen, "{}: no error was checked", self.row.case);
        let mut rows = ROWS.lock().unwrap_or_else(|e| e.into_inner());
        match rows.iter_mut().find(|r| r.case == self.row.case) {
            Some(r) if self.row.ratio() > r.ratio() => *r = self.row,
            Some(_) => {}
            None => rows.push(self.row),
        }
    }
}

/// `true` when the test binary was asked to run a subset of the tests (a name filter or
/// `--skip`): then the summary prints what it has instead of waiting for every case.
fn filtered() -> bool {
    let mut args = std::env::args().skip(1);
    let with_value = [
        "--test-threads",
        "--format",
        "--color",
        "--logfile",
        "--report-time",
        "-Z",
        "--shuffle-seed",
    ];
    while let Some(a) = args.next() {
        if a == "--skip" || !a.starts_with('-') {
            return true;
        }
        if with_value.contains(&a.as_str()) {
            args.next();
        }
    }
    false
}

/// Waits until `expected` cases have reported (at most `patience` without a new row), a test
/// has failed, or — for a filtered run — not at all; then prints the table and returns the
/// rows and whether a test failed.
pub fn wait_and_print(expected: usize, patience: Duration) -> (Vec<Row>, bool) {
    install_panic_counter();
    let filtered = filtered();
    let mut last = (0usize, Instant::now());
    loop {
        let n = ROWS.lock().unwrap_or_else(|e| e.into_inner()).len();
        if n != last.0 {
            last = (n, Instant::now());
        }
        let failed = PANICS.load(Ordering::SeqCst) > 0;
        if filtered || failed || n >= expected || last.1.elapsed() > patience {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut rows = ROWS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    rows.sort_by(|a, b| a.case.cmp(b.case));
    let failed = PANICS.load(Ordering::SeqCst) > 0;
    println!();
    println!(
        "HARD-CASE SUMMARY: {} of {expected} cases{}",
        rows.len(),
        if failed {
            " (a test failed: partial)"
        } else {
            ""
        }
    );
    println!("| case | kernel | worst error | bound | ratio | worst at |");
    println!("|---|---|---:|---:|---:|---|");
    for r in &rows {
        println!(
            "| {} | {} | {:.3e} {} | {:.3e} | {:.3} | {} |",
            r.case,
            r.kernel,
            r.err,
            r.unit,
            r.bound,
            r.ratio(),
            r.at
        );
    }
    (rows, failed || filtered)
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
