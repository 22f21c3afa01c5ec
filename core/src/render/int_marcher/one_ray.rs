//! One ray at a time: [`IntRayMarcher::cast`]'s march, the one-sample integer instances of
//! `crate::march` (and, where the marcher's [`Isa`] is AVX2, the eight-sample one of
//! `arch::avx2`).

use core::convert::Infallible;
use core::ops::ControlFlow;

use super::*;

impl<V, M, Fl, const F: u32, S> IntRayMarcher<'_, V, M, Fl, F, S>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
    S: Skipping,
{
    #[inline(always)]
    pub(super) fn march<C: Stage>(&self, ray: &Ray, corr: &C) -> (IntSample, u32) {
        let (t_first, n) = self.sample_range(ray);
        let d = self.step.d();
        let a_stop = self.stop.a_stop();
        let mut acc = IntSample::TRANSPARENT;
        // Outside these samples every sample is empty (none without skipping): exactly
        // transparent, so leaving them out changes neither `acc` nor the stop test.
        let window = self.skip.occupied(ray, (t_first, n), d);
        #[cfg(target_arch = "x86_64")]
        if let (Some(cpu), true) = (self.isa.avx2_token(), self.eight_ray_packets()) {
            // Eight consecutive samples in the AVX2 lanes (the same positions, integer
            // arithmetic and order of compositing).
            let one = OneRay {
                vol: self.sampler.volume(),
                cpu,
                ray,
                samples: crate::arch::avx2::Samples::window((t_first, n), window.clone()),
                d,
                a_stop: f32::from(a_stop),
            };
            if let Ok(Some(done)) = Fl::lanes8(self.sampler.mode(), one) {
                return done;
            }
        }
        // One sample at a time (`crate::march`'s one-lane integer instance), going while
        // `A < A_stop` before a sample: the count is the steps taken.
        let going = |acc: &IntSample| acc.a() < a_stop;
        if !S::SKIPS {
            // Software-pipelined: the voxels of sample `j + 1` are read before sample `j` is
            // combined, so their loads are in flight meanwhile. Same positions, same taps, same
            // order of compositing: the same result. (One read past the last sample, at a
            // position clamped into the volume, is not used.)
            let at = |j: u32| self.quantize_in_box(ray.at(t_first + j as f32 * d));
            let pos = at(0);
            let first = (pos, self.sampler.fetch(pos));
            let mut st = (acc, first.0, first.1);
            let taken = crate::march::march(
                &mut st,
                n,
                0,
                first,
                #[inline(always)]
                |(acc, ..), _| going(acc),
                #[inline(always)]
                |(_, pos, taps), j| {
                    let now = (*pos, *taps);
                    *pos = at(j.wrapping_add(1));
                    *taps = self.sampler.fetch(*pos);
                    now
                },
                #[inline(always)]
                |(acc, ..), (p, t), _| {
                    *acc = front_to_back(*acc, corr.apply(self.sampler.combine(t, p)));
                    ControlFlow::<Infallible>::Continue(())
                },
            );
            let ControlFlow::Continue(j) = taken;
            return (st.0, j);
        }
        let end = window.end.min(n);
        let steps = end.saturating_sub(window.start);
        let taken = crate::march::march(
            &mut acc,
            steps,
            0,
            (),
            #[inline(always)]
            |acc, _| going(acc),
            #[inline(always)]
            |_, _| (),
            #[inline(always)]
            |acc, (), i| {
                let p = ray.at(t_first + (window.start + i) as f32 * d);
                // A skipped sample is exactly transparent: `acc`, the stop test and the count
                // are what compositing it would have left.
                if !self.skip.empty(p) {
                    *acc = front_to_back(*acc, self.sample_with(p, corr));
                }
                ControlFlow::<Infallible>::Continue(())
            },
        );
        let ControlFlow::Continue(i) = taken;
        if i < steps {
            return (acc, window.start + i);
        }
        // The stop test before the first sample left out, if any.
        if end < n && acc.a() >= a_stop {
            return (acc, end);
        }
        (acc, n)
    }
}
