//! A GPU texture unit's trilinear filtering of an RGBA8 3-D texture, emulated on the CPU, so
//! that the report can show what hardware filtering costs in accuracy.
//!
//! Hardware filtering (CUDA's `cudaFilterModeLinear`, D3D11's `MIN_MAG_MIP_LINEAR` on a
//! `R8G8B8A8_UNORM` 3-D texture) reads the eight texels of the cell around the position and
//! weights them with the fractional coordinates `α, β, γ` stored with **8 fractional bits**
//! (CUDA's programming guide: "9-bit fixed point format with 8 bits of fractional value").
//! Each channel is filtered on its own: on straight RGBA8 that is [`Separate`]'s
//! interpolation, on premultiplied RGBA8 [`Preweighted`]'s. The shader then composites in
//! `f32`. This module does the same: the core's ray, sample positions
//! ([`RayMarcher::sample_range`], `ray.at(t₀ + j·d)`), clamped cell
//! ([`Volume::cell_clamped`]), opacity correction ([`correct`]) and front-to-back step
//! ([`front_to_back`]); only the weights differ from the core's `f32` trilinear filter.
//!
//! The quantisation of a fractional coordinate is named [`quantize_fraction`]: **round half
//! up** to `1/256` (the hardware's rounding is not specified by either API; any rounding to
//! 8 bits has the same error bound of half a step).
//!
//! [`Separate`]: volsample::Separate
//! [`Preweighted`]: volsample::Preweighted
//! [`RayMarcher::sample_range`]: volsample::RayMarcher::sample_range
//! [`correct`]: volsample::opacity::correct
//! [`front_to_back`]: volsample::composite::front_to_back

use volsample::composite::{front_to_back, over};
use volsample::opacity::correct;
use volsample::{Camera, Ray, Sample, Volume};

/// Fractional bits of the texture unit's weights.
pub const WEIGHT_BITS: u32 = 8;

/// `f` (a fractional coordinate in `[0, 1]`) to [`WEIGHT_BITS`] bits, **round half up**:
/// `⌊256·f + ½⌋ / 256` (the result may be 1, the next texel's full weight).
pub fn quantize_fraction(f: f32) -> f32 {
    let one = (1u32 << WEIGHT_BITS) as f32;
    (f * one + 0.5).floor() / one
}

/// How the texels store color.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Texels {
    /// Straight RGBA8: each channel filtered on its own, then `C̃ = C·α` (as [`Separate`]).
    ///
    /// [`Separate`]: volsample::Separate
    Straight,
    /// Premultiplied RGBA8 (`αC` and `α` bytes): filtered as they are (as [`Preweighted`]).
    ///
    /// [`Preweighted`]: volsample::Preweighted
    Premultiplied,
}

/// What the texture unit returns at `pos` (voxel units, voxel `i` at `i`): the four channels
/// in `[0, 1]`, trilinearly filtered with weights from [`quantize_fraction`]; or with the
/// exact fractions when `quantize` is false (the `f32` filter, for comparison).
pub fn fetch<V: volsample::voxel::Voxel + Bytes>(
    vol: &Volume<'_, V>,
    pos: [f32; 3],
    quantize: bool,
) -> [f32; 4] {
    let lo = pos.map(f32::floor);
    let f: [f32; 3] = core::array::from_fn(|k| {
        let f = pos[k] - lo[k];
        if quantize {
            quantize_fraction(f)
        } else {
            f
        }
    });
    let taps = vol.cell_clamped(lo[0] as isize, lo[1] as isize, lo[2] as isize);
    let mut out = [0.0f32; 4];
    for (i, t) in taps.iter().enumerate() {
        let w = |k: usize, bit: usize| {
            if (i >> bit) & 1 == 1 {
                f[k]
            } else {
                1.0 - f[k]
            }
        };
        let weight = w(0, 0) * w(1, 1) * w(2, 2);
        for (o, b) in out.iter_mut().zip(t.bytes()) {
            *o += weight * (f32::from(b) / 255.0);
        }
    }
    out
}

/// Voxels the texture unit reads: four bytes.
pub trait Bytes {
    /// The texel's four bytes (R, G, B, A).
    fn bytes(&self) -> [u8; 4];
}

impl Bytes for volsample::StraightU8 {
    fn bytes(&self) -> [u8; 4] {
        self.0
    }
}

impl Bytes for volsample::AssociatedU8 {
    fn bytes(&self) -> [u8; 4] {
        self.0
    }
}

/// One filtered texel as an associated sample, before opacity correction.
pub fn classify(t: [f32; 4], texels: Texels) -> Sample {
    let a = t[3].clamp(0.0, 1.0);
    match texels {
        Texels::Straight => Sample::clamped([t[0] * a, t[1] * a, t[2] * a], a),
        Texels::Premultiplied => Sample::clamped([t[0], t[1], t[2]], a),
    }
}

/// The ray marching of a fragment shader over the texture: a core marcher's sample positions
/// along each ray (its [`sample_range`](volsample::RayMarcher::sample_range) and the step
/// `d`), each sample fetched by the texture unit, corrected for `d/d′` where `ratio` is given,
/// composited front to back in `f32` until `A ≥ a_stop`, then over `background`.
pub struct Shader<'v, V> {
    /// The texture.
    pub volume: Volume<'v, V>,
    /// How its texels store color.
    pub texels: Texels,
    /// The step `d`, in voxels.
    pub d: f32,
    /// `d/d′`, where the step differs from the reference distance.
    pub ratio: Option<f32>,
    /// Early termination threshold (`1`: none).
    pub a_stop: f32,
    /// The background the ray is composited over.
    pub background: Sample,
    /// Quantise the weights (the hardware) or not (the `f32` filter, for comparison).
    pub quantize: bool,
}

impl<V: volsample::voxel::Voxel + Bytes> Shader<'_, V> {
    /// One ray, given its first sample's `t` and sample count (the core marcher's
    /// [`sample_range`](volsample::RayMarcher::sample_range)): the pixel and the number of
    /// samples taken.
    pub fn cast(&self, ray: &Ray, (t_first, n): (f32, u32)) -> (Sample, u32) {
        let mut acc = Sample::TRANSPARENT;
        let mut taken = n;
        for j in 0..n {
            let p = ray.at(t_first + j as f32 * self.d);
            let mut s = classify(fetch(&self.volume, p, self.quantize), self.texels);
            if let Some(r) = self.ratio {
                s = correct(s, r);
            }
            acc = front_to_back(acc, s);
            if acc.a >= self.a_stop {
                taken = j + 1;
                break;
            }
        }
        (over(acc, self.background), taken)
    }

    /// A `w × h` image of `cam` (row-major, row 0 at the top), the sample ranges from
    /// `range`; returns the pixels and the samples taken.
    pub fn image(
        &self,
        cam: &impl Camera,
        [w, h]: [usize; 2],
        range: impl Fn(&Ray) -> (f32, u32),
    ) -> (Vec<Sample>, u64) {
        let mut pixels = Vec::with_capacity(w * h);
        let mut samples = 0u64;
        for j in 0..h {
            for i in 0..w {
                let ray = cam.ray(i, j, w, h);
                let (p, n) = self.cast(&ray, range(&ray));
                pixels.push(p);
                samples += u64::from(n);
            }
        }
        (pixels, samples)
    }
}
