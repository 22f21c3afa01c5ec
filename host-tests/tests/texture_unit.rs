//! The emulated GPU texture unit (`texture_unit`): its weights are the fractional coordinates
//! rounded to 8 bits, its fetch is the trilinear sum of those weights (checked against an
//! independent f64 sum), and its shader is the core marcher's ray marching with only the
//! filter's weights changed.

use volsample::{
    AssociatedU8, Camera, FrontToBack, Orthographic, Preweighted, RayMarcher, Sample, Separate,
    Step, StraightU8, Trilinear, Volume,
};
use volsample_host::texture_unit::{fetch, quantize_fraction, Shader, Texels, WEIGHT_BITS};

/// Rounding to 8 fractional bits moves a fraction by at most half a step.
const QUANTIZE_BOUND: f64 = 0.5 / 256.0;

/// The fetch against the f64 sum: eight f32 products below 1 and their f32 sum.
const FETCH_ABS: f64 = 1e-6;

/// The unquantized shader against the core marcher on the same rays: the two trilinear sums
/// differ only in `f32` summation order, carried through correction and compositing.
const SHADER_VS_CORE_ABS: f32 = 2e-5;

/// A small deterministic generator (xorshift64*), so the cases are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn byte(&mut self) -> u8 {
        (self.next() >> 56) as u8
    }
}

#[test]
fn fractions_round_half_up_to_eight_bits() {
    let step = 1.0 / f64::from(1u32 << WEIGHT_BITS);
    for k in 0..=100_000u32 {
        let f = k as f32 / 100_000.0;
        let q = f64::from(quantize_fraction(f));
        assert!((q - f64::from(f)).abs() <= QUANTIZE_BOUND, "{f} -> {q}");
        assert_eq!(
            (q / step).fract(),
            0.0,
            "{f} -> {q} is not a multiple of 1/256"
        );
        // Round half up: the nearest multiple, ties upwards.
        let want = (f64::from(f) * 256.0 + 0.5).floor() / 256.0;
        assert_eq!(q, want, "{f}");
    }
    for k in 0..=256u32 {
        let f = k as f32 / 256.0;
        assert_eq!(quantize_fraction(f), f, "multiples of 1/256 are kept");
    }
}

fn texels(rng: &mut Rng, n: usize) -> Vec<StraightU8> {
    (0..n * n * n)
        .map(|_| StraightU8([rng.byte(), rng.byte(), rng.byte(), rng.byte()]))
        .collect()
}

/// The trilinear sum in f64 of the bytes, with the fractions given.
fn sum_f64(v: &[StraightU8], n: usize, lo: [usize; 3], f: [f64; 3]) -> [f64; 4] {
    let mut out = [0.0; 4];
    for dz in 0..2 {
        for dy in 0..2 {
            for dx in 0..2 {
                let at = |c: usize, d: usize| (c + d).min(n - 1);
                let idx = at(lo[0], dx) + n * (at(lo[1], dy) + n * at(lo[2], dz));
                let w = [(dx, f[0]), (dy, f[1]), (dz, f[2])]
                    .iter()
                    .map(|&(d, f)| if d == 1 { f } else { 1.0 - f })
                    .product::<f64>();
                for (o, b) in out.iter_mut().zip(v[idx].0) {
                    *o += w * f64::from(b) / 255.0;
                }
            }
        }
    }
    out
}

#[test]
fn the_fetch_is_the_trilinear_sum_of_the_rounded_weights() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let n = 5;
    let v = texels(&mut rng, n);
    let vol = Volume::new(&v, [n; 3]).unwrap();
    let mut moved = 0;
    for _ in 0..20_000 {
        let p: [f32; 3] = core::array::from_fn(|_| rng.unit() * (n - 1) as f32);
        let lo = p.map(|c| c.floor() as usize);
        let exact: [f64; 3] = core::array::from_fn(|k| f64::from(p[k]) - lo[k] as f64);
        let rounded = exact.map(|f| (f * 256.0 + 0.5).floor() / 256.0);
        for (quantize, f) in [(true, rounded), (false, exact)] {
            let got = fetch(&vol, p, quantize);
            let want = sum_f64(&v, n, lo, f);
            for k in 0..4 {
                assert!(
                    (f64::from(got[k]) - want[k]).abs() <= FETCH_ABS,
                    "{p:?} quantize {quantize}: {got:?} against {want:?}"
                );
            }
        }
        let (q, e) = (fetch(&vol, p, true), fetch(&vol, p, false));
        if q != e {
            moved += 1;
        }
    }
    // The rounding does change values (so the rows differ from the f32 filter's).
    assert!(moved > 10_000, "only {moved} of 20000 fetches moved");
}

fn shader_against_core<V, M>(data: &[V], n: usize, mode: M, texels: Texels)
where
    V: volsample::voxel::Voxel + volsample_host::texture_unit::Bytes,
    M: volsample::Mode<V>,
{
    let vol = Volume::new(data, [n; 3])
        .unwrap()
        .with_reference_distance(1.0)
        .unwrap();
    let step = Step::new(0.4).unwrap();
    let bg = Sample::clamped([0.1, 0.0, 0.2], 1.0);
    let order = FrontToBack::with_threshold(0.95).unwrap();
    let m = RayMarcher::new(vol, mode, Trilinear::new(), order, step)
        .unwrap()
        .with_background(bg)
        .unwrap();
    assert!(m.correction().is_some(), "d = 0.4, d' = 1: corrected");
    let mut shader = Shader {
        volume: vol,
        texels,
        d: step.d(),
        ratio: m.correction().map(|c| c.ratio()),
        a_stop: 0.95,
        background: bg,
        quantize: false,
    };
    let c = (n - 1) as f32 / 2.0;
    let cam = Orthographic::new([c, c, -3.0], [0.2, 0.1, 1.0], [0.0, 1.0, 0.0], n as f32).unwrap();
    let (w, h) = (16, 16);
    let mut differs = 0;
    for j in 0..h {
        for i in 0..w {
            let ray = cam.ray(i, j, w, h);
            let (want, wn) = m.cast_counted(&ray);
            shader.quantize = false;
            let (got, gn) = shader.cast(&ray, m.sample_range(&ray));
            assert!(
                (got.a - want.a).abs() <= SHADER_VS_CORE_ABS
                    && (0..3).all(|k| (got.c[k] - want.c[k]).abs() <= SHADER_VS_CORE_ABS),
                "{texels:?} pixel ({i}, {j}): shader {got:?}, core {want:?}"
            );
            // The same samples, or one fewer or more where the sums straddle A_stop.
            assert!(gn.abs_diff(wn) <= 1, "{gn} against {wn} samples");
            shader.quantize = true;
            if shader.cast(&ray, m.sample_range(&ray)).0 != got {
                differs += 1;
            }
        }
    }
    assert!(differs > 0, "{texels:?}: 8-bit weights changed no pixel");
}

#[test]
fn the_shader_is_the_core_marcher_but_for_the_weights() {
    let mut rng = Rng(7);
    let n = 6;
    let straight = texels(&mut rng, n);
    shader_against_core(&straight, n, Separate, Texels::Straight);
    let premultiplied: Vec<AssociatedU8> = straight
        .iter()
        .map(|v| {
            let a = v.0[3];
            AssociatedU8([v.0[0].min(a), v.0[1].min(a), v.0[2].min(a), a])
        })
        .collect();
    shader_against_core(&premultiplied, n, Preweighted, Texels::Premultiplied);
}
