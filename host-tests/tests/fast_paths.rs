//! The fast paths of the ray marchers (issue 9) against the plain kernels they replace:
//! bit-identical, on random volumes, positions and rays, edges and odd inputs included.
//!
//! * [`Trilinear::gather`] (interior cells without clamps) against
//!   [`Trilinear::gather_clamped`] (`floorf` and a clamp per tap);
//! * [`Mode::weighted8_f32`] (four lanes per tap) against [`Mode::weighted`] in `f32`;
//! * whole rays of [`RayMarcher`] against a plain marcher written here from the public
//!   kernels (clamped gather, generic weighted sum, `finish`, correction, compositing);
//! * the integer sampler's interior path and truncating quantization against clamped taps
//!   and `floor`;
//! * `render_into` and the integer packets in every instruction set the CPU has
//!   ([`Isa::available`]) against the baseline `cast`. On a CPU with AVX2 and FMA (by
//!   `std`'s detection) the tests fail unless the core detects them too, so they cannot pass
//!   without running the AVX2 instance.
//!
//! The other fast-path tests are binaries of their own, so that they compile in parallel:
//! `fast_paths_packets.rs` and `fast_paths_packets_f32.rs` (`cast`, four consecutive samples
//! in lanes, against one sample at a time through [`RayMarcher::sample`], and the packets
//! against single rays, for every mode, filter and stage), `fast_paths_avx2.rs` (the
//! eight-lane AVX2 packets and one-ray marches, random and coherent, and their byte
//! conversion). Their shared helpers are in `fast_paths_common/`.
//!
//! `VOLSAMPLE_FAST_PATH_CASES` sets the number of random cases (default 2000).

mod fast_paths_common;
use fast_paths_common::*;

use volsample::composite::{back_to_front, front_to_back, over, Order};
use volsample::filter::trilinear_weights;
use volsample::fixed_point::{IntMode, IntPos, IntSample, IntSampler, IntStop, IntWeights};
use volsample::opacity::correct;
use volsample::render::IntRayMarcher;
use volsample::voxel::Voxel;
use volsample::Isa;
use volsample::{
    AssociatedU8, BackToFront, Camera, ExtinctionF32, ExtinctionWeighted, FrontToBack, Mode,
    OpacityWeighted, Orthographic, Perspective, Preweighted, Ray, RayMarcher, Sample, Separate,
    Step, StraightF32, StraightU8, Threshold, Trilinear, Volume,
};

#[test]
fn gather_fast_path_is_bit_identical_to_the_clamped_path() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut interior = 0usize;
    for _ in 0..cases() {
        let dims = random_dims(&mut rng);
        let data = random_u8_volume(&mut rng, dims);
        let vol = Volume::new(&data, dims).unwrap();
        for _ in 0..32 {
            let pos = dims.map(|n| rng.coord(n));
            let (taps, f) = Trilinear::<volsample::WeightedSum>::gather(&vol, pos);
            let (taps_ref, f_ref) = Trilinear::<volsample::WeightedSum>::gather_clamped(&vol, pos);
            assert_eq!(taps, taps_ref, "taps at {pos:?} in {dims:?}");
            for (a, b) in f.iter().zip(f_ref.iter()) {
                assert!(same_f32(*a, *b), "fractions {f:?} vs {f_ref:?} at {pos:?}");
            }
            let [x, y, z] = pos;
            let [nx, ny, nz] = dims;
            if x >= 0.0
                && x < (nx - 1) as f32
                && y >= 0.0
                && y < (ny - 1) as f32
                && z >= 0.0
                && z < (nz - 1) as f32
            {
                interior += 1;
            }
        }
    }
    assert!(
        interior > cases(),
        "too few interior cells exercised: {interior}"
    );
}

/// `ExtinctionWeighted` over `ExtinctionF32` in builds for AVX CPUs reads its taps in place
/// (`Trilinear`'s own path for it, in one sample and in the four-sample lanes; elsewhere it
/// copies them as every other mode does): one sample against the public plain kernels (the
/// clamped gather, the generic weighted sum, the mode's `finish`), bit for bit, at positions
/// inside, on and beyond the edges; then `cast` against one sample at a time.
#[test]
fn extinction_f32_taps_read_in_place_are_bit_identical_to_the_plain_kernels() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let mut interior = 0usize;
    for case in 0..cases() {
        let dims = random_dims(&mut rng);
        let ext = extinction_f32(&random_u8_volume(&mut rng, dims), [1.0, 0.5][case % 2]);
        let vol = Volume::new(&ext, dims).unwrap();
        let d = [0.5, 0.3, 1.0, 2.5][case % 4];
        let step = Step::new(d).unwrap();
        let m = RayMarcher::new(
            vol,
            ExtinctionWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap();
        for _ in 0..32 {
            let pos = dims.map(|n| rng.coord(n));
            let (taps, f) = Trilinear::<volsample::WeightedSum>::gather_clamped(&vol, pos);
            let mode = ExtinctionWeighted;
            let plain =
                Mode::<ExtinctionF32>::weighted::<f32, 8>(&mode, &taps, &trilinear_weights(f));
            let want = Mode::<ExtinctionF32>::finish(&mode, plain, d);
            let got = m.sample(pos);
            assert!(
                same_sample(&got, &want),
                "{pos:?} in {dims:?}: in place {got:?} vs plain {want:?}"
            );
            if pos
                .iter()
                .zip(dims)
                .all(|(&p, n)| p >= 0.0 && p < (n - 1) as f32)
            {
                interior += 1;
            }
        }
        let rays: Vec<Ray> = (0..8).map(|_| random_ray(&mut rng, dims)).collect();
        let (never, none) = (|_: f32| false, |_: [f32; 3]| false);
        check_sample_lanes(
            &m,
            &rays,
            never,
            none,
            Sample::TRANSPARENT,
            "Extinction f32",
        );
    }
    assert!(
        interior > cases(),
        "too few interior cells exercised: {interior}"
    );
}

/// `weighted8_f32` against `weighted::<f32, 8>` for one mode and random taps.
fn check_weighted8<V: Voxel + std::fmt::Debug, M: Mode<V>>(
    mode: &M,
    rng: &mut Rng,
    tap: impl Fn(&mut Rng) -> V,
) {
    for _ in 0..cases() * 8 {
        let taps: [V; 8] = std::array::from_fn(|_| tap(rng));
        let f = [rng.unit(), rng.unit(), rng.unit()];
        let w = trilinear_weights(f);
        let fast = mode.weighted8_f32(&taps, &w);
        let plain = mode.weighted::<f32, 8>(&taps, &w);
        let ok = same_f32(fast.a, plain.a)
            && fast
                .c
                .iter()
                .zip(plain.c.iter())
                .all(|(a, b)| same_f32(*a, *b));
        assert!(ok, "{mode:?} {taps:?} at {f:?}: {fast:?} vs {plain:?}");
    }
}

#[test]
fn lane_kernels_are_bit_identical_to_the_generic_weighted_sums() {
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    let straight = |r: &mut Rng| StraightU8([r.byte(), r.byte(), r.byte(), r.byte()]);
    check_weighted8(&OpacityWeighted, &mut rng, straight);
    check_weighted8(&Separate, &mut rng, straight);
    let sf = |r: &mut Rng| StraightF32 {
        c: [r.unit(), r.unit(), r.unit()],
        a: if r.below(4) == 0 { 1.0 } else { r.unit() },
    };
    check_weighted8(&OpacityWeighted, &mut rng, sf);
    check_weighted8(&Preweighted, &mut rng, |r: &mut Rng| {
        let a = r.byte();
        let c = |r: &mut Rng| (u16::from(r.byte()) * u16::from(a) / 255) as u8;
        AssociatedU8([c(r), c(r), c(r), a])
    });
    check_weighted8(&ExtinctionWeighted, &mut rng, |r: &mut Rng| {
        ExtinctionF32::from_straight(sf(r), 1.0)
    });
}

/// A plain marcher from the public kernels: clamped gather, the generic weighted sum, the
/// mode's `finish`, opacity correction where the marcher uses it, compositing.
fn plain_cast<M: Mode<StraightU8>, O: Order>(
    m: &RayMarcher<'_, StraightU8, M, Trilinear, O>,
    mode: &M,
    ray: &Ray,
    bg: Sample,
) -> Sample {
    let (t_first, n) = m.sample_range(ray);
    let d = m.step().d();
    let sample = |j: u32| {
        let (taps, f) = Trilinear::<volsample::WeightedSum>::gather_clamped(
            m.volume(),
            ray.at(t_first + j as f32 * d),
        );
        let s = mode.finish(mode.weighted::<f32, 8>(&taps, &trilinear_weights(f)), d);
        match m.correction() {
            Some(c) => correct(s, c.ratio()),
            None => s,
        }
    };
    let mut acc = Sample::TRANSPARENT;
    if O::FRONT_TO_BACK {
        for j in 0..n {
            acc = front_to_back(acc, sample(j));
        }
    } else {
        for j in (0..n).rev() {
            acc = back_to_front(acc, sample(j));
        }
    }
    over(acc, bg)
}

#[test]
fn ray_marcher_is_bit_identical_to_the_plain_marcher() {
    let mut rng = Rng(0x0DDB_1A5E_5BAD_5EED);
    let bg = Sample {
        c: [0.1, 0.2, 0.3],
        a: 0.5,
    };
    for case in 0..cases() / 4 {
        let dims = random_dims(&mut rng);
        let data = random_u8_volume(&mut rng, dims);
        let d_ref = [1.0, 0.5, 0.75][case % 3];
        let vol = Volume::new(&data, dims)
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let step = Step::new([0.5, 0.3, 1.0][case % 3])
            .unwrap()
            .with_phase(rng.unit() * 0.99)
            .unwrap();
        let ow = RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap()
        .with_background(bg)
        .unwrap();
        let sep = RayMarcher::new(vol, Separate, Trilinear::new(), BackToFront, step).unwrap();
        for _ in 0..8 {
            let ray = random_ray(&mut rng, dims);
            let (fast, plain) = (ow.cast(&ray), plain_cast(&ow, &OpacityWeighted, &ray, bg));
            assert!(
                same_sample(&fast, &plain),
                "OW {dims:?} {ray:?}: {fast:?} vs {plain:?}"
            );
            let t = Sample::TRANSPARENT;
            let (fast, plain) = (sep.cast(&ray), plain_cast(&sep, &Separate, &ray, t));
            assert!(
                same_sample(&fast, &plain),
                "Sep {dims:?} {ray:?}: {fast:?} vs {plain:?}"
            );
        }
    }
}

#[test]
fn integer_interior_path_and_quantization_are_bit_identical() {
    let mut rng = Rng(0xC0FF_EE00_1234_5678);
    for _ in 0..cases() {
        let dims = random_dims(&mut rng);
        let data = random_u8_volume(&mut rng, dims);
        let vol = Volume::new(&data, dims).unwrap();
        let sampler = IntSampler::new(vol, OpacityWeighted, Trilinear::new());
        for _ in 0..16 {
            // Raw positions over the grid and a little past its far edge.
            let raw = dims.map(|n| rng.below(((n as u64) << 8) + 512) as u32);
            let pos = IntPos::<8>::from_raw(raw);
            let [x, y, z] = pos.index().map(|i| i as isize);
            let taps = [
                (x, y, z),
                (x + 1, y, z),
                (x, y + 1, z),
                (x + 1, y + 1, z),
                (x, y, z + 1),
                (x + 1, y, z + 1),
                (x, y + 1, z + 1),
                (x + 1, y + 1, z + 1),
            ]
            .map(|(a, b, c)| vol.fetch_clamped(a, b, c));
            let plain = OpacityWeighted.combine(&taps, &IntWeights::trilinear(pos));
            assert_eq!(sampler.sample(pos), plain, "at {raw:?} in {dims:?}");
        }
        for _ in 0..16 {
            let p = dims.map(|n| rng.coord(n) * 37.0);
            let reference = p.map(|x| (f64::from(x) * 256.0 + 0.5).floor());
            let expected = if reference.iter().all(|v| (0.0..4_294_967_296.0).contains(v)) {
                Some(reference.map(|v| v as u32))
            } else {
                None
            };
            let got = IntPos::<8>::quantize(p).ok().map(|q| q.raw());
            assert_eq!(got, expected, "quantize {p:?}");
        }
    }
}

/// `cast_rays` and `sample_into` (float and integer) reject an output of the wrong length.
#[test]
fn cast_rays_rejects_a_wrong_output_length() {
    let data = [StraightU8([1, 2, 3, 4]); 8];
    let vol = Volume::new(&data, [2, 2, 2]).unwrap();
    let step = Step::new(0.5).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    let rays = [Ray::new([0.5, 0.5, -1.0], [0.0, 0.0, 1.0]).unwrap(); 5];
    let mut out = [Sample::TRANSPARENT; 4];
    assert_eq!(
        m.cast_rays(&rays, &mut out),
        Err(volsample::Error::ImageSizeMismatch {
            expected: 5,
            actual: 4
        })
    );
    // And the batch samples, float and integer.
    let mismatch = Err(volsample::Error::ImageSizeMismatch {
        expected: 3,
        actual: 2,
    });
    assert_eq!(
        m.sample_into(&[[0.5; 3]; 3], &mut [Sample::TRANSPARENT; 2]),
        mismatch
    );
    let int = IntRayMarcher::<_, _, _, 8>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        step,
    )
    .unwrap();
    assert_eq!(
        int.sample_into(&[[0.5; 3]; 3], &mut [IntSample::TRANSPARENT; 2]),
        mismatch
    );
}

/// `sample_into` (the batch form: the instruction set entered once, the cells ahead
/// prefetched), float and integer, in every instruction set this CPU has, against `sample` in
/// the baseline instruction set at each position: random positions in and around the grid,
/// NaN and far outside (a wrong output length: `cast_rays_rejects_a_wrong_output_length`).
#[test]
fn sample_into_is_sample_at_each_position() {
    assert_best_isa_detected();
    let mut rng = Rng(0x5A3B_1E00_77AA_0C01);
    for case in 0..cases() / 16 {
        let dims = random_dims(&mut rng);
        let data = random_u8_volume(&mut rng, dims);
        let vol = Volume::new(&data, dims)
            .unwrap()
            .with_reference_distance(0.5)
            .unwrap();
        let step = Step::new([0.5, 1.0, 0.3][case % 3]).unwrap();
        let ow = RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap();
        let int = IntRayMarcher::<_, _, _, 8>::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::NEVER,
            step,
        )
        .unwrap();
        let mut pos: Vec<[f32; 3]> = (0..40).map(|_| dims.map(|n| rng.coord(n))).collect();
        pos.extend([[f32::NAN, 0.0, 1.0], [-3.0, 1e9, 0.5], [0.0; 3]]);
        for isa in Isa::available() {
            let mut out = vec![Sample::TRANSPARENT; pos.len()];
            ow.with_isa(isa).sample_into(&pos, &mut out).unwrap();
            let mut out_int = vec![IntSample::TRANSPARENT; pos.len()];
            int.clone()
                .with_isa(isa)
                .sample_into(&pos, &mut out_int)
                .unwrap();
            for ((p, got), got_int) in pos.iter().zip(&out).zip(&out_int) {
                let want = ow.with_isa(Isa::BASELINE).sample(*p);
                assert!(
                    same_sample(got, &want),
                    "{isa}, {p:?} in {dims:?}: {got:?} vs {want:?}"
                );
                let want = int.clone().with_isa(Isa::BASELINE).sample(*p);
                assert_eq!(*got_int, want, "{isa}, integer, {p:?} in {dims:?}");
            }
        }
    }
}

/// `render_into` in every instruction set this CPU has (the eight-ray AVX2 packets where it
/// has AVX2, for parallel and perspective cameras) against the baseline `cast` per pixel, for
/// widths that leave every remainder, both cameras and both orders.
#[test]
fn render_into_is_bit_identical_to_casting_each_pixel() {
    let mut rng = Rng(0x05EE_D0F1_AA6E_5001);
    let dims = [5, 4, 6];
    let data = random_u8_volume(&mut rng, dims);
    let vol = Volume::new(&data, dims).unwrap();
    let step = Step::new(0.37).unwrap();
    let ftb = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    let btf = RayMarcher::new(vol, Separate, Trilinear::new(), BackToFront, step).unwrap();
    // Front to back with `d = d′` (no correction), with and without a stop and background:
    // the eight-ray AVX2 packets in builds that have them (rows of 8, 16, 17 and 24 pixels
    // fill whole packets and leave remainders).
    let vol_d = vol.with_reference_distance(0.37).unwrap();
    let ow = RayMarcher::new(
        vol_d,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap();
    assert!(ow.correction().is_none());
    let sep = RayMarcher::new(
        vol_d,
        Separate,
        Trilinear::new(),
        FrontToBack(Threshold::new(0.9).unwrap()),
        step,
    )
    .unwrap()
    .with_background(Sample {
        c: [0.25, 0.5, 0.75],
        a: 1.0,
    })
    .unwrap();
    let ortho = Orthographic::looking_down_z(dims).unwrap();
    let persp = Perspective::new([2.0, 1.5, -6.0], [2.0, 1.5, 2.5], [0.0, 1.0, 0.0], 0.9).unwrap();
    let sizes = [
        (1, 1),
        (3, 2),
        (4, 3),
        (5, 1),
        (7, 4),
        (9, 2),
        (8, 3),
        (16, 2),
        (17, 3),
        (24, 5),
    ];
    for (w, h) in sizes {
        let mut img = vec![Sample::TRANSPARENT; w * h];
        let check = |img: &[Sample], cast: &dyn Fn(&Ray) -> Sample, cam: &dyn Camera| {
            for j in 0..h {
                for i in 0..w {
                    let want = cast(&cam.ray(i, j, w, h));
                    assert!(
                        same_sample(&img[j * w + i], &want),
                        "{w}×{h} pixel ({i}, {j})"
                    );
                }
            }
        };
        for isa in Isa::available() {
            let (ftb_i, btf_i, ow_i, sep_i) = (
                ftb.with_isa(isa),
                btf.with_isa(isa),
                ow.with_isa(isa),
                sep.with_isa(isa),
            );
            let b = Isa::BASELINE;
            let (ftb_b, btf_b, ow_b, sep_b) = (
                ftb.with_isa(b),
                btf.with_isa(b),
                ow.with_isa(b),
                sep.with_isa(b),
            );
            ftb_i.render_into(&ortho, w, h, &mut img).unwrap();
            check(&img, &|r| ftb_b.cast(r), &ortho);
            ftb_i.render_into(&persp, w, h, &mut img).unwrap();
            check(&img, &|r| ftb_b.cast(r), &persp);
            btf_i.render_into(&persp, w, h, &mut img).unwrap();
            check(&img, &|r| btf_b.cast(r), &persp);
            ow_i.render_into(&persp, w, h, &mut img).unwrap();
            check(&img, &|r| ow_b.cast(r), &persp);
            ow_i.render_into(&ortho, w, h, &mut img).unwrap();
            check(&img, &|r| ow_b.cast(r), &ortho);
            sep_i.render_into(&persp, w, h, &mut img).unwrap();
            check(&img, &|r| sep_b.cast(r), &persp);
            sep_i.render_into(&ortho, w, h, &mut img).unwrap();
            check(&img, &|r| sep_b.cast(r), &ortho);
        }
    }
}

/// The integer packets of `IntRayMarcher::cast_rays` and `render_into` (eight rays in AVX2
/// lanes where `fixed_point::AVX2_INT_PACKETS`, one at a time elsewhere) against `cast`, bit
/// for bit: random rays through random volumes; rows of parallel rays (where the kernel
/// reuses a cell's taps); rows whose origins lie on the `1/512`-voxel grid along axis-aligned
/// directions with phase 0, so that many positions lie exactly halfway between two
/// quantized ones (where **round half up** decides); thresholds from `1` to `ONE` and a
/// background; images of whole packets and remainders. With `VOLSAMPLE_EXPECT_AVX2=1` it
/// fails unless the kernel is compiled in.
#[test]
fn integer_packets_are_bit_identical_to_single_rays() {
    assert_best_isa_detected();
    let mut rng = Rng(0x1A7E_6E12_0000_8BAD);
    let bg = IntSample::new([1000, 2000, 3000], 30000).unwrap();
    let (mut rays_checked, mut ties) = (0, 0);
    for case in 0..cases() / 4 {
        let dims = if case % 5 == 0 {
            [
                1 + rng.below(40) as usize,
                1 + rng.below(40) as usize,
                1 + rng.below(3) as usize,
            ]
        } else {
            [0; 3].map(|_| 1 + rng.below(12) as usize)
        };
        let u8s = random_u8_volume(&mut rng, dims);
        let d = [0.5, 0.25, 1.0, 0.75][case % 4];
        let vol = Volume::new(&u8s, dims)
            .unwrap()
            .with_reference_distance(d)
            .unwrap();
        let kind = case % 3;
        let phase = if kind == 2 { 0.0 } else { rng.unit() * 0.99 };
        let step = Step::new(d).unwrap().with_phase(phase).unwrap();
        let len = 8 * (1 + rng.below(3) as usize) + rng.below(8) as usize;
        let major = rng.below(3) as usize;
        let sign = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        let mut dir = [0.0f32; 3];
        dir[major] = sign;
        if kind == 1 && rng.below(4) != 0 {
            for (k, c) in dir.iter_mut().enumerate() {
                if k != major {
                    *c = (rng.unit() * 2.0 - 1.0) * 0.4;
                }
            }
        }
        let across = (major + 1 + rng.below(2) as usize) % 3;
        let back = 2.0 * dims.iter().copied().max().unwrap_or(1) as f32;
        let spacing = [1.0, 0.5, 0.25, 0.37][rng.below(4) as usize];
        let start = [0, 1, 2].map(|k| {
            if k == major {
                dims[k] as f32 * 0.5 - sign * back
            } else if kind == 2 {
                // On the 1/512 grid, from half a voxel before the box to half after it.
                rng.below(dims[k] as u64 * 512 + 1) as f32 / 512.0 - 0.5
            } else {
                rng.unit() * dims[k] as f32 - 1.0
            }
        });
        let rays: Vec<Ray> = (0..len)
            .map(|i| {
                if kind == 0 {
                    return random_ray(&mut rng, dims);
                }
                let mut o = start;
                o[across] += i as f32 * if kind == 2 { 1.0 / 512.0 } else { spacing };
                Ray::new(o, dir).unwrap()
            })
            .collect();
        if kind == 2 {
            // Coordinates across the rays halfway between two quantized positions.
            ties += rays
                .iter()
                .flat_map(|r| r.origin())
                .filter(|x| (x * 256.0).fract().abs() == 0.5)
                .count();
        }
        let one = volsample::fixed_point::ONE;
        let a_stop = [one, one / 10 * 9, one / 2, 1][rng.below(4) as usize];
        let m = IntRayMarcher::<_, _, _, 8>::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::new(a_stop).unwrap(),
            step,
        )
        .unwrap();
        assert!(m.correction().is_none());
        let with_bg = m.clone().with_background(bg);
        let mut out = vec![IntSample::TRANSPARENT; len];
        for (m, what) in [(&m, "no background"), (&with_bg, "background")] {
            let base = m.clone().with_isa(Isa::BASELINE);
            for isa in Isa::available() {
                m.clone().with_isa(isa).cast_rays(&rays, &mut out).unwrap();
                for (ray, got) in rays.iter().zip(&out) {
                    let want = base.cast(ray);
                    assert_eq!(
                        *got, want,
                        "{what}, {isa}, case {case}, stop {a_stop}: {ray:?}"
                    );
                    // One ray at a time (eight consecutive samples in the AVX2 lanes), sample
                    // counts included.
                    let one = m.clone().with_isa(isa).cast_counted(ray);
                    assert_eq!(
                        one,
                        base.cast_counted(ray),
                        "{what}, {isa}, one ray: {ray:?}"
                    );
                    // One sample, where the ray enters the volume.
                    let p = ray.at(m.sample_range(ray).0);
                    assert_eq!(
                        m.clone().with_isa(isa).sample(p),
                        base.sample(p),
                        "{what}, {isa}, sample at {p:?}"
                    );
                }
                rays_checked += len;
            }
        }
        if case % 16 == 0 {
            let cam = Orthographic::looking_down_z(dims).unwrap();
            let persp =
                Perspective::new([2.0, 1.5, -6.0], [2.0, 1.5, 2.5], [0.0, 1.0, 0.0], 0.9).unwrap();
            let (w, h) = (1 + rng.below(25) as usize, 1 + rng.below(4) as usize);
            let mut img = vec![IntSample::TRANSPARENT; w * h];
            let base = with_bg.clone().with_isa(Isa::BASELINE);
            let mut check = |cam: &dyn Camera, img: &[IntSample]| {
                for j in 0..h {
                    for i in 0..w {
                        let want = base.cast(&cam.ray(i, j, w, h));
                        assert_eq!(img[j * w + i], want, "{w}×{h} pixel ({i}, {j})");
                    }
                }
                rays_checked += w * h;
            };
            for isa in Isa::available() {
                let m = with_bg.clone().with_isa(isa);
                m.render_into(&cam, w, h, &mut img).unwrap();
                check(&cam, &img);
                m.render_into(&persp, w, h, &mut img).unwrap();
                check(&persp, &img);
            }
        }
    }
    assert!(rays_checked > 1000, "{rays_checked} rays");
    assert!(ties > 100, "{ties} coordinates at a tie");
}
