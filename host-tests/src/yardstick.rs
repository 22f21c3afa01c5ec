//! Yardsticks for the `ray_march` bench: the same work as volsample's `OpacityWeighted`
//! trilinear front-to-back marcher over straight RGBA8, written the way one writes a one-off
//! loop for one volume format — so that the bench measures, in the same run and under the
//! same load, how far the library is from a hand-written kernel on the machine at hand.
//!
//! Not library code and not bit-identical to volsample: no edge handling beyond clamping the
//! cell into the grid (positions outside `[0, n − 1]` extrapolate from the edge cell),
//! positions stepped incrementally (`p += d·dir`, drifting by a few ulps over a ray), and
//! different rounding. They agree with `RayMarcher::cast` within [`YARDSTICK_ABS`] on rays
//! inside the volume (`tests/yardstick.rs`).
//!
//! * [`naive`]: the textbook loop — per sample `⌊p⌋`, eight indexed reads, the weights as
//!   products of `(1 − f, f)`, every byte divided by 255.
//! * [`tuned`]: what a hand-tuned probe does — incremental positions, the cell clamped into
//!   the grid once per sample, byte units throughout (`ω = w·α₂₅₅`, `Σ ω·C₂₅₅`), scaled once
//!   per sample; on x86-64 in SSE2 (the baseline there, so no run-time detection) with no
//!   per-tap checks and the four channels of a voxel in the four lanes; elsewhere the same
//!   arithmetic in scalar code (with indexed reads).

use volsample::{Ray, StraightU8};

/// The signature of both yardsticks: `(voxels, n, ray, t_first, count, d)` to the composite
/// `[C̃_r, C̃_g, C̃_b, α]` of the samples at `t_first + j·d`, `j < count`.
pub type Kernel = fn(&[StraightU8], usize, &Ray, f32, u32, f32) -> [f32; 4];

/// How far a yardstick's result may be from `RayMarcher::cast` (`OpacityWeighted`, trilinear,
/// front to back, `d = d′`) per channel, on rays inside the volume: different rounding of
/// a few hundred composited samples, and positions stepped incrementally.
pub const YARDSTICK_ABS: f32 = 1e-4;

/// The naive loop: samples at `t_first + j·d`, `j < count`, along `ray` through the
/// `n × n × n` volume `v` (x fastest). Returns the composite `[C̃_r, C̃_g, C̃_b, α]`.
///
/// # Panics
/// If a cell index lies outside `v` (it cannot for `v.len() == n³`, `n ≥ 2`).
pub fn naive(v: &[StraightU8], n: usize, ray: &Ray, t_first: f32, count: u32, d: f32) -> [f32; 4] {
    let (o, dir) = (ray.origin(), ray.dir());
    let mut acc = [0.0f32; 4];
    for j in 0..count {
        let t = t_first + j as f32 * d;
        let p = [0, 1, 2].map(|k| o[k] + t * dir[k]);
        let i = p.map(|x| (x.floor().max(0.0) as usize).min(n - 2));
        let f = [0, 1, 2].map(|k| p[k] - i[k] as f32);
        let mut s = [0.0f32; 4];
        for k in 0..8 {
            let (dx, dy, dz) = (k & 1, (k >> 1) & 1, k >> 2);
            let vx = v[(i[0] + dx) + n * ((i[1] + dy) + n * (i[2] + dz))].0;
            let lin = |b: usize, f: f32| if b == 1 { f } else { 1.0 - f };
            let w = lin(dx, f[0]) * lin(dy, f[1]) * lin(dz, f[2]);
            let om = w * f32::from(vx[3]) / 255.0;
            for c in 0..3 {
                s[c] += om * f32::from(vx[c]) / 255.0;
            }
            s[3] += om;
        }
        let tr = 1.0 - acc[3];
        for c in 0..4 {
            acc[c] += tr * s[c];
        }
    }
    acc
}

/// The hand-tuned loop (see the module docs); the arguments and result as for [`naive`].
///
/// # Panics
/// Unless `n ≥ 2` and `v.len() == n³`.
pub fn tuned(v: &[StraightU8], n: usize, ray: &Ray, t_first: f32, count: u32, d: f32) -> [f32; 4] {
    assert!(
        n >= 2 && v.len() == n * n * n,
        "volume must be n³ voxels, n ≥ 2"
    );
    #[cfg(target_arch = "x86_64")]
    {
        sse2::tuned(v, n, ray, t_first, count, d)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        tuned_scalar(v, n, ray, t_first, count, d)
    }
}

/// The cell's base index (clamped into the grid) and the fractions at `p`.
#[inline(always)]
fn cell(p: [f32; 3], n: usize) -> (usize, [f32; 3]) {
    // `as usize` saturates negatives to 0; the clamp keeps the cell inside.
    let i = p.map(|x| (x as usize).min(n - 2));
    let f = [p[0] - i[0] as f32, p[1] - i[1] as f32, p[2] - i[2] as f32];
    (i[0] + n * (i[1] + n * i[2]), f)
}

/// The 8 trilinear weights, corner `k` at `(k & 1, (k >> 1) & 1, k >> 2)`.
#[inline(always)]
fn weights([x, y, z]: [f32; 3]) -> [f32; 8] {
    let (x0, y0, z0) = (1.0 - x, 1.0 - y, 1.0 - z);
    let (a, b, c, e) = (x0 * y0, x * y0, x0 * y, x * y);
    [a * z0, b * z0, c * z0, e * z0, a * z, b * z, c * z, e * z]
}

/// Byte units to unit range: colors were weighted by `α₂₅₅`, so by 255².
const SCALE: [f32; 4] = [1.0 / 65025.0, 1.0 / 65025.0, 1.0 / 65025.0, 1.0 / 255.0];

#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
fn tuned_scalar(
    v: &[StraightU8],
    n: usize,
    ray: &Ray,
    t_first: f32,
    count: u32,
    d: f32,
) -> [f32; 4] {
    let (o, dir) = (ray.origin(), ray.dir());
    let mut p = [0, 1, 2].map(|k| o[k] + t_first * dir[k]);
    let dp = dir.map(|x| d * x);
    let plane = n * n;
    let mut acc = [0.0f32; 4];
    for _ in 0..count {
        let (b, f) = cell(p, n);
        let corners = [
            b,
            b + 1,
            b + n,
            b + n + 1,
            b + plane,
            b + plane + 1,
            b + plane + n,
            b + plane + n + 1,
        ];
        let w = weights(f);
        let mut s = [0.0f32; 4];
        for (&at, wk) in corners.iter().zip(w) {
            let q = v[at].0.map(f32::from);
            let om = wk * q[3];
            for c in 0..3 {
                s[c] += om * q[c];
            }
            s[3] += om;
        }
        let tr = 1.0 - acc[3];
        for c in 0..4 {
            acc[c] += tr * (s[c] * SCALE[c]);
        }
        for c in 0..3 {
            p[c] += dp[c];
        }
    }
    acc
}

#[cfg(target_arch = "x86_64")]
mod sse2 {
    use core::arch::x86_64::*;

    use volsample::{Ray, StraightU8};

    use super::{cell, weights, SCALE};

    /// [`super::tuned`] in SSE2: a voxel's `(r, g, b, a)` in the four lanes.
    pub fn tuned(
        v: &[StraightU8],
        n: usize,
        ray: &Ray,
        t_first: f32,
        count: u32,
        d: f32,
    ) -> [f32; 4] {
        let (o, dir) = (ray.origin(), ray.dir());
        let mut p = [0, 1, 2].map(|k| o[k] + t_first * dir[k]);
        let dp = dir.map(|x| d * x);
        let plane = n * n;
        let base = v.as_ptr().cast::<u8>();
        let mut out = [0.0f32; 4];
        // SAFETY: SSE2 is part of the x86-64 baseline. Every read is of 8 bytes at voxel
        // index `b + off` with `b` the base of a cell clamped into the grid
        // (`x, y, z ≤ n − 2`) and `off ∈ {0, n, n², n² + n}`: the two voxels read,
        // `b + off` and `b + off + 1`, are corners of that cell, inside `v` (`v.len() = n³`,
        // checked by the caller).
        unsafe {
            let zero = _mm_setzero_si128();
            let scale = _mm_loadu_ps(SCALE.as_ptr());
            let one = _mm_set1_ps(1.0);
            // Lanes (r, g, b, 1): the color lanes of a voxel and a one where α was.
            let rgb = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
            let one_a = _mm_setr_ps(0.0, 0.0, 0.0, 1.0);
            let mut acc = _mm_setzero_ps();
            for _ in 0..count {
                let (b, f) = cell(p, n);
                // Two neighbouring voxels (8 bytes) as two vectors of four f32 lanes.
                let pair = |off: usize| {
                    let x = _mm_loadl_epi64(base.add(4 * (b + off)).cast::<__m128i>());
                    let x = _mm_unpacklo_epi8(x, zero);
                    (
                        _mm_cvtepi32_ps(_mm_unpacklo_epi16(x, zero)),
                        _mm_cvtepi32_ps(_mm_unpackhi_epi16(x, zero)),
                    )
                };
                let (t0, t1) = pair(0);
                let (t2, t3) = pair(n);
                let (t4, t5) = pair(plane);
                let (t6, t7) = pair(plane + n);
                let w = weights(f);
                let mut s = _mm_setzero_ps();
                for (t, wk) in [t0, t1, t2, t3, t4, t5, t6, t7].into_iter().zip(w) {
                    // ω = w·α₂₅₅ in every lane, times (r, g, b, 1).
                    let om = _mm_mul_ps(_mm_set1_ps(wk), _mm_shuffle_ps::<0xFF>(t, t));
                    let u = _mm_or_ps(_mm_and_ps(t, rgb), one_a);
                    s = _mm_add_ps(s, _mm_mul_ps(om, u));
                }
                let s = _mm_mul_ps(s, scale);
                let tr = _mm_sub_ps(one, _mm_shuffle_ps::<0xFF>(acc, acc));
                acc = _mm_add_ps(acc, _mm_mul_ps(tr, s));
                for c in 0..3 {
                    p[c] += dp[c];
                }
            }
            _mm_storeu_ps(out.as_mut_ptr(), acc);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SSE2 kernel and the scalar fallback compute the same arithmetic.
    #[test]
    fn tuned_matches_its_scalar_form() {
        let n = 8;
        let v: Vec<StraightU8> = (0..n * n * n)
            .map(|k| {
                StraightU8([
                    (k * 7) as u8,
                    (k * 3) as u8,
                    (k * 11) as u8,
                    (k * 5 % 256) as u8,
                ])
            })
            .collect();
        let ray = Ray::new([1.3, 2.6, 0.2], [0.2, 0.1, 1.0]).unwrap();
        let a = tuned(&v, n, &ray, 0.0, 12, 0.5);
        let b = tuned_scalar(&v, n, &ray, 0.0, 12, 0.5);
        // The same operations in the same order (no fused multiply-add on x86-64's
        // baseline), so the same bits.
        assert_eq!(a, b);
        assert!(a[3] > 0.1, "the ray must composite something: {a:?}");
    }
}
