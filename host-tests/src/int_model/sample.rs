//! Models of the integer sampling kernels (`OpacityWeighted`, `Separate`, `Preweighted`).

use super::{round_half_up, to_u16, Modelled, ONE};

/// Integer `OpacityWeighted` on straight bytes `[r, g, b, a]` with real weights `w` (summing
/// to 1): exact `α = 256·Σ w·α_i`, `C̃ = 256·Σ w·α_i·C_i/255`; each **round half up**.
pub fn opacity_weighted(taps: &[[u8; 4]], w: &[f64]) -> Modelled {
    let mut s_a = 0.0;
    let mut s_c = [0.0f64; 3];
    for (v, &w) in taps.iter().zip(w) {
        let a = f64::from(v[3]);
        s_a += w * a;
        for k in 0..3 {
            s_c[k] += w * a * f64::from(v[k]);
        }
    }
    let exact_a = 256.0 * s_a;
    let exact_c = s_c.map(|s| 256.0 * s / 255.0);
    Modelled {
        exact_c,
        exact_a,
        c: exact_c.map(|x| to_u16(round_half_up(x))),
        a: to_u16(round_half_up(exact_a)),
    }
}

/// Integer `Separate`: `α = ⌊256·Σ w·α_i + ½⌋`, `C = ⌊256·Σ w·C_i + ½⌋`,
/// `C̃ = ⌊α·C/ONE + ½⌋` (all **round half up**). Exact value: `α_e·C_e/ONE` of the unrounded.
pub fn separate(taps: &[[u8; 4]], w: &[f64]) -> Modelled {
    let mut s_a = 0.0;
    let mut s_c = [0.0f64; 3];
    for (v, &w) in taps.iter().zip(w) {
        s_a += w * f64::from(v[3]);
        for k in 0..3 {
            s_c[k] += w * f64::from(v[k]);
        }
    }
    let exact_a = 256.0 * s_a;
    let a = round_half_up(exact_a);
    let exact_c = s_c.map(|s| exact_a * 256.0 * s / ONE);
    let c = s_c.map(|s| to_u16(round_half_up(a * round_half_up(256.0 * s) / ONE)));
    Modelled {
        exact_c,
        exact_a,
        c,
        a: to_u16(a),
    }
}

/// Integer `Preweighted` on associated bytes: `α = ⌊256·Σ w·α_i + ½⌋`,
/// `C̃ = ⌊256·Σ w·C̃_i + ½⌋` (**round half up**).
pub fn preweighted(taps: &[[u8; 4]], w: &[f64]) -> Modelled {
    let mut s_a = 0.0;
    let mut s_c = [0.0f64; 3];
    for (v, &w) in taps.iter().zip(w) {
        s_a += w * f64::from(v[3]);
        for k in 0..3 {
            s_c[k] += w * f64::from(v[k].min(v[3]));
        }
    }
    let exact_a = 256.0 * s_a;
    let exact_c = s_c.map(|s| 256.0 * s);
    Modelled {
        exact_c,
        exact_a,
        c: exact_c.map(|x| to_u16(round_half_up(x))),
        a: to_u16(round_half_up(exact_a)),
    }
}
