//! Model of the integer `ExtinctionWeighted` path: fixed-point storage, the `φ`/`e^(−x)`
//! tables and the kernel, written from the documented arithmetic of
//! `volsample::fixed_point::{exp_phi, extinction}`.
//!
//! Unlike the opacity-based models, the extinction sums do not fit in an `f64` exactly
//! (`S_τ` has up to 63 significant bits, the products up to 103), so this model keeps every
//! exact intermediate as an integer (`u128`) and rounds each documented quotient with its own
//! **round half up** (`q = ⌊n/d⌋`, plus one when the remainder is at least `d/2`). Table
//! entries and storage conversions are computed in `f64` with `std`'s `exp_m1`, `exp`,
//! `ln_1p`, independently of the core's `libm`. The real-valued results the bounds are
//! measured against ([`exact`], [`reference()`]) are plain `f64` formulas.

use super::{round_half_up, ONE};

/// `2^20`: one in the U7.20 depth format.
pub const DEPTH_UNIT: f64 = 1_048_576.0;
/// The depth cap (`MAX_OPTICAL_DEPTH`).
pub const MAX_DEPTH: f64 = 64.0;
/// `64·2^20`.
pub const MAX_DEPTH_RAW: u32 = 64 << 20;

/// **Round half up** of the exact quotient `n/d` (`d > 0`), by remainder.
pub fn rhu(n: u128, d: u128) -> u128 {
    let (q, r) = (n / d, n % d);
    if r >= d - r {
        q + 1
    } else {
        q
    }
}

/// `min(−ln(1 − α), 64)`, the capped optical depth per `d′`.
pub fn depth(a: f64) -> f64 {
    (-(-a).ln_1p()).min(MAX_DEPTH)
}

/// Stored depth of opacity `a ∈ [0, 1]`: `⌊2^20·depth(a) + ½⌋`.
pub fn depth_raw(a: f64) -> u32 {
    round_half_up(depth(a) * DEPTH_UNIT) as u32
}

/// The stored `(D, D·C)` of a straight `u8` voxel `[r, g, b, a]`.
pub fn from_u8(v: [u8; 4]) -> (u32, [u32; 3]) {
    let t = depth_raw(f64::from(v[3]) / 255.0);
    let c = |c: u8| round_half_up(f64::from(t) * f64::from(c) / 255.0) as u32;
    (t, [c(v[0]), c(v[1]), c(v[2])])
}

/// The stored `(D, D·C)` of a straight `f32` voxel in `[0, 1]`.
pub fn from_f32(c: [f32; 3], a: f32) -> (u32, [u32; 3]) {
    let t = depth_raw(f64::from(a));
    (
        t,
        c.map(|c| round_half_up(f64::from(t) * f64::from(c)) as u32),
    )
}

/// `r` quantized: `⌊r·2^32 + ½⌋`.
pub fn ratio_raw(r: f32) -> u64 {
    round_half_up(f64::from(r) * 4_294_967_296.0) as u64
}

/// `φ(x) = (1 − e^(−x))/x`, `φ(0) = 1`.
pub fn phi(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else {
        -(-x).exp_m1() / x
    }
}

/// The model's tables for `n = 2^B + 1` nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Tables {
    /// `B`.
    pub b: u32,
    /// `⌊2^31·φ(j/2^B) + ½⌋`.
    pub phi: Vec<u32>,
    /// `⌊2^31·e^(−j/2^B) + ½⌋`.
    pub exp: Vec<u32>,
    /// `⌊2^32·e^(−n) + ½⌋`, `n = 1..=15`.
    pub exp_int: Vec<u32>,
}

/// Builds the tables for `n` nodes (`n − 1` a power of two).
pub fn tables(n: usize) -> Tables {
    let b = (n - 1).trailing_zeros();
    let s = f64::from(1u32 << b);
    let x = |j: usize| j as f64 / s;
    Tables {
        b,
        phi: (0..n)
            .map(|j| round_half_up(phi(x(j)) * 2_147_483_648.0) as u32)
            .collect(),
        exp: (0..n)
            .map(|j| round_half_up((-x(j)).exp() * 2_147_483_648.0) as u32)
            .collect(),
        exp_int: (1..=15)
            .map(|n| round_half_up((-f64::from(n)).exp() * 4_294_967_296.0) as u32)
            .collect(),
    }
}

impl Tables {
    /// `k = 28 − B`.
    pub fn k(&self) -> u32 {
        28 - self.b
    }

    fn interp(&self, t: &[u32], arg: u64) -> u128 {
        let k = self.k();
        let i = (arg >> k) as usize;
        let f = u128::from(arg % (1 << k));
        u128::from(t[i]) * ((1u128 << k) - f) + u128::from(t[i + 1]) * f
    }

    /// `α` (and `C̃` for `x_c ≤ x`) of a step with optical depth `x_raw/2^28`, the model of
    /// steps 3–5 given the exact sums (`s_t`, `s_c`) for the `x ≥ 1` color.
    pub fn integrate(&self, x: u64, xc: [u64; 3], s_t: u128, s_c: [u128; 3]) -> ([u16; 3], u16) {
        let one = u128::from(ONE as u16);
        let k = self.k();
        if x < 1 << 28 {
            let p = self.interp(&self.phi, x);
            let d = 1u128 << (59 + k);
            let a = rhu(one * u128::from(x) * p, d) as u16;
            let c = xc.map(|xc| rhu(one * u128::from(xc) * p, d) as u16);
            return (c, a);
        }
        let n = x >> 28;
        let a = if n >= 16 {
            ONE as u16
        } else {
            let q =
                u128::from(self.exp_int[n as usize - 1]) * self.interp(&self.exp, x % (1 << 28));
            let d = 1u128 << (63 + k);
            rhu(one * (d - q), d) as u16
        };
        let c = s_c.map(|sc| rhu(u128::from(a) * sc, s_t) as u16);
        (c, a)
    }
}

/// Exact integer trilinear weights at `F` bits (`(2^F − f, f)` per axis, corner `i` at
/// `(i & 1, (i >> 1) & 1, i >> 2)`), summing to `2^(3F)`.
pub fn int_weights(frac_bits: u32, frac: [u32; 3]) -> [u128; 8] {
    let one = 1u128 << frac_bits;
    let p = frac.map(|f| [one - u128::from(f), u128::from(f)]);
    std::array::from_fn(|i| p[0][i & 1] * p[1][(i >> 1) & 1] * p[2][i >> 2])
}

/// The model of the kernel: stored voxels `(D, D·C)`, integer weights summing to `2^shift`,
/// the quantized ratio, the tables.
pub fn kernel(
    taps: &[(u32, [u32; 3])],
    w: &[u128],
    shift: u32,
    r: u64,
    t: &Tables,
) -> ([u16; 3], u16) {
    let mut s_t = 0u128;
    let mut s_c = [0u128; 3];
    for (&(tau, c), &w) in taps.iter().zip(w) {
        let tau = tau.min(MAX_DEPTH_RAW);
        s_t += w * u128::from(tau);
        for k in 0..3 {
            s_c[k] += w * u128::from(c[k].min(tau));
        }
    }
    let depth = |s: u128| -> u64 {
        let x = rhu(s * u128::from(r), 1u128 << (shift + 24));
        x.min(16 << 28) as u64
    };
    t.integrate(depth(s_t), s_c.map(depth), s_t, s_c)
}

/// The exact `(C̃, α)` (U8.8 units, unrounded) of the method on stored voxels with real
/// weights and ratio `r`: `x = r·Σw·D/2^20`, `α = 1 − e^(−x)`, `C̃ = r·Σw·(D·C)/2^20·φ(x)`.
pub fn exact(taps: &[(u32, [u32; 3])], w: &[f64], r: f64) -> ([f64; 3], f64) {
    let mut d = 0.0;
    let mut c = [0.0f64; 3];
    for (&(tau, ct), &w) in taps.iter().zip(w) {
        d += w * f64::from(tau) / DEPTH_UNIT;
        for k in 0..3 {
            c[k] += w * f64::from(ct[k]) / DEPTH_UNIT;
        }
    }
    let x = d * r;
    (c.map(|c| ONE * c * r * phi(x)), -ONE * (-x).exp_m1())
}

/// The `f64` reference on the straight voxels themselves (no storage rounding): depths
/// `min(−ln(1 − α), 64)`, `C^τ·d′ = D·C`, then as [`exact`].
pub fn reference(taps: &[[u8; 4]], w: &[f64], r: f64) -> ([f64; 3], f64) {
    let mut d = 0.0;
    let mut c = [0.0f64; 3];
    for (v, &w) in taps.iter().zip(w) {
        let dv = depth(f64::from(v[3]) / 255.0);
        d += w * dv;
        for k in 0..3 {
            c[k] += w * dv * f64::from(v[k]) / 255.0;
        }
    }
    let x = d * r;
    (c.map(|c| ONE * c * r * phi(x)), -ONE * (-x).exp_m1())
}
