//! Model of the integer downsampling in `volsample::downsample::integer`, written from its
//! documented arithmetic.
//!
//! * Taps: `(a_q, 2^15 − a_q, 2^15 − a_q, a_q)`, Q0.16; [`quantise_a`] is `⌊2^16·a + ½⌋`.
//! * Sums: the direct 64-tap form `Σ w_i w_j w_k·v` with indices clamped into the grid (not the
//!   kernel's separable passes), as exact integers (`u128`; up to 74 bits, too wide for `f64`).
//! * Roundings, each **round half up** computed differently from the kernel: the shift of a
//!   sum splits it as `hi·2^s + lo` and rounds the exact `f64` fraction `lo/2^s`; the opacity
//!   correction divides in `f64` and rounds the quotient. That quotient is exact enough: its
//!   numerator is below `2^49` (exact), its denominator `D = 2^16·FULL ≤ 255·2^24`, so an exact
//!   quotient not on a tie is at least `1/(2D) > 2^−34` from one, more than the `f64` rounding
//!   of a quotient below `2^16` (`2^−37`).
//! * Extinction: `min(round_half_up(S/2^47), 64·2^20)`.
//!
//! Each model voxel also carries the exact (real-number) result of the method for the same
//! quantised taps and stored input, which the kernel's error bounds are measured against.

use super::round_half_up;

/// Fractional bits of a tap.
pub const TAP_FRAC_BITS: u32 = 16;
/// The extinction cap `64·2^20` (U7.20).
pub const MAX_DEPTH_RAW: u64 = 64 << 20;

/// `⌊2^16·a + ½⌋` for `a ∈ [0, ½]`.
pub fn quantise_a(a: f64) -> u32 {
    round_half_up(a * 65536.0) as u32
}

/// The four taps of `a_q`.
pub fn taps(a_q: u32) -> [u128; 4] {
    let b = (1u128 << 15) - u128::from(a_q);
    [u128::from(a_q), b, b, u128::from(a_q)]
}

/// `⌈n/2⌉` per axis.
pub fn level_dims(dims: [usize; 3]) -> [usize; 3] {
    dims.map(|n| n.div_ceil(2))
}

/// The exact 64-tap sums of every coarse voxel of one level, four channels per voxel
/// (units `2^−48` raw).
pub fn sums(dims: [usize; 3], ch: &[[u64; 4]], a_q: u32) -> ([usize; 3], Vec<[u128; 4]>) {
    assert_eq!(ch.len(), dims[0] * dims[1] * dims[2]);
    let out = level_dims(dims);
    let w = taps(a_q);
    let clamp = |i: i64, n: usize| i.clamp(0, n as i64 - 1) as usize;
    let mut res = Vec::with_capacity(out[0] * out[1] * out[2]);
    for z in 0..out[2] {
        for y in 0..out[1] {
            for x in 0..out[0] {
                let mut s = [0u128; 4];
                for k in 0..4 {
                    for j in 0..4 {
                        for i in 0..4 {
                            let fx = clamp(2 * x as i64 - 1 + i as i64, dims[0]);
                            let fy = clamp(2 * y as i64 - 1 + j as i64, dims[1]);
                            let fz = clamp(2 * z as i64 - 1 + k as i64, dims[2]);
                            let v = ch[fx + dims[0] * (fy + dims[1] * fz)];
                            let wt = w[i] * w[j] * w[k];
                            for (acc, &c) in s.iter_mut().zip(v.iter()) {
                                *acc += wt * u128::from(c);
                            }
                        }
                    }
                }
                res.push(s);
            }
        }
    }
    (out, res)
}

/// **Round half up** of `s/2^shift`: `hi + ⌊lo/2^shift + ½⌋` with `s = hi·2^shift + lo`
/// (`lo/2^shift` is exact in `f64` for `shift ≤ 52`).
pub fn round_shift(s: u128, shift: u32) -> u64 {
    let hi = s >> shift;
    let lo = s - (hi << shift);
    (hi as u64) + round_half_up(lo as f64 / 2f64.powi(shift as i32)) as u64
}

/// One model voxel: the rounded channels the kernel must produce and the exact ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DsVoxel {
    /// `[c₀, c₁, c₂, α or D]`, rounded as the kernel rounds.
    pub raw: [u64; 4],
    /// The exact (real-number) values of the method, same units.
    pub exact: [f64; 4],
}

/// One modelled level: its dimensions and voxels.
pub type Level = ([usize; 3], Vec<DsVoxel>);

/// One opacity-based level of voxels `[C̃₀, C̃₁, C̃₂, α]` in storage units of full scale
/// `full` (255 or 65280), each `C̃ ≤ α` (the model clamps like the kernel's read).
pub fn opacity_level(dims: [usize; 3], voxels: &[[u64; 4]], a_q: u32, full: u64) -> Level {
    let ch: Vec<[u64; 4]> = voxels
        .iter()
        .map(|v| [v[0].min(v[3]), v[1].min(v[3]), v[2].min(v[3]), v[3]])
        .collect();
    let (out, s) = sums(dims, &ch, a_q);
    let fullf = full as f64;
    let den = fullf * 65536.0;
    let vox = s
        .iter()
        .map(|s| {
            let a_g = round_shift(s[3], 40);
            let gain = 2 * 256 * full - a_g;
            let corr = |x: u64| round_half_up((x * gain) as f64 / den) as u64;
            let raw = [
                corr(round_shift(s[0], 40)),
                corr(round_shift(s[1], 40)),
                corr(round_shift(s[2], 40)),
                corr(a_g),
            ];
            // Exact: ᾱ = S_α/(2^48·full) in [0, 1].
            let unit = 2f64.powi(48) * fullf;
            let ab = s[3] as f64 / unit;
            let g = 2.0 - ab;
            let e = |x: u128| x as f64 / unit * g * fullf;
            DsVoxel {
                raw,
                exact: [e(s[0]), e(s[1]), e(s[2]), ab * g * fullf],
            }
        })
        .collect();
    (out, vox)
}

/// One extinction-based level of voxels `[(D·C)₀, (D·C)₁, (D·C)₂, D]` (U7.20 raw).
pub fn extinction_level(dims: [usize; 3], voxels: &[[u64; 4]], a_q: u32) -> Level {
    let ch: Vec<[u64; 4]> = voxels
        .iter()
        .map(|v| {
            let t = v[3].min(MAX_DEPTH_RAW);
            [v[0].min(t), v[1].min(t), v[2].min(t), t]
        })
        .collect();
    let (out, s) = sums(dims, &ch, a_q);
    let vox = s
        .iter()
        .map(|s| DsVoxel {
            raw: s.map(|x| round_shift(x, 47).min(MAX_DEPTH_RAW)),
            exact: s.map(|x| x as f64 / 2f64.powi(47)),
        })
        .collect();
    (out, vox)
}

/// A whole chain: every level from the rounded level before, level 1 first, down to
/// `1 × 1 × 1` (empty for a `1 × 1 × 1` base).
pub fn chain(
    dims: [usize; 3],
    voxels: &[[u64; 4]],
    level: impl Fn([usize; 3], &[[u64; 4]]) -> Level,
) -> Vec<Level> {
    let mut out: Vec<Level> = Vec::new();
    let mut cur = (dims, voxels.to_vec());
    while cur.0 != [1, 1, 1] {
        let (d, v) = level(cur.0, &cur.1);
        cur = (d, v.iter().map(|x| x.raw).collect());
        out.push((d, v));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_shift_is_round_half_up() {
        assert_eq!(round_shift(3 << 39, 40), 2); // 1.5 → 2
        assert_eq!(round_shift((1 << 39) - 1, 40), 0);
        assert_eq!(
            round_shift(u128::from(u64::MAX) << 10, 40),
            (u64::MAX >> 30) + 1
        );
    }

    #[test]
    fn constant_opacity_level() {
        // α = 128: 128·382/255 = 191.75 → 192.
        let (_, v) = opacity_level([2, 2, 2], &[[40, 20, 0, 128]; 8], 13107, 255);
        assert_eq!(v[0].raw, [60, 30, 0, 192]);
    }
}
