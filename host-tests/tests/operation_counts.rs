//! Wittenbrink, Malzbender, Goss 1998, Table 1: the multiplications (M) and additions (A) of
//! one trilinear RGBα sample, reproduced by running the *real* generic kernels of `volsample`
//! with a number type that counts.
//!
//! | interpolation method   | binary tree | sum of weighted products |
//! |------------------------|-------------|--------------------------|
//! | separate color/opacity | 28M 56A     | 36M 47A                  |
//! | opacity-weighted color | 52M 56A     | 36M 47A                  |
//!
//! How the paper counts (§6), and where each count arises in the core:
//!
//! * A subtraction is an addition; converting a voxel value or a fraction into the number type
//!   (`Num::from_f32`) is a load, not an operation, and is not counted.
//! * **Lerp** `a + t·(b − a)` (`mode::lerp`): 1M 2A. One channel of trilinear interpolation as
//!   a binary tree (`mode::lerp8`) is 4 lerps in x, 2 in y, 1 in z: 7 lerps, 7M 14A.
//! * **Separate, tree** (`Separate::tree8` → `linear_tree`): 4 channels (R, G, B, α) of 7
//!   lerps: 4·7·(1M 2A) = **28M 56A**.
//! * **Opacity-weighted, tree** (`OpacityWeighted::tree8`): first premultiply the 8 voxel
//!   colors, `C̃_i = α_i·C_i`, 3·8 = 24M; then lerp-tree C̃ and α exactly like the separate
//!   tree, 28M 56A: **52M 56A**.
//! * **The 8 weights** (`filter::trilinear_weights`): the products `xy, xz, yz` (3M) and
//!   `xyz = xy·z` (1M): 4M; then `w110 = xy − xyz`, `w101`, `w011` (1A each, 3A),
//!   `w100 = x − xy − xz + xyz`, `w010`, `w001` (3A each, 9A) and
//!   `w000` (7A), `w111 = xyz` (free): **4M 19A**. The paper writes
//!   `w000 = 1 − x − y − z + xy + xz + yz − xyz`; the core computes the same value as
//!   `1 − (w111 + w011 + … + w100)` (6A for the sum, 1A for the difference), summed in the
//!   kernels' order so the weights add up to exactly 1 in floating point — the same 7A.
//! * **Separate, weighted sum** (`Trilinear::<WeightedSum>` → `trilinear_weights` then
//!   `Separate::weighted` → `linear_weighted`): the weights, 4M 19A, then for each of the
//!   4 channels `Σ w_i·x_i` starting from one product (`mode::weighted_sums` sums from the last tap down), 8M 7A:
//!   4M 19A + 4·(8M 7A) = **36M 47A**.
//! * **Opacity-weighted, weighted sum** (`OpacityWeighted::weighted`): the weights, 4M 19A;
//!   `ω_i = w_i·α_i`, 8M; `α = Σ ω_i`, 7A; each color channel `Σ ω_i·C_i`, 8M 7A, three times:
//!   4M 19A + 8M + 7A + 3·(8M 7A) = **36M 47A** — the same as the separate sum, because the
//!   `ω_i` are shared by the three color channels.
//!
//! Table 1 costs the interpolation of an RGBα sample only: turning the separate result into an
//! associated color (`Separate::finish`, `C̃ = α·C`, 3M) and compositing are outside it, and
//! outside `Trilinear::interpolate_taps`, which is what is counted here.
//!
//! The counting type also carries its value in `f64`, so every counted run is checked against
//! the interpolation computed independently here (factored weights `(1 − x)(1 − y)(1 − z)`, …,
//! plain sums), within [`COUNTED_VALUE_TOL`].

use std::cell::Cell;
use std::fmt;
use std::ops::{Add, Mul, Sub};

use volsample::filter::trilinear_weights;
use volsample::mode::Mode;
use volsample::sample::Interp;
use volsample::{Num, OpacityWeighted, Separate, StraightF32, Tree, Trilinear, WeightedSum};

/// Largest difference allowed between a counted (f64) result and the independent f64 value.
///
/// Both are f64 evaluations of the same exact expression on inputs in `[0, 1]`; the kernel's
/// expanded weights (`w000` is a sum of 8 terms of magnitude ≤ 1) and sums of 8 products stay
/// within a few dozen ulp of 1: 1e-14 (45 ulp of 1).
const COUNTED_VALUE_TOL: f64 = 1e-14;

thread_local! {
    static MULS: Cell<u32> = const { Cell::new(0) };
    static ADDS: Cell<u32> = const { Cell::new(0) };
}

fn bump(counter: &'static std::thread::LocalKey<Cell<u32>>) {
    counter.with(|c| c.set(c.get() + 1));
}

/// An `f64` that counts every `×` (in `MULS`) and every `+` or `−` (in `ADDS`) on this thread.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Counted(f64);

impl Add for Counted {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        bump(&ADDS);
        Counted(self.0 + rhs.0)
    }
}

impl Sub for Counted {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        // The paper counts a subtraction as an addition.
        bump(&ADDS);
        Counted(self.0 - rhs.0)
    }
}

impl Mul for Counted {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        bump(&MULS);
        Counted(self.0 * rhs.0)
    }
}

impl Num for Counted {
    const ZERO: Self = Counted(0.0);
    const ONE: Self = Counted(1.0);
    fn from_f32(x: f32) -> Self {
        // A load, not an operation: not counted.
        Counted(f64::from(x))
    }
}

/// A number of multiplications and additions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Ops {
    m: u32,
    a: u32,
}

impl fmt::Display for Ops {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}M {}A", self.m, self.a)
    }
}

const fn ops(m: u32, a: u32) -> Ops {
    Ops { m, a }
}

/// Runs `f` with fresh counters and returns its result and the operations it performed.
fn counted<R>(f: impl FnOnce() -> R) -> (R, Ops) {
    MULS.with(|c| c.set(0));
    ADDS.with(|c| c.set(0));
    let r = f();
    let used = Ops {
        m: MULS.with(Cell::get),
        a: ADDS.with(Cell::get),
    };
    (r, used)
}

// ---------------------------------------------------------------------------------------------
// Inputs and the independent f64 interpolation.

/// Fractions `[x, y, z]` to count at: interior, on cell faces, and at the corners.
const FRACTIONS: [[f64; 3]; 6] = [
    [0.3, 0.6, 0.85],
    [0.5, 0.5, 0.5],
    [0.0, 0.0, 0.0],
    [1.0, 1.0, 1.0],
    [0.125, 0.999, 0.0],
    [0.71, 0.0, 0.42],
];

/// Tap sets (tap `i` at corner `(i & 1, (i >> 1) & 1, i >> 2)`): mixed, with transparent
/// voxels, and the fig. 4 boundary (opaque white beside transparent red).
fn tap_sets() -> Vec<[StraightF32; 8]> {
    let v = |r: f32, g: f32, b: f32, a: f32| StraightF32 { c: [r, g, b], a };
    let mixed = [
        v(0.9, 0.1, 0.3, 0.2),
        v(0.2, 0.8, 0.5, 0.7),
        v(0.4, 0.4, 0.9, 0.0),
        v(1.0, 0.0, 0.25, 1.0),
        v(0.05, 0.6, 0.75, 0.35),
        v(0.3, 0.3, 0.3, 0.9),
        v(0.7, 0.2, 0.1, 0.05),
        v(0.6, 0.9, 0.0, 0.5),
    ];
    let mut boundary = [v(1.0, 0.0, 0.0, 0.0); 8];
    for (i, t) in boundary.iter_mut().enumerate() {
        if i & 1 == 1 {
            *t = v(1.0, 1.0, 1.0, 1.0);
        }
    }
    let transparent = [v(0.5, 0.25, 1.0, 0.0); 8];
    vec![mixed, boundary, transparent]
}

/// The trilinear weight of tap `i`, factored: `(1 − x or x)·(1 − y or y)·(1 − z or z)`.
fn factored_weight(i: usize, f: [f64; 3]) -> f64 {
    let axis = |bit: usize, t: f64| if bit == 1 { t } else { 1.0 - t };
    axis(i & 1, f[0]) * axis((i >> 1) & 1, f[1]) * axis(i >> 2, f[2])
}

/// Independent separate interpolation: `(Σ w_i C_i, Σ w_i α_i)`.
fn expected_separate(taps: &[StraightF32; 8], f: [f64; 3]) -> ([f64; 3], f64) {
    let mut c = [0.0; 3];
    let mut a = 0.0;
    for (i, t) in taps.iter().enumerate() {
        let w = factored_weight(i, f);
        for (ck, &tk) in c.iter_mut().zip(&t.c) {
            *ck += w * f64::from(tk);
        }
        a += w * f64::from(t.a);
    }
    (c, a)
}

/// Independent opacity-weighted interpolation: `(Σ w_i α_i C_i, Σ w_i α_i)`.
fn expected_opacity_weighted(taps: &[StraightF32; 8], f: [f64; 3]) -> ([f64; 3], f64) {
    let mut c = [0.0; 3];
    let mut a = 0.0;
    for (i, t) in taps.iter().enumerate() {
        let wa = factored_weight(i, f) * f64::from(t.a);
        for (ck, &tk) in c.iter_mut().zip(&t.c) {
            *ck += wa * f64::from(tk);
        }
        a += wa;
    }
    (c, a)
}

fn counted_fractions(f: [f64; 3]) -> [Counted; 3] {
    f.map(Counted)
}

/// Asserts the counted value is the independent one within [`COUNTED_VALUE_TOL`]; returns the
/// largest difference.
fn assert_value(what: &str, got: &Interp<Counted>, want: ([f64; 3], f64)) -> f64 {
    let (wc, wa) = want;
    let mut worst: f64 = 0.0;
    for (k, (g, w)) in got.c.iter().zip(wc).enumerate() {
        let err = (g.0 - w).abs();
        assert!(
            err <= COUNTED_VALUE_TOL,
            "{what}: channel {k} = {} but the f64 interpolation gives {w}",
            g.0
        );
        worst = worst.max(err);
    }
    let err = (got.a.0 - wa).abs();
    assert!(
        err <= COUNTED_VALUE_TOL,
        "{what}: alpha = {} but the f64 interpolation gives {wa}",
        got.a.0
    );
    worst.max(err)
}

/// Counts `kernel` on every tap set and fraction, checks its value against `expected`, and
/// returns the count, asserting that it is the same for every input (no data-dependent work),
/// and the largest difference from the independent value.
fn count_over_inputs(
    what: &str,
    kernel: impl Fn(&[StraightF32; 8], [Counted; 3]) -> Interp<Counted>,
    expected: impl Fn(&[StraightF32; 8], [f64; 3]) -> ([f64; 3], f64),
) -> (Ops, f64) {
    let mut seen: Option<Ops> = None;
    let mut worst: f64 = 0.0;
    for taps in tap_sets() {
        for f in FRACTIONS {
            let (got, used) = counted(|| kernel(&taps, counted_fractions(f)));
            worst = worst.max(assert_value(what, &got, expected(&taps, f)));
            match seen {
                None => seen = Some(used),
                Some(first) => assert_eq!(
                    used, first,
                    "{what}: the count depends on the input (f = {f:?})"
                ),
            }
        }
    }
    (seen.unwrap_or(ops(0, 0)), worst)
}

// ---------------------------------------------------------------------------------------------
// The counts.

fn separate_tree() -> (Ops, f64) {
    count_over_inputs(
        "Separate, tree",
        |taps, f| Trilinear::<Tree>::interpolate_taps(&Separate, taps, f),
        expected_separate,
    )
}

fn separate_weighted_sum() -> (Ops, f64) {
    count_over_inputs(
        "Separate, weighted sum",
        |taps, f| Trilinear::<WeightedSum>::interpolate_taps(&Separate, taps, f),
        expected_separate,
    )
}

fn opacity_weighted_tree() -> (Ops, f64) {
    count_over_inputs(
        "OpacityWeighted, tree",
        |taps, f| Trilinear::<Tree>::interpolate_taps(&OpacityWeighted, taps, f),
        expected_opacity_weighted,
    )
}

fn opacity_weighted_weighted_sum() -> (Ops, f64) {
    count_over_inputs(
        "OpacityWeighted, weighted sum",
        |taps, f| Trilinear::<WeightedSum>::interpolate_taps(&OpacityWeighted, taps, f),
        expected_opacity_weighted,
    )
}

#[test]
fn trilinear_weights_cost_4m_19a_and_are_the_trilinear_weights() {
    let mut seen: Option<Ops> = None;
    for f in FRACTIONS {
        let (w, used) = counted(|| trilinear_weights(counted_fractions(f)));
        let mut sum = 0.0;
        for (i, wi) in w.iter().enumerate() {
            let want = factored_weight(i, f);
            assert!(
                (wi.0 - want).abs() <= COUNTED_VALUE_TOL,
                "w[{i}] at {f:?} = {} but (1 − x or x)(1 − y or y)(1 − z or z) = {want}",
                wi.0
            );
            sum += wi.0;
        }
        assert!(
            (sum - 1.0).abs() <= COUNTED_VALUE_TOL,
            "Σw = {sum} at {f:?}"
        );
        if let Some(first) = seen {
            assert_eq!(used, first, "weight count depends on the fractions");
        }
        seen = Some(used);
        assert_eq!(used, ops(4, 19), "trilinear_weights at {f:?}");
    }
}

#[test]
fn separate_tree_costs_28m_56a() {
    // 4 channels × 7 lerps × (1M 2A).
    let (used, _) = separate_tree();
    assert_eq!(used, ops(4 * 7, 4 * 7 * 2));
    assert_eq!(used, ops(28, 56));
}

#[test]
fn separate_weighted_sum_costs_36m_47a() {
    // weights 4M 19A + 4 channels × (8M 7A).
    let (used, _) = separate_weighted_sum();
    assert_eq!(used, ops(4 + 4 * 8, 19 + 4 * 7));
    assert_eq!(used, ops(36, 47));
}

#[test]
fn opacity_weighted_tree_costs_52m_56a() {
    // premultiply 3 × 8 = 24M, then the separate tree's 28M 56A.
    let (used, _) = opacity_weighted_tree();
    assert_eq!(used, ops(3 * 8 + 28, 56));
    assert_eq!(used, ops(52, 56));
}

#[test]
fn opacity_weighted_weighted_sum_costs_36m_47a() {
    // weights 4M 19A + ω 8M + α 7A + 3 colors × (8M 7A).
    let (used, _) = opacity_weighted_weighted_sum();
    assert_eq!(used, ops(4 + 8 + 3 * 8, 19 + 7 + 3 * 7));
    assert_eq!(used, ops(36, 47));
}

/// The pieces of each count, measured separately on the kernels the totals call.
#[test]
fn the_counts_break_down_as_the_paper_says() {
    let taps = tap_sets()[0];
    let f = counted_fractions(FRACTIONS[0]);
    let (w, weights) = counted(|| trilinear_weights(f));
    assert_eq!(weights, ops(4, 19), "the 8 weights");

    // Given the weights: the separate sum is 4 × (8M 7A); the opacity-weighted sum is
    // ω 8M + α 7A + 3 × (8M 7A). Both 32M 28A.
    let (sep, sep_sum) = counted(|| Mode::<StraightF32>::weighted(&Separate, &taps, &w));
    assert_eq!(
        sep_sum,
        ops(4 * 8, 4 * 7),
        "separate sums given the weights"
    );
    let (ow, ow_sum) = counted(|| Mode::<StraightF32>::weighted(&OpacityWeighted, &taps, &w));
    assert_eq!(ow_sum, ops(8 + 3 * 8, 7 + 3 * 7), "ω, α and 3 color sums");
    assert_value(
        "Separate::weighted",
        &sep,
        expected_separate(&taps, FRACTIONS[0]),
    );
    assert_value(
        "OpacityWeighted::weighted",
        &ow,
        expected_opacity_weighted(&taps, FRACTIONS[0]),
    );

    // One lerp tree per channel is 7M 14A; the premultiplication is the whole difference
    // between the two tree counts: 24M 0A.
    let (_, sep_tree) = counted(|| Mode::<StraightF32>::tree8(&Separate, &taps, f));
    let (_, ow_tree) = counted(|| Mode::<StraightF32>::tree8(&OpacityWeighted, &taps, f));
    assert_eq!(sep_tree, ops(4 * 7, 4 * 14), "4 channels × 7 lerps");
    assert_eq!(
        ops(ow_tree.m - sep_tree.m, ow_tree.a - sep_tree.a),
        ops(24, 0),
        "premultiplying 8 colors"
    );
}

/// The whole of Table 1 at once (printed with `--nocapture`), and the paper's conclusion:
/// as a weighted sum, opacity weighting costs nothing extra; as a tree it costs 24M more.
#[test]
fn table_1() {
    let cells = [
        ("separate color/opacity", "binary tree", separate_tree()),
        (
            "separate color/opacity",
            "weighted sum",
            separate_weighted_sum(),
        ),
        (
            "opacity-weighted color",
            "binary tree",
            opacity_weighted_tree(),
        ),
        (
            "opacity-weighted color",
            "weighted sum",
            opacity_weighted_weighted_sum(),
        ),
    ];
    for (method, order, (used, worst)) in cells {
        println!(
            "{method:<24} {order:<14} {:>9}   worst |counted − f64| = {worst:.1e} (tolerance {COUNTED_VALUE_TOL:.0e})",
            used.to_string()
        );
    }
    assert_eq!(
        cells.map(|(_, _, (used, _))| used),
        [ops(28, 56), ops(36, 47), ops(52, 56), ops(36, 47)]
    );
}

/// Both evaluation orders compute the same interpolation (within f64 rounding).
#[test]
fn both_orders_agree_on_the_counted_values() {
    for taps in tap_sets() {
        for f in FRACTIONS {
            let cf = counted_fractions(f);
            let pairs = [
                (
                    Trilinear::<Tree>::interpolate_taps(&Separate, &taps, cf),
                    Trilinear::<WeightedSum>::interpolate_taps(&Separate, &taps, cf),
                ),
                (
                    Trilinear::<Tree>::interpolate_taps(&OpacityWeighted, &taps, cf),
                    Trilinear::<WeightedSum>::interpolate_taps(&OpacityWeighted, &taps, cf),
                ),
            ];
            for (tree, sum) in pairs {
                for (t, s) in tree
                    .c
                    .iter()
                    .chain([&tree.a])
                    .zip(sum.c.iter().chain([&sum.a]))
                {
                    assert!(
                        (t.0 - s.0).abs() <= COUNTED_VALUE_TOL,
                        "{t:?} vs {s:?} at {f:?}"
                    );
                }
            }
        }
    }
}
