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
//! * [`tuned_rays`]: the hand-tuned loop across rays — on x86-64 CPUs with AVX2 and FMA
//!   (detected at run time) eight rays march in lock step, one ray per lane, the eight
//!   corners fetched by gather instructions and every channel converted and summed in
//!   eight-lane vectors; rays beyond the last full eight, and other machines, go through
//!   [`tuned`] one at a time. [`tuned_rays_lanes`] says which runs.

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

/// How many rays [`tuned_rays`] marches at once on this machine (for volumes up to 1024³): 8
/// where the CPU has AVX2 and FMA (x86-64, detected at run time), else 1 ([`tuned`] per ray).
pub fn tuned_rays_lanes() -> usize {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        return avx2::LANES;
    }
    1
}

/// The hand-tuned loop across rays (see the module docs): `out[i]` is the composite
/// `[C̃_r, C̃_g, C̃_b, α]` of the samples at `t + j·d`, `j < count`, along `rays[i]`, with
/// `(t, count) = ranges[i]`. Agrees with [`tuned`] per ray within [`YARDSTICK_ABS`] (the
/// AVX2 lanes use fused multiply-adds and do not stop stepping early, so they are not
/// bit-identical to it).
///
/// # Panics
/// Unless `n ≥ 2`, `v.len() == n³` and `rays`, `ranges` and `out` have the same length.
pub fn tuned_rays(
    v: &[StraightU8],
    n: usize,
    rays: &[Ray],
    ranges: &[(f32, u32)],
    d: f32,
    out: &mut [[f32; 4]],
) {
    assert!(
        n >= 2 && v.len() == n * n * n,
        "volume must be n³ voxels, n ≥ 2"
    );
    assert!(
        rays.len() == ranges.len() && rays.len() == out.len(),
        "one range and one output per ray"
    );
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx2::available() && n <= avx2::MAX_N {
        let l = avx2::LANES;
        done = rays.len() / l * l;
        for ((r, g), o) in rays[..done]
            .chunks_exact(l)
            .zip(ranges.chunks_exact(l))
            .zip(out.chunks_exact_mut(l))
        {
            let r: &[Ray; avx2::LANES] = r.try_into().expect("chunks of LANES");
            let g: &[(f32, u32); avx2::LANES] = g.try_into().expect("chunks of LANES");
            // SAFETY: `available()` found AVX2 and FMA on this CPU; `2 ≤ n ≤ MAX_N` and
            // `v.len() == n³` were checked above.
            o.copy_from_slice(&unsafe { avx2::tuned8(v, n, r, g, d) });
        }
    }
    for ((r, &(t, k)), o) in rays.iter().zip(ranges).zip(out.iter_mut()).skip(done) {
        *o = tuned(v, n, r, t, k, d);
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

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use core::arch::x86_64::*;

    use volsample::{Ray, StraightU8};

    use super::SCALE;

    /// Rays per pass: one per `f32` lane of a 256-bit vector.
    pub const LANES: usize = 8;

    /// The largest `n` [`tuned8`] takes: every voxel index of an `n³` volume fits an `i32`
    /// lane.
    pub const MAX_N: usize = 1 << 10;

    /// Whether this CPU runs [`tuned8`].
    pub fn available() -> bool {
        is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
    }

    /// Eight rays in the eight lanes: incremental positions, the cell clamped into the grid,
    /// eight gathers of whole voxels, each channel unpacked and converted in eight lanes,
    /// `ω = w·α₂₅₅` and `Σ ω·C₂₅₅` with fused multiply-adds, scaled once per sample. A lane
    /// whose ray has no more samples keeps stepping (its cell is still clamped into the grid)
    /// but composites nothing.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA ([`available`]), and `v.len() == n³` with
    /// `2 ≤ n ≤ MAX_N`.
    #[target_feature(enable = "avx2,fma")]
    pub unsafe fn tuned8(
        v: &[StraightU8],
        n: usize,
        rays: &[Ray; LANES],
        ranges: &[(f32, u32); LANES],
        d: f32,
    ) -> [[f32; 4]; LANES] {
        let lane = |f: &dyn Fn(usize) -> f32| {
            let a: [f32; LANES] = core::array::from_fn(f);
            _mm256_loadu_ps(a.as_ptr())
        };
        let start = |k: usize| lane(&|l| rays[l].origin()[k] + ranges[l].0 * rays[l].dir()[k]);
        let delta = |k: usize| lane(&|l| d * rays[l].dir()[k]);
        let (mut px, mut py, mut pz) = (start(0), start(1), start(2));
        let (dx, dy, dz) = (delta(0), delta(1), delta(2));
        let counts: [i32; LANES] = core::array::from_fn(|l| ranges[l].1 as i32);
        let count = _mm256_loadu_si256(counts.as_ptr().cast());
        let steps = ranges.iter().map(|r| r.1).max().unwrap_or(0);

        let (n32, plane) = (n as i32, (n * n) as i32);
        let hi = _mm256_set1_epi32(n32 - 2);
        let zero = _mm256_setzero_si256();
        let nv = _mm256_set1_epi32(n32);
        let one = _mm256_set1_ps(1.0);
        let byte = _mm256_set1_epi32(0xff);
        let off = [
            0,
            1,
            n32,
            n32 + 1,
            plane,
            plane + 1,
            plane + n32,
            plane + n32 + 1,
        ]
        .map(|o| _mm256_set1_epi32(o));
        let (sc, sa) = (_mm256_set1_ps(SCALE[0]), _mm256_set1_ps(SCALE[3]));
        let base = v.as_ptr().cast::<i32>();
        let zf = _mm256_setzero_ps();
        let (mut ar, mut ag, mut ab, mut aa) = (zf, zf, zf, zf);
        for j in 0..steps as i32 {
            let live = _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, _mm256_set1_epi32(j)));
            // `cvtt` truncates (positions ≥ 0 inside the grid); the clamp keeps the cell in.
            let cell = |p| _mm256_min_epi32(_mm256_max_epi32(_mm256_cvttps_epi32(p), zero), hi);
            let (ix, iy, iz) = (cell(px), cell(py), cell(pz));
            let fx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(ix));
            let fy = _mm256_sub_ps(py, _mm256_cvtepi32_ps(iy));
            let fz = _mm256_sub_ps(pz, _mm256_cvtepi32_ps(iz));
            let at = _mm256_add_epi32(
                ix,
                _mm256_mullo_epi32(nv, _mm256_add_epi32(iy, _mm256_mullo_epi32(nv, iz))),
            );
            let (x0, y0, z0) = (
                _mm256_sub_ps(one, fx),
                _mm256_sub_ps(one, fy),
                _mm256_sub_ps(one, fz),
            );
            let (a, b, c, e) = (
                _mm256_mul_ps(x0, y0),
                _mm256_mul_ps(fx, y0),
                _mm256_mul_ps(x0, fy),
                _mm256_mul_ps(fx, fy),
            );
            let w = [
                (a, z0),
                (b, z0),
                (c, z0),
                (e, z0),
                (a, fz),
                (b, fz),
                (c, fz),
                (e, fz),
            ]
            .map(|(p, q)| _mm256_mul_ps(p, q));
            let (mut sr, mut sg, mut sb, mut s_a) = (zf, zf, zf, zf);
            for (o, wk) in off.iter().zip(w) {
                // SAFETY (of the gather): every lane's index is a corner of a cell clamped
                // into the grid, inside `v` (the caller's contract).
                let g = _mm256_i32gather_epi32::<4>(base, _mm256_add_epi32(at, *o));
                let chan = |s: __m256i| _mm256_cvtepi32_ps(_mm256_and_si256(s, byte));
                let r = chan(g);
                let gg = chan(_mm256_srli_epi32::<8>(g));
                let bb = chan(_mm256_srli_epi32::<16>(g));
                let om = _mm256_mul_ps(wk, _mm256_cvtepi32_ps(_mm256_srli_epi32::<24>(g)));
                s_a = _mm256_add_ps(s_a, om);
                sr = _mm256_fmadd_ps(om, r, sr);
                sg = _mm256_fmadd_ps(om, gg, sg);
                sb = _mm256_fmadd_ps(om, bb, sb);
            }
            let tr = _mm256_and_ps(_mm256_sub_ps(one, aa), live);
            ar = _mm256_fmadd_ps(tr, _mm256_mul_ps(sr, sc), ar);
            ag = _mm256_fmadd_ps(tr, _mm256_mul_ps(sg, sc), ag);
            ab = _mm256_fmadd_ps(tr, _mm256_mul_ps(sb, sc), ab);
            aa = _mm256_fmadd_ps(tr, _mm256_mul_ps(s_a, sa), aa);
            px = _mm256_add_ps(px, dx);
            py = _mm256_add_ps(py, dy);
            pz = _mm256_add_ps(pz, dz);
        }
        let mut o = [[0.0f32; LANES]; 4];
        for (o, acc) in o.iter_mut().zip([ar, ag, ab, aa]) {
            _mm256_storeu_ps(o.as_mut_ptr(), acc);
        }
        core::array::from_fn(|l| [o[0][l], o[1][l], o[2][l], o[3][l]])
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
