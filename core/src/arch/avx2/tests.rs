// Tests may map arrays the standard way (`core/clippy.toml` is about the kernels' IR).
#![allow(clippy::disallowed_methods)]

use super::*;
use crate::mode::{ExtinctionWeighted, LaneMode};
use crate::sample::Interp;
use crate::voxel::StraightU8;

mod gathers;

fn indices(a: [i32; LANES]) -> __m256i {
    from_i32s(a)
}

/// xorshift64: deterministic test data from `seed` (not 0).
fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

/// `Taps::new` proves the indices inside exactly when all 64 are below the length (as
/// unsigned numbers), and both loads read the voxels' words; an index outside reads the
/// transparent voxel.
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn taps_are_loaded_unchecked_only_when_all_indices_are_inside() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { taps_check() }
}

#[target_feature(enable = "avx2,fma")]
fn taps_check() {
    let data: [StraightU8; 10] = core::array::from_fn(|i| StraightU8([i as u8, 1, 2, 200]));
    let word = |i: usize| data.get(i).map_or(0, |v| i32::from_le_bytes(v.0));
    let ok = [0, 1, 2, 3, 4, 5, 8, 9];
    for bad in [None, Some(10), Some(-1), Some(i32::MAX)] {
        let mut at = [indices(ok); 8];
        if let Some(b) = bad {
            let mut lanes = ok;
            lanes[5] = b;
            at[3] = indices(lanes);
        }
        let taps = Taps::new(&data, at);
        assert_eq!(taps.inside(), bad.is_none(), "{bad:?}");
        for k in 0..8 {
            for got in [
                to_i32s(taps.load::<true>(k)),
                to_i32s(taps.load::<false>(k)),
            ] {
                let want = ok.map(|i| word(i as usize));
                if k == 3 && bad.is_some() {
                    assert_eq!(got[5], 0, "{bad:?}");
                    assert_eq!(got[..5], want[..5]);
                    assert_eq!(got[6..], want[6..]);
                } else {
                    assert_eq!(got, want, "{bad:?} tap {k}");
                }
            }
        }
    }
    assert!(!Taps::<StraightU8>::new(&[], [indices([0; LANES]); 8]).inside());
}

/// `Taps::new` sets `pairs` exactly where every odd tap lies just after its even one or at
/// it (x clamped at an edge), all inside and every even tap's pair too, in `StraightU8`
/// data; `load_pair` reads what `load` reads, with `pairs` or without (its fallback), for
/// even and odd `k`, and `load_pair_tau` the same words with the `τ` of their opacity bytes.
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn pairs_are_read_only_side_by_side() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    assert_eq!(unsafe { pairs_check() }, Ok(()));
}

/// A format like `StraightU8` but not it: never read in pairs, and read as transparent
/// words (the kernels read words of `StraightU8` only; `Voxel::as_straight_u8`).
#[derive(Clone, Copy)]
// (Its bytes are what no load may read.)
#[allow(dead_code)]
struct Other([u8; 4]);

impl Voxel for Other {
    const TRANSPARENT: Self = Self([0; 4]);
    fn check(&self) -> Result<(), crate::voxel::VoxelFault> {
        Ok(())
    }
}

#[target_feature(enable = "avx2,fma")]
fn pairs_check() -> Result<(), crate::Error> {
    let table = crate::mode::TauTable::new(0.7)?;
    let bytes = |i: usize| [i as u8, 3 * i as u8, 7, 255 - i as u8];
    let data: [StraightU8; 20] = core::array::from_fn(|i| StraightU8(bytes(i)));
    let other: [Other; 20] = core::array::from_fn(|i| Other(bytes(i)));
    let even = [0, 3, 7, 2, 10, 18, 5, 11];
    let odd = even.map(|i| i + 1);
    let side_by_side = [even, odd, even, odd, even, odd, even, odd].map(indices);
    let mut apart = side_by_side;
    apart[5] = indices([1, 4, 8, 3, 12, 19, 6, 12]);
    let mut outside = side_by_side;
    outside[0] = indices([0, 3, 7, 2, 10, 19, 5, 11]);
    outside[1] = indices([1, 4, 8, 3, 11, 20, 6, 12]);
    // x clamped at an edge of the grid in some lanes: tap `k + 1` is tap `k`'s voxel there,
    // read from the pair starting at it.
    let mut clamped = side_by_side;
    clamped[3] = indices([0, 4, 7, 3, 10, 18, 6, 11]);
    clamped[7] = indices(even);
    // The same, but with tap `k` the last voxel of the data: its pair would end outside.
    let mut last = clamped;
    last[2] = indices([0, 3, 7, 2, 10, 19, 5, 11]);
    last[3] = indices([0, 4, 7, 3, 10, 19, 6, 11]);
    // A step of −1 from tap `k` to tap `k + 1` (`apart` has one of 2).
    let mut backwards = side_by_side;
    backwards[1] = indices([1, 4, 8, 1, 11, 19, 6, 12]);
    // One voxel: inside, but no pair fits (every lane's taps clamped together).
    assert!(Taps::new(&data[..1], [indices([0; LANES]); 8]).inside());
    assert!(!Taps::new(&data[..1], [indices([0; LANES]); 8]).pairs());
    for (at, pairs) in [
        (side_by_side, true),
        (apart, false),
        (outside, false),
        (clamped, true),
        (last, false),
        (backwards, false),
    ] {
        let taps = Taps::new(&data, at);
        assert_eq!(taps.pairs(), pairs);
        let others = Taps::new(&other, at);
        assert!(!others.pairs());
        for k in 0..7 {
            let want = [taps.load::<false>(k), taps.load::<false>(k + 1)].map(to_i32s);
            assert_eq!(taps.load_pair(k).map(to_i32s), want, "tap {k}, {pairs}");
            assert_eq!(
                others.load_pair(k).map(to_i32s),
                [[0; 8]; 2],
                "tap {k}, {pairs}"
            );
            // With the `τ` of each word's opacity byte (0 for the transparent words).
            // SAFETY: this function's AVX2 and FMA; so below.
            let got = unsafe { taps.load_pair_tau(k, table.taus()) };
            // SAFETY: as above.
            let got_others = unsafe { others.load_pair_tau(k, table.taus()) };
            for (got, want) in [(got, want), (got_others, [[0; 8]; 2])] {
                for ((word, tau), want) in got.into_iter().zip(want) {
                    assert_eq!(to_i32s(word), want, "tap {k}, {pairs}");
                    let want = want.map(|w| table.tau((w as u32 >> 24) as u8).to_bits());
                    assert_eq!(array(tau).map(f32::to_bits), want, "tap {k}, {pairs}");
                }
            }
        }
    }
    Ok(())
}

/// `integrate_in` in `F32x8` lanes (the kernel's extinction step) is `integrate_step` in
/// every lane:
/// packets of sums all below `τd = 1` (the lanes' path: `phi_poly`), among them whole
/// packets of tiny `τd` (`2⁻³⁰..2⁻¹⁰`) and packets just below 1, and packets with a lane
/// at or above 1, NaN, infinite or negative `τ` (the per-lane path); colors `C^τ ≤ τ`
/// mostly, so that `φ` shows (the clamp of `C̃` into `[0, α]` would hide it).
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn extinction_step_is_integrate_step_per_lane() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { extinction_check() }
}

#[target_feature(enable = "avx2,fma")]
fn extinction_check() {
    let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
    let mut unit = || (next() >> 40) as f32 / (1u64 << 24) as f32;
    // Under Miri (an interpreter) every 73rd case: 274 cases, of every kind below.
    for case in (0..20_000).step_by(if cfg!(miri) { 73 } else { 1 }) {
        let d = match case % 4 {
            0 => 0.5,
            1 => 1.0,
            2 => 0.3,
            _ => 2.0,
        };
        let wild = case % 3 == 0;
        // `τ` per lane: some whole packets of tiny `τd`, some of `τd` in `[0.9, 1)`, else
        // mostly `[0, 0.9)`, with single lanes of edge values (1 and just below it among
        // them).
        let tiny = case % 7 == 0;
        let near_one = case % 11 == 0;
        let tau: [f32; LANES] = core::array::from_fn(|l| {
            let u = unit();
            if tiny {
                libm::exp2f(-10.0 - 20.0 * u) / d
            } else if near_one {
                (0.9 + 0.1 * u).min(f32::from_bits(1.0f32.to_bits() - 1)) / d
            } else if l == case % 8 && u < 0.1 {
                match l % 4 {
                    0 => 0.0,
                    1 => 1e-9,
                    2 => 3e-5,
                    _ => 2e-4,
                }
            } else if wild && l == 3 {
                match case % 6 {
                    0 => f32::NAN,
                    1 => f32::INFINITY,
                    2 => 40.0,
                    3 => 1.0 / d,
                    4 => 1.02 / d,
                    _ => -1.0,
                }
            } else {
                u * 0.9 / d
            }
        });
        // `C^τ = τ·C` (so that the clamps of `C̃` into `[0, α]` rarely hide `φ`), and
        // sometimes above `τ`.
        let s: [[f32; LANES]; 4] = core::array::from_fn(|k| {
            if k == 3 {
                return tau;
            }
            core::array::from_fn(|l| {
                let t = tau.get(l).copied().unwrap_or(0.0);
                let u = unit();
                if case % 5 == 0 {
                    u * 0.3
                } else {
                    t * u
                }
            })
        });
        let [c, a] = [[s[0], s[1], s[2]], [s[3]; 3]].map(|v| v.map(|v| F32x8(lanes(v))));
        let i = <ExtinctionWeighted as LaneMode>::finish_lanes(Interp { c, a: a[0] }, d);
        let c = i.c.map(|c| array(c.0));
        let a = array(i.a.0);
        for l in 0..LANES {
            let [r, g, b, t] = s.map(|v| v.get(l).copied().unwrap_or(0.0));
            let want = crate::mode::integrate_step([r, g, b], t, d);
            let got = c.map(|c| c.get(l).copied().unwrap_or(-1.0));
            let got_a = a.get(l).copied().unwrap_or(-1.0);
            assert_eq!(
                got_a.to_bits(),
                want.a.to_bits(),
                "α, case {case}, lane {l}"
            );
            for (g, w) in got.into_iter().zip(want.c) {
                assert_eq!(g.to_bits(), w.to_bits(), "C̃, case {case}, lane {l}");
            }
        }
    }
}

/// Opacity correction in the eight lanes (`Corrected::apply_in`, the kernel's) is
/// `opacity::correct` lane by lane, bit for bit (a zero's sign aside): packets whose lanes all
/// lie in the series form (`α < 1/2`, `x < 1`), packets with one lane outside it (`α` at or
/// above 1/2, at 1, 0, subnormal, negative, NaN: the per-lane path), whole packets of `α = 0`
/// and of `α = 1`, at ratios on both sides of where `x` reaches 1.
#[test]
fn correction_is_correct_per_lane() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { correction_check() }
}

#[target_feature(enable = "avx2,fma")]
fn correction_check() {
    use crate::opacity::{correct, Corrected, Correction};
    let mut next = xorshift(0x2545_F491_4F6C_DD1D);
    let mut unit = || (next() >> 40) as f32 / (1u64 << 24) as f32;
    let ratios = [1e-3f32, 0.25, 0.5, 0.8, 1.0, 1.3, 1.6, 3.0, 40.0];
    let mut fast = 0;
    for case in 0..20_000usize {
        let r = ratios.get(case % ratios.len()).copied().unwrap_or(0.5);
        let odd = case % 3 == 0;
        // Whole packets of empty and of opaque samples (the early outs), beside mixed ones.
        let whole = match case % 13 {
            0 => Some(0.0),
            1 => Some(1.0),
            _ => None,
        };
        let alpha: [f32; LANES] = core::array::from_fn(|l| {
            let u = unit();
            if let Some(w) = whole {
                w
            } else if odd && l == case % LANES {
                match case % 8 {
                    0 => 0.5 + 0.5 * u,
                    1 => 1.0,
                    2 => 0.0,
                    3 => 1e-40,
                    4 => -0.25,
                    5 => f32::NAN,
                    6 => f32::from_bits(0.5f32.to_bits() - 1),
                    _ => 0.999_9,
                }
            } else if case % 5 == 0 {
                libm::exp2f(-24.0 * u) * 0.5
            } else {
                0.5 * u
            }
        });
        let color: [[f32; LANES]; 3] = core::array::from_fn(|k| {
            core::array::from_fn(|l| {
                let a = alpha.get(l).copied().unwrap_or(0.0);
                let u = unit();
                if k == 2 && case % 7 == 0 {
                    u
                } else {
                    a * u
                }
            })
        });
        if alpha.iter().all(|&a| a < 0.5) && r < 1.4 {
            fast += 1;
        }
        let i = Interp {
            c: color.map(|c| F32x8(lanes(c))),
            a: F32x8(lanes(alpha)),
        };
        let corr = Corrected::new(r);
        assert!(corr.is_some(), "ratio {r}");
        let o = corr.map_or(i, |c| c.apply_in(i));
        let (c, a) = (o.c.map(|c| array(c.0)), array(o.a.0));
        let same = |g: f32, w: f32| g == w || g.to_bits() == w.to_bits();
        for l in 0..LANES {
            let at = |v: &[f32; LANES]| v.get(l).copied().unwrap_or(-1.0);
            let s = crate::sample::Sample {
                c: color.each_ref().map(at),
                a: at(&alpha),
            };
            let want = correct(s, r);
            assert!(
                same(at(&a), want.a),
                "α, case {case}, lane {l}: {s:?} r = {r}"
            );
            for (g, w) in c.each_ref().map(at).into_iter().zip(want.c) {
                assert!(same(g, w), "C̃, case {case}, lane {l}: {s:?} r = {r}");
            }
        }
    }
    // Most packets take the series form in lanes.
    assert!(fast > 5_000, "{fast}");
}

/// `over_u16` is `⌊(t·x + ONE/2)/ONE⌋` (`fixed_point::front_to_back`'s increment, in `u64`
/// here) for every pair `t, x ≤ ONE`, in every 16-bit lane.
#[test]
#[cfg_attr(
    miri,
    ignore = "exhaustive (every pair of U8.8 values): too slow for Miri; runs natively and under ASan"
)]
fn over_u16_is_the_rounded_increment_for_every_pair() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { over_u16_check() }
}

#[target_feature(enable = "avx2,fma")]
fn over_u16_check() {
    const ONE: u16 = crate::fixed_point::ONE;
    let want = |t: u16, x: u16| {
        let one = u64::from(ONE);
        ((u64::from(t) * u64::from(x) + one / 2) / one) as u16
    };
    for t in 0..=ONE {
        let tv = _mm256_set1_epi16(t as i16);
        for x0 in (0..=ONE).step_by(16) {
            // Lane `l` holds one of `x0..x0 + 16`, rotated by `t` and `x0`, so that every `x`
            // meets every lane; past `ONE` (the last vector), `ONE` again.
            let xs: [u16; 16] = core::array::from_fn(|l| {
                let k = (l as u16).wrapping_add(t).wrapping_add(x0 / 16) & 15;
                x0.saturating_add(k).min(ONE)
            });
            // SAFETY: a bit cast between two 32-byte plain-data types.
            let xv = unsafe { core::mem::transmute::<[u16; 16], __m256i>(xs) };
            // SAFETY: as above.
            let got = unsafe { core::mem::transmute::<__m256i, [u16; 16]>(over_u16(tv, xv)) };
            assert_eq!(got, xs.map(|x| want(t, x)), "t = {t}, x = {xs:?}");
        }
    }
}

/// `⌊(q + 1)·RECIP255/2^32⌋ = ⌊q/255⌋` for every `q < 2^24` (the quotient `int_sums`
/// forms; `black_box` keeps the compiler from folding the comparison).
#[test]
#[cfg_attr(
    miri,
    ignore = "exhaustive (2^24 quotients): too slow for Miri; runs natively and under ASan"
)]
fn quotient_by_255_is_exact_below_2_24() {
    let m = u64::from(core::hint::black_box(RECIP255));
    for q in 0u64..1 << 24 {
        assert_eq!(((q + 1) * m) >> 32, q / 255, "q = {q}");
    }
}

/// `quantize8` is `⌊256·p + ½⌋` for every `f32` `p` in `[0, 2^14)` (`IntPos::quantize`'s
/// `⌊x·2^8 + ½⌋`, which it computes in `f64`), in every lane.
#[test]
#[cfg_attr(
    miri,
    ignore = "exhaustive (every f32 below 2^14): too slow for Miri; runs natively and under ASan"
)]
fn quantization_rounds_half_up_for_every_f32_below_2_14() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { quantize8_check() }
}

#[target_feature(enable = "avx2,fma")]
fn quantize8_check() {
    let end = 16_384f32.to_bits();
    for b0 in (0..end).step_by(LANES) {
        let lanes: [f32; LANES] =
            core::array::from_fn(|l| f32::from_bits((b0 + ((l as u32 + b0 / 8) & 7)).min(end - 1)));
        let got = to_i32s(quantize8(super::lanes(lanes)));
        let want = lanes.map(|p| libm::floor(f64::from(p) * 256.0 + 0.5) as i32);
        assert_eq!(got, want, "{lanes:?}");
    }
}

/// `int_sums` is `IntMode::combine` of `OpacityWeighted` at `F = 8`, bit for bit: the
/// widest sums (all bytes 255, and opaque taps of mixed colors), the extreme fractions
/// (0, 1, 127, 128, 254, 255 on each axis), and random taps and fractions; with the taps
/// packed into pairs along x and along y ([`int_pair`]).
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn integer_sums_are_the_portable_kernel() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { int_sums_check() }
}

#[target_feature(enable = "avx2,fma")]
fn int_sums_check() {
    use crate::fixed_point::{IntMode, IntWeights};
    let mut next = xorshift(0x2545_F491_4F6C_DD1D);
    let edges = [0u32, 1, 127, 128, 254, 255];
    // Under Miri (an interpreter) every 47th case: 128 cases, edge fractions and random.
    for case in (0..6000).step_by(if cfg!(miri) { 47 } else { 1 }) {
        // Eight lanes of taps (tap `k` of lane `l`) and fractions.
        let taps: [[StraightU8; 8]; LANES] = core::array::from_fn(|_| {
            core::array::from_fn(|_| {
                let r = next().to_le_bytes();
                match case % 3 {
                    0 => StraightU8([255; 4]),
                    1 => StraightU8([r[0], r[1], r[2], 255]),
                    _ => StraightU8([r[0], r[1], r[2], r[3]]),
                }
            })
        });
        let frac: [[u32; 3]; LANES] = core::array::from_fn(|l| {
            core::array::from_fn(|k| {
                if case < 216 * 8 {
                    let e = case / 8 + l;
                    let pick = [e % 6, (e / 6) % 6, (e / 36) % 6];
                    edges
                        .get(pick.get(k).copied().unwrap_or(0))
                        .copied()
                        .unwrap_or(0)
                } else {
                    (next() & 0xff) as u32
                }
            })
        });
        let word = |k: usize| {
            indices(core::array::from_fn(|l| {
                let t = taps.get(l).and_then(|t| t.get(k)).copied();
                i32::from_le_bytes(t.unwrap_or(StraightU8([0; 4])).0)
            }))
        };
        let f = |k: usize| {
            indices(core::array::from_fn(|l| {
                frac.get(l).and_then(|f| f.get(k)).copied().unwrap_or(0) as i32
            }))
        };
        // Pairs along x (taps `2j`, `2j + 1`), and along y (taps `b`, `b + 2`, with the
        // fractions of y and x swapped), as the kernel forms them.
        let along_x = int_sums(
            |j| int_pair(word(2 * j), word(2 * j + 1)),
            [f(0), f(1), f(2)],
        );
        let base = |j: usize| (j & 1) | ((j >> 1) << 2);
        let along_y = int_sums(
            |j| int_pair(word(base(j)), word(base(j) + 2)),
            [f(1), f(0), f(2)],
        );
        for (first, got) in [("x", along_x), ("y", along_y)] {
            let got = got.map(|v| to_i32s(_mm256_castps_si256(v)));
            for l in 0..LANES {
                let (Some(t), Some(&fr)) = (taps.get(l), frac.get(l)) else {
                    continue;
                };
                let want = crate::OpacityWeighted.combine(t, &IntWeights::trilinear_frac::<8>(fr));
                let [r, g, b, a] = got.map(|c| c.get(l).copied().unwrap_or(-1));
                assert_eq!(
                    ([r, g, b], a),
                    (want.c().map(i32::from), i32::from(want.a())),
                    "pairs along {first}, case {case}, lane {l}: {t:?} {fr:?}"
                );
            }
        }
    }
}

/// `unorm8` of every byte, in each lane, is the table's correctly rounded `n/255`.
#[test]
#[cfg_attr(
    all(miri, not(all(target_feature = "avx2", target_feature = "fma"))),
    ignore = "Miri: no AVX2 (Avx2::detect answers the compiled target features there)"
)]
fn byte_conversion_is_the_correctly_rounded_quotient() {
    let Some(_cpu) = Avx2::detect() else {
        return; // no AVX2 here: nothing to check (`tests/isa.rs` checks the detection)
    };
    // SAFETY: `detect` found AVX2 and FMA on this CPU.
    unsafe { unorm8_check() }
}

#[target_feature(enable = "avx2,fma")]
fn unorm8_check() {
    for n in 0..=255 {
        let lanes: [i32; LANES] = core::array::from_fn(|l| (n + 37 * l as i32) & 0xff);
        let got = array(unorm8(indices(lanes)));
        for (g, b) in got.into_iter().zip(lanes) {
            let want = crate::voxel::unorm8(b as u8);
            assert_eq!(g.to_bits(), want.to_bits(), "byte {b}: {g} against {want}");
        }
    }
}
