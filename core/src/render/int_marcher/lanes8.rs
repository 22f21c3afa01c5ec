//! The visitors of [`IntRayMarcher`]'s eight-lane AVX2 kernel (`IntMode::lanes8`): the mode's
//! type picks the kernel, these run it.

use super::*;
use crate::each::Each;
use crate::fixed_point::{IntLaneMode, IntLaneVisitor};
use crate::mode::NO_TAUS;

impl<V, M, Fl, const F: u32, S> IntRayMarcher<'_, V, M, Fl, F, S>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
    S: Skipping,
{
    /// Where the eight-ray kernel applies ([`eight_ray_packets`](Self::eight_ray_packets)),
    /// casts the leading multiple of eight rays with it and returns the rest; otherwise
    /// returns all of them.
    #[inline(always)]
    pub(super) fn cast_rays8<'r, 'o>(
        &self,
        rays: &'r [Ray],
        out: &'o mut [IntSample],
    ) -> (&'r [Ray], &'o mut [IntSample]) {
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
        match Fl::lanes8(self.sampler.mode(), packets) {
            Ok(rest) => rest,
            Err(p) => (p.rays, p.out),
        }
    }
}

/// [`IntRayMarcher::cast_rays8`] for the lane kernel of the marcher's mode.
pub(super) struct Packets<'m, 'v, 'r, 'o, V, M, Fl, const F: u32, S> {
    pub(super) marcher: &'m IntRayMarcher<'v, V, M, Fl, F, S>,
    pub(super) cpu: crate::arch::avx2::Avx2,
    pub(super) rays: &'r [Ray],
    pub(super) out: &'o mut [IntSample],
}

impl<'r, 'o, V, M, Fl, const F: u32, S> IntLaneVisitor for Packets<'_, '_, 'r, 'o, V, M, Fl, F, S>
where
    V: Voxel,
    M: IntMode<V>,
    Fl: IntFilter,
    S: Skipping,
{
    type Out = (&'r [Ray], &'o mut [IntSample]);

    #[inline(always)]
    fn visit<K: IntLaneMode>(self, _mode: &K) -> Self::Out {
        use crate::arch::avx2::{in_packets, march8, IntOw, Samples};
        let m = self.marcher;
        let vol = m.sampler.volume();
        let Some(data) = K::voxels(vol.data()) else {
            return (self.rays, self.out);
        };
        let vol = vol.with_data(data);
        let (d, a_stop) = (m.step.d(), f32::from(m.stop.a_stop()));
        in_packets(self.rays, self.out, |r| {
            let samples =
                Samples::packet(r, |r| m.sample_range(r), |r, s| m.skip.occupied(r, s, d));
            let acc = march8::<K::Voxel, IntOw>(self.cpu, &vol, r, &samples, stage(d, a_stop));
            acc.each(|a| front_to_back(a, m.background))
        })
    }
}

/// [`IntRayMarcher`]'s march of one ray by the lane kernel of its mode.
pub(super) struct OneRay<'v, 'r, V> {
    pub(super) vol: &'r Volume<'v, V>,
    pub(super) cpu: crate::arch::avx2::Avx2,
    pub(super) ray: &'r Ray,
    pub(super) samples: crate::arch::avx2::Samples,
    pub(super) d: f32,
    pub(super) a_stop: f32,
}

impl<V: Voxel> IntLaneVisitor for OneRay<'_, '_, V> {
    type Out = Option<(IntSample, u32)>;

    #[inline(always)]
    fn visit<K: IntLaneMode>(self, _mode: &K) -> Self::Out {
        use crate::arch::avx2::{march_one, IntOw};
        let vol = self.vol.with_data(K::voxels(self.vol.data())?);
        let stage = stage(self.d, self.a_stop);
        Some(march_one::<K::Voxel, IntOw>(
            self.cpu,
            &vol,
            self.ray,
            &self.samples,
            stage,
        ))
    }
}

/// The integer kernel's [`Stage`](crate::arch::avx2::Stage): step `d`, the U8.8 stop level,
/// no `τ` table and no correction (table-driven correction keeps the portable paths).
fn stage(d: f32, a_stop: f32) -> crate::arch::avx2::Stage<'static, ()> {
    crate::arch::avx2::Stage {
        d,
        a_stop,
        taus: NO_TAUS,
        corr: (),
    }
}

/// Whether the lane kernel of an integer mode reads voxels of the format of `.0`.
pub(super) struct Reads<'d, V>(pub(super) &'d [V]);

impl<V: Voxel> IntLaneVisitor for Reads<'_, V> {
    type Out = bool;

    #[inline(always)]
    fn visit<K: IntLaneMode>(self, _mode: &K) -> bool {
        K::voxels(self.0).is_some()
    }
}
