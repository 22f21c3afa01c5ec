//! The integer ray marcher against a host loop doing the same steps (bit for bit), and against
//! the float marcher (within the position-quantization and rounding error).

use volsample::fixed_point::{
    front_to_back, ExtinctionFx, ExtinctionTables, IntCorrection, IntExtinction, IntFilter,
    IntMode, IntPos, IntSample, IntSampler, IntStop, ONE,
};
use volsample::render::IntRayMarcher;
use volsample::voxel::Voxel;
use volsample::{
    Camera, Error, FrontToBack, Nearest, OpacityWeighted, Orthographic, Perspective, Preweighted,
    Ray, RayMarcher, Separate, Step, StraightU8, Trilinear, Volume,
};

/// A smooth 12×10×8 RGBA volume with an opaque core, faint haze and a transparent corner.
fn voxels() -> Vec<StraightU8> {
    let (nx, ny, nz) = (12, 10, 8);
    let mut v = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let (fx, fy, fz) = (x as f32 - 5.5, y as f32 - 4.5, z as f32 - 3.5);
                let r2 = fx * fx + fy * fy + fz * fz;
                let a = (255.0 * (-r2 / 10.0).exp()) as u8;
                let a = if x + y < 3 { 0 } else { a.max(3) };
                v.push(StraightU8([
                    (20 * x) as u8,
                    (25 * y) as u8,
                    (30 * z) as u8,
                    a,
                ]));
            }
        }
    }
    v
}

const DIMS: [usize; 3] = [12, 10, 8];

/// The host loop: the documented steps, written out.
#[allow(clippy::too_many_arguments)]
fn host_cast<V: Voxel, M: IntMode<V>, Fl: IntFilter, const F: u32>(
    vol: Volume<'_, V>,
    mode: M,
    filter: Fl,
    corr: Option<&IntCorrection>,
    step: Step,
    a_stop: u16,
    bg: IntSample,
    ray: &Ray,
) -> (IntSample, u32) {
    let sampler = IntSampler::new(vol, mode, filter);
    let Some((t0, t1)) = ray.clip(DIMS) else {
        return (front_to_back(IntSample::TRANSPARENT, bg), 0);
    };
    let (d, phase) = (step.d(), step.phase());
    let k0 = (t0 / d - phase).ceil();
    let n = ((t1 / d - phase).ceil() - k0).max(0.0) as u32;
    let t_first = (k0 + phase) * d;
    let hi = DIMS.map(|n| n as f32 - 1.0);
    let mut acc = IntSample::TRANSPARENT;
    let mut used = 0;
    for j in 0..n {
        if acc.a() >= a_stop {
            break;
        }
        let p = ray.at(t_first + j as f32 * d);
        let p = [0, 1, 2].map(|k| p[k].clamp(0.0, hi[k]));
        let mut s = sampler.sample(IntPos::<F>::quantize(p).unwrap());
        if let Some(c) = corr {
            s = c.apply(s);
        }
        acc = front_to_back(acc, s);
        used += 1;
    }
    (front_to_back(acc, bg), used)
}

fn rays() -> Vec<Ray> {
    let ortho = Orthographic::looking_down_z(DIMS).unwrap();
    let persp = Perspective::new([5.5, 4.5, -20.0], [5.5, 4.5, 3.5], [0.0, 1.0, 0.0], 0.6).unwrap();
    let tilted =
        Orthographic::new([-10.0, -7.0, -9.0], [1.0, 0.8, 0.7], [0.0, 0.0, 1.0], 20.0).unwrap();
    let mut out = Vec::new();
    for j in 0..9 {
        for i in 0..11 {
            out.push(ortho.ray(i, j, 11, 9));
            out.push(persp.ray(i, j, 11, 9));
            out.push(tilted.ray(i, j, 11, 9));
        }
    }
    // Grazing and missing rays.
    out.push(Ray::new([-0.5, -0.5, -3.0], [0.0, 0.0, 1.0]).unwrap());
    out.push(Ray::new([-0.6, 3.0, -3.0], [0.0, 0.0, 1.0]).unwrap());
    out
}

fn compare<V: Voxel, M: IntMode<V>, Fl: IntFilter + Default, const F: u32>(
    data: &[V],
    mode: M,
    step: Step,
    d_ref: f32,
    stop: IntStop,
    bg: IntSample,
) -> u32 {
    let vol = Volume::new(data, DIMS)
        .unwrap()
        .with_reference_distance(d_ref)
        .unwrap();
    let m = IntRayMarcher::<V, M, Fl, F>::new(vol, mode, Fl::default(), stop, step)
        .unwrap()
        .with_background(bg);
    let ratio = step.d() / d_ref;
    assert_eq!(
        m.correction().is_some(),
        M::OPACITY_BASED && ratio != 1.0,
        "correction only for opacity-based modes with d ≠ d′"
    );
    let host_mode = mode.for_step_ratio(ratio).unwrap();
    let mut total = 0;
    for ray in rays() {
        let got = m.cast_counted(&ray);
        let want = host_cast::<V, M, Fl, F>(
            vol,
            host_mode,
            Fl::default(),
            m.correction(),
            step,
            stop.a_stop(),
            bg,
            &ray,
        );
        assert_eq!(got, want, "ray {ray:?}");
        assert_eq!(m.cast(&ray), got.0);
        total += got.1;
    }
    total
}

#[test]
fn marcher_matches_host_loop_bit_for_bit() {
    let v = voxels();
    let assoc: Vec<_> = v
        .iter()
        .map(|&s| volsample::fixed_point::premultiply_voxel(s))
        .collect();
    let ext: Vec<_> = v
        .iter()
        .map(|&s| ExtinctionFx::from_straight_u8(s))
        .collect();
    let tables = ExtinctionTables::<257>::new();
    let stop = IntStop::new(ONE - 2000).unwrap();
    let bg = IntSample::new([1000, 2000, 3000], 3000).unwrap();
    let none = IntSample::TRANSPARENT;
    let half = Step::new(0.5).unwrap().with_phase(0.25).unwrap();
    let one = Step::new(1.0).unwrap();
    let odd = Step::new(0.7).unwrap().with_phase(0.9).unwrap();
    let mut total = 0;
    total += compare::<_, _, Trilinear, 8>(&v, OpacityWeighted, one, 1.0, IntStop::NEVER, none);
    total += compare::<_, _, Trilinear, 8>(&v, OpacityWeighted, half, 1.0, stop, bg);
    total += compare::<_, _, Nearest, 4>(&v, Separate, odd, 1.0, IntStop::NEVER, bg);
    total += compare::<_, _, Trilinear, 12>(&v, Separate, half, 2.0, stop, none);
    total += compare::<_, _, Trilinear, 8>(&assoc, Preweighted, odd, 0.5, IntStop::NEVER, none);
    total += compare::<_, _, Nearest, 8>(&assoc, Preweighted, one, 1.0, stop, bg);
    let ext_mode = IntExtinction::new(&tables, 1.0).unwrap();
    total += compare::<_, _, Trilinear, 8>(&ext, ext_mode, half, 1.0, IntStop::NEVER, bg);
    total += compare::<_, _, Nearest, 12>(&ext, ext_mode, odd, 2.0, stop, none);
    total += compare::<_, _, Trilinear, 4>(&ext, ext_mode, one, 1.0, stop, none);
    assert!(total > 10_000, "{total} samples");
}

/// Against the float marcher on the same volume: within the integer kernel's rounding and
/// the position quantization at `F = 12` (the float path has its own ulp-level error).
#[test]
fn marcher_close_to_float_marcher() {
    let v = voxels();
    let vol = Volume::new(&v, DIMS).unwrap();
    for step in [
        Step::new(1.0).unwrap(),
        Step::new(0.5).unwrap().with_phase(0.3).unwrap(),
    ] {
        let fm = RayMarcher::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            FrontToBack::new(),
            step,
        )
        .unwrap();
        let im = IntRayMarcher::<_, _, _, 12>::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::NEVER,
            step,
        )
        .unwrap();
        let mut worst = 0.0f64;
        for ray in rays() {
            let (f, nf) = fm.cast_counted(&ray);
            let (i, ni) = im.cast_counted(&ray);
            // Same sample positions (the integer marcher stops only when fully opaque).
            assert!(ni <= nf, "{ni} > {nf}");
            let i = i.to_f32();
            let e =
                f.c.iter()
                    .zip(i.c.iter())
                    .map(|(a, b)| (a - b).abs())
                    .fold((f.a - i.a).abs(), f32::max);
            worst = worst.max(f64::from(e) * 65280.0);
        }
        println!(
            "d = {}: integer vs float marcher, worst {worst:.1} LSB",
            step.d()
        );
        // Position quantization at F = 12 (2^-13 voxel per axis) and at most 1 LSB per
        // sample of sampling, correction and compositing rounding over ~25 samples.
        assert!(worst < 40.0, "worst {worst} LSB");
    }
}

#[test]
fn render_into_and_errors() {
    let v = voxels();
    let vol = Volume::new(&v, DIMS).unwrap();
    let step = Step::new(0.5).unwrap();
    let m = IntRayMarcher::<_, _, _, 8>::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        IntStop::NEVER,
        step,
    )
    .unwrap();
    let cam = Orthographic::looking_down_z(DIMS).unwrap();
    let mut img = vec![IntSample::TRANSPARENT; 12 * 10];
    m.render_into(&cam, 12, 10, &mut img).unwrap();
    for j in 0..10 {
        for i in 0..12 {
            assert_eq!(img[i + 12 * j], m.cast(&cam.ray(i, j, 12, 10)));
        }
    }
    assert!(img[0].a() == 0 && img[5 + 12 * 4].a() > ONE / 2);
    assert_eq!(m.render_into(&cam, 0, 10, &mut img), Err(Error::EmptyImage));
    assert_eq!(
        m.render_into(&cam, 11, 10, &mut img),
        Err(Error::ImageSizeMismatch {
            expected: 110,
            actual: 120
        })
    );
    // Coordinates beyond u32 at F = 12 are rejected at construction.
    let wide = vec![StraightU8::default(); (1 << 20) + 1];
    let wvol = Volume::new(&wide, [(1 << 20) + 1, 1, 1]).unwrap();
    assert_eq!(
        IntRayMarcher::<_, _, _, 12>::new(wvol, Separate, Nearest, IntStop::NEVER, step)
            .unwrap_err(),
        Error::DimensionTooLarge
    );
    assert!(
        IntRayMarcher::<_, _, _, 8>::new(wvol, Separate, Nearest, IntStop::NEVER, step).is_ok()
    );
    // A NaN position reads as 0 (never panics).
    let s = m.sample([f32::NAN, 0.0, 0.0]);
    assert_eq!(s, m.sample([0.0, 0.0, 0.0]));
}
