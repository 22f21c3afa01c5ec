//! The fast paths of the ray marchers (issue 9) against the plain kernels they replace:
//! bit-identical, on random volumes, positions and rays, edges and odd inputs included.
//!
//! * [`Trilinear::gather`] (interior cells without clamps) against
//!   [`Trilinear::gather_clamped`] (`floorf` and a clamp per tap);
//! * [`Mode::weighted8_f32`] (four lanes per tap) against [`Mode::weighted`] in `f32`;
//! * whole rays of [`RayMarcher`] against a plain marcher written here from the public
//!   kernels (clamped gather, generic weighted sum, `finish`, correction, compositing);
//! * `cast` (four consecutive samples in lanes) against one sample at a time through
//!   [`RayMarcher::sample`], and the packets (four rays in lanes) against single rays;
//! * the integer sampler's interior path and truncating quantization against clamped taps
//!   and `floor`;
//! * the packets of `cast_rays` in every instruction set the CPU has ([`Isa::available`]:
//!   eight rays in AVX2 lanes where it has AVX2) against the baseline `cast`, and the byte
//!   conversion they use against the library's `n/255` for every byte. On a CPU with AVX2
//!   and FMA (by `std`'s detection) the tests fail unless the core detects them too, so they
//!   cannot pass without running the AVX2 instance; coherent packets (rows of parallel rays),
//!   where that kernel reuses a cell's channels.
//!
//! `VOLSAMPLE_FAST_PATH_CASES` sets the number of random cases (default 2000).

use volsample::composite::{back_to_front, front_to_back, over, Order, Termination};
use volsample::filter::trilinear_weights;
use volsample::fixed_point::{IntMode, IntPos, IntSample, IntSampler, IntStop, IntWeights};
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::opacity::correct;
use volsample::render::IntRayMarcher;
use volsample::skip::Skipping;
use volsample::voxel::Voxel;
use volsample::Isa;
use volsample::{
    AssociatedU8, BackToFront, Camera, ControlPoint, ExtinctionF32, ExtinctionWeighted, Filter,
    FrontToBack, Mode, Nearest, OpacityWeighted, Orthographic, Perspective, PostClassified,
    Preweighted, Ray, RayMarcher, Sample, Separate, Step, StraightF32, StraightU8, Threshold,
    TransferFunction, Trilinear, TriquadraticBSpline, Volume,
};

/// On an x86-64 CPU with AVX2 and FMA (by `std`'s detection, independent of the core's), the
/// core must detect them too, so that the AVX2 instances checked below do run there.
fn assert_best_isa_detected() {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        assert_eq!(
            Isa::detect().name(),
            "avx2",
            "AVX2 and FMA present but not detected"
        );
        assert_eq!(Isa::available().len(), 2);
    }
    println!("instances checked: {:?}", Isa::available());
}

/// xorshift64*: deterministic, seedable.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / 16_777_216.0
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    /// A coordinate for an axis of `n` voxels: mostly inside, often on or near the edges,
    /// sometimes odd (−0, negative, NaN, ±∞, huge).
    fn coord(&mut self, n: usize) -> f32 {
        let hi = (n - 1) as f32;
        match self.below(16) {
            0 => -0.0,
            1 => hi,
            2 => hi - f32::EPSILON * hi.max(1.0),
            3 => -self.unit() * 2.0,
            4 => hi + self.unit() * 2.0,
            5 => [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30][self.below(5) as usize],
            6 => self.below(n as u64) as f32,
            _ => (self.unit() * (hi + 1.0)) - 0.5,
        }
    }
}

fn cases() -> usize {
    std::env::var("VOLSAMPLE_FAST_PATH_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000)
}

fn random_dims(rng: &mut Rng) -> [usize; 3] {
    [0; 3].map(|_| 1 + rng.below(6) as usize)
}

fn random_u8_volume(rng: &mut Rng, dims: [usize; 3]) -> Vec<StraightU8> {
    let n = dims.iter().product();
    (0..n)
        .map(|_| {
            // Some opaque and some empty voxels, the rest random.
            match rng.below(4) {
                0 => StraightU8([rng.byte(), rng.byte(), rng.byte(), 255]),
                1 => StraightU8([rng.byte(), rng.byte(), rng.byte(), 0]),
                _ => StraightU8([rng.byte(), rng.byte(), rng.byte(), rng.byte()]),
            }
        })
        .collect()
}

/// `v` with its opacities below 61/255 (zeros kept): soft enough that a step of `d = d′`
/// through it keeps `τd` below 1 (`τd ≤ −ln(1 − 60/255) ≈ 0.27`).
fn soft(v: &[StraightU8]) -> Vec<StraightU8> {
    v.iter()
        .map(|&StraightU8([r, g, b, a])| StraightU8([r, g, b, a % 61]))
        .collect()
}

/// `v` as `ExtinctionF32` voxels for steps of `d_ref` (`ExtinctionF32::from_straight` of the
/// bytes over 255): the 16-byte voxels of the AVX2 packets' `ExtinctionWeighted` rows.
fn extinction_f32(v: &[StraightU8], d_ref: f32) -> Vec<ExtinctionF32> {
    v.iter()
        .map(|&StraightU8(rgba)| {
            let [r, g, b, a] = rgba.map(|n| f32::from(n) / 255.0);
            ExtinctionF32::from_straight(StraightF32 { c: [r, g, b], a }, d_ref)
        })
        .collect()
}

fn same_f32(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits()
}

fn same_sample(a: &Sample, b: &Sample) -> bool {
    same_f32(a.a, b.a) && a.c.iter().zip(b.c.iter()).all(|(x, y)| same_f32(*x, *y))
}

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

fn random_ray(rng: &mut Rng, dims: [usize; 3]) -> Ray {
    let c = dims.map(|n| n as f32 * 0.5 - 0.5);
    let dir = [0; 3].map(|_| rng.unit() * 2.0 - 1.0);
    let dir = if dir.iter().all(|d| d.abs() < 1e-3) {
        [0.0, 0.0, 1.0]
    } else if rng.below(4) == 0 {
        // Axis-aligned rays, which run along cell faces.
        let mut a = [0.0; 3];
        a[rng.below(3) as usize] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        a
    } else {
        dir
    };
    // Start outside the box, aimed near its centre.
    let back = 2.0 * dims.iter().copied().max().unwrap_or(1) as f32;
    let jitter = [0; 3].map(|_| rng.unit() * 2.0 - 1.0);
    let origin = [0, 1, 2].map(|k| c[k] + jitter[k] * c[k].max(0.5) - dir[k] * back);
    Ray::new(origin, dir).unwrap()
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

/// Every ray of `rays` through `m` four at a time ([`RayMarcher::cast4`], and
/// [`RayMarcher::cast_rays`] for the tails) against one at a time, in every instruction set
/// this CPU has against the baseline one ray at a time; `what` names the case.
fn check_packets<V, M, F, O, S>(m: &RayMarcher<'_, V, M, F, O, S>, rays: &[Ray], what: &str)
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
    for<'a> RayMarcher<'a, V, M, F, O, S>: Copy,
{
    let base = m.with_isa(Isa::BASELINE);
    for isa in Isa::available() {
        check_packets_in(&m.with_isa(isa), &base, rays, &format!("{what}, {isa}"));
    }
}

/// [`check_packets`] of `m` against `base`.
fn check_packets_in<V, M, F, O, S>(
    m: &RayMarcher<'_, V, M, F, O, S>,
    base: &RayMarcher<'_, V, M, F, O, S>,
    rays: &[Ray],
    what: &str,
) where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    for four in rays.chunks_exact(4) {
        let four: &[Ray; 4] = four.try_into().unwrap();
        for (ray, (got, n)) in four.iter().zip(m.cast4(four)) {
            let (want, k) = base.cast_counted(ray);
            assert!(
                same_sample(&got, &want) && n == k,
                "{what}: {ray:?}: packet {got:?} ({n} samples) vs single {want:?} ({k})"
            );
        }
    }
    // Every length, so that each tail (0 to 3 rays after the packets) is covered.
    for len in 0..=rays.len().min(9) {
        let mut out = vec![Sample::TRANSPARENT; len];
        m.cast_rays(&rays[..len], &mut out).unwrap();
        for (ray, got) in rays.iter().zip(&out) {
            assert!(
                same_sample(got, &base.cast(ray)),
                "{what}: cast_rays {ray:?}"
            );
            assert!(same_sample(got, &m.cast(ray)), "{what}: cast {ray:?}");
        }
    }
}

/// A front-to-back ray one sample at a time from the public per-sample kernel
/// ([`RayMarcher::sample`]): `empty` samples skipped, stopping after the sample at which
/// `done(A)` holds, then over `bg`; with the number of samples taken.
fn one_at_a_time<V, M, F, O, S>(
    m: &RayMarcher<'_, V, M, F, O, S>,
    ray: &Ray,
    done: impl Fn(f32) -> bool,
    empty: impl Fn([f32; 3]) -> bool,
    bg: Sample,
) -> (Sample, u32)
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
{
    let (t_first, n) = m.sample_range(ray);
    let d = m.step().d();
    let mut acc = Sample::TRANSPARENT;
    for j in 0..n {
        let p = ray.at(t_first + j as f32 * d);
        if empty(p) {
            continue;
        }
        acc = front_to_back(acc, m.sample(p));
        if done(acc.a) {
            return (over(acc, bg), j + 1);
        }
    }
    (over(acc, bg), n)
}

/// `cast_counted` (which marches four consecutive samples of a ray in lanes), in every
/// instruction set this CPU has, against [`one_at_a_time`]: bit-identical results and counts.
fn check_sample_lanes<V, M, F, O, S>(
    m: &RayMarcher<'_, V, M, F, O, S>,
    rays: &[Ray],
    done: impl Fn(f32) -> bool,
    empty: impl Fn([f32; 3]) -> bool,
    bg: Sample,
    what: &str,
) where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
    for<'a> RayMarcher<'a, V, M, F, O, S>: Copy,
{
    for ray in rays {
        let (want, k) = one_at_a_time(m, ray, &done, &empty, bg);
        for isa in Isa::available() {
            let (got, n) = m.with_isa(isa).cast_counted(ray);
            assert!(
                same_sample(&got, &want) && n == k,
                "{what}, {isa}: {ray:?}: lanes {got:?} ({n} samples) vs one at a time {want:?} ({k})"
            );
        }
    }
}

/// The packet kernels (four rays in [`volsample::lanes::F32x4`] lanes) are bit-identical to
/// single rays, and single rays (four consecutive samples in lanes, front to back) to one
/// sample at a time, for every mode, filter, voxel format, order and stage: opacity
/// correction, early termination, a background, empty-space skipping, rays that miss or end
/// early.
#[test]
fn packets_are_bit_identical_to_single_rays() {
    let mut rng = Rng(0x7AC4_E75A_11CE_0004);
    let bg = Sample {
        c: [0.1, 0.2, 0.3],
        a: 0.5,
    };
    let tf = TransferFunction::<3>::new(&[
        ControlPoint {
            s: 0.0,
            c: [0.0; 3],
            a: 0.0,
        },
        ControlPoint {
            s: 0.4,
            c: [1.0, 0.5, 0.2],
            a: 0.3,
        },
        ControlPoint {
            s: 1.0,
            c: [1.0; 3],
            a: 0.9,
        },
    ])
    .unwrap();
    let mut grid = vec![0u8; 4096];
    for case in 0..cases() / 8 {
        let dims = random_dims(&mut rng);
        let u8s = random_u8_volume(&mut rng, dims);
        let f32s: Vec<StraightF32> = u8s
            .iter()
            .map(|v| {
                let [r, g, b, a] = v.0.map(|n| f32::from(n) / 255.0 + 1e-4);
                StraightF32 {
                    c: [r.min(1.0), g.min(1.0), b.min(1.0)],
                    a: a.min(1.0),
                }
            })
            .collect();
        let assoc: Vec<AssociatedU8> = u8s
            .iter()
            .map(|v| {
                let [r, g, b, a] = v.0;
                let m = |c: u8| ((u16::from(c) * u16::from(a)) / 255) as u8;
                AssociatedU8([m(r), m(g), m(b), a])
            })
            .collect();
        let d_ref = [1.0, 0.5, 0.75][case % 3];
        let ext: Vec<ExtinctionF32> = f32s
            .iter()
            .map(|&v| ExtinctionF32::from_straight(v, d_ref))
            .collect();
        let scalars: Vec<f32> = u8s.iter().map(|v| f32::from(v.0[0]) / 255.0).collect();
        let step = Step::new([0.5, 0.3, 1.0, 0.75][case % 4])
            .unwrap()
            .with_phase(rng.unit() * 0.99)
            .unwrap();
        let rays: Vec<Ray> = (0..12).map(|_| random_ray(&mut rng, dims)).collect();
        let v8 = Volume::new(&u8s, dims)
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let vf = Volume::new(&f32s, dims)
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let va = Volume::new(&assoc, dims)
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let ve = Volume::new(&ext, dims).unwrap();
        let vs = Volume::new(&scalars, dims)
            .unwrap()
            .with_reference_distance(d_ref)
            .unwrap();
        let stop = FrontToBack(Threshold::new([1.0, 0.9, 0.5, 0.05][case % 4]).unwrap());
        let ftb = FrontToBack::new();

        macro_rules! all_filters {
            ($vol:expr, $mode:expr, $what:expr) => {{
                let t = Sample::TRANSPARENT;
                let done = |a| stop.0.done(a);
                let never = |_: f32| false;
                let none = |_: [f32; 3]| false;
                let m = RayMarcher::new($vol, $mode, Trilinear::new(), stop, step).unwrap();
                let m = m.with_background(bg).unwrap();
                check_packets(&m, &rays, concat!($what, " trilinear"));
                check_sample_lanes(&m, &rays, done, none, bg, concat!($what, " trilinear"));
                let m = RayMarcher::new($vol, $mode, Trilinear::tree(), ftb, step).unwrap();
                check_packets(&m, &rays, concat!($what, " tree"));
                check_sample_lanes(&m, &rays, never, none, t, concat!($what, " tree"));
                let m = RayMarcher::new($vol, $mode, Nearest, stop, step).unwrap();
                check_packets(&m, &rays, concat!($what, " nearest"));
                check_sample_lanes(&m, &rays, done, none, t, concat!($what, " nearest"));
                let m = RayMarcher::new($vol, $mode, TriquadraticBSpline, ftb, step).unwrap();
                check_packets(&m, &rays, concat!($what, " bspline"));
                check_sample_lanes(&m, &rays, never, none, t, concat!($what, " bspline"));
                let m = RayMarcher::new($vol, $mode, Trilinear::new(), BackToFront, step).unwrap();
                check_packets(&m, &rays, concat!($what, " back to front"));
            }};
        }
        all_filters!(v8, OpacityWeighted, "OW u8");
        all_filters!(vf, OpacityWeighted, "OW f32");
        all_filters!(v8, Separate, "Separate u8");
        all_filters!(vf, Separate, "Separate f32");
        all_filters!(va, Preweighted, "Preweighted u8");
        all_filters!(ve, ExtinctionWeighted, "Extinction");
        let taus = TauTable::new(d_ref).unwrap();
        all_filters!(v8, ExtinctionWeightedU8::new(&taus), "Extinction u8");
        all_filters!(vs, PostClassified::new(&tf), "PostClassified");

        // Empty-space skipping: lanes skip samples independently.
        let m = RayMarcher::new(v8, OpacityWeighted, Trilinear::new(), stop, step).unwrap();
        let skip = m.with_skipping(&mut grid, [0, 1, 2][case % 3]).unwrap();
        check_packets(&skip, &rays, "OW u8 skipping");
        let occ = *skip.occupancy().unwrap();
        let (done, empty) = (|a| stop.0.done(a), |p| occ.is_empty_at(p));
        let t = Sample::TRANSPARENT;
        check_sample_lanes(&skip, &rays, done, empty, t, "OW u8 skipping");
    }
}

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

/// `cast_rays` (eight rays at a time in AVX2 lanes where compiled in, else four) against
/// `cast`, bit for bit: `OpacityWeighted` and `Separate` trilinear over `StraightU8`, front to
/// back with `d = d′`, every termination threshold, with and without a background, on random
/// volumes (non-cubic, 1-voxel axes included) and random rays (missing, grazing,
/// axis-aligned), in batches that leave every tail length.
#[test]
fn avx2_packets_are_bit_identical_to_single_rays() {
    assert_best_isa_detected();
    let mut rng = Rng(0x0A5C_2000_8BAD_F00D);
    let bg = Sample {
        c: [0.1, 0.2, 0.3],
        a: 0.5,
    };
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
        let mut out = vec![Sample::TRANSPARENT; len];
        let mut check = |got: &[Sample], want: &dyn Fn(&Ray) -> Sample, what: &str| {
            for (ray, g) in rays.iter().zip(got) {
                let w = want(ray);
                assert!(
                    same_sample(g, &w),
                    "{what}, case {case}: {ray:?}: {g:?} vs {w:?}"
                );
            }
            rays_checked += got.len();
        };
        let a_stop = [1.0, 0.9, 0.5, 0.05][rng.below(4) as usize];
        let stop = FrontToBack(Threshold::new(a_stop).unwrap());
        // The same volume with opacities below 61/255 (and zeros): the extinction steps of
        // whole packets then stay below `τd = 1`, where the kernel integrates in lanes (by
        // `phi_poly`) rather than per lane.
        let soft_u8s = soft(&u8s);
        let soft_vol = Volume::new(&soft_u8s, dims).unwrap();
        let tau = TauTable::new(d).unwrap();
        macro_rules! both_orders {
            ($mode:expr, $what:expr) => {
                both_orders!($mode, $what, vol)
            };
            ($mode:expr, $what:expr, $vol:expr) => {{
                let vol = $vol;
                let ftb = FrontToBack::new();
                let never = RayMarcher::new(vol, $mode, Trilinear::new(), ftb, step).unwrap();
                assert!(never.correction().is_none());
                let base = never.with_isa(Isa::BASELINE);
                for isa in Isa::available() {
                    never.with_isa(isa).cast_rays(&rays, &mut out).unwrap();
                    check(&out, &|r| base.cast(r), concat!($what, ", no termination"));
                    // One ray at a time (eight consecutive samples in the AVX2 lanes),
                    // sample counts included.
                    for r in &rays {
                        let (got, n) = never.with_isa(isa).cast_counted(r);
                        let (want, k) = base.cast_counted(r);
                        assert!(
                            same_sample(&got, &want) && n == k,
                            "{}, {isa}: {r:?}",
                            $what
                        );
                    }
                }
                let m = RayMarcher::new(vol, $mode, Trilinear::new(), stop, step)
                    .unwrap()
                    .with_background(bg)
                    .unwrap();
                let base = m.with_isa(Isa::BASELINE);
                for isa in Isa::available() {
                    m.with_isa(isa).cast_rays(&rays, &mut out).unwrap();
                    check(
                        &out,
                        &|r| base.cast(r),
                        concat!($what, ", threshold and background"),
                    );
                    for r in &rays {
                        let (got, n) = m.with_isa(isa).cast_counted(r);
                        let (want, k) = base.cast_counted(r);
                        assert!(
                            same_sample(&got, &want) && n == k,
                            "{}, {isa}: {r:?}",
                            $what
                        );
                    }
                }
            }};
        }
        both_orders!(OpacityWeighted, "OpacityWeighted");
        both_orders!(Separate, "Separate");
        both_orders!(ExtinctionWeightedU8::new(&tau), "ExtinctionWeightedU8");
        let ext = ExtinctionWeightedU8::new(&tau);
        both_orders!(ext, "ExtinctionWeightedU8, soft", soft_vol);
        let (e16, soft_e16) = (extinction_f32(&u8s, d), extinction_f32(&soft_u8s, d));
        let e16_vol = Volume::new(&e16, dims).unwrap();
        both_orders!(ExtinctionWeighted, "ExtinctionWeighted", e16_vol);
        let soft_e16_vol = Volume::new(&soft_e16, dims).unwrap();
        both_orders!(ExtinctionWeighted, "ExtinctionWeighted, soft", soft_e16_vol);
    }
    assert!(rays_checked > 1000, "{rays_checked} rays");
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
        let mut out = vec![Sample::TRANSPARENT; len];
        let a_stop = [1.0, 0.9, 0.5][rng.below(3) as usize];
        macro_rules! check {
            ($mode:expr, $what:expr) => {
                check!($mode, $what, vol)
            };
            ($mode:expr, $what:expr, $vol:expr) => {{
                let vol = $vol;
                let stop = FrontToBack(Threshold::new(a_stop).unwrap());
                let m = RayMarcher::new(vol, $mode, Trilinear::new(), stop, step).unwrap();
                let base = m.with_isa(Isa::BASELINE);
                for isa in Isa::available() {
                    m.with_isa(isa).cast_rays(&rays, &mut out).unwrap();
                    for (ray, g) in rays.iter().zip(&out) {
                        let w = base.cast(ray);
                        assert!(
                            same_sample(g, &w),
                            "{}, {isa}, case {case}: {ray:?}: {g:?} vs {w:?}",
                            $what
                        );
                    }
                    rays_checked += len;
                }
            }};
        }
        let soft_u8s = soft(&u8s);
        let soft_vol = Volume::new(&soft_u8s, dims).unwrap();
        let tau = TauTable::new(d).unwrap();
        check!(OpacityWeighted, "OpacityWeighted");
        check!(Separate, "Separate");
        check!(ExtinctionWeightedU8::new(&tau), "ExtinctionWeightedU8");
        let ext = ExtinctionWeightedU8::new(&tau);
        check!(ext, "ExtinctionWeightedU8, soft", soft_vol);
        let (e16, soft_e16) = (extinction_f32(&u8s, d), extinction_f32(&soft_u8s, d));
        check!(
            ExtinctionWeighted,
            "ExtinctionWeighted",
            Volume::new(&e16, dims).unwrap()
        );
        let soft_e16_vol = Volume::new(&soft_e16, dims).unwrap();
        check!(ExtinctionWeighted, "ExtinctionWeighted, soft", soft_e16_vol);
    }
    assert!(rays_checked > 1000, "{rays_checked} rays");
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
