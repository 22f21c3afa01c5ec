//! Helpers shared by the fast-path test binaries (`fast_paths*.rs`): a seeded generator,
//! random volumes and rays, and the checks of packets and sample lanes against single rays.
//! The tests are split over several binaries so that their compilation (the marchers of
//! every mode, filter and instruction set) runs on several cores at once.
#![allow(dead_code)]

use volsample::composite::{front_to_back, over, Order, Termination};
use volsample::skip::Skipping;
use volsample::voxel::Voxel;
use volsample::Isa;
use volsample::{
    AssociatedU8, BackToFront, ExtinctionF32, Filter, FrontToBack, Mode, Nearest, Ray, RayMarcher,
    Sample, Step, StraightF32, StraightU8, Threshold, Trilinear, TriquadraticBSpline, Volume,
};

/// On an x86-64 CPU with AVX2 and FMA (by `std`'s detection, independent of the core's), the
/// core must detect them too, so that the AVX2 instances checked below do run there.
pub fn assert_best_isa_detected() {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        assert_eq!(
            Isa::detect().name(),
            "avx2",
            "AVX2 and FMA present but not detected"
        );
        assert_eq!(Isa::available().len(), 2);
    }
    let line = format!(
        "{}: instances checked: {:?}",
        env!("CARGO_CRATE_NAME"),
        Isa::available()
    );
    println!("{line}");
    // CI's instruction-set stage reads these lines from the file `VOLSAMPLE_ISA_LOG` names,
    // so that it can require the AVX2 instances to have run without running the tests twice.
    if let Some(path) = std::env::var_os("VOLSAMPLE_ISA_LOG") {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .expect("open VOLSAMPLE_ISA_LOG");
        writeln!(f, "{line}").expect("write VOLSAMPLE_ISA_LOG");
    }
}

/// xorshift64*: deterministic, seedable.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / 16_777_216.0
    }
    pub fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    /// A coordinate for an axis of `n` voxels: mostly inside, often on or near the edges,
    /// sometimes odd (−0, negative, NaN, ±∞, huge).
    pub fn coord(&mut self, n: usize) -> f32 {
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

pub fn cases() -> usize {
    std::env::var("VOLSAMPLE_FAST_PATH_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000)
}

pub fn random_dims(rng: &mut Rng) -> [usize; 3] {
    [0; 3].map(|_| 1 + rng.below(6) as usize)
}

pub fn random_u8_volume(rng: &mut Rng, dims: [usize; 3]) -> Vec<StraightU8> {
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
pub fn soft(v: &[StraightU8]) -> Vec<StraightU8> {
    v.iter()
        .map(|&StraightU8([r, g, b, a])| StraightU8([r, g, b, a % 61]))
        .collect()
}

/// `v` as `ExtinctionF32` voxels for steps of `d_ref` (`ExtinctionF32::from_straight` of the
/// bytes over 255): the 16-byte voxels of the AVX2 packets' `ExtinctionWeighted` rows.
pub fn extinction_f32(v: &[StraightU8], d_ref: f32) -> Vec<ExtinctionF32> {
    v.iter()
        .map(|&StraightU8(rgba)| {
            let [r, g, b, a] = rgba.map(|n| f32::from(n) / 255.0);
            ExtinctionF32::from_straight(StraightF32 { c: [r, g, b], a }, d_ref)
        })
        .collect()
}

pub fn same_f32(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits()
}

pub fn same_sample(a: &Sample, b: &Sample) -> bool {
    same_f32(a.a, b.a) && a.c.iter().zip(b.c.iter()).all(|(x, y)| same_f32(*x, *y))
}

pub fn random_ray(rng: &mut Rng, dims: [usize; 3]) -> Ray {
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

/// Every ray of `rays` through `m` four at a time ([`RayMarcher::cast4`], and
/// [`RayMarcher::cast_rays`] for the tails) against one at a time, in every instruction set
/// this CPU has against the baseline one ray at a time; `what` names the case.
#[inline(never)]
pub fn check_packets<V, M, F, O, S>(m: &RayMarcher<'_, V, M, F, O, S>, rays: &[Ray], what: &str)
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
#[inline(never)]
pub fn check_packets_in<V, M, F, O, S>(
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
#[inline(never)]
pub fn one_at_a_time<V, M, F, O, S>(
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

/// `cast_counted` (which marches four consecutive samples of a ray in lanes) and
/// [`one_at_a_time`], in every instruction set this CPU has, against [`one_at_a_time`] in the
/// baseline instruction set: bit-identical results and counts.
#[inline(never)]
pub fn check_sample_lanes<V, M, F, O, S>(
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
        let (want, k) = one_at_a_time(&m.with_isa(Isa::BASELINE), ray, &done, &empty, bg);
        for isa in Isa::available() {
            let (got, n) = m.with_isa(isa).cast_counted(ray);
            assert!(
                same_sample(&got, &want) && n == k,
                "{what}, {isa}: {ray:?}: lanes {got:?} ({n} samples) vs one at a time {want:?} ({k})"
            );
            // `sample` runs in the marcher's instruction set too.
            let (one, j) = one_at_a_time(&m.with_isa(isa), ray, &done, &empty, bg);
            assert!(
                same_sample(&one, &want) && j == k,
                "{what}, {isa}: {ray:?}: samples {one:?} ({j}) vs the baseline's {want:?} ({k})"
            );
        }
    }
}

/// One random case of the packet tests: a volume in every voxel format (the same random
/// bytes), a reference distance, a step with a random phase, an early-termination threshold
/// and twelve rays.
pub struct PacketCase {
    pub case: usize,
    pub dims: [usize; 3],
    pub d_ref: f32,
    pub u8s: Vec<StraightU8>,
    pub f32s: Vec<StraightF32>,
    pub assoc: Vec<AssociatedU8>,
    pub ext: Vec<ExtinctionF32>,
    pub scalars: Vec<f32>,
    pub step: Step,
    pub stop: FrontToBack<Threshold>,
    pub rays: Vec<Ray>,
}

impl PacketCase {
    /// `data` as a volume of the case's dimensions, with its reference distance.
    pub fn volume<'a, V: Voxel>(&self, data: &'a [V]) -> Volume<'a, V> {
        Volume::new(data, self.dims)
            .unwrap()
            .with_reference_distance(self.d_ref)
            .unwrap()
    }
}

/// The background of the packet tests' trilinear front-to-back marchers.
pub const PACKET_BG: Sample = Sample {
    c: [0.1, 0.2, 0.3],
    a: 0.5,
};

/// `cases() / 8` random [`PacketCase`]s from the seed of the packet tests, each given to `f`.
pub fn packet_cases(mut f: impl FnMut(&PacketCase)) {
    let mut rng = Rng(0x7AC4_E75A_11CE_0004);
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
        let stop = FrontToBack(Threshold::new([1.0, 0.9, 0.5, 0.05][case % 4]).unwrap());
        f(&PacketCase {
            case,
            dims,
            d_ref,
            u8s,
            f32s,
            assoc,
            ext,
            scalars,
            step,
            stop,
            rays,
        });
    }
}

/// Checks the packets ([`check_packets`]) and the sample lanes ([`check_sample_lanes`]) of
/// the mode `mode` over the volume `vol` of the case `c`, with every filter (trilinear with
/// early termination and a background, the lerp tree, nearest with early termination, the
/// B-spline) front to back, and trilinear back to front. Out of line, one function per voxel
/// format and mode (as a macro expanded into one test function, the checks of all modes made
/// a function the compiler took minutes to optimise).
#[inline(never)]
pub fn all_filters<V: Voxel, M: Mode<V> + Copy>(
    c: &PacketCase,
    vol: Volume<'_, V>,
    mode: M,
    what: &str,
) {
    let (stop, step, rays, ftb) = (c.stop, c.step, &c.rays, FrontToBack::new());
    let t = Sample::TRANSPARENT;
    let done = |a| stop.0.done(a);
    let never = |_: f32| false;
    let none = |_: [f32; 3]| false;
    let w = |filter: &str| format!("{what} {filter}");
    let m = RayMarcher::new(vol, mode, Trilinear::new(), stop, step).unwrap();
    let m = m.with_background(PACKET_BG).unwrap();
    check_packets(&m, rays, &w("trilinear"));
    check_sample_lanes(&m, rays, done, none, PACKET_BG, &w("trilinear"));
    let m = RayMarcher::new(vol, mode, Trilinear::tree(), ftb, step).unwrap();
    check_packets(&m, rays, &w("tree"));
    check_sample_lanes(&m, rays, never, none, t, &w("tree"));
    let m = RayMarcher::new(vol, mode, Nearest, stop, step).unwrap();
    check_packets(&m, rays, &w("nearest"));
    check_sample_lanes(&m, rays, done, none, t, &w("nearest"));
    let m = RayMarcher::new(vol, mode, TriquadraticBSpline, ftb, step).unwrap();
    check_packets(&m, rays, &w("bspline"));
    check_sample_lanes(&m, rays, never, none, t, &w("bspline"));
    let m = RayMarcher::new(vol, mode, Trilinear::new(), BackToFront, step).unwrap();
    check_packets(&m, rays, &w("back to front"));
}
