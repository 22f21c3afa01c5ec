//! The march: the one loop every marcher runs, whatever runs in its lanes.
//!
//! A march takes `steps` steps; at step `j` an instance computes the sums of its samples
//! (`sums`: one sample of one ray, four or eight consecutive samples of one ray, or one sample
//! of each of four or eight rays, in the lanes of its [`Lanes`](crate::lanes::Lanes) type)
//! and composites them (`composite`: in lanes with a live mask, or one lane after the other
//! onto one ray), and may end the march early (`going`, before a step; `composite`, with its
//! result). The loop itself — the step count, the early exits and the software pipelining —
//! is written here once, and every marcher is an instance of it:
//!
//! | instance | lanes | where |
//! |---|---|---|
//! | one sample at a time, front to back and back to front | `f32` | `RayMarcher::cast` (tail, Cortex-M) |
//! | four consecutive samples of one ray | [`F32x4`](crate::lanes::F32x4) | `RayMarcher::cast` on SIMD targets |
//! | four rays | [`F32x4`](crate::lanes::F32x4) | `RayMarcher::cast4`, `cast_rays` |
//! | eight rays, or eight samples of one ray, float or integer | AVX2 `__m256` | `arch::avx2`, `cast`, `cast_rays` |
//! | one integer sample at a time (pipelined reads, or skipping) | `IntSample` | `IntRayMarcher::cast` |
//!
//! (`IntRayMarcher::march_positions` keeps a loop of its own: its positions come from a
//! caller's iterator, of no known length, and none may be read after the stop.)
//!
//! **Pipelining** (`lag` > 0): the sums of step `j` are composited at step `j + lag`, after the
//! next steps' sums have been issued, so that a long chain of dependent operations (the
//! extinction step's two divisions) overlaps the next samples' reads and sums. The same sums
//! are composited in the same order, so the results do not change; after the last step the
//! pending sums are composited while the march is `going`.
//!
//! Everything here is `#[inline(always)]`: the loop is compiled into each instance's entry,
//! in its instruction set (for AVX2, inside a `#[target_feature(enable = "avx2,fma")]`
//! function, whose closures are compiled so too).

use core::ops::ControlFlow;

/// The most steps a march's compositing may lag behind its sums (the extinction modes' lag in
/// the AVX2 kernel: a lag of 1 took `ExtinctionWeightedU8` from 7.8 to 7.1 ns/sample in a
/// probe; 2 gained nothing, 6.3–7.9 against 6.3–6.5 for both modes).
pub(crate) const MAX_LAG: u32 = 1;

/// Runs a march of `steps` steps over the state `st`: while `going(st, j)` (tested before
/// step `j`), `sums(st, j)` issues step `j`'s sums and `composite(st, s, i)` composites those of
/// step `i = j − lag` (`lag ≤ MAX_LAG`; `zero` fills the pipeline and is never composited).
/// Returns `Break` of `composite`'s result where it ended the march, else `Continue` of the
/// number of steps issued (the step before which `going` said no, or `steps`).
#[inline(always)]
pub(crate) fn march<St, S: Copy, R>(
    st: &mut St,
    steps: u32,
    lag: u32,
    zero: S,
    mut going: impl FnMut(&mut St, u32) -> bool,
    mut sums: impl FnMut(&mut St, u32) -> S,
    mut composite: impl FnMut(&mut St, S, u32) -> ControlFlow<R>,
) -> ControlFlow<R, u32> {
    let lag = lag.min(MAX_LAG);
    let mut pending = [zero; MAX_LAG as usize];
    let mut j = 0u32;
    while j < steps && going(st, j) {
        let s = sums(st, j);
        // The sums to composite now, of step `j − lag`: this step's, or (pipelined) the oldest
        // pending.
        let s = if lag > 0 {
            let [oldest, ..] = pending;
            pending.rotate_left(1);
            if let Some(newest) = pending.last_mut() {
                *newest = s;
            }
            if j < lag {
                j += 1;
                continue;
            }
            oldest
        } else {
            s
        };
        composite(st, s, j - lag)?;
        j += 1;
    }
    // The pipelined sums left (of steps `j − lag` to `j − 1`, of those that exist).
    if lag > 0 {
        let first = j.saturating_sub(lag);
        let left = pending.iter().skip((MAX_LAG - (j - first)) as usize);
        for (i, s) in (first..j).zip(left) {
            if going(st, i) {
                composite(st, *s, i)?;
            }
        }
    }
    ControlFlow::Continue(j)
}
