//! Empty-space skipping changes nothing: for every mode that offers it, every filter, both
//! compositing orders, with and without termination and opacity correction, and every brick
//! size, a marcher with an occupancy grid returns bit-identical pixels and sample counts.
//! The grid itself is checked against a brute-force recomputation of its definition.

use volsample::composite::Order;
use volsample::filter::Filter;
use volsample::skip::{Emptiness, Occupancy, MAX_BRICK_LOG2};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedF32, AssociatedU8, BackToFront, ExtinctionF32, ExtinctionWeighted, FrontToBack, Mode,
    Nearest, OpacityWeighted, Preweighted, Ray, RayMarcher, Sample, Separate, Step, StraightF32,
    StraightU8, Trilinear, TriquadraticBSpline, Volume,
};

/// SplitMix64: a small deterministic generator for the test volumes and rays.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
}

const DIMS: [usize; 3] = [13, 9, 17];

/// A sparse volume: a few small clusters of non-empty voxels in empty air whose (straight)
/// colors are random and non-zero, so `Separate` would bleed them if it read them.
fn sparse_u8(rng: &mut Rng) -> Vec<StraightU8> {
    let [nx, ny, nz] = DIMS;
    let mut v: Vec<StraightU8> = (0..nx * ny * nz)
        .map(|_| StraightU8([rng.byte(), rng.byte(), rng.byte(), 0]))
        .collect();
    for _ in 0..3 {
        let c = [
            rng.next() as usize % nx,
            rng.next() as usize % ny,
            rng.next() as usize % nz,
        ];
        for dz in 0..2 {
            for dy in 0..2 {
                for dx in 0..2 {
                    let (x, y, z) = (c[0] + dx, c[1] + dy, c[2] + dz);
                    if x < nx && y < ny && z < nz && rng.next() % 3 != 0 {
                        v[x + nx * (y + ny * z)].0[3] = 1 + rng.byte() % 255;
                    }
                }
            }
        }
    }
    // One voxel on the far corner, so the last plane and the clamped edge matter.
    let last = v.len() - 1;
    v[last].0[3] = 255;
    v
}

/// Rays from outside through the box in random directions, plus axis-aligned rays along the
/// faces and edges (grazing) and rays that miss.
fn rays(rng: &mut Rng) -> Vec<Ray> {
    let mut out = Vec::new();
    let c = DIMS.map(|n| (n as f32 - 1.0) * 0.5);
    for _ in 0..300 {
        let d = [
            rng.unit() * 2.0 - 1.0,
            rng.unit() * 2.0 - 1.0,
            rng.unit() * 2.0 - 1.0,
        ];
        let target = [0, 1, 2].map(|k| rng.unit() * DIMS[k] as f32 - 0.5);
        let o = [0, 1, 2].map(|k| target[k] - d[k] * 30.0);
        if let Ok(r) = Ray::new(o, d) {
            out.push(r);
        }
    }
    for (x, y) in [
        (0.0, 0.0),
        (12.0, 8.0),
        (-0.5, 3.0),
        (6.0, 8.5),
        (c[0], c[1]),
    ] {
        out.push(Ray::new([x, y, -3.0], [0.0, 0.0, 1.0]).unwrap());
        out.push(Ray::new([x, y, 20.0], [0.0, 0.0, -1.0]).unwrap());
    }
    out.push(Ray::new([-5.0, -5.0, -5.0], [-1.0, 0.0, 0.0]).unwrap());
    out
}

fn bits(s: Sample) -> [u32; 4] {
    [
        s.c[0].to_bits(),
        s.c[1].to_bits(),
        s.c[2].to_bits(),
        s.a.to_bits(),
    ]
}

/// Checks one configuration at every brick size; returns how many rays hit something.
fn check<V, M, F, O>(
    vol: Volume<'_, V>,
    mode: M,
    filter: F,
    order: O,
    d: f32,
    rays: &[Ray],
) -> usize
where
    V: Voxel,
    M: Mode<V> + Emptiness<V> + Copy,
    F: Filter + Copy,
    O: Order + Copy,
{
    let plain = RayMarcher::new(vol, mode, filter, order, Step::new(d).unwrap())
        .unwrap()
        .with_background(Sample {
            c: [0.0, 0.1, 0.2],
            a: 0.5,
        })
        .unwrap();
    let mut hits = 0;
    for log2 in 0..=4 {
        let mut buf = vec![0u8; Occupancy::buffer_len(vol.dims(), log2)];
        let fast = plain.with_skipping(&mut buf, log2).unwrap();
        let grid = fast.occupancy().unwrap();
        assert!(grid.occupied_bricks() > 0);
        for r in rays {
            let (a, na) = plain.cast_counted(r);
            let (b, nb) = fast.cast_counted(r);
            assert_eq!(
                (bits(a), na),
                (bits(b), nb),
                "{mode:?} {} log2 {log2} ray {r:?}",
                core::any::type_name::<F>()
            );
            if log2 == 0 && a.a > 0.5 {
                hits += 1;
            }
        }
    }
    hits
}

fn all_filters_and_orders<V, M>(vol: Volume<'_, V>, mode: M, rays: &[Ray]) -> usize
where
    V: Voxel,
    M: Mode<V> + Emptiness<V> + Copy,
{
    let mut hits = 0;
    for d in [vol.reference_distance(), 0.37] {
        let ftb = FrontToBack::new();
        let stop = FrontToBack::with_threshold(0.6).unwrap();
        let btf = BackToFront;
        hits += check(vol, mode, Nearest, ftb, d, rays);
        hits += check(vol, mode, Trilinear::new(), ftb, d, rays);
        hits += check(vol, mode, Trilinear::tree(), stop, d, rays);
        hits += check(vol, mode, Trilinear::new(), btf, d, rays);
        hits += check(vol, mode, TriquadraticBSpline, ftb, d, rays);
        hits += check(vol, mode, TriquadraticBSpline, stop, d, rays);
    }
    hits
}

#[test]
fn skipping_is_bit_identical_for_every_mode_filter_and_order() {
    let mut rng = Rng(7);
    let rays = rays(&mut rng);
    for seed in 0..4 {
        let mut rng = Rng(100 + seed);
        let u8s = sparse_u8(&mut rng);
        let vol = Volume::new(&u8s, DIMS).unwrap();
        let mut hits = all_filters_and_orders(vol, OpacityWeighted, &rays);
        hits += all_filters_and_orders(vol, Separate, &rays);

        let f32s: Vec<StraightF32> = u8s
            .iter()
            .map(|v| {
                let [r, g, b, a] = v.0.map(|x| f32::from(x) / 255.0);
                StraightF32 { c: [r, g, b], a }
            })
            .collect();
        let vol = Volume::new(&f32s, DIMS)
            .unwrap()
            .with_reference_distance(0.5)
            .unwrap();
        hits += all_filters_and_orders(vol, OpacityWeighted, &rays);

        let assoc: Vec<AssociatedU8> = u8s
            .iter()
            .map(|v| {
                let a = v.0[3];
                let c = |x: u8| ((u32::from(x) * u32::from(a) + 127) / 255) as u8;
                AssociatedU8([c(v.0[0]), c(v.0[1]), c(v.0[2]), a])
            })
            .collect();
        let vol = Volume::new(&assoc, DIMS).unwrap();
        hits += all_filters_and_orders(vol, Preweighted, &rays);
        let assoc_f: Vec<AssociatedF32> = f32s
            .iter()
            .map(|&v| AssociatedF32::from_straight(v))
            .collect();
        let vol = Volume::new(&assoc_f, DIMS).unwrap();
        hits += all_filters_and_orders(vol, Preweighted, &rays);

        let ext: Vec<ExtinctionF32> = f32s
            .iter()
            .map(|&v| ExtinctionF32::from_straight(v, 1.0))
            .collect();
        let vol = Volume::new(&ext, DIMS).unwrap();
        hits += all_filters_and_orders(vol, ExtinctionWeighted, &rays);
        // The comparison is not vacuous: many rays cross material.
        assert!(hits > 100, "{hits}");
    }
}

/// The grid is what its definition says: a brick is occupied exactly when a non-empty voxel
/// lies in `[b·B − 1, b·B + B + 1]` per axis (recomputed here brick by brick).
#[test]
fn grid_matches_its_definition() {
    let mut rng = Rng(3);
    let v = sparse_u8(&mut rng);
    let vol = Volume::new(&v, DIMS).unwrap();
    let [nx, ny, nz] = DIMS;
    for log2 in 0..=MAX_BRICK_LOG2 {
        let mut buf = vec![0xAAu8; Occupancy::buffer_len(DIMS, log2) + 3];
        let g = Occupancy::build(&vol, &OpacityWeighted, log2, &mut buf).unwrap();
        let b = 1i64 << log2;
        let [bx, by, bz] = g.bricks();
        assert_eq!(
            [bx, by, bz],
            DIMS.map(|n| (n as i64 + b - 1) as usize / b as usize)
        );
        let mut occupied = 0;
        for cz in 0..bz {
            for cy in 0..by {
                for cx in 0..bx {
                    let lo = |c: usize| c as i64 * b - 1;
                    let hi = |c: usize| c as i64 * b + b + 1;
                    let mut any = false;
                    for z in 0..nz {
                        for y in 0..ny {
                            for x in 0..nx {
                                let inside =
                                    |p: usize, c: usize| (lo(c)..=hi(c)).contains(&(p as i64));
                                if inside(x, cx) && inside(y, cy) && inside(z, cz) {
                                    any |= v[x + nx * (y + ny * z)].0[3] != 0;
                                }
                            }
                        }
                    }
                    occupied += usize::from(any);
                    // A position at the brick's first voxel reads that brick.
                    let p = [cx, cy, cz].map(|c| (c << log2) as f32 + 0.25);
                    let p = [
                        p[0].min(nx as f32 - 1.0),
                        p[1].min(ny as f32 - 1.0),
                        p[2].min(nz as f32 - 1.0),
                    ];
                    assert_eq!(g.is_empty_at(p), !any, "log2 {log2} brick {cx},{cy},{cz}");
                }
            }
        }
        assert_eq!(g.occupied_bricks(), occupied, "log2 {log2}");
        // The bytes past the grid are untouched.
        let n = Occupancy::buffer_len(DIMS, log2);
        assert_eq!(&buf[n..], &[0xAA; 3]);
    }
}

/// Samples whose taps are all empty are exactly transparent for every mode that offers
/// skipping, with colors that are not zero (`Separate` interpolates them).
#[test]
fn empty_taps_give_exactly_transparent_samples() {
    let mut rng = Rng(11);
    let air: Vec<StraightU8> = (0..27)
        .map(|_| StraightU8([rng.byte() | 1, rng.byte() | 1, rng.byte() | 1, 0]))
        .collect();
    let vol = Volume::new(&air, [3; 3]).unwrap();
    for k in 0..200 {
        let p = [0, 1, 2].map(|_| rng.unit() * 4.0 - 0.7);
        for d in [1.0, 0.3] {
            let step = Step::new(d).unwrap();
            let ow = RayMarcher::new(
                vol,
                OpacityWeighted,
                TriquadraticBSpline,
                FrontToBack::new(),
                step,
            )
            .unwrap();
            let sep =
                RayMarcher::new(vol, Separate, Trilinear::new(), FrontToBack::new(), step).unwrap();
            let sep_n = RayMarcher::new(vol, Separate, Nearest, FrontToBack::new(), step).unwrap();
            for s in [ow.sample(p), sep.sample(p), sep_n.sample(p)] {
                assert_eq!(bits(s), bits(Sample::TRANSPARENT), "sample {k} at {p:?}");
            }
        }
    }
}

#[test]
fn bad_grid_parameters_are_errors() {
    let v = vec![StraightU8([0; 4]); 64];
    let vol = Volume::new(&v, [4; 3]).unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(0.5).unwrap(),
    )
    .unwrap();
    let mut buf = vec![0u8; 64];
    assert_eq!(
        m.with_skipping(&mut buf, MAX_BRICK_LOG2 + 1).err(),
        Some(volsample::Error::InvalidBrickSize)
    );
    assert_eq!(Occupancy::buffer_len([4; 3], MAX_BRICK_LOG2 + 1), 0);
    let mut small = vec![0u8; 7];
    assert_eq!(
        m.with_skipping(&mut small, 1).err(),
        Some(volsample::Error::OutputLengthMismatch {
            expected: 8,
            actual: 7
        })
    );
    assert_eq!(Occupancy::buffer_len([usize::MAX, 2, 2], 0), usize::MAX);
    // An all-empty volume has no occupied brick and every ray is the background.
    let mut buf = vec![0u8; 1];
    let fast = m.with_skipping(&mut buf, 2).unwrap();
    assert_eq!(fast.occupancy().map(|g| g.occupied_bricks()), Some(0));
    let r = Ray::new([1.0, 1.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
    assert_eq!(fast.cast_counted(&r), m.cast_counted(&r));
}

/// The integer marcher with an occupancy grid is bit-identical too: every opacity-based
/// integer mode, nearest and trilinear, with correction and early stop, at F = 4 and 8 (the
/// quantized position may round up into the next voxel, which the grid's apron covers).
#[test]
fn integer_skipping_is_bit_identical() {
    use volsample::fixed_point::{IntFilter, IntMode, IntStop};
    use volsample::render::IntRayMarcher;

    fn check_int<V, M, Fl, const F: u32>(
        vol: Volume<'_, V>,
        mode: M,
        filter: Fl,
        rays: &[Ray],
    ) -> usize
    where
        V: Voxel,
        M: IntMode<V> + Emptiness<V>,
        Fl: IntFilter,
    {
        let mut hits = 0;
        for (d, stop) in [(1.0, IntStop::NEVER), (0.37, IntStop::new(40_000).unwrap())] {
            let plain =
                IntRayMarcher::<_, _, _, F>::new(vol, mode, filter, stop, Step::new(d).unwrap())
                    .unwrap();
            for log2 in 0..=3 {
                let mut buf = vec![0u8; Occupancy::buffer_len(vol.dims(), log2)];
                let fast = plain.clone().with_skipping(&mut buf, log2).unwrap();
                assert!(fast.occupancy().unwrap().occupied_bricks() > 0);
                for r in rays {
                    let a = plain.cast_counted(r);
                    assert_eq!(
                        a,
                        fast.cast_counted(r),
                        "{mode:?} F {F} log2 {log2} d {d} {r:?}"
                    );
                    hits += usize::from(log2 == 0 && a.0.a() > 20_000);
                }
            }
        }
        hits
    }

    let mut rng = Rng(17);
    let rays = rays(&mut rng);
    let mut hits = 0;
    for seed in 0..3 {
        let mut rng = Rng(200 + seed);
        let u8s = sparse_u8(&mut rng);
        let vol = Volume::new(&u8s, DIMS).unwrap();
        hits += check_int::<_, _, _, 8>(vol, OpacityWeighted, Trilinear::new(), &rays);
        hits += check_int::<_, _, _, 4>(vol, OpacityWeighted, Trilinear::new(), &rays);
        hits += check_int::<_, _, _, 8>(vol, OpacityWeighted, Nearest, &rays);
        hits += check_int::<_, _, _, 8>(vol, Separate, Trilinear::new(), &rays);
        hits += check_int::<_, _, _, 4>(vol, Separate, Nearest, &rays);
        let assoc: Vec<AssociatedU8> = u8s
            .iter()
            .map(|v| {
                let a = v.0[3];
                let c = |x: u8| ((u32::from(x) * u32::from(a) + 127) / 255) as u8;
                AssociatedU8([c(v.0[0]), c(v.0[1]), c(v.0[2]), a])
            })
            .collect();
        let vol = Volume::new(&assoc, DIMS).unwrap();
        hits += check_int::<_, _, _, 8>(vol, Preweighted, Trilinear::new(), &rays);
        hits += check_int::<_, _, _, 4>(vol, Preweighted, Nearest, &rays);
    }
    assert!(hits > 100, "{hits}");
}

/// A hollow shell in `n³` (a skull-like wall a few voxels thick around empty space, in empty
/// air), with random colors everywhere and random opacities in the wall: rays cross air,
/// wall, the empty inside, wall and air, so both ends of each ray and its middle are empty.
fn shell_u8(rng: &mut Rng, n: usize) -> Vec<StraightU8> {
    let c = (n as f32 - 1.0) * 0.5;
    let r = n as f32 * 0.35;
    let mut v = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let d = [x, y, z].map(|k| k as f32 - c);
                let len = (d[0] * d[0] + d[1] * d[1] * 1.3 + d[2] * d[2] * 0.8).sqrt();
                let a = if (len - r).abs() < 1.6 {
                    1 + rng.byte() % 120
                } else {
                    0
                };
                v.push(StraightU8([rng.byte(), rng.byte(), rng.byte(), a]));
            }
        }
    }
    v
}

/// [`Occupancy::occupied_samples`] bounds every sample that is not empty, tightly: every
/// sample before `lo` or from `hi` on is empty (`is_empty_at` at the position the marcher
/// computes), and samples `lo` and `hi − 1` are not; for every brick size, steps that are
/// not powers of two, and rays in every direction, grazing and missing ones included.
#[test]
fn occupied_samples_bound_every_sample_that_is_not_empty() {
    let mut rng = Rng(5);
    let rays = rays(&mut rng);
    let mut shell_rng = Rng(6);
    let shell = shell_u8(&mut shell_rng, 24);
    let sparse = sparse_u8(&mut rng);
    let vols = [
        Volume::new(&sparse, DIMS).unwrap(),
        Volume::new(&shell, [24; 3]).unwrap(),
    ];
    let (mut clipped, mut samples) = (0u64, 0u64);
    for vol in vols {
        // Rays aimed at the shell's box too (the `rays` aim at `DIMS`).
        let mut rays = rays.clone();
        for k in 0..200 {
            let f = k as f32 * 0.37;
            let dir = [f.sin(), (1.7 * f).cos(), 0.3 + (0.5 * f).sin()];
            let o = [
                12.0 - 40.0 * dir[0],
                11.0 - 40.0 * dir[1],
                12.5 - 40.0 * dir[2],
            ];
            rays.push(Ray::new(o, dir).unwrap());
        }
        for d in [1.0, 0.5, 0.37, 0.1] {
            let m = RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                FrontToBack::new(),
                Step::new(d).unwrap(),
            )
            .unwrap();
            for log2 in 0..=MAX_BRICK_LOG2 {
                let mut buf = vec![0u8; Occupancy::buffer_len(vol.dims(), log2)];
                let g = Occupancy::build(&vol, &OpacityWeighted, log2, &mut buf).unwrap();
                for r in &rays {
                    let (t_first, n) = m.sample_range(r);
                    let w = g.occupied_samples(r, (t_first, n), d);
                    assert!(w.start <= w.end && w.end <= n, "{w:?} of {n}");
                    let empty = |j: u32| g.is_empty_at(r.at(t_first + j as f32 * d));
                    for j in 0..n {
                        if !w.contains(&j) {
                            assert!(empty(j), "log2 {log2} d {d} sample {j} of {w:?} {r:?}");
                        }
                    }
                    if !w.is_empty() {
                        assert!(
                            !empty(w.start) && !empty(w.end - 1),
                            "{w:?} not tight {r:?}"
                        );
                    } else {
                        assert_eq!(w.start, n);
                    }
                    clipped += u64::from(n - w.len() as u32);
                    samples += u64::from(n);
                }
            }
        }
    }
    // The walk does leave samples out (not a vacuous `0..n`): 13 % of them here.
    assert!(clipped * 10 > samples, "{clipped} of {samples}");
}

/// With skipping, the eight-ray AVX2 packets (and the eight-sample one-ray kernel) march
/// only each ray's occupied samples: images (orthographic along an axis and obliquely, and
/// perspective; widths with and without a remainder of eight), `cast_rays` and
/// `cast_counted` are bit-identical to the marcher without skipping, in every instruction
/// set this CPU has, for every mode with a lane kernel and the integer `OpacityWeighted`,
/// with and without early termination; and the packets are used with skipping (where there
/// is no opacity correction, which the eight-ray kernel does not compute).
#[test]
fn packets_and_images_with_skipping_are_bit_identical() {
    use volsample::mode::{ExtinctionWeightedU8, TauTable};
    use volsample::render::IntRayMarcher;
    use volsample::{Camera, IntStop, Isa, Orthographic, Perspective};

    fn cameras(dims: [usize; 3]) -> (Orthographic, Orthographic, Perspective) {
        let c = dims.map(|n| (n as f32 - 1.0) * 0.5);
        let ext = dims.iter().copied().max().unwrap_or(1) as f32 * 1.2;
        let along_z = Orthographic::looking_down_z(dims).unwrap();
        let oblique = Orthographic::new(
            [c[0] - 30.0, c[1] - 20.0, c[2] - 25.0],
            [30.0, 20.0, 25.0],
            [0.0, 1.0, 0.0],
            ext,
        )
        .unwrap();
        let persp = Perspective::new(
            [c[0] + 9.0, c[1] - 40.0, c[2] + 31.0],
            c,
            [0.0, 0.0, 1.0],
            0.6,
        )
        .unwrap();
        (along_z, oblique, persp)
    }

    fn image<C: Camera>(
        render: impl Fn(&C, usize, usize, &mut [Sample]),
        cam: &C,
        w: usize,
        h: usize,
    ) -> Vec<[u32; 4]> {
        let mut img = vec![Sample::TRANSPARENT; w * h];
        render(cam, w, h, &mut img);
        img.into_iter().map(bits).collect()
    }

    /// One float configuration: the plain marcher in the baseline instance against the
    /// skipping one in `isa`. Returns the pixels with `A > 0.5`.
    fn check_float<V, M>(vol: Volume<'_, V>, mode: M, isa: Isa, rays: &[Ray]) -> usize
    where
        V: Voxel,
        M: Mode<V> + Emptiness<V> + Copy,
    {
        let stop = FrontToBack::with_threshold(0.6).unwrap();
        check_order(vol, mode, FrontToBack::new(), isa, rays)
            + check_order(vol, mode, stop, isa, rays)
    }

    fn check_order<V, M, O>(vol: Volume<'_, V>, mode: M, order: O, isa: Isa, rays: &[Ray]) -> usize
    where
        V: Voxel,
        M: Mode<V> + Emptiness<V> + Copy,
        O: Order + Copy,
    {
        let (along_z, oblique, persp) = cameras(vol.dims());
        let mut hits = 0;
        for d in [0.5, 0.37] {
            // The step is the reference distance: no opacity correction, which the eight-ray
            // kernel does not compute (the tests above cover skipping with correction).
            let vol = vol.with_reference_distance(d).unwrap();
            let plain = RayMarcher::new(vol, mode, Trilinear::new(), order, Step::new(d).unwrap())
                .unwrap()
                .with_isa(Isa::BASELINE);
            for log2 in [1, 3] {
                let mut buf = vec![0u8; Occupancy::buffer_len(vol.dims(), log2)];
                let fast = plain.with_skipping(&mut buf, log2).unwrap().with_isa(isa);
                assert_eq!(fast.packet_width(), plain.with_isa(isa).packet_width());
                let what = format!("{mode:?} {isa:?} d {d} log2 {log2}");
                for (w, h) in [(32, 16), (21, 13)] {
                    let p = |c: &Orthographic, w, h, o: &mut [Sample]| {
                        plain.render_into(c, w, h, o).unwrap()
                    };
                    let f = |c: &Orthographic, w, h, o: &mut [Sample]| {
                        fast.render_into(c, w, h, o).unwrap()
                    };
                    for cam in [&along_z, &oblique] {
                        let a = image(p, cam, w, h);
                        assert_eq!(a, image(f, cam, w, h), "{what} {cam:?}");
                        hits += a.iter().filter(|x| f32::from_bits(x[3]) > 0.5).count();
                    }
                    let p = |c: &Perspective, w, h, o: &mut [Sample]| {
                        plain.render_into(c, w, h, o).unwrap()
                    };
                    let f = |c: &Perspective, w, h, o: &mut [Sample]| {
                        fast.render_into(c, w, h, o).unwrap()
                    };
                    assert_eq!(
                        image(p, &persp, w, h),
                        image(f, &persp, w, h),
                        "{what} perspective"
                    );
                }
                let mut a = vec![Sample::TRANSPARENT; rays.len()];
                let mut b = a.clone();
                plain.cast_rays(rays, &mut a).unwrap();
                fast.cast_rays(rays, &mut b).unwrap();
                assert_eq!(
                    a.into_iter().map(bits).collect::<Vec<_>>(),
                    b.into_iter().map(bits).collect::<Vec<_>>(),
                    "{what} cast_rays"
                );
                for r in rays {
                    let (x, nx) = plain.cast_counted(r);
                    let (y, ny) = fast.cast_counted(r);
                    assert_eq!((bits(x), nx), (bits(y), ny), "{what} {r:?}");
                }
            }
        }
        hits
    }

    let mut rng = Rng(23);
    let rays = rays(&mut rng);
    let mut shell_rng = Rng(29);
    let shell = shell_u8(&mut shell_rng, 40);
    let sparse = sparse_u8(&mut rng);
    let table = TauTable::new(1.0).unwrap();
    let mut hits = 0;
    for isa in Isa::available() {
        for (data, dims) in [(&shell, [40; 3]), (&sparse, DIMS)] {
            let vol = Volume::new(data, dims).unwrap();
            if isa != Isa::BASELINE {
                // The skipping marcher does use the eight-ray kernel.
                let mut buf = vec![0u8; Occupancy::buffer_len(dims, 3)];
                let m = RayMarcher::new(
                    vol.with_reference_distance(0.5).unwrap(),
                    OpacityWeighted,
                    Trilinear::new(),
                    FrontToBack::new(),
                    Step::new(0.5).unwrap(),
                )
                .unwrap();
                assert_eq!(
                    m.with_skipping(&mut buf, 3)
                        .unwrap()
                        .with_isa(isa)
                        .packet_width(),
                    8
                );
            }
            hits += check_float(vol, OpacityWeighted, isa, &rays);
            hits += check_float(vol, Separate, isa, &rays);
            hits += check_float(vol, ExtinctionWeightedU8::new(&table), isa, &rays);
            let ext: Vec<ExtinctionF32> = data
                .iter()
                .map(|v| {
                    let [r, g, b, a] = v.0.map(|x| f32::from(x) / 255.0);
                    ExtinctionF32::from_straight(StraightF32 { c: [r, g, b], a }, 1.0)
                })
                .collect();
            let vol_e = Volume::new(&ext, dims).unwrap();
            hits += check_float(vol_e, ExtinctionWeighted, isa, &rays);

            // The integer `OpacityWeighted` trilinear march at F = 8.
            let (along_z, oblique, persp) = cameras(dims);
            for (d, stop) in [(0.5, IntStop::NEVER), (0.37, IntStop::new(40_000).unwrap())] {
                let plain = IntRayMarcher::<_, _, _, 8>::new(
                    vol.with_reference_distance(d).unwrap(),
                    OpacityWeighted,
                    Trilinear::new(),
                    stop,
                    Step::new(d).unwrap(),
                )
                .unwrap()
                .with_isa(Isa::BASELINE);
                let mut buf = vec![0u8; Occupancy::buffer_len(dims, 3)];
                let fast = plain
                    .clone()
                    .with_skipping(&mut buf, 3)
                    .unwrap()
                    .with_isa(isa);
                assert_eq!(
                    fast.packet_width(),
                    plain.clone().with_isa(isa).packet_width()
                );
                for (w, h) in [(32, 16), (21, 13)] {
                    let mut a = vec![volsample::IntSample::TRANSPARENT; w * h];
                    let mut b = a.clone();
                    for k in 0..3 {
                        match k {
                            0 => {
                                plain.render_into(&along_z, w, h, &mut a).unwrap();
                                fast.render_into(&along_z, w, h, &mut b).unwrap();
                            }
                            1 => {
                                plain.render_into(&oblique, w, h, &mut a).unwrap();
                                fast.render_into(&oblique, w, h, &mut b).unwrap();
                            }
                            _ => {
                                plain.render_into(&persp, w, h, &mut a).unwrap();
                                fast.render_into(&persp, w, h, &mut b).unwrap();
                            }
                        }
                        assert_eq!(a, b, "integer {isa:?} d {d} camera {k}");
                        hits += a.iter().filter(|s| s.a() > 20_000).count();
                    }
                }
                for r in &rays {
                    assert_eq!(
                        plain.cast_counted(r),
                        fast.cast_counted(r),
                        "integer {isa:?} d {d} {r:?}"
                    );
                }
            }
        }
    }
    assert!(hits > 1000, "{hits}");
}
