//! The packet paths of [`RayMarcher`]: four rays in [`F32x4`] lanes ([`RayMarcher::cast4`]),
//! and where the marcher's [`Isa`] is AVX2, the eight-lane kernel of `arch::avx2` (eight rays,
//! or eight samples of one ray).

use super::*;

impl<'v, V, M, F, O, S> RayMarcher<'v, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    /// Where the eight-ray AVX2 kernel applies (an AVX2 [`Isa`] and an `OpacityWeighted`,
    /// `Separate` or `ExtinctionWeightedU8` marcher over straight RGBA8 or an
    /// `ExtinctionWeighted` one over `ExtinctionF32`, `Trilinear<WeightedSum>`, front to back
    /// without correction or skipping), casts the leading multiple of eight rays with it and
    /// returns the rest; otherwise returns all of them.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn cast_rays8<'r, 'o>(
        &self,
        rays: &'r [Ray],
        out: &'o mut [Sample],
    ) -> (&'r [Ray], &'o mut [Sample]) {
        use crate::arch::avx2::{in_packets, march8};
        use crate::mode::{ExtinctionWeighted, ExtinctionWeightedU8, OpacityWeighted, Separate};
        let separate = <M as Mode<V>>::SEPARATE;
        let extinction = <M as Mode<V>>::EXTINCTION;
        let taus = self.mode.tau_table().map(|t| t.taus());
        let Some(cpu) = self.isa.avx2_token() else {
            return (rays, out);
        };
        if !self.eight_ray_packets() {
            return (rays, out);
        }
        let a_stop = self.order.termination().a_stop_or_inf();
        in_packets(rays, out, |r| {
            let ranges = r.each_ref().map(|r| self.samples(r));
            let (vol, d) = (&self.volume, self.step.d);
            let acc = match taus {
                Some(t) => {
                    march8::<V, ExtinctionWeightedU8<'static>>(cpu, vol, r, &ranges, d, a_stop, t)
                }
                None if extinction => {
                    march8::<V, ExtinctionWeighted>(cpu, vol, r, &ranges, d, a_stop, &[0.0; 256])
                }
                None if separate => {
                    march8::<V, Separate>(cpu, vol, r, &ranges, d, a_stop, &[0.0; 256])
                }
                None => march8::<V, OpacityWeighted>(cpu, vol, r, &ranges, d, a_stop, &[0.0; 256]),
            };
            acc.map(|a| over(a, self.background))
        })
    }

    /// Where the eight-lane AVX2 kernel applies ([`eight_ray_packets`](Self::eight_ray_packets)),
    /// the front-to-back march of `ray` over its samples `range` with eight consecutive
    /// samples in the lanes (bit-identical to [`march_from`](Self::march_from) from sample 0).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn march_one_avx2(&self, ray: &Ray, range: (f32, u32)) -> Option<(Sample, u32)> {
        use crate::arch::avx2::march_one;
        use crate::mode::{ExtinctionWeighted, ExtinctionWeightedU8, OpacityWeighted, Separate};
        let cpu = self.isa.avx2_token()?;
        if !self.eight_ray_packets() {
            return None;
        }
        let (vol, d) = (&self.volume, self.step.d);
        let a_stop = self.order.termination().a_stop_or_inf();
        let none = &[0.0; 256];
        Some(match self.mode.tau_table().map(|t| t.taus()) {
            Some(t) => {
                march_one::<V, ExtinctionWeightedU8<'static>>(cpu, vol, ray, range, d, a_stop, t)
            }
            None if <M as Mode<V>>::EXTINCTION => {
                march_one::<V, ExtinctionWeighted>(cpu, vol, ray, range, d, a_stop, none)
            }
            None if <M as Mode<V>>::SEPARATE => {
                march_one::<V, Separate>(cpu, vol, ray, range, d, a_stop, none)
            }
            None => march_one::<V, OpacityWeighted>(cpu, vol, ray, range, d, a_stop, none),
        })
    }

    /// Whether the eight-ray AVX2 kernel applies to this marcher (an AVX2 [`Isa`] and an
    /// `OpacityWeighted`, `Separate` or `ExtinctionWeightedU8` marcher over straight RGBA8 or
    /// an `ExtinctionWeighted` one over `ExtinctionF32`, `Trilinear<WeightedSum>`, front to
    /// back without correction or skipping, over a volume it can index).
    #[inline]
    pub(super) fn eight_ray_packets(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            let rgba8 = V::STRAIGHT_RGBA8
                && (<M as Mode<V>>::OPACITY_WEIGHTED
                    || <M as Mode<V>>::SEPARATE
                    || self.mode.tau_table().is_some());
            let extinction_f32 =
                <M as Mode<V>>::EXTINCTION && V::as_extinction_f32(self.volume.data()).is_some();
            (rgba8 || extinction_f32)
                && F::TRILINEAR_WEIGHTED_SUM
                && O::FRONT_TO_BACK
                && !S::SKIPS
                && self.correction.is_none()
                && self.isa.avx2_token().is_some()
                && crate::arch::avx2::fits(&self.volume)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// Without the eight-ray kernel: all of `rays` go to the four-ray packets.
    #[cfg(not(target_arch = "x86_64"))]
    #[inline(always)]
    pub(super) fn cast_rays8<'r, 'o>(
        &self,
        rays: &'r [Ray],
        out: &'o mut [Sample],
    ) -> (&'r [Ray], &'o mut [Sample]) {
        (rays, out)
    }

    /// The packet form of [`march`](Self::march) (front to back only): the accumulated
    /// samples (before the background) and the sample counts.
    #[inline(always)]
    pub(super) fn march4<C: Correction>(
        &self,
        rays: &[Ray; 4],
        corr: &C,
    ) -> ([Sample; 4], [u32; 4]) {
        let ranges = rays.each_ref().map(|r| self.samples(r));
        let n = ranges.map(|r| r.1);
        let d = self.step.d;
        let term = self.order.termination();
        let mut acc = Interp {
            c: [F32x4::ZERO; 3],
            a: F32x4::ZERO,
        };
        let mut count = n;
        let mut live = n.map(|k| k > 0);
        let mut j = 0u32;
        while live.iter().any(|&l| l) {
            let jd = j as f32 * d;
            let mut pos = [[0.0f32; 3]; 4];
            let mut active = [false; 4];
            for (((p, a), (r, &(t_first, _))), &l) in pos
                .iter_mut()
                .zip(active.iter_mut())
                .zip(rays.iter().zip(ranges.iter()))
                .zip(live.iter())
            {
                if l {
                    *p = r.at(t_first + jd);
                    // A skipped sample is transparent: the lane's `acc` and its termination
                    // test are unchanged by it, as in `march`.
                    *a = !self.skip.empty(*p);
                }
            }
            if let Some(fill) = pos.iter().zip(active).find(|x| x.1).map(|x| *x.0) {
                // Idle lanes sample an active lane's position; their result is discarded.
                for (p, a) in pos.iter_mut().zip(active) {
                    if !a {
                        *p = fill;
                    }
                }
                let i = F::interpolate_x4(&self.mode, &self.volume, pos);
                let s = corr.apply_in(self.mode.finish_in(i, d));
                // `front_to_back` in lanes, kept only in the active lanes.
                acc = front_to_back_in(acc, s, active);
                let a = acc.a.to_array();
                for (((l, k), a), &act) in live.iter_mut().zip(count.iter_mut()).zip(a).zip(&active)
                {
                    if act && term.done(a) {
                        *l = false;
                        *k = j + 1;
                    }
                }
            }
            j += 1;
            for (l, &k) in live.iter_mut().zip(&n) {
                if j >= k {
                    *l = false;
                }
            }
            if live.iter().filter(|&&l| l).count() == 1 {
                break;
            }
        }
        let mut samples = unpack_interp(acc).map(|x| Sample { c: x.c, a: x.a });
        // The last ray still going (rays of a packet differ in length) finishes one sample at
        // a time, from the sample and the `acc` it reached: the same operations as in its
        // lane, without carrying three idle lanes through its remaining samples.
        for (((s, k), &l), (ray, &range)) in samples
            .iter_mut()
            .zip(count.iter_mut())
            .zip(&live)
            .zip(rays.iter().zip(&ranges))
        {
            if l {
                (*s, *k) = self.march_from(ray, corr, range, j, *s);
            }
        }
        (samples, count)
    }
}
