//! Group 4, geometry: rays grazing a material boundary (a cell face) for their whole length,
//! samples exactly on voxel centres, cell faces and the last plane, rays along a box face or
//! edge and rays touching the box in one point, volumes of `1×1×1`, `1×N×1` and `2×2×2`,
//! empty and all-opaque volumes, steps larger than the volume.
//!
//! Every ray here is axis-aligned with origins and steps exact in `f32`, so the core's `f32`
//! ray and the reference's `f64` ray take the *same* samples: the sample counts must be
//! equal, and the pixels within the render bound. (`render_vs_reference` skips exactly these
//! pixels — a decision within `10⁻⁴` of a boundary — for random rays, where the two may
//! legitimately disagree.)

use volsample::{
    FrontToBack, OpacityWeighted, Ray, RayMarcher, Sample, Step, StraightF32, Trilinear, Volume,
};
use volsample_host::edge_cases::{next_down, next_up};
use volsample_host::float_checks::{CameraSpec, FilterKind, FloatCase, ModeKind, RenderSpec};
use volsample_host::reference::{self, RefRay};
use volsample_host::tolerance::{self as tol, EPS32};

use crate::common::{abs_err, assert_valid, Worst};

const DIMS: [[usize; 3]; 4] = [[1, 1, 1], [1, 7, 1], [2, 2, 2], [3, 2, 4]];

/// The contents: empty, all opaque, a one-voxel opaque red wall at `x = 0` in transparent
/// blue air (the material boundary is the cell face `x = ½`), and a mixed pattern with
/// `α ∈ {0, 10⁻⁷, ½, 1 − 2⁻²⁴, 1}`.
fn contents(dims: [usize; 3]) -> Vec<(&'static str, FloatCase)> {
    let n = dims[0] * dims[1] * dims[2];
    let idx = |i: usize| {
        [
            i % dims[0],
            (i / dims[0]) % dims[1],
            i / (dims[0] * dims[1]),
        ]
    };
    let tf = vec![
        volsample::ControlPoint {
            s: 0.0,
            c: [0.0, 0.0, 1.0],
            a: 0.0,
        },
        volsample::ControlPoint {
            s: 100.0,
            c: [1.0, 0.5, 0.0],
            a: 0.5,
        },
        volsample::ControlPoint {
            s: 200.0,
            c: [1.0, 0.0, 0.0],
            a: 1.0,
        },
    ];
    let make = |f: &dyn Fn(usize) -> (StraightF32, f32)| FloatCase {
        dims,
        voxels: (0..n).map(|i| f(i).0).collect(),
        scalars: (0..n).map(|i| f(i).1).collect(),
        tf: tf.clone(),
        d_ref: 1.0,
    };
    let alphas = [0.0f32, 1e-7, 0.5, next_down(1.0), 1.0];
    vec![
        (
            "empty",
            make(&|_| {
                (
                    StraightF32 {
                        c: [1.0, 0.0, 0.0],
                        a: 0.0,
                    },
                    0.0,
                )
            }),
        ),
        (
            "opaque",
            make(&|_| {
                (
                    StraightF32 {
                        c: [0.2, 0.4, 0.6],
                        a: 1.0,
                    },
                    200.0,
                )
            }),
        ),
        (
            "wall",
            make(&|i| {
                if idx(i)[0] == 0 {
                    (
                        StraightF32 {
                            c: [1.0, 0.0, 0.0],
                            a: 1.0,
                        },
                        200.0,
                    )
                } else {
                    (
                        StraightF32 {
                            c: [0.0, 0.0, 1.0],
                            a: 0.0,
                        },
                        0.0,
                    )
                }
            }),
        ),
        (
            "mixed",
            make(&|i| {
                let a = alphas[(i * 7 + 3) % alphas.len()];
                (
                    StraightF32 {
                        c: [(i % 3) as f32 / 2.0, 1.0, 0.25],
                        a,
                    },
                    ((i * 37) % 201) as f32,
                )
            }),
        ),
    ]
}

/// A `1×1` orthographic image whose only ray is `origin + t·dir` exactly (the pixel centre
/// is the image plane's centre).
fn one_ray(origin: [f32; 3], dir: [f32; 3], step: f32, phase: f32) -> RenderSpec {
    let up = if dir[1] == 0.0 {
        [0.0, 1.0, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    RenderSpec {
        camera: CameraSpec::Orthographic(origin, dir, up, 1.0),
        width: 1,
        height: 1,
        step,
        phase,
        background: Sample::TRANSPARENT,
        a_stop: 1.0,
        back_to_front: false,
    }
}

/// The rays along `axis` (both directions): origins on voxel centres, on the cell face
/// `½` (the wall's boundary), on the box faces `−½` and `n − ½` (and one ulp inside), on
/// a box edge, on the last voxel plane, and starting inside the volume on a centre.
fn rays(dims: [usize; 3], axis: usize) -> Vec<([f32; 3], [f32; 3])> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let last = |k: usize| dims[k] as f32 - 1.0;
    let hi = |k: usize| dims[k] as f32 - 0.5;
    let across: Vec<(f32, f32)> = vec![
        (0.0, 0.0),
        (0.5, 0.0),
        (next_down(0.5), 0.0),
        (next_up(0.5), 0.0),
        (-0.5, 0.0),
        (next_up(-0.5), 0.0),
        (hi(u), last(v)),
        (-0.5, -0.5),
        (hi(u), hi(v)),
        (last(u), last(v)),
    ];
    let mut out = Vec::new();
    for (a, b) in across {
        for (start, sign) in [
            (-1.0f32, 1.0f32),
            (-0.5, 1.0),
            (0.0, 1.0),
            (dims[axis] as f32, -1.0),
            (hi(axis), -1.0),
        ] {
            let mut o = [0.0f32; 3];
            o[axis] = start;
            o[u] = a;
            o[v] = b;
            let mut d = [0.0f32; 3];
            d[axis] = sign;
            out.push((o, d));
        }
    }
    out
}

/// The render bound for `n` samples at `d = d′` or for a uniform volume (no conditioning).
fn ray_bound(case: &FloatCase, mode: ModeKind, filter: FilterKind, n: usize, d: f32) -> f64 {
    let per = 2.0 * tol::sample_bound(mode, filter, case, d) + tol::CORRECTION_ABS + 4.0 * EPS32;
    (n as f64 + 1.0) * (2.0 * per + tol::COMPOSITE_STEP)
}

/// Every mode × filter on every exact ray through every small volume and content, at steps
/// from ¼ voxel to larger than the volume and three phases: the same sample count as the
/// reference, and the pixel within the render bound. Steps `d ≠ 1` are used only where
/// correction is exact or well conditioned (empty, opaque, and the wall, whose opacities
/// are 0 or 1).
#[test]
fn exact_rays_through_small_volumes() {
    let mut w = Worst::new(
        "4 exact rays: centres/faces/edges/last plane, 1×1×1…3×2×4",
        "RayMarcher::cast, 5 modes × 4 filters, both orders",
        "abs",
    );
    let mut rays_checked = 0usize;
    for dims in DIMS {
        for (name, case) in contents(dims) {
            let steps: &[f32] = if name == "mixed" {
                &[1.0]
            } else {
                &[0.25, 1.0, 3.0, 1000.0]
            };
            for axis in 0..3 {
                for (o, dir) in rays(dims, axis) {
                    for &d in steps {
                        for phase in [0.0f32, 0.5, 0.75] {
                            let spec = one_ray(o, dir, d, phase);
                            let rr = RefRay::new(o.map(f64::from), dir.map(f64::from));
                            let want_n = reference::sample_positions(
                                dims,
                                &rr,
                                f64::from(d),
                                f64::from(phase),
                            )
                            .len();
                            let data = vec![StraightF32::default(); dims[0] * dims[1] * dims[2]];
                            let vol = Volume::new(&data, dims).unwrap();
                            let step = Step::new(d).unwrap().with_phase(phase).unwrap();
                            let m = RayMarcher::new(
                                vol,
                                OpacityWeighted,
                                Trilinear::new(),
                                FrontToBack::new(),
                                step,
                            )
                            .unwrap();
                            let got_n = m.sample_range(&Ray::new(o, dir).unwrap()).1 as usize;
                            assert_eq!(
                                got_n, want_n,
                                "{dims:?} origin {o:?} dir {dir:?} d={d} phase={phase}"
                            );
                            rays_checked += 1;
                            for mode in ModeKind::ALL {
                                for filter in FilterKind::ALL {
                                    let got = case.core_render(mode, filter, &spec)[0];
                                    let want = case.reference_render(mode, filter, &spec)[0];
                                    assert_valid(got, || {
                                        format!("{name} {dims:?} {o:?} {dir:?} d={d}")
                                    });
                                    let bound = ray_bound(&case, mode, filter, want_n, d);
                                    w.check(abs_err(got, want), bound, || {
                                        format!("{name} {dims:?} {mode:?} {filter:?} o={o:?} dir={dir:?} d={d} φ={phase}")
                                    });
                                    if name == "empty" {
                                        assert_eq!(got, Sample::TRANSPARENT);
                                    }
                                    if name == "opaque"
                                        && want_n > 0
                                        && mode != ModeKind::ExtinctionWeighted
                                    {
                                        assert_eq!(got.a, 1.0, "{mode:?} {filter:?} d={d}");
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    println!("exact rays checked: {rays_checked}");
    w.report();
}

/// Rays that touch the box in a single point (a corner, at 45°) or miss it by one ulp take no
/// sample and return the background exactly; the reference agrees.
#[test]
fn rays_touching_the_box_in_one_point() {
    let mut w = Worst::new(
        "4 rays touching the box in one point / along an edge",
        "RayMarcher::{sample_range, cast}",
        "mismatches",
    );
    w.exact(|| "touching rays".to_string(), rays_touching_body);
    w.report();
}

fn rays_touching_body() {
    let data = [StraightF32 {
        c: [1.0; 3],
        a: 1.0,
    }; 8];
    let vol = Volume::new(&data, [2, 2, 2]).unwrap();
    let bg = Sample {
        c: [0.1, 0.2, 0.3],
        a: 0.5,
    };
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        FrontToBack::new(),
        Step::new(1.0).unwrap(),
    )
    .unwrap()
    .with_background(bg)
    .unwrap();
    // Through the corner (−½, −½) in the x–y plane, from outside, at 45°: touches it only.
    for (o, d) in [
        ([-1.5f32, 0.5, 0.0], [1.0f32, -1.0, 0.0]),
        ([0.5, -1.5, 0.0], [-1.0, 1.0, 0.0]),
        ([2.5, 0.5, 0.0], [-1.0, 1.0, 0.0]),
        // Along an edge line, one ulp outside the box.
        ([next_down(-0.5), -0.5, -3.0], [0.0, 0.0, 1.0]),
        ([-0.5, next_up(1.5), -3.0], [0.0, 0.0, 1.0]),
    ] {
        let ray = Ray::new(o, d).unwrap();
        let (_, n) = m.sample_range(&ray);
        let rr = RefRay::new(ray.origin().map(f64::from), ray.dir().map(f64::from));
        let want = reference::sample_positions([2, 2, 2], &rr, 1.0, 0.0).len();
        assert_eq!((n, want), (0, 0), "{o:?} {d:?}");
        assert_eq!(m.cast(&ray), bg, "{o:?} {d:?}");
    }
}

/// Point samples exactly on voxel centres, cell faces, box faces and the last plane (and one
/// ulp either side of them), every mode × filter, every small volume and content: within the
/// sample bound.
#[test]
fn samples_on_centres_faces_and_the_last_plane() {
    let mut w = Worst::new(
        "4 point samples on centres/faces/last plane ±1 ulp",
        "sample, 5 modes × 4 filters",
        "abs",
    );
    for dims in DIMS {
        for (name, case) in contents(dims) {
            let per_axis = |k: usize| {
                let n = dims[k] as f32;
                let mut v = vec![-0.5f32, -0.0, 0.0, 0.5, n - 1.0, n - 0.5, n];
                for x in v.clone() {
                    v.push(next_up(x));
                    v.push(next_down(x));
                }
                v
            };
            let (xs, ys, zs) = (per_axis(0), per_axis(1), per_axis(2));
            for (i, &x) in xs.iter().enumerate() {
                // All x, with y and z walking through their lists (not the full product).
                for j in 0..ys.len().max(zs.len()) {
                    let pos = [x, ys[(i + j) % ys.len()], zs[(2 * i + j) % zs.len()]];
                    for mode in ModeKind::ALL {
                        for filter in FilterKind::ALL {
                            let got = case.core_sample(mode, filter, pos, 1.0);
                            assert_valid(got, || format!("{name} {pos:?}"));
                            let want = case.reference_sample(mode, filter, pos, 1.0);
                            let bound = tol::sample_bound(mode, filter, &case, 1.0);
                            w.check(abs_err(got, want), bound, || {
                                format!("{name} {dims:?} {mode:?} {filter:?} {pos:?}")
                            });
                        }
                    }
                }
            }
        }
    }
    w.report();
}
