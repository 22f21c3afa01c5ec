//! Generators for the papers' scenes.

use volsample::shade::Light;
use volsample::{ControlPoint, Sample, StraightF32};

use super::continuous::Continuous;
use super::{Classification, Scene, VolumeData};
use crate::float_checks::CameraSpec;

/// Opaque white material.
pub const WHITE: StraightF32 = StraightF32 {
    c: [1.0; 3],
    a: 1.0,
};
/// Transparent air with a red straight color: invisible, unless a method bleeds it.
pub const RED_AIR: StraightF32 = StraightF32 {
    c: [1.0, 0.0, 0.0],
    a: 0.0,
};
/// Transparent black air: invisible, unless a method darkens with it.
pub const BLACK_AIR: StraightF32 = StraightF32 {
    c: [0.0; 3],
    a: 0.0,
};
/// Opaque black.
pub const BLACK_BG: Sample = Sample {
    c: [0.0; 3],
    a: 1.0,
};

fn idx(n: usize, x: usize, y: usize, z: usize) -> usize {
    x + n * (y + n * z)
}

/// An orthographic camera looking at the centre of an `n³` volume along `dir`, framing it.
pub fn camera_towards(n: usize, dir: [f32; 3]) -> CameraSpec {
    let len = dir.iter().map(|d| d * d).sum::<f32>().sqrt();
    let dir = dir.map(|d| d / len);
    let c = (n as f32 - 1.0) * 0.5;
    let back = n as f32 * 2.0;
    let eye = [c - dir[0] * back, c - dir[1] * back, c - dir[2] * back];
    let up = if dir[1].abs() > 0.9 {
        [0.0, 0.0, 1.0]
    } else {
        [0.0, -1.0, 0.0]
    };
    CameraSpec::Orthographic(eye, dir, up, n as f32 * 1.15)
}

/// Lanczos-3 kernel.
fn lanczos3(x: f32) -> f32 {
    let sinc = |t: f32| {
        if t.abs() < 1e-6 {
            1.0
        } else {
            let p = std::f32::consts::PI * t;
            p.sin() / p
        }
    };
    if x.abs() >= 3.0 {
        0.0
    } else {
        sinc(x) * sinc(x / 3.0)
    }
}

/// The coverage of the half-space `x ≥ x0` at voxel centre `x`, aliased (a step) or
/// antialiased (the step filtered with a Lanczos-3 windowed sinc, clamped to `[0, 1]`).
pub fn edge_coverage(x: f32, x0: f32, antialiased: bool) -> f32 {
    if !antialiased {
        return if x >= x0 { 1.0 } else { 0.0 };
    }
    // ∫ step(x − u − x0) L(u) du by a fine midpoint rule, normalised.
    let (mut num, mut den) = (0.0f32, 0.0f32);
    let m = 120;
    for k in 0..m {
        let u = -3.0 + 6.0 * (k as f32 + 0.5) / m as f32;
        let w = lanczos3(u);
        den += w;
        if x - u >= x0 {
            num += w;
        }
    }
    (num / den).clamp(0.0, 1.0)
}

/// A scene of straight RGBA voxels defined by `field` at every point of voxel space: its
/// voxels are `field` at the voxel centres, and the field itself is the scene's continuous
/// definition ([`Continuous`]).
fn rgba_scene(
    name: &str,
    description: &str,
    n: usize,
    dir: [f32; 3],
    field: impl Fn([f32; 3]) -> StraightF32 + Send + Sync + 'static,
) -> Scene {
    let mut voxels = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                voxels.push(field([x as f32, y as f32, z as f32]));
            }
        }
    }
    Scene {
        name: name.into(),
        description: description.into(),
        dims: [n; 3],
        data: VolumeData::Rgba(voxels),
        classification: Classification::None,
        light: None,
        step: 0.5,
        phase: 0.0,
        d_ref: 1.0,
        a_stop: 1.0,
        background: BLACK_BG,
        camera: camera_towards(n, dir),
        image: [64, 64],
        continuous: Some(Continuous::rgba(move |p| {
            let v = field(p.map(|x| x as f32));
            (v.c.map(f64::from), f64::from(v.a))
        })),
    }
}

/// Wittenbrink's corner object: an opaque white cube in `air`, its corner towards the eye;
/// with `antialiased`, the face at `x = x0` is band-limited by a windowed sinc.
pub fn corner(n: usize, antialiased: bool, air: StraightF32) -> Scene {
    let (lo, hi) = (n as f32 * 0.25 + 0.3, n as f32 * 0.75 + 0.3);
    let field = move |[x, y, z]: [f32; 3]| {
        let inside_yz = y >= lo && y < hi && z >= lo && z < hi;
        let a = if inside_yz && x < hi {
            edge_coverage(x, lo, antialiased)
        } else {
            0.0
        };
        if a > 0.0 {
            StraightF32 { c: [1.0; 3], a }
        } else {
            air
        }
    };
    let aa = if antialiased { "aa" } else { "aliased" };
    rgba_scene(
        &format!("corner-{aa}-{n}"),
        &format!(
            "cube corner, {n}³, {} x-face",
            if antialiased {
                "windowed-sinc antialiased"
            } else {
                "aliased"
            }
        ),
        n,
        [-1.0, 0.8, 0.9],
        field,
    )
}

/// A slab seen at a grazing angle (rays nearly parallel to its face), aliased: the name is
/// `graze-{n}`; [`graze_aa`] is the same slab with its face antialiased.
pub fn graze(n: usize) -> Scene {
    graze_with(n, false)
}

/// [`graze`] with its principal face (`y = y0 + 0.05·x`) band-limited by a windowed sinc
/// across the face, as Wittenbrink's fig. 10 objects: `graze-aa-{n}`.
pub fn graze_aa(n: usize) -> Scene {
    graze_with(n, true)
}

fn graze_with(n: usize, antialiased: bool) -> Scene {
    let y0 = n as f32 * 0.5 + 0.25;
    let (name, description) = if antialiased {
        (
            format!("graze-aa-{n}"),
            format!("slab at a grazing angle, {n}³, windowed-sinc antialiased face"),
        )
    } else {
        (
            format!("graze-{n}"),
            format!("slab at a grazing angle, {n}³"),
        )
    };
    rgba_scene(
        &name,
        &description,
        n,
        [1.0, 0.12, 0.35],
        move |[x, y, _]| {
            // Coverage of the half-space y ≥ y0 + 0.05·x, filtered along y (the face's normal
            // to within 3°).
            let a = if antialiased {
                edge_coverage(y - 0.05 * x, y0, true)
            } else if y >= y0 + 0.05 * x {
                1.0
            } else {
                0.0
            };
            if a > 0.0 {
                StraightF32 { c: [1.0; 3], a }
            } else {
                BLACK_AIR
            }
        },
    )
}

/// A solid face slightly tilted to the view, so the ray phase at the boundary sweeps across
/// the image (Wittenbrink §4's phase experiment), aliased: `phase-{n}`; [`phase_aa`] is the
/// same face antialiased.
pub fn phase(n: usize) -> Scene {
    phase_with(n, false)
}

/// [`phase`] with its face (`z = 0.4·n + 0.07·x`) band-limited by a windowed sinc across the
/// face, as Wittenbrink's fig. 10 objects: `phase-aa-{n}`.
pub fn phase_aa(n: usize) -> Scene {
    phase_with(n, true)
}

fn phase_with(n: usize, antialiased: bool) -> Scene {
    let z0 = n as f32 * 0.4;
    let (name, description) = if antialiased {
        (
            format!("phase-aa-{n}"),
            format!("tilted semi-opaque face, {n}³ (phase sweep), windowed-sinc antialiased"),
        )
    } else {
        (
            format!("phase-{n}"),
            format!("tilted semi-opaque face, {n}³ (phase sweep)"),
        )
    };
    rgba_scene(&name, &description, n, [0.0, 0.0, 1.0], move |[x, _, z]| {
        // Coverage of the half-space z ≥ 0.4·n + 0.07·x, filtered along z.
        let cov = if antialiased {
            edge_coverage(z - 0.07 * x, z0, true)
        } else if z >= z0 + 0.07 * x {
            1.0
        } else {
            0.0
        };
        if cov > 0.0 {
            StraightF32 {
                c: [0.9, 0.9, 0.9],
                a: 0.6 * cov,
            }
        } else {
            BLACK_AIR
        }
    })
}

/// An opaque white ball in transparent air of straight color `air` (red: bleeding; black:
/// darkening).
pub fn ball_in_air(n: usize, air: StraightF32, name: &str) -> Scene {
    let c = (n as f32 - 1.0) * 0.5 + 0.27;
    let r = 0.32 * n as f32;
    rgba_scene(
        &format!("{name}-{n}"),
        &format!("white ball in transparent {name} air, {n}³"),
        n,
        [0.3, -0.4, 1.0],
        move |p| {
            let d2 = p.iter().map(|&i| (i - c).powi(2)).sum::<f32>();
            if d2 <= r * r {
                WHITE
            } else {
                air
            }
        },
    )
}

/// A one-voxel-wide opaque wall (the slab `|x − n/2| < ½`), seen obliquely, sampled at
/// `d = d′` (Kraus §3.6).
pub fn wall(n: usize, d: f32) -> Scene {
    let x0 = (n / 2) as f32;
    let mut s = rgba_scene(
        &format!("wall-{n}"),
        &format!("one-voxel opaque wall, {n}³, d = d′ = {d}"),
        n,
        [1.0, 0.3, 0.6],
        move |[x, _, _]| {
            if (x - x0).abs() < 0.5 {
                StraightF32 {
                    c: [0.2, 0.8, 1.0],
                    a: 1.0,
                }
            } else {
                BLACK_AIR
            }
        },
    );
    s.step = d;
    s.d_ref = d;
    s
}

/// Scattered single opaque voxels (about 2 %; each the unit cube around its centre), sampled
/// at `d = d′` (Kraus §3.6).
pub fn scattered(n: usize, d: f32) -> Scene {
    // A fixed xorshift so the scene is the same everywhere.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let chosen: Vec<bool> = (0..n * n * n)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % 50 == 0
        })
        .collect();
    let mut s = rgba_scene(
        &format!("scattered-{n}"),
        &format!("scattered opaque voxels, {n}³, d = d′ = {d}"),
        n,
        [0.7, 0.5, 1.0],
        move |p| {
            // The voxel whose unit cube holds `p`.
            let [x, y, z] = p.map(|c| (c + 0.5).floor());
            let inside = [x, y, z].iter().all(|&c| c >= 0.0 && c < n as f32);
            if inside && chosen[idx(n, x as usize, y as usize, z as usize)] {
                StraightF32 {
                    c: [1.0, 0.9, 0.3],
                    a: 1.0,
                }
            } else {
                BLACK_AIR
            }
        },
    );
    s.step = d;
    s.d_ref = d;
    s
}

/// The low-pass filtered 8-bit torus, classified with Levoy's isosurface classifier,
/// pre-shaded with a directional light, step 0.5 voxel (Wittenbrink figs. 11–12).
pub fn torus(n: usize) -> Scene {
    let c = (n as f32 - 1.0) * 0.5;
    let (big, small) = (0.3 * n as f32, 0.13 * n as f32);
    let mut raw = vec![0.0f32; n * n * n];
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let (px, py, pz) = (x as f32 - c, y as f32 - c, z as f32 - c);
                let ring = ((px * px + py * py).sqrt() - big).hypot(pz);
                // Signed distance to the tube, a smooth 2-voxel ramp across the surface.
                raw[idx(n, x, y, z)] = (0.5 + (small - ring) / 2.0).clamp(0.0, 1.0);
            }
        }
    }
    // Low-pass: separable [1 2 1]/4 along each axis (clamped), then 8-bit quantisation.
    for axis in 0..3 {
        let src = raw.clone();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let p = [x, y, z];
                    let at = |k: isize| {
                        let mut q = p;
                        q[axis] = (p[axis] as isize + k).clamp(0, n as isize - 1) as usize;
                        src[idx(n, q[0], q[1], q[2])]
                    };
                    raw[idx(n, x, y, z)] = 0.25 * at(-1) + 0.5 * at(0) + 0.25 * at(1);
                }
            }
        }
    }
    let scalars = raw.iter().map(|v| (v * 255.0 + 0.5).floor()).collect();
    Scene {
        name: format!("torus-{n}"),
        description: format!("low-pass 8-bit torus, {n}³, Levoy isosurface, pre-shaded, d = 0.5"),
        dims: [n; 3],
        data: VolumeData::Scalar(scalars),
        classification: Classification::Isosurface {
            f_v: 128.0,
            alpha_v: 0.8,
            r: 1.5,
            color: [1.0, 0.85, 0.6],
        },
        light: Light::new([-0.5, 0.6, 1.0], 0.25, 0.75).ok(),
        step: 0.5,
        phase: 0.0,
        d_ref: 1.0,
        a_stop: 1.0,
        background: BLACK_BG,
        camera: camera_towards(n, [0.2, -0.7, 1.0]),
        image: [64, 64],
        continuous: Some(torus_field(n)),
    }
}

/// A scalar ramp volume post-classified through a transfer function (the scene where
/// `PostClassified` runs).
pub fn tf_ramp(n: usize) -> Scene {
    let c = (n as f32 - 1.0) * 0.5;
    let mut s = vec![0.0f32; n * n * n];
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let r = ((x as f32 - c).powi(2) + (y as f32 - c).powi(2) + (z as f32 - c).powi(2))
                    .sqrt();
                s[idx(n, x, y, z)] = (255.0 * (1.0 - r / (0.55 * n as f32)))
                    .clamp(0.0, 255.0)
                    .floor();
            }
        }
    }
    let tf = vec![
        ControlPoint {
            s: 0.0,
            c: [0.0, 0.0, 0.0],
            a: 0.0,
        },
        ControlPoint {
            s: 90.0,
            c: [1.0, 0.2, 0.1],
            a: 0.0,
        },
        ControlPoint {
            s: 120.0,
            c: [1.0, 0.6, 0.2],
            a: 0.3,
        },
        ControlPoint {
            s: 180.0,
            c: [0.3, 0.6, 1.0],
            a: 0.05,
        },
        ControlPoint {
            s: 230.0,
            c: [1.0, 1.0, 1.0],
            a: 0.9,
        },
    ];
    Scene {
        name: format!("tf-shells-{n}"),
        description: format!("radial scalar field, {n}³, transfer-function shells"),
        dims: [n; 3],
        data: VolumeData::Scalar(s),
        classification: Classification::Transfer(tf),
        light: None,
        step: 0.5,
        phase: 0.0,
        d_ref: 1.0,
        a_stop: 1.0,
        background: BLACK_BG,
        camera: camera_towards(n, [0.3, 0.2, 1.0]),
        image: [64, 64],
        continuous: Some(tf_ramp_field(n)),
    }
}

/// The torus's scalar field before voxelization: the tube's smooth ramp, low-passed by the
/// same separable `[1 2 1]/4` filter one voxel apart (at any point, not only at voxel
/// centres), in 8-bit units, not quantized.
fn torus_field(n: usize) -> Continuous {
    let c = (n as f64 - 1.0) * 0.5;
    let (big, small) = (0.3 * n as f64, 0.13 * n as f64);
    let raw = move |[x, y, z]: [f64; 3]| {
        let (px, py, pz) = (x - c, y - c, z - c);
        let ring = ((px * px + py * py).sqrt() - big).hypot(pz);
        (0.5 + (small - ring) / 2.0).clamp(0.0, 1.0)
    };
    const W: [(f64, f64); 3] = [(-1.0, 0.25), (0.0, 0.5), (1.0, 0.25)];
    Continuous::scalar(move |[x, y, z]| {
        let mut s = 0.0;
        for (dz, wz) in W {
            for (dy, wy) in W {
                for (dx, wx) in W {
                    s += wx * wy * wz * raw([x + dx, y + dy, z + dz]);
                }
            }
        }
        255.0 * s
    })
}

/// The radial scalar field of [`tf_ramp`] before voxelization (not floored to integers).
fn tf_ramp_field(n: usize) -> Continuous {
    let c = (n as f64 - 1.0) * 0.5;
    Continuous::scalar(move |p| {
        let r = p.iter().map(|&x| (x - c).powi(2)).sum::<f64>().sqrt();
        (255.0 * (1.0 - r / (0.55 * n as f64))).clamp(0.0, 255.0)
    })
}

/// The scenes of the default report (32³), or of the full one (32³ and 128³, larger images).
pub fn paper_scenes(full: bool) -> Vec<Scene> {
    let mut v = Vec::new();
    let sizes: &[usize] = if full { &[32, 128] } else { &[32] };
    for &n in sizes {
        v.push(torus(n));
        v.push(corner(n, false, BLACK_AIR));
        v.push(corner(n, true, BLACK_AIR));
        v.push(graze(n));
        v.push(phase(n));
        v.push(ball_in_air(n, RED_AIR, "red"));
        v.push(ball_in_air(n, BLACK_AIR, "black"));
        v.push(wall(n, 1.0));
        v.push(scattered(n, 1.0));
        v.push(tf_ramp(n));
    }
    if full {
        for s in &mut v {
            s.image = [128, 128];
        }
    }
    v
}

/// A tiny preset for CI smoke runs: three 12³ scenes at 16×16.
pub fn tiny_scenes() -> Vec<Scene> {
    let mut v = vec![torus(12), ball_in_air(12, RED_AIR, "red"), tf_ramp(12)];
    for s in &mut v {
        s.image = [16, 16];
    }
    v
}
