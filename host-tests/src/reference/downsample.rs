//! Downsampling and mipmap chains (Kraus §4), written from the
//! design alone with plain loops in `f64`.
//!
//! - One level halves each axis, `n ↦ ⌈n/2⌉`. Coarse voxel `(X, Y, Z)` is the 64-tap sum
//!   `Σ w[i]·w[j]·w[k]·v(2X − 1 + i, 2Y − 1 + j, 2Z − 1 + k)`, `i, j, k ∈ 0..4`,
//!   `w = (a, ½ − a, ½ − a, a)`, each fine index clamped into `[0, n − 1]`.
//! - Opacity-based: filter `α` and `C̃` to `ᾱ`, `C̄`; then `α′ = 1 − (1 − ᾱ)²` and
//!   `C̃′ = C̄·α′/ᾱ` (`0` when `ᾱ = 0`).
//! - Extinction-based: filter `τ` and `C^τ`; the coarse voxel is twice as long, and each
//!   level is kept in its own voxel units, so the stored values are `τ′ = 2τ̄`,
//!   `C^τ′ = 2C̄^τ` (per coarse voxel).
//! - Level `ℓ` position of a level-0 position `p`: `(p + ½)/2^ℓ − ½`; its reference distance
//!   is `d′` in its own voxels (`2^ℓ·d′` fine voxels).

use super::volume::{linear_index, RefAssoc, RefExtinction};

/// `⌈n/2⌉` per axis.
pub fn ref_level_dims(dims: [usize; 3]) -> [usize; 3] {
    [
        dims[0].div_ceil(2),
        dims[1].div_ceil(2),
        dims[2].div_ceil(2),
    ]
}

/// The weights `(a, ½ − a, ½ − a, a)`.
pub fn weights(a: f64) -> [f64; 4] {
    [a, 0.5 - a, 0.5 - a, a]
}

/// One level of one channel: returns the coarse dimensions and values.
pub fn filter_channel(dims: [usize; 3], values: &[f64], a: f64) -> ([usize; 3], Vec<f64>) {
    assert_eq!(values.len(), dims[0] * dims[1] * dims[2]);
    let out_dims = ref_level_dims(dims);
    let w = weights(a);
    let clamp = |i: i64, n: usize| -> usize { i.clamp(0, n as i64 - 1) as usize };
    let mut out = Vec::with_capacity(out_dims[0] * out_dims[1] * out_dims[2]);
    for z in 0..out_dims[2] {
        for y in 0..out_dims[1] {
            for x in 0..out_dims[0] {
                let mut sum = 0.0;
                for k in 0..4 {
                    for j in 0..4 {
                        for i in 0..4 {
                            let fx = clamp(2 * x as i64 - 1 + i as i64, dims[0]);
                            let fy = clamp(2 * y as i64 - 1 + j as i64, dims[1]);
                            let fz = clamp(2 * z as i64 - 1 + k as i64, dims[2]);
                            sum += w[i] * w[j] * w[k] * values[linear_index(dims, [fx, fy, fz])];
                        }
                    }
                }
                out.push(sum);
            }
        }
    }
    (out_dims, out)
}

/// The four channels `[c0, c1, c2, α or τ]` of every voxel filtered by one level.
fn filter_channels(dims: [usize; 3], ch: &[[f64; 4]], a: f64) -> ([usize; 3], Vec<[f64; 4]>) {
    let mut out_dims = dims;
    let per: Vec<Vec<f64>> = (0..4)
        .map(|k| {
            let v: Vec<f64> = ch.iter().map(|c| c[k]).collect();
            let (d, o) = filter_channel(dims, &v, a);
            out_dims = d;
            o
        })
        .collect();
    let n = per[0].len();
    (
        out_dims,
        (0..n)
            .map(|i| [per[0][i], per[1][i], per[2][i], per[3][i]])
            .collect(),
    )
}

/// One opacity-based level of associated voxels.
pub fn downsample_opacity(
    dims: [usize; 3],
    voxels: &[RefAssoc],
    a: f64,
) -> ([usize; 3], Vec<RefAssoc>) {
    let ch: Vec<[f64; 4]> = voxels
        .iter()
        .map(|v| [v.color[0], v.color[1], v.color[2], v.alpha])
        .collect();
    let (out_dims, f) = filter_channels(dims, &ch, a);
    let out = f
        .iter()
        .map(|c| {
            let alpha_bar = c[3];
            let alpha = 1.0 - (1.0 - alpha_bar) * (1.0 - alpha_bar);
            let ratio = if alpha_bar > 0.0 {
                alpha / alpha_bar
            } else {
                0.0
            };
            RefAssoc::new([c[0] * ratio, c[1] * ratio, c[2] * ratio], alpha)
        })
        .collect();
    (out_dims, out)
}

/// One extinction-based level of extinction voxels (values per coarse voxel: `2τ̄`, `2C̄^τ`).
pub fn downsample_extinction(
    dims: [usize; 3],
    voxels: &[RefExtinction],
    a: f64,
) -> ([usize; 3], Vec<RefExtinction>) {
    let ch: Vec<[f64; 4]> = voxels
        .iter()
        .map(|v| [v.color_tau[0], v.color_tau[1], v.color_tau[2], v.tau])
        .collect();
    let (out_dims, f) = filter_channels(dims, &ch, a);
    let out = f
        .iter()
        .map(|c| RefExtinction {
            tau: 2.0 * c[3],
            color_tau: [2.0 * c[0], 2.0 * c[1], 2.0 * c[2]],
        })
        .collect();
    (out_dims, out)
}

/// Every level down to `1 × 1 × 1`, level 0 (the input) first.
pub fn chain<T: Clone>(
    dims: [usize; 3],
    voxels: &[T],
    a: f64,
    level: impl Fn([usize; 3], &[T], f64) -> ([usize; 3], Vec<T>),
) -> Vec<([usize; 3], Vec<T>)> {
    let mut out = vec![(dims, voxels.to_vec())];
    while out.last().unwrap().0 != [1, 1, 1] {
        let (d, v) = out.last().unwrap();
        let next = level(*d, v, a);
        out.push(next);
    }
    out
}

/// The level-`level` position of the level-0 position `p`.
pub fn to_level(p: [f64; 3], level: u32) -> [f64; 3] {
    let s = 2f64.powi(level as i32);
    p.map(|x| (x + 0.5) / s - 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_filter_averages_two_by_two_by_two() {
        let v: Vec<f64> = (0..8).map(f64::from).collect();
        let (d, o) = filter_channel([2, 2, 2], &v, 0.0);
        assert_eq!(d, [1, 1, 1]);
        assert!((o[0] - 3.5).abs() < 1e-15);
    }

    #[test]
    fn odd_sizes_round_up_and_clamp() {
        // 3 voxels along x: 0, 0, 8. Coarse voxel 1 reads fine 1, 2, 3→2, 4→2.
        let (d, o) = filter_channel([3, 1, 1], &[0.0, 0.0, 8.0], 0.25);
        assert_eq!(d, [2, 1, 1]);
        assert!((o[0] - 2.0).abs() < 1e-15); // ¼·(0 + 0 + 0 + 8)
        assert!((o[1] - 6.0).abs() < 1e-15); // ¼·(0 + 8 + 8 + 8)
    }
}
