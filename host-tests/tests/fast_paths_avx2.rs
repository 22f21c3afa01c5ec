//! The eight-lane AVX2 kernels (see `fast_paths.rs`) against the baseline instance, bit for
//! bit: the byte conversion they use, random packets and one-ray marches of every mode with a
//! lane kernel, and coherent packets (rows of parallel rays, where the kernel reuses a cell's
//! channels). On a CPU with AVX2 and FMA (by `std`'s detection) the tests fail unless the
//! core detects them too, so they cannot pass without running the AVX2 instance. Each mode's
//! checks are a generic function of their own, kept out of line: the test bodies they were
//! expanded into by macros were single functions of up to 700 KB of machine code, which took
//! most of this test's compile time.
//!
//! `VOLSAMPLE_FAST_PATH_CASES` sets the number of random cases (default 2000).

mod fast_paths_common;
use fast_paths_common::*;

use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::voxel::Voxel;
use volsample::Isa;
use volsample::{
    ExtinctionWeighted, FrontToBack, Mode, OpacityWeighted, Ray, RayMarcher, Sample, Separate,
    Step, Threshold, Trilinear, Volume,
};

/// The byte conversion of the AVX2 packets — `n·h + (n·l)` with `h = 1/255` rounded and
/// `l = 1/255 − h` rounded, the sum one fused multiply-add (`mul_add` rounds once, as the
/// vector instruction does) — is the library's `unorm8(n)` for every byte, and both are
/// `n/255` correctly rounded: `q·255` is exact in `f64` (a 24-bit significand times 255), so
/// `|q·255 − n| ≤ 255·ulp(q)/2` is an exact test that `q` is within half an ulp of `n/255`.
/// (The kernel's own conversion is checked against the table by a unit test in the core.)
#[test]
fn byte_conversion_of_the_avx2_packets_is_the_correctly_rounded_quotient() {
    let h = 1.0f32 / 255.0;
    let l = (1.0f64 / 255.0 - f64::from(h)) as f32;
    for n in 0..=255u8 {
        let q = volsample::voxel::unorm8(n);
        let x = f32::from(n);
        assert_eq!(
            x.mul_add(h, x * l),
            q,
            "byte {n}: split product against the table"
        );
        let ulp = f64::from(f32::from_bits(q.to_bits() + 1) - q);
        let err = (f64::from(q) * 255.0 - f64::from(n)).abs();
        assert!(
            err <= 255.0 * ulp / 2.0,
            "byte {n}: {q} is not n/255 rounded"
        );
    }
}

/// One random case of [`avx2_packets_are_bit_identical_to_single_rays`]: the rays, the step,
/// the early-termination threshold, and the case number for the messages.
struct Avx2Case<'r> {
    case: usize,
    rays: &'r [Ray],
    step: Step,
    a_stop: f32,
}

/// The packets (`cast_rays`) and the one-ray marches (`cast_counted`, eight consecutive
/// samples in the AVX2 lanes) of the trilinear front-to-back marchers of `mode` over `vol`,
/// without termination and with the case's threshold and a background, in every instruction
/// set this CPU has, against the baseline `cast`: results and sample counts bit-identical.
/// Returns the number of rays checked.
#[inline(never)]
fn both_orders<V: Voxel, M: Mode<V> + Copy>(
    c: &Avx2Case<'_>,
    vol: Volume<'_, V>,
    mode: M,
    what: &str,
) -> usize {
    let bg = Sample {
        c: [0.1, 0.2, 0.3],
        a: 0.5,
    };
    let ftb = FrontToBack::new();
    let never = RayMarcher::new(vol, mode, Trilinear::new(), ftb, c.step).unwrap();
    assert!(never.correction().is_none());
    let stop = FrontToBack(Threshold::new(c.a_stop).unwrap());
    let m = RayMarcher::new(vol, mode, Trilinear::new(), stop, c.step)
        .unwrap()
        .with_background(bg)
        .unwrap();
    check_packets_and_rays(c, &never, &format!("{what}, no termination"))
        + check_packets_and_rays(c, &m, &format!("{what}, threshold and background"))
}

/// [`both_orders`] for one marcher.
#[inline(never)]
fn check_packets_and_rays<V: Voxel, M: Mode<V>, O: volsample::composite::Order>(
    c: &Avx2Case<'_>,
    m: &RayMarcher<'_, V, M, Trilinear, O>,
    what: &str,
) -> usize
where
    for<'a> RayMarcher<'a, V, M, Trilinear, O>: Copy,
{
    let (case, rays) = (c.case, c.rays);
    let mut out = vec![Sample::TRANSPARENT; rays.len()];
    let base = m.with_isa(Isa::BASELINE);
    let mut checked = 0;
    for isa in Isa::available() {
        m.with_isa(isa).cast_rays(rays, &mut out).unwrap();
        for (ray, g) in rays.iter().zip(&out) {
            let w = base.cast(ray);
            assert!(
                same_sample(g, &w),
                "{what}, {isa}, case {case}: {ray:?}: {g:?} vs {w:?}"
            );
        }
        checked += rays.len();
        // One ray at a time (eight consecutive samples in the AVX2 lanes), sample counts
        // included.
        for r in rays {
            let (got, n) = m.with_isa(isa).cast_counted(r);
            let (want, k) = base.cast_counted(r);
            assert!(
                same_sample(&got, &want) && n == k,
                "{what}, {isa}, case {case}: {r:?}"
            );
        }
    }
    checked
}

/// `cast_rays` (eight rays at a time in AVX2 lanes where the CPU has AVX2, else four) and
/// `cast` against the baseline `cast`, bit for bit: `OpacityWeighted`, `Separate` and
/// `ExtinctionWeightedU8` trilinear over `StraightU8`, `ExtinctionWeighted` over
/// `ExtinctionF32`, front to back with `d = d′`, every termination threshold, with and
/// without a background, on random volumes (non-cubic, 1-voxel axes included) and random
/// rays (missing, grazing, axis-aligned), in batches that leave every tail length.
#[test]
fn avx2_packets_are_bit_identical_to_single_rays() {
    assert_best_isa_detected();
    let mut rng = Rng(0x0A5C_2000_8BAD_F00D);
    let mut rays_checked = 0;
    for case in 0..cases() / 4 {
        let dims = if case % 5 == 0 {
            [
                1 + rng.below(40) as usize,
                1 + rng.below(40) as usize,
                1 + rng.below(3) as usize,
            ]
        } else {
            random_dims(&mut rng)
        };
        let u8s = random_u8_volume(&mut rng, dims);
        let d = [0.5, 0.3, 1.0, 0.75][case % 4];
        let vol = Volume::new(&u8s, dims)
            .unwrap()
            .with_reference_distance(d)
            .unwrap();
        let step = Step::new(d).unwrap().with_phase(rng.unit() * 0.99).unwrap();
        let len = 8 * (1 + rng.below(3) as usize) + rng.below(8) as usize;
        let rays: Vec<Ray> = (0..len).map(|_| random_ray(&mut rng, dims)).collect();
        let a_stop = [1.0, 0.9, 0.5, 0.05][rng.below(4) as usize];
        let c = Avx2Case {
            case,
            rays: &rays,
            step,
            a_stop,
        };
        // The same volume with opacities below 61/255 (and zeros): the extinction steps of
        // whole packets then stay below `τd = 1`, where the kernel integrates in lanes (by
        // `phi_poly`) rather than per lane.
        let soft_u8s = soft(&u8s);
        let soft_vol = Volume::new(&soft_u8s, dims).unwrap();
        let tau = TauTable::new(d).unwrap();
        let ext = ExtinctionWeightedU8::new(&tau);
        let (e16, soft_e16) = (extinction_f32(&u8s, d), extinction_f32(&soft_u8s, d));
        let e16_vol = Volume::new(&e16, dims).unwrap();
        let soft_e16_vol = Volume::new(&soft_e16, dims).unwrap();
        rays_checked += both_orders(&c, vol, OpacityWeighted, "OpacityWeighted");
        rays_checked += both_orders(&c, vol, Separate, "Separate");
        rays_checked += both_orders(&c, vol, ext, "ExtinctionWeightedU8");
        rays_checked += both_orders(&c, soft_vol, ext, "ExtinctionWeightedU8, soft");
        rays_checked += both_orders(&c, e16_vol, ExtinctionWeighted, "ExtinctionWeighted");
        let what = "ExtinctionWeighted, soft";
        rays_checked += both_orders(&c, soft_e16_vol, ExtinctionWeighted, what);
    }
    assert!(rays_checked > 1000, "{rays_checked} rays");
}

/// One case of [`coherent_packets_are_bit_identical_to_single_rays`].
type CoherentCase<'r> = Avx2Case<'r>;

/// `cast_rays` of the trilinear front-to-back marcher of `mode` over `vol` with the case's
/// threshold, in every instruction set this CPU has, against the baseline `cast`, bit for
/// bit. Returns the number of rays checked.
#[inline(never)]
fn check_coherent<V: Voxel, M: Mode<V> + Copy>(
    c: &CoherentCase<'_>,
    vol: Volume<'_, V>,
    mode: M,
    what: &str,
) -> usize {
    let (case, rays) = (c.case, c.rays);
    let mut out = vec![Sample::TRANSPARENT; rays.len()];
    let stop = FrontToBack(Threshold::new(c.a_stop).unwrap());
    let m = RayMarcher::new(vol, mode, Trilinear::new(), stop, c.step).unwrap();
    let base = m.with_isa(Isa::BASELINE);
    let mut checked = 0;
    for isa in Isa::available() {
        m.with_isa(isa).cast_rays(rays, &mut out).unwrap();
        for (ray, g) in rays.iter().zip(&out) {
            let w = base.cast(ray);
            assert!(
                same_sample(g, &w),
                "{what}, {isa}, case {case}: {ray:?}: {g:?} vs {w:?}"
            );
        }
        checked += rays.len();
    }
    checked
}

/// Coherent packets, as a renderer makes them: rows of parallel rays (pixel spacings of a
/// voxel, half a voxel and less) along a major axis (x, y or z, either sign, sometimes exactly
/// axis-aligned), through the whole box and out of it. Every lane then stays in its cell for
/// some steps and moves on by one cell together with the others, so the AVX2 kernel's reuse
/// of a cell's channels and of its far face runs often (in every face orientation), on the
/// box's clamped edges too; `cast_rays` must still equal `cast` bit for bit.
#[test]
fn coherent_packets_are_bit_identical_to_single_rays() {
    let mut rng = Rng(0xC0DE_0F1A_7E55_0009);
    let mut rays_checked = 0;
    for case in 0..cases() / 8 {
        let dims = [0; 3].map(|_| 1 + rng.below(12) as usize);
        let u8s = random_u8_volume(&mut rng, dims);
        let d = [0.5, 0.3, 0.25, 0.7][case % 4];
        let vol = Volume::new(&u8s, dims)
            .unwrap()
            .with_reference_distance(d)
            .unwrap();
        let step = Step::new(d).unwrap().with_phase(rng.unit() * 0.99).unwrap();
        let major = case % 3;
        let sign = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        let mut dir = [0.0f32; 3];
        dir[major] = sign;
        if rng.below(4) != 0 {
            for (k, c) in dir.iter_mut().enumerate() {
                if k != major {
                    *c = (rng.unit() * 2.0 - 1.0) * 0.4;
                }
            }
        }
        // The row runs along one of the other axes, from a corner region outside the box.
        let across = (major + 1 + rng.below(2) as usize) % 3;
        let spacing = [1.0, 0.5, 0.25, 0.37][rng.below(4) as usize];
        let len = 8 * (1 + rng.below(3) as usize) + rng.below(8) as usize;
        let back = 2.0 * dims.iter().copied().max().unwrap_or(1) as f32;
        let start = [0, 1, 2].map(|k| {
            if k == major {
                dims[k] as f32 * 0.5 - sign * back
            } else {
                rng.unit() * dims[k] as f32 - 1.0
            }
        });
        let rays: Vec<Ray> = (0..len)
            .map(|i| {
                let mut o = start;
                o[across] += i as f32 * spacing;
                Ray::new(o, dir).unwrap()
            })
            .collect();
        let a_stop = [1.0, 0.9, 0.5][rng.below(3) as usize];
        let c = CoherentCase {
            case,
            rays: &rays,
            step,
            a_stop,
        };
        let soft_u8s = soft(&u8s);
        let soft_vol = Volume::new(&soft_u8s, dims).unwrap();
        let tau = TauTable::new(d).unwrap();
        let ext = ExtinctionWeightedU8::new(&tau);
        let (e16, soft_e16) = (extinction_f32(&u8s, d), extinction_f32(&soft_u8s, d));
        let e16_vol = Volume::new(&e16, dims).unwrap();
        let soft_e16_vol = Volume::new(&soft_e16, dims).unwrap();
        rays_checked += check_coherent(&c, vol, OpacityWeighted, "OpacityWeighted");
        rays_checked += check_coherent(&c, vol, Separate, "Separate");
        rays_checked += check_coherent(&c, vol, ext, "ExtinctionWeightedU8");
        rays_checked += check_coherent(&c, soft_vol, ext, "ExtinctionWeightedU8, soft");
        rays_checked += check_coherent(&c, e16_vol, ExtinctionWeighted, "ExtinctionWeighted");
        let what = "ExtinctionWeighted, soft";
        rays_checked += check_coherent(&c, soft_e16_vol, ExtinctionWeighted, what);
    }
    assert!(rays_checked > 1000, "{rays_checked} rays");
}
