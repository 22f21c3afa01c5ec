//! `map` over the kernels' small arrays: [`Each::each`] and [`build`].
//!
//! `[T; N]::map` and `core::array::from_fn` run through the standard library's general
//! machinery (`try_from_fn`, `try_map`, a drain guard that drops the elements made so far if
//! the closure panics): five functions of LLVM IR for every closure type, in every instance of
//! every generic kernel. In the host library that was a fifth of all its IR, and a
//! corresponding share of its build time. Over `Copy` values nothing needs dropping, so a
//! loop does the same in one function. Both call the closure once per element, in order, so
//! the results are the same values. The machine code is not always the same: where the
//! standard form measured smaller or faster (the integer kernels at the firmware's
//! `opt-level = "s"`, the voxel decodes in the baseline instance), it stays, with the figures
//! beside it. (`core/clippy.toml` disallows the standard forms elsewhere in the core.)

/// `f` of each element of an array of `Copy` values, in order: `[T; N]::map` for `N ≥ 1`.
pub(crate) trait Each<T, const N: usize> {
    /// `[f(self[0]), …, f(self[N − 1])]`, `f` called in that order.
    fn each<U: Copy>(self, f: impl FnMut(T) -> U) -> [U; N];
}

// Every index below is below `N` (`0 < N`, asserted at compile time, or the loop's
// condition), so each bounds check is dead and optimised away: no panic remains. A plain loop
// rather than iterator adapters: a fifth of the IR per instance.
#[allow(clippy::indexing_slicing)]
impl<T: Copy, const N: usize> Each<T, N> for [T; N] {
    #[inline(always)]
    fn each<U: Copy>(self, mut f: impl FnMut(T) -> U) -> [U; N] {
        const { assert!(N >= 1, "`each` maps arrays of at least one element") };
        let mut out = [f(self[0]); N];
        let mut i = 1;
        while i < N {
            out[i] = f(self[i]);
            i += 1;
        }
        out
    }
}

impl<T: Copy, const N: usize> Each<T, N> for &[T; N] {
    #[inline(always)]
    fn each<U: Copy>(self, f: impl FnMut(T) -> U) -> [U; N] {
        (*self).each(f)
    }
}

/// `[f(0), …, f(N − 1)]`, `f` called in that order: `core::array::from_fn` for `N ≥ 1`.
#[inline(always)]
#[allow(clippy::indexing_slicing)] // `i < N`: the check is dead, as in `each`.
pub(crate) fn build<U: Copy, const N: usize>(mut f: impl FnMut(usize) -> U) -> [U; N] {
    const { assert!(N >= 1, "`build` makes arrays of at least one element") };
    let mut out = [f(0); N];
    let mut i = 1;
    while i < N {
        out[i] = f(i);
        i += 1;
    }
    out
}

#[cfg(test)]
#[allow(clippy::disallowed_methods, clippy::indexing_slicing)]
mod tests {
    use super::*;

    #[test]
    fn each_and_build_match_the_standard_forms_and_their_order() {
        let a = [3u32, 1, 4, 1, 5, 9, 2, 6];
        let std_map = a.map(|x| x * 7 + 1);
        assert_eq!(a.each(|x| x * 7 + 1), std_map);
        let mut seen = [0usize; 8];
        let mut k = 0;
        let got: [usize; 8] = build(|i| {
            seen[k] = i;
            k += 1;
            i * i
        });
        assert_eq!(seen, [0, 1, 2, 3, 4, 5, 6, 7]);
        let std_from_fn: [usize; 8] = core::array::from_fn(|i| i * i);
        assert_eq!(got, std_from_fn);
        let one: [f32; 1] = [2.5f32].each(|x| x * 2.0);
        assert_eq!(one, [5.0]);
    }
}
