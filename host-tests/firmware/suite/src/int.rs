//! Integer (fixed-point) cases: rounding helpers, positions, weights, every integer mode over
//! both integer filters at three position precisions, table-driven opacity correction,
//! compositing, premultiplication, integer rays, table-driven integer extinction and the
//! integer ray marcher.

use volsample::fixed_point::{
    composite_front_to_back, front_to_back, nearest_index, premultiply, premultiply_voxel,
    round_half_up_div, round_half_up_shift, saturate_u16, trilinear_weights, truncate_shift,
    unpremultiply, ExtinctionFx, ExtinctionTables, IntCorrection, IntExtinction, IntFilter,
    IntMode, IntPos, IntSample, IntSampler, IntStop, IntWeights, ONE,
};
use volsample::render::IntRayMarcher;
use volsample::voxel::Voxel;
use volsample::{
    Nearest, OpacityWeighted, Orthographic, Preweighted, Ray, Separate, Step, StraightU8,
    Trilinear, Volume,
};

use crate::float::positions;
use crate::{Emitter, Inputs, Lcg, DIMS};

fn words(s: IntSample) -> [u32; 4] {
    let [r, g, b] = s.c();
    [r, g, b, s.a()].map(u32::from)
}

fn split(x: u64) -> [u32; 2] {
    [(x >> 32) as u32, x as u32]
}

pub(crate) fn rounding(e: &mut Emitter<'_>, _: &Inputs) {
    let ns = [
        0u64,
        1,
        127,
        128,
        255,
        256,
        65_279,
        1 << 40,
        (1 << 62) + 3,
        u64::MAX,
    ];
    let ds = [1u64, 2, 3, 255, 256, 510, 1 << 36, 0];
    for (i, n) in ns.iter().enumerate() {
        let mut v = [0u32; 2 * 8];
        for (k, d) in ds.iter().enumerate() {
            let [hi, lo] = split(round_half_up_div(*n, *d));
            if let Some(s) = v.get_mut(2 * k..2 * k + 2) {
                s.copy_from_slice(&[hi, lo]);
            }
        }
        e.words(format_args!("int.rounding.div"), i, v);
        let sh = [0u32, 1, 8, 24, 36, 63, 64];
        e.words(
            format_args!("int.rounding.shift"),
            i,
            sh.iter().flat_map(|s| {
                let [a, b] = split(round_half_up_shift(*n, *s));
                let [c, d] = split(truncate_shift(*n, *s));
                [a, b, c, d]
            }),
        );
        e.words(
            format_args!("int.rounding.sat"),
            i,
            [u32::from(saturate_u16(*n))],
        );
    }
}

fn quantized<const F: u32>() -> [Option<IntPos<F>>; 20] {
    positions().map(|p| IntPos::<F>::quantize(p).ok())
}

pub(crate) fn pos(e: &mut Emitter<'_>, _: &Inputs) {
    fn one<const F: u32>(e: &mut Emitter<'_>) {
        for (i, p) in quantized::<F>().iter().enumerate() {
            match p {
                Some(p) => {
                    let [a, b, c] = p.raw();
                    let [x, y, z] = p.to_f32();
                    let n = p.raw().map(nearest_index::<F>);
                    e.words(
                        format_args!("int.pos.f{F}"),
                        i,
                        [
                            a,
                            b,
                            c,
                            x.to_bits(),
                            y.to_bits(),
                            z.to_bits(),
                            n[0],
                            n[1],
                            n[2],
                        ],
                    );
                }
                None => e.words(format_args!("int.pos.f{F}.none"), i, []),
            }
        }
    }
    one::<4>(e);
    one::<8>(e);
    one::<12>(e);
}

pub(crate) fn weights(e: &mut Emitter<'_>, _: &Inputs) {
    fn one<const F: u32>(e: &mut Emitter<'_>) {
        for (i, p) in quantized::<F>().iter().enumerate() {
            if let Some(p) = p {
                let w = trilinear_weights::<F>(p.frac());
                let t = IntWeights::trilinear(*p);
                e.words(
                    format_args!("int.weights.f{F}"),
                    i,
                    w.iter()
                        .chain(t.weights().iter())
                        .flat_map(|x| split(*x))
                        .chain([t.shift()]),
                );
            }
        }
    }
    one::<4>(e);
    one::<8>(e);
    one::<12>(e);
}

fn sample_filter<V: Voxel, M: IntMode<V>, Fl: IntFilter, const F: u32>(
    e: &mut Emitter<'_>,
    s: &IntSampler<'_, V, M, Fl>,
    name: &str,
) {
    for (i, p) in quantized::<F>().iter().enumerate() {
        if let Some(p) = p {
            let x = s.sample(*p);
            let b = x.to_u8();
            let f = x.to_f32();
            e.words(
                format_args!("int.sample.{name}.f{F}"),
                i,
                words(x)
                    .into_iter()
                    .chain(b.map(u32::from))
                    .chain(f.c.map(f32::to_bits))
                    .chain([f.a.to_bits()]),
            );
        }
    }
    // Generated raw positions, including far outside the volume (clamped to the edge).
    let mut g = Lcg::new(0x1e7 + F);
    for i in 0..16usize {
        let raw = [
            g.next_u32() >> (28 - F),
            g.next_u32() >> (28 - F),
            g.next_u32() >> (25 - F),
        ];
        let raw = if i == 0 { [u32::MAX; 3] } else { raw };
        e.words(
            format_args!("int.sample.{name}.f{F}.raw"),
            i,
            words(s.sample(IntPos::<F>::from_raw(raw))),
        );
    }
}

fn sample_mode<V: Voxel, M: IntMode<V>>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    name: &str,
) {
    let n = IntSampler::new(vol, mode, Nearest);
    let t = IntSampler::new(vol, mode, Trilinear::new());
    sample_filter::<_, _, _, 4>(e, &n, name);
    sample_filter::<_, _, _, 8>(e, &n, name);
    sample_filter::<_, _, _, 12>(e, &n, name);
    sample_filter::<_, _, _, 4>(e, &t, name);
    sample_filter::<_, _, _, 8>(e, &t, name);
    sample_filter::<_, _, _, 12>(e, &t, name);
}

pub(crate) fn sample(e: &mut Emitter<'_>, inp: &Inputs) {
    match Volume::new(&inp.su8, DIMS) {
        Ok(v) => {
            sample_mode(e, v, OpacityWeighted, "ow.u8");
            sample_mode(e, v, Separate, "separate.u8");
        }
        Err(err) => e.error(format_args!("int.sample.volume.su8"), 0, err),
    }
    match Volume::new(&inp.au8, DIMS) {
        Ok(v) => sample_mode(e, v, Preweighted, "pre.u8"),
        Err(err) => e.error(format_args!("int.sample.volume.au8"), 0, err),
    }
}

/// Valid U8.8 samples: the corners of the domain and generated ones.
fn int_samples() -> [IntSample; 24] {
    let mut g = Lcg::new(0x5a_3b1e);
    core::array::from_fn(|i| {
        let a = match i {
            0 => 0,
            1 => ONE,
            2 => 1,
            3 => 256,
            4 => ONE - 1,
            _ => (g.next_u32() % (u32::from(ONE) + 1)) as u16,
        };
        let c = |g: &mut Lcg| (g.next_u32() % (u32::from(a) + 1)) as u16;
        let (r, gr, b) = (c(&mut g), c(&mut g), c(&mut g));
        IntSample::new([r, gr, b], a).unwrap_or(IntSample::TRANSPARENT)
    })
}

pub(crate) fn correction(e: &mut Emitter<'_>, _: &Inputs) {
    for (ri, r) in [0.125f32, 0.37, 0.5, 1.0, 2.0, 4.0].iter().enumerate() {
        match IntCorrection::new(*r) {
            Ok(c) => {
                for (row, chunk) in c.table().chunks(16).enumerate() {
                    e.words(
                        format_args!("int.correction.r{ri}.table"),
                        row,
                        chunk.iter().map(|x| u32::from(*x)),
                    );
                }
                for (i, s) in int_samples().iter().enumerate() {
                    e.words(
                        format_args!("int.correction.r{ri}.apply"),
                        i,
                        words(c.apply(*s)),
                    );
                }
                e.digest(
                    format_args!("int.correction.r{ri}.every_alpha"),
                    (0..=ONE).flat_map(|a| {
                        let s = IntSample::new([a, a / 2, 0], a).unwrap_or(IntSample::TRANSPARENT);
                        words(c.apply(s))
                    }),
                );
            }
            Err(err) => e.error(format_args!("int.correction.r{ri}"), 0, err),
        }
    }
}

pub(crate) fn composite(e: &mut Emitter<'_>, _: &Inputs) {
    let s = int_samples();
    e.digest(
        format_args!("int.composite.f2b_pairs"),
        s.iter()
            .flat_map(|a| s.iter().flat_map(move |b| words(front_to_back(*a, *b)))),
    );
    for (i, a) in s.iter().take(8).enumerate() {
        for (j, b) in s.iter().take(8).enumerate() {
            e.words(
                format_args!("int.composite.f2b"),
                i * 8 + j,
                words(front_to_back(*a, *b)),
            );
        }
    }
    let stops = [
        IntStop::NEVER,
        IntStop::new(60_000).unwrap_or(IntStop::NEVER),
        IntStop::new(1).unwrap_or(IntStop::NEVER),
    ];
    for (k, stop) in stops.iter().enumerate() {
        let (acc, used) = composite_front_to_back(s.iter().copied().cycle().take(60), *stop);
        e.words(
            format_args!("int.composite.chain"),
            k,
            words(acc).into_iter().chain([used as u32]),
        );
    }
}

pub(crate) fn premul(e: &mut Emitter<'_>, inp: &Inputs) {
    e.digest(
        format_args!("int.premul.premultiply"),
        (0..=255u8).flat_map(|c| (0..=255u8).map(move |a| u32::from(premultiply(c, a)))),
    );
    e.digest(
        format_args!("int.premul.unpremultiply"),
        (0..=255u8).flat_map(|c| (0..=255u8).map(move |a| u32::from(unpremultiply(c, a)))),
    );
    for (i, v) in inp.su8.iter().enumerate() {
        e.words(
            format_args!("int.premul.voxel"),
            i,
            premultiply_voxel(*v).0.map(u32::from),
        );
    }
}

/// An integer ray: `n` samples at `start + k·step` (raw, `F` fractional bits), each optionally
/// opacity-corrected, composited front to back.
fn int_ray<M: IntMode<StraightU8>, Fl: IntFilter, const F: u32>(
    s: &IntSampler<'_, StraightU8, M, Fl>,
    corr: Option<&IntCorrection>,
    start: [u32; 3],
    step: [i32; 3],
    n: u32,
    stop: IntStop,
) -> (IntSample, usize) {
    let samples = (0..n).map(|k| {
        let raw: [u32; 3] = core::array::from_fn(|a| {
            let st = step.get(a).copied().unwrap_or(0);
            let s0 = start.get(a).copied().unwrap_or(0);
            s0.wrapping_add_signed(st.wrapping_mul(k as i32))
        });
        let x = s.sample(IntPos::<F>::from_raw(raw));
        match corr {
            Some(c) => c.apply(x),
            None => x,
        }
    });
    composite_front_to_back(samples, stop)
}

pub(crate) fn ray(e: &mut Emitter<'_>, inp: &Inputs) {
    let Ok(vol) = Volume::new(&inp.su8, DIMS) else {
        return;
    };
    let ow = IntSampler::new(vol, OpacityWeighted, Trilinear::new());
    let sep = IntSampler::new(vol, Separate, Trilinear::new());
    let near = IntSampler::new(vol, OpacityWeighted, Nearest);
    let half = IntCorrection::new(0.5).ok();
    let rays: [([u32; 3], [i32; 3]); 5] = [
        ([300, 180, 0], [0, 0, 128]),
        ([0, 256, 256], [96, 3, 1]),
        ([767, 511, 511], [-64, -40, -35]),
        ([768, 0, 512], [0, 64, 0]),
        ([10, 20, 30], [77, 51, 33]),
    ];
    let stop = IntStop::new(62_000).unwrap_or(IntStop::NEVER);
    for (i, (o, d)) in rays.iter().enumerate() {
        let out = [
            int_ray::<_, _, 8>(&ow, None, *o, *d, 12, IntStop::NEVER),
            int_ray::<_, _, 8>(&ow, half.as_ref(), *o, *d, 24, IntStop::NEVER),
            int_ray::<_, _, 8>(&ow, None, *o, *d, 12, stop),
            int_ray::<_, _, 8>(&sep, None, *o, *d, 12, IntStop::NEVER),
            int_ray::<_, _, 8>(&near, None, *o, *d, 12, IntStop::NEVER),
        ];
        for (k, (acc, used)) in out.iter().enumerate() {
            e.words(
                format_args!("int.ray.v{k}"),
                i,
                words(*acc).into_iter().chain([*used as u32]),
            );
        }
    }
}

/// Table-driven integer extinction (`IntExtinction` over `ExtinctionFx` voxels) at two table
/// sizes and three step ratios, both integer filters.
pub(crate) fn extinction(e: &mut Emitter<'_>, inp: &Inputs) {
    fn tables<const N: usize>(e: &mut Emitter<'_>, inp: &Inputs, name: &str) {
        let t = ExtinctionTables::<N>::new();
        e.digest(
            format_args!("int.extinction.{name}.tables"),
            t.phi()
                .iter()
                .chain(t.exp().iter())
                .chain(t.exp_int().iter())
                .copied(),
        );
        let fx = inp.su8.map(ExtinctionFx::from_straight_u8);
        let Ok(vol) = Volume::new(&fx, DIMS) else {
            e.words(format_args!("int.extinction.{name}.volume_rejected"), 0, []);
            return;
        };
        for (ri, r) in [0.5f32, 1.0, 2.0].iter().enumerate() {
            match IntExtinction::new(&t, *r) {
                Ok(m) => {
                    let near = IntSampler::new(vol, m, Nearest);
                    let tri = IntSampler::new(vol, m, Trilinear::new());
                    for (i, p) in quantized::<8>().iter().enumerate() {
                        if let Some(p) = p {
                            let v = words(near.sample(*p))
                                .into_iter()
                                .chain(words(tri.sample(*p)));
                            e.words(format_args!("int.extinction.{name}.r{ri}"), i, v);
                        }
                    }
                }
                Err(err) => e.error(format_args!("int.extinction.{name}.r{ri}"), 0, err),
            }
        }
    }
    for (i, v) in inp.su8.iter().enumerate() {
        let x = ExtinctionFx::from_straight_u8(*v);
        let y = ExtinctionFx::from_straight_f32(inp.sf32.get(i).copied().unwrap_or_default());
        e.words(
            format_args!("int.extinction.voxel"),
            i,
            [
                x.tau, x.c_tau[0], x.c_tau[1], x.c_tau[2], y.tau, y.c_tau[0], y.c_tau[1],
                y.c_tau[2],
            ],
        );
    }
    tables::<17>(e, inp, "n17");
    tables::<257>(e, inp, "n257");
}

fn march<V: Voxel, M: IntMode<V>, Fl: IntFilter>(
    e: &mut Emitter<'_>,
    vol: Volume<'_, V>,
    mode: M,
    fl: Fl,
    name: &str,
) {
    let steps = [(1.0f32, 0.0f32), (0.5, 0.25), (2.5, 0.0)];
    let stops = [
        IntStop::NEVER,
        IntStop::new(60_000).unwrap_or(IntStop::NEVER),
    ];
    for (si, (d, ph)) in steps.iter().enumerate() {
        for (ti, stop) in stops.iter().enumerate() {
            let m = Step::new(*d)
                .and_then(|s| s.with_phase(*ph))
                .and_then(|s| IntRayMarcher::<_, _, _, 8>::new(vol, mode, fl, *stop, s));
            let m = match m {
                Ok(m) => m,
                Err(err) => {
                    e.error(format_args!("int.march.{name}.s{si}.t{ti}"), 0, err);
                    continue;
                }
            };
            for (i, (o, dir)) in crate::float::rays().iter().enumerate() {
                if let Ok(r) = Ray::new(*o, *dir) {
                    let (acc, n) = m.cast_counted(&r);
                    e.words(
                        format_args!("int.march.{name}.s{si}.t{ti}"),
                        i,
                        words(acc).into_iter().chain([n]),
                    );
                }
            }
        }
    }
}

/// The integer ray marcher (float rays, quantized sample positions, integer everything else)
/// over every integer mode, plus an orthographic render.
pub(crate) fn marcher(e: &mut Emitter<'_>, inp: &Inputs) {
    let t = ExtinctionTables::<257>::new();
    let fx = inp.su8.map(ExtinctionFx::from_straight_u8);
    if let Ok(vol) = Volume::new(&inp.su8, DIMS) {
        march(e, vol, OpacityWeighted, Trilinear::new(), "ow.u8.trilinear");
        march(e, vol, OpacityWeighted, Nearest, "ow.u8.nearest");
        march(e, vol, Separate, Trilinear::new(), "separate.u8.trilinear");
        let mut img = [IntSample::TRANSPARENT; 12];
        let r = Step::new(0.5)
            .and_then(|s| {
                IntRayMarcher::<_, _, _, 8>::new(
                    vol,
                    OpacityWeighted,
                    Trilinear::new(),
                    IntStop::NEVER,
                    s,
                )
            })
            .and_then(|m| {
                Orthographic::looking_down_z(DIMS).and_then(|c| m.render_into(&c, 4, 3, &mut img))
            });
        match r {
            Ok(()) => e.digest(
                format_args!("int.march.render.ortho"),
                img.iter().flat_map(|s| words(*s)),
            ),
            Err(err) => e.error(format_args!("int.march.render.ortho"), 0, err),
        }
    }
    if let Ok(vol) = Volume::new(&inp.au8, DIMS) {
        march(e, vol, Preweighted, Trilinear::new(), "pre.u8.trilinear");
    }
    if let (Ok(vol), Ok(m)) = (Volume::new(&fx, DIMS), IntExtinction::new(&t, 1.0)) {
        march(e, vol, m, Trilinear::new(), "ext.n257.trilinear");
    }
}
