//! Float cases: every sampling mode over every filter, opacity correction, the extinction
//! step, compositing, transfer functions, ray clipping, ray casts and small renders.

use core::fmt;

use volsample::composite::{back_to_front, front_to_back, over, Order};
use volsample::filter::{bspline2_weights, trilinear_weights};
use volsample::opacity::{correct as correct_op, phi as phi_op};
use volsample::voxel::{unorm8 as unorm8_op, Voxel};
use volsample::{
    BackToFront, Camera, ExtinctionWeighted, Filter, FrontToBack, Mode, Nearest, OpacityWeighted,
    Orthographic, Perspective, PostClassified, Preweighted, Ray, RayMarcher, Sample, Separate,
    Step, Trilinear, TriquadraticBSpline, Volume,
};
use volsample::{ExtinctionF32, Interp};

use crate::{Emitter, Inputs, Lcg, DIMS};

/// Fixed sample positions (voxel units): centres, midpoints, cell interiors, the last voxel
/// plane, just inside and outside the box, then generated ones over and beyond the box.
pub fn positions() -> [[f32; 3]; 20] {
    let mut p = [[0.0f32; 3]; 20];
    let fixed: [[f32; 3]; 12] = [
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [1.25, 0.75, 0.5],
        [2.999, 1.5, 1.001],
        [3.0, 2.0, 2.0],
        [-0.7, 1.3, 0.2],
        [3.6, 2.6, 2.6],
        [1.0 / 3.0, 2.0 / 3.0, 0.1],
        [0.5, 0.5, 0.5],
        [2.5, 0.25, 1.75],
        [1e-7, 0.9999999, 1.5],
        [-0.5, -0.5, -0.5],
    ];
    let mut g = Lcg::new(0x0b05_1710);
    for (i, q) in p.iter_mut().enumerate() {
        *q = match fixed.get(i) {
            Some(f) => *f,
            None => [
                g.next_f32(-0.75, 3.75),
                g.next_f32(-0.75, 2.75),
                g.next_f32(-0.75, 2.75),
            ],
        };
    }
    p
}

/// Fixed rays: along each axis, diagonal, grazing a face, along the last voxel plane, from
/// inside, missing, and generated ones aimed through the box.
pub fn rays() -> [([f32; 3], [f32; 3]); 10] {
    let mut r = [([0.0f32; 3], [1.0f32, 0.0, 0.0]); 10];
    let fixed = [
        ([1.2, 0.7, -2.0], [0.0, 0.0, 1.0]),
        ([-2.0, 1.0, 1.0], [1.0, 0.1, 0.05]),
        ([5.0, 3.1, 2.9], [-1.0, -0.8, -0.7]),
        ([-1.0, -0.5, 1.0], [1.0, 0.0, 0.0]),
        ([3.0, -1.0, 2.0], [0.0, 1.0, 0.0]),
        ([1.5, 1.0, 1.0], [0.3, -0.2, 0.9]),
        ([10.0, 10.0, 10.0], [1.0, 0.0, 0.0]),
        ([0.4, 4.0, 0.6], [0.01, -1.0, 0.02]),
    ];
    let mut g = Lcg::new(0x0ca5_7000);
    for (i, q) in r.iter_mut().enumerate() {
        *q = match fixed.get(i) {
            Some(f) => *f,
            None => {
                let o = [g.next_f32(-3.0, 7.0), g.next_f32(-3.0, 6.0), -3.0];
                let t = [
                    g.next_f32(0.0, 3.0),
                    g.next_f32(0.0, 2.0),
                    g.next_f32(0.0, 2.0),
                ];
                (o, [t[0] - o[0], t[1] - o[1], t[2] - o[2]])
            }
        };
    }
    r
}

pub(crate) fn unorm8(e: &mut Emitter<'_>, _: &Inputs) {
    for row in 0..16u8 {
        let v: [f32; 16] = core::array::from_fn(|k| unorm8_op(row * 16 + k as u8));
        e.f32s(format_args!("unorm8"), usize::from(row), &v);
    }
}

pub(crate) fn weights(e: &mut Emitter<'_>, _: &Inputs) {
    for (i, p) in positions().iter().enumerate() {
        let f = p.map(|x| x - libm::floorf(x));
        e.f32s(format_args!("weights.trilinear"), i, &trilinear_weights(f));
        e.f32s(
            format_args!("weights.bspline2"),
            i,
            &bspline2_weights(f[0] - 0.5),
        );
    }
}

pub(crate) fn phi(e: &mut Emitter<'_>, _: &Inputs) {
    let xs = [
        0.0,
        1e-30,
        1e-7,
        5e-5,
        9.999e-5,
        1e-4,
        1.0001e-4,
        1e-3,
        0.1,
        0.5,
        1.0,
        2.0,
        10.0,
        88.0,
        100.0,
        1e30,
        f32::INFINITY,
    ];
    for (i, x) in xs.iter().enumerate() {
        e.f32s(format_args!("phi"), i, &[*x, phi_op(*x)]);
    }
}

fn alphas() -> [f32; 16] {
    [
        0.0,
        1e-40,
        1e-20,
        1e-7,
        1.0 / 255.0,
        0.01,
        0.1,
        0.25,
        0.5,
        0.75,
        0.9,
        0.99,
        0.999_999,
        1.0 - f32::EPSILON / 2.0,
        1.0,
        0.333_333_34,
    ]
}

pub(crate) fn correct(e: &mut Emitter<'_>, _: &Inputs) {
    let ratios = [1e-6, 0.125, 0.37, 0.5, 1.0, 2.0, 3.3, 1000.0];
    for (ri, r) in ratios.iter().enumerate() {
        for (i, a) in alphas().iter().enumerate() {
            let s = Sample {
                c: [*a, a * 0.5, a * 0.125],
                a: *a,
            };
            e.sample(format_args!("correct.r{ri}"), i, correct_op(s, *r));
        }
    }
}

pub(crate) fn integrate_step(e: &mut Emitter<'_>, _: &Inputs) {
    let taus = [
        0.0, 1e-30, 1e-5, 1e-3, 0.2, 0.999, 1.0, 2.5, 30.0, 64.0, 1e6, 1e18,
    ];
    let ds = [0.01, 0.5, 1.0, 3.0];
    for (di, d) in ds.iter().enumerate() {
        for (i, t) in taus.iter().enumerate() {
            let c = [*t, t * 0.5, 0.0];
            // `integrate_step` itself sits in a private module; `finish` is its public door.
            let i_ = Interp { c, a: *t };
            let s =
                <ExtinctionWeighted as Mode<ExtinctionF32>>::finish(&ExtinctionWeighted, i_, *d);
            e.sample(format_args!("integrate_step.d{di}"), i, s);
        }
    }
}

fn samples() -> [Sample; 12] {
    let mut g = Lcg::new(0xc0_0517);
    core::array::from_fn(|i| {
        let a = match i {
            0 => 0.0,
            1 => 1.0,
            2 => 1e-38,
            _ => g.next_f32(0.0, 1.0),
        };
        Sample {
            c: [a * g.next_f32(0.0, 1.0), a * g.next_f32(0.0, 1.0), a],
            a,
        }
    })
}

pub(crate) fn composite(e: &mut Emitter<'_>, _: &Inputs) {
    let s = samples();
    for (i, a) in s.iter().enumerate() {
        for (j, b) in s.iter().enumerate() {
            let k = i * s.len() + j;
            e.sample(format_args!("composite.f2b"), k, front_to_back(*a, *b));
            e.sample(format_args!("composite.b2f"), k, back_to_front(*a, *b));
            e.sample(format_args!("composite.over"), k, over(*a, *b));
        }
    }
    // A long chain: the accumulation the ray loop performs.
    let mut f = Sample::TRANSPARENT;
    let mut b = Sample::TRANSPARENT;
    for (i, x) in s.iter().cycle().take(100).enumerate() {
        let y = Sample {
            c: x.c.map(|c| c * 0.0625),
            a: x.a * 0.0625,
        };
        f = front_to_back(f, y);
        b = back_to_front(b, y);
        if i % 10 == 9 {
            e.sample(format_args!("composite.chain_f2b"), i, f);
            e.sample(format_args!("composite.chain_b2f"), i, b);
        }
    }
}

pub(crate) fn tf(e: &mut Emitter<'_>, inp: &Inputs) {
    let mut g = Lcg::new(0x7f);
    for i in 0..40usize {
        let s = match i {
            0 => -1.0,
            1 => 0.0,
            2 => 40.0,
            3 => 160.0,
            4 => 255.0,
            5 => 1e9,
            6 => f32::NAN,
            _ => g.next_f32(-10.0, 270.0),
        };
        let (c, a) = inp.tf.eval(s);
        e.f32s(format_args!("tf"), i, &[s, c[0], c[1], c[2], a]);
    }
}

pub(crate) fn clip(e: &mut Emitter<'_>, _: &Inputs) {
    for (i, (o, d)) in rays().iter().enumerate() {
        match Ray::new(*o, *d) {
            Ok(r) => {
                let [d0, d1, d2] = r.dir();
                let (t0, t1, hit) = match r.clip(DIMS) {
                    Some((a, b)) => (a, b, 1.0),
                    None => (0.0, 0.0, 0.0),
                };
                e.f32s(format_args!("clip"), i, &[d0, d1, d2, t0, t1, hit]);
            }
            Err(err) => e.error(format_args!("clip"), i, err),
        }
    }
}

/// A case label: mode, voxel format, filter.
#[derive(Clone, Copy)]
struct Lbl<'a>(&'a str, &'a str);

impl fmt::Display for Lbl<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.0, self.1)
    }
}

const STEPS: [(&str, f32, f32); 3] = [("d1", 1.0, 0.0), ("d0.37p", 0.37, 0.25), ("d2.5", 2.5, 0.0)];

fn sample_one<V: Voxel, M: Mode<V> + Copy, F: Filter>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    filter: F,
    lbl: Lbl<'_>,
    fname: &str,
) {
    for (sname, d, _) in STEPS {
        let m =
            Step::new(d).and_then(|s| RayMarcher::new(vol, mode, filter, FrontToBack::new(), s));
        match m {
            Ok(m) => {
                for (i, p) in positions().iter().enumerate() {
                    e.sample(
                        format_args!("sample.{lbl}.{fname}.{sname}"),
                        i,
                        m.sample(*p),
                    );
                }
            }
            Err(err) => e.error(format_args!("sample.{lbl}.{fname}.{sname}"), 0, err),
        }
    }
}

fn sample_mode<V: Voxel, M: Mode<V> + Copy>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    lbl: Lbl<'_>,
) {
    sample_one(e, vol, mode, Nearest, lbl, "nearest");
    sample_one(e, vol, mode, Trilinear::new(), lbl, "trilinear");
    sample_one(e, vol, mode, Trilinear::tree(), lbl, "tree");
    sample_one(e, vol, mode, TriquadraticBSpline, lbl, "bspline2");
}

/// Runs `$body` with `vol` and `mode` bound for every (mode, voxel format) pair.
macro_rules! each_mode {
    ($e:ident, $inp:ident, |$vol:ident, $mode:ident, $lbl:ident| $body:expr) => {{
        let tf_mode = PostClassified::new(&$inp.tf);
        macro_rules! go {
            ($data:expr, $m:expr, $a:literal, $b:literal) => {
                match Volume::new(&$data, DIMS) {
                    Ok($vol) => {
                        let $mode = $m;
                        let $lbl = Lbl($a, $b);
                        $body
                    }
                    Err(err) => $e.error(format_args!("volume.{}.{}", $a, $b), 0, err),
                }
            };
        }
        go!($inp.su8, Separate, "separate", "u8");
        go!($inp.sf32, Separate, "separate", "f32");
        go!($inp.su8, OpacityWeighted, "ow", "u8");
        go!($inp.sf32, OpacityWeighted, "ow", "f32");
        go!($inp.au8, Preweighted, "pre", "u8");
        go!($inp.af32, Preweighted, "pre", "f32");
        go!($inp.ext, ExtinctionWeighted, "ext", "f32");
        go!($inp.s8, tf_mode, "post", "u8");
        go!($inp.s16, tf_mode, "post", "u16");
    }};
}

pub(crate) fn sample(e: &mut Emitter<'_>, inp: &Inputs) {
    each_mode!(e, inp, |vol, mode, lbl| sample_mode(e, vol, mode, lbl));
    // The reference distance enters through the correction ratio d/d′.
    if let Ok(vol) = Volume::new(&inp.su8, DIMS).and_then(|v| v.with_reference_distance(0.5)) {
        sample_one(
            e,
            vol,
            OpacityWeighted,
            Trilinear::new(),
            Lbl("ow", "u8.dref0.5"),
            "trilinear",
        );
    }
}

fn cast_order<V: Voxel, M: Mode<V> + Copy, F: Filter, O: volsample::composite::Order>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    filter: F,
    order: O,
    name: fmt::Arguments<'_>,
) {
    for (si, (_, d, phase)) in STEPS.iter().enumerate() {
        let m = Step::new(*d)
            .and_then(|s| s.with_phase(*phase))
            .and_then(|s| RayMarcher::new(vol, mode, filter, order, s));
        let m = match m {
            Ok(m) => m,
            Err(err) => {
                e.error(format_args!("cast.{name}.s{si}"), 0, err);
                continue;
            }
        };
        for (i, (o, dir)) in rays().iter().enumerate() {
            match Ray::new(*o, *dir) {
                Ok(r) => e.sample(format_args!("cast.{name}.s{si}"), i, m.cast(&r)),
                Err(err) => e.error(format_args!("cast.{name}.s{si}"), i, err),
            }
        }
    }
}

fn cast_filter<V: Voxel, M: Mode<V> + Copy, F: Filter>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    filter: F,
    lbl: Lbl<'_>,
    fname: &str,
) {
    cast_order(
        e,
        vol,
        mode,
        filter,
        FrontToBack::new(),
        format_args!("{lbl}.{fname}.f2b"),
    );
    match FrontToBack::with_threshold(0.9) {
        Ok(o) => cast_order(
            e,
            vol,
            mode,
            filter,
            o,
            format_args!("{lbl}.{fname}.f2b0.9"),
        ),
        Err(err) => e.error(format_args!("cast.threshold"), 0, err),
    }
    cast_order(
        e,
        vol,
        mode,
        filter,
        BackToFront,
        format_args!("{lbl}.{fname}.b2f"),
    );
}

fn cast_mode<V: Voxel, M: Mode<V> + Copy>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    lbl: Lbl<'_>,
) {
    cast_filter(e, vol, mode, Trilinear::new(), lbl, "trilinear");
}

/// The other filters, for one mode: front to back and back to front. (Casting is the biggest
/// code in the image: every mode × filter × order would not fit the lm3s6965's 256 KiB flash;
/// the sample sweep covers every mode × filter.)
fn cast_filters<V: Voxel, M: Mode<V> + Copy>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    lbl: Lbl<'_>,
) {
    cast_order(
        e,
        vol,
        mode,
        Nearest,
        FrontToBack::new(),
        format_args!("{lbl}.nearest.f2b"),
    );
    cast_order(
        e,
        vol,
        mode,
        Trilinear::tree(),
        BackToFront,
        format_args!("{lbl}.tree.b2f"),
    );
    cast_order(
        e,
        vol,
        mode,
        TriquadraticBSpline,
        FrontToBack::new(),
        format_args!("{lbl}.bspline2.f2b"),
    );
    cast_order(
        e,
        vol,
        mode,
        TriquadraticBSpline,
        BackToFront,
        format_args!("{lbl}.bspline2.b2f"),
    );
}

pub(crate) fn cast(e: &mut Emitter<'_>, inp: &Inputs) {
    each_mode!(e, inp, |vol, mode, lbl| cast_mode(e, vol, mode, lbl));
    if let Ok(vol) = Volume::new(&inp.su8, DIMS) {
        cast_filters(e, vol, OpacityWeighted, Lbl("ow", "u8"));
    }
    if let Ok(vol) = Volume::new(&inp.ext, DIMS) {
        cast_filters(e, vol, ExtinctionWeighted, Lbl("ext", "f32"));
    }
    if let Ok(vol) = Volume::new(&inp.s8, DIMS) {
        let tf_mode = PostClassified::new(&inp.tf);
        cast_order(
            e,
            vol,
            tf_mode,
            TriquadraticBSpline,
            FrontToBack::new(),
            format_args!("post.u8.bspline2.f2b"),
        );
    }
    // A background behind every ray.
    let bg = Sample {
        c: [0.25, 0.0, 0.5],
        a: 0.75,
    };
    let m = Volume::new(&inp.su8, DIMS).and_then(|v| {
        Step::new(0.5).and_then(|s| {
            RayMarcher::new(v, OpacityWeighted, Trilinear::new(), FrontToBack::new(), s)
        })
    });
    match m.and_then(|m| m.with_background(bg)) {
        Ok(m) => {
            for (i, (o, dir)) in rays().iter().enumerate() {
                if let Ok(r) = Ray::new(*o, *dir) {
                    e.sample(format_args!("cast.ow.u8.background"), i, m.cast(&r));
                }
            }
        }
        Err(err) => e.error(format_args!("cast.ow.u8.background"), 0, err),
    }
}

fn render_with<V: Voxel, M: Mode<V> + Copy, F: Filter, O: Order, C: Camera>(
    e: &mut Emitter<'_>,
    m: Result<RayMarcher<'_, V, M, F, O>, volsample::Error>,
    cam: Result<C, volsample::Error>,
    w: usize,
    h: usize,
    name: &str,
) {
    let mut img = [Sample::TRANSPARENT; 20];
    let res = m.and_then(|m| {
        cam.and_then(|c| m.render_into(&c, w, h, img.get_mut(..w * h).unwrap_or(&mut [])))
    });
    match res {
        Ok(()) => {
            for (i, px) in img.iter().take(w * h).enumerate() {
                e.sample(format_args!("render.{name}"), i, *px);
            }
        }
        Err(err) => e.error(format_args!("render.{name}"), 0, err),
    }
}

pub(crate) fn render(e: &mut Emitter<'_>, inp: &Inputs) {
    let ortho = Orthographic::looking_down_z(DIMS);
    let persp = Perspective::new([6.0, 5.0, -4.0], [1.5, 1.0, 1.0], [0.0, 1.0, 0.0], 0.8);
    let ow = Volume::new(&inp.su8, DIMS).and_then(|v| {
        Step::new(0.5).and_then(|s| {
            RayMarcher::new(v, OpacityWeighted, Trilinear::new(), FrontToBack::new(), s)
        })
    });
    render_with(e, ow, ortho, 4, 3, "ow.u8.trilinear.ortho");
    let ext = Volume::new(&inp.ext, DIMS).and_then(|v| {
        Step::new(0.3).and_then(|s| {
            RayMarcher::new(v, ExtinctionWeighted, TriquadraticBSpline, BackToFront, s)
        })
    });
    render_with(e, ext, persp, 5, 4, "ext.f32.bspline2.persp");
    let ow2 = Volume::new(&inp.su8, DIMS).and_then(|v| {
        Step::new(1.0)
            .and_then(|s| RayMarcher::new(v, OpacityWeighted, Nearest, FrontToBack::new(), s))
    });
    render_with(e, ow2, ortho, 3, 3, "ow.u8.nearest.ortho3x3");
}
