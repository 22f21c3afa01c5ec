//! One ray at a time: [`RayMarcher::cast`]'s march, the one-sample and four-sample instances of
//! `crate::march` (and, where the marcher's [`Isa`] is AVX2, the eight-sample one of
//! `arch::avx2`).

use core::convert::Infallible;

use super::*;

impl<'v, V, M, F, O, S> RayMarcher<'v, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    #[inline(always)]
    pub(super) fn march<C: Correction>(&self, ray: &Ray, corr: &C) -> (Sample, u32) {
        let (t_first, n) = self.samples(ray);
        let d = self.step.d;
        // Outside these samples every sample is empty (none without skipping): transparent,
        // so leaving them out changes neither `acc` nor the count.
        let window = self.skip.occupied(ray, (t_first, n), d);
        if O::FRONT_TO_BACK {
            #[cfg(target_arch = "x86_64")]
            if let Some(done) = self.march_one_avx2(ray, (t_first, n), window.clone()) {
                return done;
            }
            return self.march_from(ray, corr, (t_first, n), window, Sample::TRANSPARENT);
        }
        // Back to front, one sample at a time from the last (`crate::march`'s one-lane
        // instance); a skipped sample is transparent.
        let last = window.end.min(n);
        let mut acc = Sample::TRANSPARENT;
        let ControlFlow::Continue(_) = crate::march::march(
            &mut acc,
            last.saturating_sub(window.start),
            0,
            None,
            #[inline(always)]
            |_, _| true,
            #[inline(always)]
            |_, i| {
                let p = ray.at(t_first + (last - 1 - i) as f32 * d);
                if self.skip.empty(p) {
                    None
                } else {
                    Some(self.sample_with(p, corr))
                }
            },
            #[inline(always)]
            |acc, s: Option<Sample>, _| {
                if let Some(s) = s {
                    *acc = back_to_front(*acc, s);
                }
                ControlFlow::<Infallible>::Continue(())
            },
        );
        (acc, n)
    }

    /// Front to back over the samples `window` of the ray's `n`, with `acc` composited so
    /// far, four samples at a time in lanes where [`sample_lanes`] says so (the four-lane
    /// instance of `crate::march`), then one at a time (its one-lane instance): the tail of
    /// [`march`](Self::march), where [`march4`](Self::march4) hands over a ray that is the
    /// last of its packet still going. A sample that skipping proves empty is transparent,
    /// so `acc` and the termination test are unchanged by it, and it is not computed. The
    /// count is `n` unless the ray stops early.
    #[inline(always)]
    pub(super) fn march_from<C: Correction>(
        &self,
        ray: &Ray,
        corr: &C,
        (t_first, n): (f32, u32),
        window: core::ops::Range<u32>,
        mut acc: Sample,
    ) -> (Sample, u32) {
        let d = self.step.d;
        let term = self.order.termination();
        let (mut j0, end) = (window.start, window.end.min(n));
        if sample_lanes::<V, M, F>() {
            // Four consecutive samples at a time in lanes, composited in order; the samples
            // after an early stop are computed and dropped.
            let at = |b: u32| j0 + 4 * b;
            let blocks = crate::march::march(
                &mut acc,
                end.saturating_sub(j0) / 4,
                0,
                None,
                #[inline(always)]
                |_, _| true,
                #[inline(always)]
                |_, b| {
                    let pos: [[f32; 3]; 4] = crate::each::build(
                        #[inline(always)]
                        |l| ray.at(t_first + (at(b) + l as u32) as f32 * d),
                    );
                    let keep = pos.each(
                        #[inline(always)]
                        |p| !self.skip.empty(p),
                    );
                    if !keep.iter().any(|&k| k) {
                        return None;
                    }
                    let i = F::interpolate_x4(&self.mode, &self.volume, pos);
                    Some((
                        unpack_interp(corr.apply_in(self.mode.finish_in(i, d))),
                        keep,
                    ))
                },
                #[inline(always)]
                |acc, s, b| {
                    let Some((s, keep)) = s else {
                        return ControlFlow::Continue(());
                    };
                    for (l, (s, k)) in s.iter().zip(keep).enumerate() {
                        if k {
                            *acc = front_to_back(*acc, Sample { c: s.c, a: s.a });
                            if term.done(acc.a) {
                                return ControlFlow::Break(at(b) + l as u32 + 1);
                            }
                        }
                    }
                    ControlFlow::Continue(())
                },
            );
            match blocks {
                ControlFlow::Break(count) => return (acc, count),
                ControlFlow::Continue(b) => j0 = at(b),
            }
        }
        let one = crate::march::march(
            &mut acc,
            end.saturating_sub(j0),
            0,
            None,
            #[inline(always)]
            |_, _| true,
            #[inline(always)]
            |_, i| {
                let p = ray.at(t_first + (j0 + i) as f32 * d);
                if self.skip.empty(p) {
                    None
                } else {
                    Some(self.sample_with(p, corr))
                }
            },
            #[inline(always)]
            |acc, s, i| {
                if let Some(s) = s {
                    *acc = front_to_back(*acc, s);
                    if term.done(acc.a) {
                        return ControlFlow::Break(j0 + i + 1);
                    }
                }
                ControlFlow::Continue(())
            },
        );
        match one {
            ControlFlow::Break(count) => (acc, count),
            ControlFlow::Continue(_) => (acc, n),
        }
    }
}
