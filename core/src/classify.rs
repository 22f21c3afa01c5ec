//! Pre-classification: scalar voxels → straight RGBA voxels, before any interpolation.
//!
//! A scene with RGBA data skips this stage entirely; a scene with scalars either
//! pre-classifies here (then samples the RGBA result with any mode) or post-classifies
//! per sample ([`PostClassified`](crate::PostClassified)).

use crate::each::Each;
use crate::error::Error;
use crate::transfer::TransferFunction;
use crate::volume::Volume;
use crate::voxel::{ScalarVoxel, StraightF32};

/// Levoy's isosurface classifier (Levoy 1988): opacity `α_v` on the isosurface `f = f_v`,
/// falling linearly to 0 over a thickness of `r` voxels measured along the gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Isosurface {
    f_v: f32,
    alpha_v: f32,
    r: f32,
}

impl Isosurface {
    /// Isovalue `f_v` (scalar units), opacity `α_v ∈ [0, 1]`, thickness `r > 0` (voxels).
    ///
    /// # Errors
    /// [`Error::InvalidClassifier`] for non-finite values, `α_v` outside `[0, 1]`, or `r ≤ 0`.
    pub fn new(f_v: f32, alpha_v: f32, r: f32) -> Result<Self, Error> {
        if f_v.is_finite() && (0.0..=1.0).contains(&alpha_v) && r.is_finite() && r > 0.0 {
            Ok(Self { f_v, alpha_v, r })
        } else {
            Err(Error::InvalidClassifier)
        }
    }

    /// The opacity for value `f` and gradient magnitude `g ≥ 0`:
    /// `α_v·(1 − |f_v − f|/(r·g))` when `g > 0` and `|f_v − f| ≤ r·g`; `α_v` when `f = f_v`;
    /// otherwise 0.
    ///
    /// The ratio `|f_v − f|/(r·g)` is formed from the mantissas of its three terms, so no
    /// step overflows or underflows: every finite `f`, `f_v`, `r` and `g` (subnormal to
    /// `f32::MAX`) gives the ratio to a few roundings. (Formed directly, `r·g` overflowed to
    /// `∞` — opacity `α_v` where it should fall off — and `|f_v − f|` overflowed for `f`, `f_v`
    /// of opposite signs near `±f32::MAX`.)
    ///
    /// Error bound: within `4ε` (`ε = 2⁻²³`) of the exact value for the given `f32` input
    /// (`ISOSURFACE_ABS` in the tests).
    #[inline]
    pub fn opacity(&self, f: f32, g: f32) -> f32 {
        // g = m·2^k with m ∈ [½, 1) (∞ and NaN pass through as m).
        let (m, k) = libm::frexpf(g);
        self.opacity_scaled(f, m, k)
    }

    /// [`opacity`](Self::opacity) for the gradient magnitude `g = m·2^k`, `m ≥ 0`.
    #[inline]
    fn opacity_scaled(&self, f: f32, m: f32, k: i32) -> f32 {
        let (d, e) = difference(self.f_v, f);
        let diff = d.abs();
        if diff == 0.0 {
            return self.alpha_v;
        }
        // A zero, negative or NaN gradient, or a NaN `f`: no opacity off the isovalue.
        if m.is_nan() || m <= 0.0 || diff.is_nan() {
            return 0.0;
        }
        // q = |f_v − f|/(r·g) = (m_d/(m_r·m))·2^(e_d + e − e_r − k): the quotient of the
        // mantissas lies in [¼, 4], and one scaling rounds it only if `q` is subnormal.
        let (m_d, e_d) = libm::frexpf(diff);
        let (m_r, e_r) = libm::frexpf(self.r);
        let q = libm::scalbnf(m_d / (m_r * m), e_d + e - e_r - k);
        if q <= 1.0 {
            (self.alpha_v * (1.0 - q)).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// `a − b` as `(d, e)` with `a − b = d·2^e` and `d` finite for finite `a`, `b`: `(a − b, 0)`,
/// or, when that overflows, `(a/2 − b/2, 1)` (the halves are exact unless one is subnormal,
/// and then it is negligible against the other, which exceeds `f32::MAX/4`).
#[inline(always)]
fn difference(a: f32, b: f32) -> (f32, i32) {
    let d = a - b;
    if d.is_infinite() && a.is_finite() && b.is_finite() {
        (a * 0.5 - b * 0.5, 1)
    } else {
        (d, 0)
    }
}

/// The per-axis difference quotients of [`gradient`] as `(d, e)` pairs, component
/// `d·2^e`, never overflowing (see [`difference`]).
fn gradient_parts<V: ScalarVoxel>(
    vol: &Volume<'_, V>,
    x: usize,
    y: usize,
    z: usize,
) -> [(f32, i32); 3] {
    let [nx, ny, nz] = vol.dims();
    let at = |p: [usize; 3]| -> f32 {
        let [cx, cy, cz] = p;
        vol.get(cx, cy, cz).map_or(0.0, |v| v.scalar::<f32>())
    };
    let axis = |n: usize, c: usize, f: &dyn Fn(usize) -> f32| -> (f32, i32) {
        if n < 2 {
            (0.0, 0)
        } else if c == 0 {
            difference(f(1), f(0))
        } else if c >= n - 1 {
            difference(f(n - 1), f(n - 2))
        } else {
            // The halving goes into the exponent: no rounding, even for subnormals.
            let (d, e) = difference(f(c + 1), f(c - 1));
            (d, e - 1)
        }
    };
    let (x, y, z) = (x.min(nx - 1), y.min(ny - 1), z.min(nz - 1));
    [
        axis(nx, x, &|k| at([k, y, z])),
        axis(ny, y, &|k| at([x, k, z])),
        axis(nz, z, &|k| at([x, y, k])),
    ]
}

/// The gradient of a scalar volume at voxel `(x, y, z)` as `(v, k)`, `∇f = v·2^k`, scaled so
/// that the largest `|v_i|` lies in `[½, 1)` (`v = 0`, `k = 0` for a zero gradient): its
/// length and direction can be formed without overflow or underflow for every finite
/// scalar field. Components more than `2^125` times smaller than the largest may be
/// flushed, a relative change of the length below `2^−250`.
pub(crate) fn scaled_gradient<V: ScalarVoxel>(
    vol: &Volume<'_, V>,
    x: usize,
    y: usize,
    z: usize,
) -> ([f32; 3], i32) {
    let parts = gradient_parts(vol, x, y, z);
    let k = parts
        .iter()
        .filter(|(d, _)| *d != 0.0)
        .map(|&(d, e)| libm::frexpf(d).1 + e)
        .max();
    match k {
        Some(k) => (parts.each(|(d, e)| libm::scalbnf(d, e - k)), k),
        None => ([0.0; 3], 0),
    }
}

/// The gradient of a scalar volume at voxel `(x, y, z)`, per voxel: central differences
/// `(f[i+1] − f[i−1])/2` inside, one-sided differences at the faces, 0 along an axis of
/// length 1. Coordinates outside the grid are clamped.
///
/// A central difference of values near `±f32::MAX` is formed from their halves, so it does
/// not overflow; a one-sided difference beyond `f32::MAX` is `±∞` (it has no `f32` value).
///
/// Error bound: each component within `ε·m` of the exact difference of the `f32` values,
/// `ε = 2⁻²³`, `m` the largest magnitude of the differenced values (`GRADIENT_REL` in the
/// tests); relative to the component, one rounding (`ε/2`), plus `2⁻¹⁵⁰` where the result is
/// subnormal (`GRADIENT_EDGE_REL`).
pub fn gradient<V: ScalarVoxel>(vol: &Volume<'_, V>, x: usize, y: usize, z: usize) -> [f32; 3] {
    gradient_parts(vol, x, y, z).each(|(d, e)| libm::scalbnf(d, e))
}

fn check_out_len(expected: usize, out: usize) -> Result<(), Error> {
    if expected == out {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            expected,
            actual: out,
        })
    }
}

/// Classifies every voxel with Levoy's isosurface opacity and one straight `color`, writing
/// straight voxels into `out` (same layout).
///
/// The gradient magnitude and the ratio `|f_v − f|/(r·|∇f|)` are formed on scaled
/// mantissas, so every finite scalar field — values near `±f32::MAX`, subnormal differences —
/// is classified as its exact gradient says (Levoy's opacity depends only on that ratio).
///
/// Error bound: each `α` within `4ε` (`ε = 2⁻²³`) of the exact classification of the same
/// `f32` scalars, gradient included (`CLASSIFY_ISOSURFACE_ABS` in the tests).
///
/// # Errors
/// [`Error::LengthMismatch`] if `out` does not hold one voxel per input voxel,
/// [`Error::VoxelOutOfRange`] (index 0) if `color` is not in `[0, 1]`.
pub fn classify_isosurface<V: ScalarVoxel>(
    vol: &Volume<'_, V>,
    iso: &Isosurface,
    color: [f32; 3],
    out: &mut [StraightF32],
) -> Result<(), Error> {
    check_out_len(vol.data().len(), out.len())?;
    if !color.iter().all(|c| (0.0..=1.0).contains(c)) {
        return Err(Error::VoxelOutOfRange { index: 0 });
    }
    let [nx, ny, _] = vol.dims();
    for (i, (o, v)) in out.iter_mut().zip(vol.data()).enumerate() {
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        // |∇f| = |v|·2^k with |v| ∈ [½, √3]: no overflow or underflow on the way.
        let ([gx, gy, gz], k) = scaled_gradient(vol, x, y, z);
        let m = libm::sqrtf(gx * gx + gy * gy + gz * gz);
        *o = StraightF32 {
            c: color,
            a: iso.opacity_scaled(v.scalar::<f32>(), m, k),
        };
    }
    Ok(())
}

/// Classifies every voxel through a transfer function, writing straight voxels into `out`.
///
/// # Errors
/// [`Error::LengthMismatch`] if `out` does not hold one voxel per input voxel.
pub fn classify_transfer<V: ScalarVoxel, const N: usize>(
    vol: &Volume<'_, V>,
    tf: &TransferFunction<N>,
    out: &mut [StraightF32],
) -> Result<(), Error> {
    check_out_len(vol.data().len(), out.len())?;
    for (o, v) in out.iter_mut().zip(vol.data()) {
        let (c, a) = tf.eval(v.scalar::<f32>());
        *o = StraightF32 { c, a };
    }
    Ok(())
}
