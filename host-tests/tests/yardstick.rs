//! The bench's yardsticks (`volsample_host::yardstick`) do the work of volsample's
//! `OpacityWeighted` trilinear front-to-back marcher: on rays through a volume whose outer two
//! voxel layers are transparent (where the yardsticks, which extrapolate from the edge cell,
//! and volsample, which clamps to the edge, both read only transparent voxels), they agree
//! with `RayMarcher::cast` within `YARDSTICK_ABS` per channel — one ray at a time, and across
//! rays (`tuned_rays`, eight rays in AVX2 lanes where the CPU has them, on a ray count that
//! leaves a remainder for the one-at-a-time loop).

use volsample::{
    FrontToBack, OpacityWeighted, Ray, RayMarcher, Step, StraightU8, Trilinear, Volume,
};
use volsample_host::yardstick::{naive, tuned, tuned_rays, tuned_rays_lanes, YARDSTICK_ABS};

const N: usize = 32;
const D: f32 = 0.5;

/// The bench's voxel formula; transparent in the outer two layers where `shell`.
fn volume(shell: bool) -> Vec<StraightU8> {
    let mut v = Vec::with_capacity(N * N * N);
    for z in 0..N {
        for y in 0..N {
            for x in 0..N {
                let outer = [x, y, z].iter().any(|c| !(2..N - 2).contains(c));
                let a = if shell && outer {
                    0
                } else {
                    4 + (7 * x + 13 * y + 29 * z) % 61
                };
                v.push(StraightU8([
                    (8 * x) as u8,
                    (8 * y) as u8,
                    (8 * z) as u8,
                    a as u8,
                ]));
            }
        }
    }
    v
}

/// volsample's marcher of the work the yardsticks do: `OpacityWeighted` trilinear, front to
/// back, `d = d′ = D`.
fn marcher(
    v: &[StraightU8],
) -> RayMarcher<'_, StraightU8, OpacityWeighted, Trilinear, FrontToBack> {
    let vol = Volume::new(v, [N; 3])
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let step = Step::new(D).unwrap();
    RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        step,
    )
    .unwrap()
}

#[test]
fn yardsticks_agree_with_the_library() {
    let v = volume(true);
    let m = marcher(&v);
    // 67 rays: eight packets of eight and a remainder of three for `tuned_rays`.
    let rays: Vec<Ray> = (0..67)
        .map(|k| {
            let (i, j) = (k % 8, k / 8);
            let o = [
                3.0 + 3.0 * i as f32 + 0.25,
                2.0 + 3.0 * j as f32 + 0.25,
                -1.0,
            ];
            Ray::new(o, [0.12, 0.08, 1.0]).unwrap()
        })
        .collect();
    let ranges: Vec<(f32, u32)> = rays.iter().map(|r| m.sample_range(r)).collect();
    let mut across = vec![[0.0f32; 4]; rays.len()];
    tuned_rays(&v, N, &rays, &ranges, D, &mut across);
    println!("tuned_rays marched {} ray(s) at a time", tuned_rays_lanes());
    let mut composited = 0;
    for (k, ((ray, &(t_first, count)), across)) in rays.iter().zip(&ranges).zip(across).enumerate()
    {
        let lib = m.cast(ray);
        let lib = [lib.c[0], lib.c[1], lib.c[2], lib.a];
        for (name, got) in [
            ("naive", naive(&v, N, ray, t_first, count, D)),
            ("tuned", tuned(&v, N, ray, t_first, count, D)),
            ("tuned_rays", across),
        ] {
            for (g, l) in got.iter().zip(lib) {
                assert!(
                    (g - l).abs() <= YARDSTICK_ABS,
                    "{name} at ray {k}: {got:?} vs volsample {lib:?}"
                );
            }
        }
        if lib[3] > 0.5 {
            composited += 1;
        }
    }
    // Most rays cross enough of the interior to be far from transparent, so the comparison
    // is not one of zeros.
    assert!(
        composited > 33,
        "only {composited} of 67 rays reached α > 0.5"
    );
}

/// `tuned_rays` against `tuned` one ray at a time where the rays of a packet have different
/// sample counts (different directions, one ray that misses the volume) through a volume
/// with no transparent shell: samples past a ray's end would read opaque voxels, so a lane
/// that went on compositing after its ray ended would show.
#[test]
fn across_rays_stop_each_ray_at_its_end() {
    let v = volume(false);
    let m = marcher(&v);
    let rays: Vec<Ray> = (0..21)
        .map(|k| {
            if k == 5 {
                // Misses the volume: no samples.
                return Ray::new([-4.0, -4.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
            }
            let sx = 0.5 * (k % 8) as f32 - 1.5;
            Ray::new([15.25, 14.25, -1.0], [sx, 0.3, 1.0]).unwrap()
        })
        .collect();
    let ranges: Vec<(f32, u32)> = rays.iter().map(|r| m.sample_range(r)).collect();
    let counts: Vec<u32> = ranges[..8].iter().map(|r| r.1).collect();
    assert_eq!(counts[5], 0);
    assert!(
        counts.iter().max() > counts.iter().filter(|&&c| c > 0).min(),
        "the first packet's rays must end at different samples: {counts:?}"
    );
    let mut across = vec![[0.0f32; 4]; rays.len()];
    tuned_rays(&v, N, &rays, &ranges, D, &mut across);
    for (k, ((ray, &(t, c)), got)) in rays.iter().zip(&ranges).zip(&across).enumerate() {
        let one = tuned(&v, N, ray, t, c, D);
        for (g, o) in got.iter().zip(one) {
            assert!(
                (g - o).abs() <= YARDSTICK_ABS,
                "ray {k} ({c} samples): {got:?} across rays vs {one:?} alone"
            );
        }
    }
    assert_eq!(across[5], [0.0; 4]);
}
