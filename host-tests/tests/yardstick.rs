//! The bench's yardsticks (`volsample_host::yardstick`) do the work of volsample's
//! `OpacityWeighted` trilinear front-to-back marcher: on rays through a volume whose outer two
//! voxel layers are transparent (where the yardsticks, which extrapolate from the edge cell,
//! and volsample, which clamps to the edge, both read only transparent voxels), they agree
//! with `RayMarcher::cast` within `YARDSTICK_ABS` per channel.

use volsample::{
    FrontToBack, OpacityWeighted, Ray, RayMarcher, Step, StraightU8, Trilinear, Volume,
};
use volsample_host::yardstick::{naive, tuned, YARDSTICK_ABS};

const N: usize = 32;
const D: f32 = 0.5;

/// The bench's voxel formula, transparent in the outer two layers.
fn volume() -> Vec<StraightU8> {
    let mut v = Vec::with_capacity(N * N * N);
    for z in 0..N {
        for y in 0..N {
            for x in 0..N {
                let shell = [x, y, z].iter().any(|c| !(2..N - 2).contains(c));
                let a = if shell {
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

#[test]
fn yardsticks_agree_with_the_library() {
    let v = volume();
    let vol = Volume::new(&v, [N; 3])
        .unwrap()
        .with_reference_distance(D)
        .unwrap();
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(D).unwrap(),
    )
    .unwrap();
    let mut composited = 0;
    for j in 0..8 {
        for i in 0..8 {
            let o = [
                3.0 + 3.0 * i as f32 + 0.25,
                2.0 + 3.0 * j as f32 + 0.25,
                -1.0,
            ];
            let ray = Ray::new(o, [0.12, 0.08, 1.0]).unwrap();
            let (t_first, count) = m.sample_range(&ray);
            let lib = m.cast(&ray);
            let lib = [lib.c[0], lib.c[1], lib.c[2], lib.a];
            for (name, got) in [
                ("naive", naive(&v, N, &ray, t_first, count, D)),
                ("tuned", tuned(&v, N, &ray, t_first, count, D)),
            ] {
                for (g, l) in got.iter().zip(lib) {
                    assert!(
                        (g - l).abs() <= YARDSTICK_ABS,
                        "{name} at ray ({i}, {j}): {got:?} vs volsample {lib:?}"
                    );
                }
            }
            if lib[3] > 0.5 {
                composited += 1;
            }
        }
    }
    // Most rays cross enough of the interior to be far from transparent, so the comparison
    // is not one of zeros.
    assert!(
        composited > 32,
        "only {composited} of 64 rays reached α > 0.5"
    );
}
