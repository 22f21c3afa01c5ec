//! The worst f32-vs-f64 error of every mode × filter over a seeded sweep, printed next to its
//! stated bound (run with `--nocapture` to see the table) and held to it.
//!
//! Environment: `VOLSAMPLE_SWEEP_CASES` (default 3000), `VOLSAMPLE_SEED` (default 1).

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use volsample_host::float_checks::{max_abs_diff, FilterKind, ModeKind};
use volsample_host::strategies::case_and_pos;
use volsample_host::tolerance as tol;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn worst_float_errors_within_bounds() {
    let cases = env_u64("VOLSAMPLE_SWEEP_CASES", 3000);
    let seed = env_u64("VOLSAMPLE_SEED", 1);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes);
    let mut runner = TestRunner::new_with_rng(Config::default(), rng);
    let strategy = case_and_pos();

    // (largest error, then the error and bound of the case closest to its bound, and their ratio)
    let mut worst =
        vec![(0.0f64, 0.0f64, 0.0f64, 0.0f64); ModeKind::ALL.len() * FilterKind::ALL.len()];
    for _ in 0..cases {
        let (case, pos) = strategy
            .new_tree(&mut runner)
            .expect("strategy generates")
            .current();
        for (mi, mode) in ModeKind::ALL.iter().enumerate() {
            for (fi, filter) in FilterKind::ALL.iter().enumerate() {
                let core = case.core_sample(*mode, *filter, pos, case.d_ref);
                let r = case.reference_sample(*mode, *filter, pos, case.d_ref);
                let err = max_abs_diff(core, r);
                let bound = tol::sample_bound(*mode, *filter, &case, case.d_ref);
                let w = &mut worst[mi * FilterKind::ALL.len() + fi];
                w.0 = w.0.max(err);
                if err / bound > w.3 {
                    (w.1, w.2, w.3) = (err, bound, err / bound);
                }
            }
        }
    }

    println!("f32 vs f64 reference, {cases} random cases (seed {seed}), d = d':");
    println!(
        "{:<20} {:<14} {:>10} | {:>10} {:>10} {:>7}",
        "mode", "filter", "max err", "tightest:", "its bound", "ratio"
    );
    let mut failures = Vec::new();
    for (mi, mode) in ModeKind::ALL.iter().enumerate() {
        for (fi, filter) in FilterKind::ALL.iter().enumerate() {
            let (max_err, err, bound, ratio) = worst[mi * FilterKind::ALL.len() + fi];
            println!(
                "{:<20} {:<14} {:>10.2e} | {:>10.2e} {:>10.2e} {:>7.3}",
                format!("{mode:?}"),
                format!("{filter:?}"),
                max_err,
                err,
                bound,
                ratio
            );
            if ratio > 1.0 {
                failures.push(format!(
                    "{mode:?} {filter:?}: {err:e} exceeds its bound {bound:e}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
