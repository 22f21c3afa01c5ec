//! The packet paths of [`RayMarcher`]: four rays in [`F32x4`] lanes ([`RayMarcher::cast4`]),
//! and where the marcher's [`Isa`] is AVX2, the eight-lane kernel of `arch::avx2` (eight rays,
//! or eight samples of one ray).

use core::convert::Infallible;

use super::*;
#[cfg(target_arch = "x86_64")]
use crate::arch::avx2::{Samples, Stage};
use crate::each::Each;
#[cfg(target_arch = "x86_64")]
use crate::mode::{LaneCorrection, LaneMode, LaneVisitor};

impl<'v, V, M, F, O, S> RayMarcher<'v, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    /// Where the eight-ray AVX2 kernel applies ([`eight_ray_packets`](Self::eight_ray_packets)),
    /// casts the leading multiple of eight rays with it and returns the rest; otherwise
    /// returns all of them.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn cast_rays8<'r, 'o>(
        &self,
        rays: &'r [Ray],
        out: &'o mut [Sample],
    ) -> (&'r [Ray], &'o mut [Sample]) {
        let Some(cpu) = self.isa.avx2_token() else {
            return (rays, out);
        };
        if !self.eight_ray_packets() {
            return (rays, out);
        }
        let packets = Packets {
            marcher: self,
            cpu,
            rays,
            out,
        };
        match F::lanes8(&self.mode, packets) {
            Ok(rest) => rest,
            Err(p) => (p.rays, p.out),
        }
    }

    /// Where the eight-lane AVX2 kernel applies ([`eight_ray_packets`](Self::eight_ray_packets)),
    /// the front-to-back march of `ray` over the samples `window` of its `range` with eight
    /// consecutive samples in the lanes (bit-identical to [`march_from`](Self::march_from)).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(super) fn march_one_avx2(
        &self,
        ray: &Ray,
        range: (f32, u32),
        window: core::ops::Range<u32>,
    ) -> Option<(Sample, u32)> {
        let cpu = self.isa.avx2_token()?;
        if !self.eight_ray_packets() {
            return None;
        }
        let one = OneRay {
            marcher: self,
            cpu,
            ray,
            samples: Samples::window(range, window),
        };
        F::lanes8(&self.mode, one).ok().flatten()
    }

    /// Whether the eight-ray AVX2 kernel applies to this marcher: an AVX2 [`Isa`], a filter
    /// and mode with a lane kernel over voxels of its format (`Filter::lanes8`:
    /// `Trilinear<WeightedSum>` with `OpacityWeighted`, `Separate` and
    /// `ExtinctionWeightedU8` over `StraightU8`, the first two also over `StraightF32`,
    /// `ExtinctionWeighted` over `ExtinctionF32`),
    /// front to back, over a volume it can index; with the marcher's opacity correction, in
    /// the lanes (`opacity::correct_in`). (With skipping, each lane marches only the samples
    /// between its ray's first and last occupied ones, [`Skipping::occupied`].)
    #[inline]
    pub(super) fn eight_ray_packets(&self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            O::FRONT_TO_BACK
                && self.isa.avx2_token().is_some()
                && crate::arch::avx2::fits(&self.volume)
                && F::lanes8(&self.mode, Reads(self.volume.data())).unwrap_or(false)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// What the eight-lane kernel does with each finished sample: this marcher's step,
    /// correction and stop level, and the mode's `taus`.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn stage<'t, C: LaneCorrection>(&self, taus: &'t [f32; 256]) -> Stage<'t, C> {
        Stage {
            d: self.step.d,
            a_stop: self.order.termination().a_stop_or_inf(),
            taus,
            corr: C::of(self.correction),
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

    /// The packet form of [`march`](Self::march) (front to back only; the four-ray instance
    /// of `crate::march`): the accumulated samples (before the background) and the sample
    /// counts.
    #[inline(always)]
    pub(super) fn march4<C: Correction>(
        &self,
        rays: &[Ray; 4],
        corr: &C,
    ) -> ([Sample; 4], [u32; 4]) {
        let ranges = rays.each_ref().each(|r| self.samples(r));
        let n = ranges.each(|r| r.1);
        let d = self.step.d;
        let term = self.order.termination();
        let mut st = Four {
            acc: Interp {
                c: [F32x4::ZERO; 3],
                a: F32x4::ZERO,
            },
            count: n,
            live: n.each(|k| k > 0),
        };
        let steps = n.iter().copied().max().unwrap_or(0);
        let marched = crate::march::march(
            &mut st,
            steps,
            0,
            None,
            // Lanes go while before their last sample and not stopped; the march goes while
            // two or more do (the last ray still going finishes below, one sample at a time).
            #[inline(always)]
            |st: &mut Four, j: u32| {
                for (l, &k) in st.live.iter_mut().zip(&n) {
                    if j >= k {
                        *l = false;
                    }
                }
                st.live.iter().filter(|&&l| l).count() > 1
            },
            // Step `j`'s samples where a live lane's is not skipped (`None` where no lane's is).
            #[inline(always)]
            |st: &mut Four, j: u32| {
                let jd = j as f32 * d;
                let mut pos = [[0.0f32; 3]; 4];
                let mut active = [false; 4];
                for (((p, a), (r, &(t_first, _))), &l) in pos
                    .iter_mut()
                    .zip(active.iter_mut())
                    .zip(rays.iter().zip(ranges.iter()))
                    .zip(st.live.iter())
                {
                    if l {
                        *p = r.at(t_first + jd);
                        // A skipped sample is transparent: the lane's `acc` and its termination
                        // test are unchanged by it, as in `march`.
                        *a = !self.skip.empty(*p);
                    }
                }
                let fill = pos.iter().zip(active).find(|x| x.1).map(|x| *x.0)?;
                // Idle lanes sample an active lane's position; their result is discarded.
                for (p, a) in pos.iter_mut().zip(active) {
                    if !a {
                        *p = fill;
                    }
                }
                let i = F::interpolate_x4(&self.mode, &self.volume, pos);
                Some((corr.apply_in(self.mode.finish_in(i, d)), active))
            },
            // `front_to_back` in lanes, kept only in the active lanes.
            #[inline(always)]
            |st: &mut Four, s: Option<(Interp<F32x4>, [bool; 4])>, j: u32| {
                if let Some((s, active)) = s {
                    st.acc = front_to_back_in(st.acc, s, active);
                    let a = st.acc.a.to_array();
                    for (((l, k), a), &act) in
                        st.live.iter_mut().zip(&mut st.count).zip(a).zip(&active)
                    {
                        if act && term.done(a) {
                            *l = false;
                            *k = j + 1;
                        }
                    }
                }
                ControlFlow::<Infallible>::Continue(())
            },
        );
        let ControlFlow::Continue(j) = marched;
        let Four {
            acc,
            mut count,
            live,
        } = st;
        let mut samples = unpack_interp(acc).each(|x| Sample { c: x.c, a: x.a });
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
                (*s, *k) = self.march_from(ray, corr, range, j..range.1, *s);
            }
        }
        (samples, count)
    }
}

/// What [`RayMarcher::march4`]'s steps carry: the four lanes' accumulated samples, their
/// counts (a lane's `n` until it stops early) and which lanes still go.
struct Four {
    acc: Interp<F32x4>,
    count: [u32; 4],
    live: [bool; 4],
}

/// [`RayMarcher::cast_rays8`] for the lane kernel of the marcher's mode.
#[cfg(target_arch = "x86_64")]
struct Packets<'m, 'v, 'r, 'o, V: Voxel, M, F, O, S> {
    marcher: &'m RayMarcher<'v, V, M, F, O, S>,
    cpu: crate::arch::avx2::Avx2,
    rays: &'r [Ray],
    out: &'o mut [Sample],
}

#[cfg(target_arch = "x86_64")]
impl<'r, 'o, V, M, F, O, S> LaneVisitor for Packets<'_, '_, 'r, 'o, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    type Out = (&'r [Ray], &'o mut [Sample]);

    #[inline(always)]
    fn visit<K: LaneMode>(self, mode: &K) -> Self::Out {
        use crate::arch::avx2::{in_packets, march8};
        let m = self.marcher;
        let Some(data) = K::voxels(m.volume.data()) else {
            return (self.rays, self.out);
        };
        let vol = m.volume.with_data(data);
        let (d, stage) = (m.step.d, m.stage::<K::Correction>(mode.taus()));
        in_packets(self.rays, self.out, |r| {
            let samples = Samples::packet(r, |r| m.samples(r), |r, s| m.skip.occupied(r, s, d));
            let acc = march8::<K::Voxel, K>(self.cpu, &vol, r, &samples, stage);
            acc.each(|a| over(a, m.background))
        })
    }
}

/// [`RayMarcher::march_one_avx2`] for the lane kernel of the marcher's mode.
#[cfg(target_arch = "x86_64")]
struct OneRay<'m, 'v, 'r, V: Voxel, M, F, O, S> {
    marcher: &'m RayMarcher<'v, V, M, F, O, S>,
    cpu: crate::arch::avx2::Avx2,
    ray: &'r Ray,
    samples: Samples,
}

#[cfg(target_arch = "x86_64")]
impl<V, M, F, O, S> LaneVisitor for OneRay<'_, '_, '_, V, M, F, O, S>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    type Out = Option<(Sample, u32)>;

    #[inline(always)]
    fn visit<K: LaneMode>(self, mode: &K) -> Self::Out {
        let m = self.marcher;
        let vol = m.volume.with_data(K::voxels(m.volume.data())?);
        Some(crate::arch::avx2::march_one::<K::Voxel, K>(
            self.cpu,
            &vol,
            self.ray,
            &self.samples,
            m.stage::<K::Correction>(mode.taus()),
        ))
    }
}

/// Whether the lane kernel of a mode reads voxels of the format of `.0`.
#[cfg(target_arch = "x86_64")]
struct Reads<'d, V>(&'d [V]);

#[cfg(target_arch = "x86_64")]
impl<V: Voxel> LaneVisitor for Reads<'_, V> {
    type Out = bool;

    #[inline(always)]
    fn visit<K: LaneMode>(self, _mode: &K) -> bool {
        K::voxels(self.0).is_some()
    }
}
