//! `int_marcher`: the integer ray marcher against the bit-exact integer model (built with the
//! feature `marcher-checks`: its two dozen marcher instances are most of an instrumented
//! build's time).

use arbitrary::Arbitrary;
use std::sync::OnceLock;
use volsample::fixed_point::{
    ExtinctionFx, ExtinctionTables, IntExtinction, IntFilter, IntMode, IntPos, IntSample, IntStop,
    ONE,
};
use volsample::render::{IntRayMarcher, MAX_SAMPLES_PER_RAY};
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, Nearest, OpacityWeighted, Preweighted, Ray, Separate, Step, StraightU8,
    Trilinear, Volume,
};

use super::{filled, raw};
use crate::int_model::{
    self, composite as cm, correction as corr_model, extinction as em, sample as sm,
};

/// The integer mode of the `int_marcher` check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub enum MarchMode {
    /// `OpacityWeighted` on the straight bytes.
    #[default]
    OpacityWeighted,
    /// `Separate` on the straight bytes.
    Separate,
    /// `Preweighted` on the bytes read as associated, `C̃` clamped to `α` (`Volume::new`
    /// refuses others).
    Preweighted,
    /// `IntExtinction` (65-entry tables) on the bytes converted with
    /// `ExtinctionFx::from_straight_u8`.
    Extinction,
}

/// A ray: origin `o/64` and direction `d/256` per axis, or the raw `f32` bits of origin and
/// direction (a ray `Ray::new` refuses is left out).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Arbitrary)]
pub struct RayInput {
    /// Origin in 1/64 voxel.
    pub origin: [i16; 3],
    /// Direction in 1/256 (normalised by `Ray::new`).
    pub dir: [i16; 3],
    /// Origin and direction as `f32` bits instead.
    pub bits: Option<[u32; 6]>,
}

impl RayInput {
    /// The ray, if `Ray::new` accepts it.
    pub fn ray(&self) -> Option<Ray> {
        let (o, d) = match self.bits {
            Some(b) => (
                [b[0], b[1], b[2]].map(f32::from_bits),
                [b[3], b[4], b[5]].map(f32::from_bits),
            ),
            None => (
                self.origin.map(|x| f32::from(x) / 64.0),
                self.dir.map(|x| f32::from(x) / 256.0),
            ),
        };
        Ray::new(o, d).ok()
    }
}

/// Input of the `int_marcher` check.
#[derive(Debug, Clone, PartialEq, Eq, Default, Arbitrary)]
pub struct MarcherInput {
    /// Dimensions, each `1 + x mod 8`.
    pub dims: [u8; 3],
    /// The mode.
    pub mode: MarchMode,
    /// Trilinear (`true`) or nearest.
    pub trilinear: bool,
    /// `F = [4, 8, 12][sel mod 3]`.
    pub frac_sel: u8,
    /// Step `d = (1 + x)/32` voxel.
    pub step: u8,
    /// Phase `x/256`.
    pub phase: u8,
    /// Reference distance: `d′ = d` (no correction) when `x mod 4 = 0`, else
    /// `(1 + (x/4) mod 64)/16`.
    pub d_ref: u8,
    /// Stop threshold: `IntStop::NEVER` for 0, else `1 + (x − 1) mod ONE`.
    pub a_stop: u16,
    /// Background `[r, g, b, a]`, reduced (`α mod (ONE + 1)`, each `C̃ mod (α + 1)`).
    pub background: [u16; 4],
    /// Voxel bytes; past them the volume is filled with a fixed pattern (`kernel_checks::fill`).
    pub voxels: Vec<[u8; 4]>,
    /// The rays (at most 16).
    pub rays: Vec<RayInput>,
}

/// The decoded, valid configuration of a [`MarcherInput`].
#[derive(Debug, Clone)]
struct MarchCfg {
    dims: [usize; 3],
    bytes: Vec<[u8; 4]>,
    frac_bits: u32,
    step: Step,
    d_ref: f32,
    stop: IntStop,
    background: IntSample,
}

/// Most samples a ray may take for the check to model it (longer rays, from far-away raw
/// origins, are cast but not compared: the model would take too long).
const MODELLED_SAMPLES: u32 = 4096;

/// Extinction tables of the `int_marcher` check.
const MARCH_TABLE: usize = 65;

fn march_tables() -> &'static ExtinctionTables<MARCH_TABLE> {
    static T: OnceLock<ExtinctionTables<MARCH_TABLE>> = OnceLock::new();
    T.get_or_init(ExtinctionTables::new)
}

fn march_model_tables() -> &'static em::Tables {
    static T: OnceLock<em::Tables> = OnceLock::new();
    T.get_or_init(|| em::tables(MARCH_TABLE))
}

impl MarcherInput {
    fn cfg(&self) -> Result<MarchCfg, String> {
        let dims = self.dims.map(|x| 1 + usize::from(x % 8));
        let d = (1.0 + f32::from(self.step)) / 32.0;
        let step = Step::new(d)
            .and_then(|s| s.with_phase(f32::from(self.phase) / 256.0))
            .map_err(|e| format!("step {d}: {e}"))?;
        let d_ref = if self.d_ref % 4 == 0 {
            d
        } else {
            (1.0 + f32::from((self.d_ref / 4) % 64)) / 16.0
        };
        let stop = if self.a_stop == 0 {
            IntStop::NEVER
        } else {
            IntStop::new(1 + (self.a_stop - 1) % ONE).map_err(|e| e.to_string())?
        };
        let [r, g, b, a] = self.background;
        let a = a % (ONE + 1);
        let background = IntSample::new([r, g, b].map(|c| c % (a + 1)), a)
            .map_err(|e| format!("background reduced out of range: {e}"))?;
        Ok(MarchCfg {
            dims,
            bytes: filled(&self.voxels, dims[0] * dims[1] * dims[2]),
            frac_bits: [4, 8, 12][usize::from(self.frac_sel % 3)],
            step,
            d_ref,
            stop,
            background,
        })
    }
}

/// The model of one ray: its quantized positions (raw, `F` bits), the composite over the
/// background and the number of samples composited.
#[derive(Debug, Clone, PartialEq)]
struct ModelRay {
    positions: Vec<[u32; 3]>,
    result: cm::Raw,
    used: u32,
}

/// The model's quantization of a float position: clamped into `[0, n − 1]` (NaN as 0), then
/// `⌊x·2^F + ½⌋` (**round half up**) in `f64`.
fn model_quantize(p: [f32; 3], dims: [usize; 3], frac_bits: u32) -> [u32; 3] {
    std::array::from_fn(|k| {
        let hi = (dims[k] - 1) as f32;
        let x = if p[k] >= 0.0 { p[k].min(hi) } else { 0.0 };
        (f64::from(x) * f64::from(1u32 << frac_bits) + 0.5).floor() as u32
    })
}

/// The taps (linear voxel indices), real weights and integer weights with their shift, of a
/// raw position: nearest `⌊raw/2^F + ½⌋`, trilinear the cell at `⌊raw/2^F⌋`, both clamped
/// to the edge.
fn model_taps(
    pos: [u32; 3],
    dims: [usize; 3],
    frac_bits: u32,
    trilinear: bool,
) -> (Vec<usize>, Vec<f64>, Vec<u128>, u32) {
    let lin = |c: [usize; 3]| c[0] + dims[0] * (c[1] + dims[1] * c[2]);
    if trilinear {
        let mask = (1u32 << frac_bits) - 1;
        let base = pos.map(|r| (r >> frac_bits) as usize);
        let frac = pos.map(|r| r & mask);
        let idx = (0..8)
            .map(|i| {
                let o = [i & 1, (i >> 1) & 1, i >> 2];
                lin(std::array::from_fn(|k| (base[k] + o[k]).min(dims[k] - 1)))
            })
            .collect();
        (
            idx,
            int_model::trilinear_weights(frac_bits, frac).to_vec(),
            em::int_weights(frac_bits, frac).to_vec(),
            3 * frac_bits,
        )
    } else {
        let half = 1u64 << (frac_bits - 1);
        let c = std::array::from_fn(|k| {
            (((u64::from(pos[k]) + half) >> frac_bits) as usize).min(dims[k] - 1)
        });
        (vec![lin(c)], vec![1.0], vec![1], 0)
    }
}

/// The model's sample (before correction) at a raw position.
fn model_sample(
    mode: MarchMode,
    cfg: &MarchCfg,
    trilinear: bool,
    ratio: f32,
    pos: [u32; 3],
) -> ([u16; 3], u16) {
    let (idx, w, wi, shift) = model_taps(pos, cfg.dims, cfg.frac_bits, trilinear);
    let bytes: Vec<[u8; 4]> = idx.iter().map(|&i| cfg.bytes[i]).collect();
    let m = match mode {
        MarchMode::OpacityWeighted => sm::opacity_weighted(&bytes, &w),
        MarchMode::Separate => sm::separate(&bytes, &w),
        MarchMode::Preweighted => sm::preweighted(&bytes, &w),
        MarchMode::Extinction => {
            let taps: Vec<(u32, [u32; 3])> = bytes.iter().map(|&v| em::from_u8(v)).collect();
            return em::kernel(
                &taps,
                &wi,
                shift,
                em::ratio_raw(ratio),
                march_model_tables(),
            );
        }
    };
    (m.c, m.a)
}

/// The model of one ray, `None` when it takes more than [`MODELLED_SAMPLES`].
fn model_ray(
    mode: MarchMode,
    trilinear: bool,
    cfg: &MarchCfg,
    correction: Option<&corr_model::CorrTables>,
    ray: &Ray,
) -> Option<ModelRay> {
    let bg = raw(&cfg.background);
    let Some((t0, t1)) = ray.clip(cfg.dims) else {
        let (result, _) = cm::front_to_back(&[[0; 4], bg], u16::MAX);
        return Some(ModelRay {
            positions: Vec::new(),
            result,
            used: 0,
        });
    };
    let (d, phase) = (cfg.step.d(), cfg.step.phase());
    let k0 = (t0 / d - phase).ceil();
    let k1 = (t1 / d - phase).ceil();
    let n = (k1 - k0).clamp(0.0, MAX_SAMPLES_PER_RAY as f32) as u32;
    if n > MODELLED_SAMPLES {
        return None;
    }
    let t_first = (k0 + phase) * d;
    let ratio = d / cfg.d_ref;
    let positions: Vec<[u32; 3]> = (0..n)
        .map(|j| model_quantize(ray.at(t_first + j as f32 * d), cfg.dims, cfg.frac_bits))
        .collect();
    let samples: Vec<cm::Raw> = positions
        .iter()
        .map(|&p| {
            let (c, a) = model_sample(mode, cfg, trilinear, ratio, p);
            let (c, a) = match correction {
                Some(t) => t.apply(c, a),
                None => (c, a),
            };
            [c[0], c[1], c[2], a]
        })
        .collect();
    let (acc, used) = cm::front_to_back(&samples, cfg.stop.a_stop());
    let (result, _) = cm::front_to_back(&[acc, bg], u16::MAX);
    Some(ModelRay {
        positions,
        result,
        used: used as u32,
    })
}

/// The kernel's results for every ray against the model's: `cast_counted` (result and
/// count), `march_positions` on the model's positions, `cast_rays` on all rays, `C̃ ≤ α`.
/// Returns the number of samples compared.
fn compare_marcher<V: Voxel, M: IntMode<V>, Fl: IntFilter + Default, const F: u32>(
    data: &[V],
    mode: M,
    cfg: &MarchCfg,
    rays: &[Ray],
    want: &[Option<ModelRay>],
) -> Result<u64, String> {
    let vol = Volume::new(data, cfg.dims)
        .and_then(|v| v.with_reference_distance(cfg.d_ref))
        .map_err(|e| format!("volume: {e}"))?;
    let m = IntRayMarcher::<V, M, Fl, F>::new(vol, mode, Fl::default(), cfg.stop, cfg.step)
        .map_err(|e| format!("marcher refused a valid configuration {cfg:?}: {e}"))?
        .with_background(cfg.background);
    let ratio = cfg.step.d() / cfg.d_ref;
    if m.correction().is_some() != (M::OPACITY_BASED && ratio != 1.0) {
        return Err(format!(
            "correction {} for ratio {ratio}",
            m.correction().is_some()
        ));
    }
    let mut cast = Vec::with_capacity(rays.len());
    let mut compared = 0u64;
    for (ray, want) in rays.iter().zip(want) {
        let (got, n) = m.cast_counted(ray);
        cast.push(got);
        let Some(want) = want else { continue };
        let [r, g, b] = got.c();
        if r > got.a() || g > got.a() || b > got.a() {
            return Err(format!("C̃ > α: {got:?} for {ray:?}"));
        }
        compared += u64::from(n);
        if (raw(&got), n) != (want.result, want.used) {
            return Err(format!(
                "cast_counted {got:?}/{n} != model {:?}/{} for {ray:?} in {cfg:?}",
                want.result, want.used
            ));
        }
        let (p, pn) = m.march_positions(want.positions.iter().map(|&r| IntPos::<F>::from_raw(r)));
        if (raw(&p), pn) != (want.result, want.used) {
            return Err(format!(
                "march_positions {p:?}/{pn} != model {:?}/{} for {ray:?}",
                want.result, want.used
            ));
        }
    }
    let mut out = vec![IntSample::TRANSPARENT; rays.len()];
    m.cast_rays(rays, &mut out)
        .map_err(|e| format!("cast_rays: {e}"))?;
    if out != cast {
        return Err(format!("cast_rays {out:?} != cast {cast:?}"));
    }
    Ok(compared)
}

/// Runs `$body` with the const `F` of the `int_marcher` check (4, 8 or 12).
macro_rules! with_march_frac_bits {
    ($f_val:expr, $f:ident => $body:expr) => {
        match $f_val {
            4 => {
                const $f: u32 = 4;
                $body
            }
            8 => {
                const $f: u32 = 8;
                $body
            }
            _ => {
                const $f: u32 = 12;
                $body
            }
        }
    };
}

/// `int_marcher`: the integer ray marcher agrees bit for bit with the integer model of every
/// step (sample positions, taps, the mode's sample, the opacity correction when `d ≠ d′`,
/// front-to-back compositing with the stop test, the background) on every ray, sample count
/// included; `march_positions` on the model's positions and `cast_rays` agree too. Returns
/// the number of samples compared.
///
/// # Errors
/// The first disagreement, with the values.
pub fn int_marcher(inp: &MarcherInput) -> Result<u64, String> {
    let cfg = inp.cfg()?;
    let rays: Vec<Ray> = inp.rays.iter().take(16).filter_map(RayInput::ray).collect();
    let ratio = cfg.step.d() / cfg.d_ref;
    let opacity_based = inp.mode != MarchMode::Extinction;
    let ct = (opacity_based && ratio != 1.0).then(|| corr_model::tables(ratio));
    let want: Vec<Option<ModelRay>> = rays
        .iter()
        .map(|r| model_ray(inp.mode, inp.trilinear, &cfg, ct.as_ref(), r))
        .collect();
    let straight: Vec<StraightU8> = cfg.bytes.iter().map(|&v| StraightU8(v)).collect();
    with_march_frac_bits!(cfg.frac_bits, F => match (inp.mode, inp.trilinear) {
        (MarchMode::OpacityWeighted, true) => {
            compare_marcher::<_, _, Trilinear, F>(&straight, OpacityWeighted, &cfg, &rays, &want)
        }
        (MarchMode::OpacityWeighted, false) => {
            compare_marcher::<_, _, Nearest, F>(&straight, OpacityWeighted, &cfg, &rays, &want)
        }
        (MarchMode::Separate, true) => {
            compare_marcher::<_, _, Trilinear, F>(&straight, Separate, &cfg, &rays, &want)
        }
        (MarchMode::Separate, false) => {
            compare_marcher::<_, _, Nearest, F>(&straight, Separate, &cfg, &rays, &want)
        }
        (MarchMode::Preweighted, tri) => {
            let assoc: Vec<AssociatedU8> = cfg
                .bytes
                .iter()
                .map(|&[r, g, b, a]| AssociatedU8([r.min(a), g.min(a), b.min(a), a]))
                .collect();
            if tri {
                compare_marcher::<_, _, Trilinear, F>(&assoc, Preweighted, &cfg, &rays, &want)
            } else {
                compare_marcher::<_, _, Nearest, F>(&assoc, Preweighted, &cfg, &rays, &want)
            }
        }
        (MarchMode::Extinction, tri) => {
            let ext: Vec<ExtinctionFx> =
                straight.iter().map(|&v| ExtinctionFx::from_straight_u8(v)).collect();
            let mode = IntExtinction::new(march_tables(), 1.0).map_err(|e| e.to_string())?;
            if tri {
                compare_marcher::<_, _, Trilinear, F>(&ext, mode, &cfg, &rays, &want)
            } else {
                compare_marcher::<_, _, Nearest, F>(&ext, mode, &cfg, &rays, &want)
            }
        }
    })
}
