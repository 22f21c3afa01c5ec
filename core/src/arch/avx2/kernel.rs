//! The march: eight rays (or eight samples of one ray) in the lanes, step by step.

use core::arch::x86_64::*;

use super::*;

/// [`march8`] (or [`march8_int`]) in AVX2; where `REUSE` (parallel rays), the taps' channels
/// kept as faces across axis `A` ([`Cell`]) and the voxels ahead prefetched. Returns the
/// accumulated `[r, g, b, α]` lanes as bit patterns.
///
/// Where `ONE` ([`march_one`]), the eight lanes are eight consecutive samples of one ray
/// instead (`rays[0]`, `ranges[0]`; lane `l` of step `j` is sample `8j + l`, at
/// `t₀ + (8j + l)·d` as the one-ray march computes it), composited in order, one lane after
/// the other, by `composite::front_to_back` until `A ≥ a_stop` after a sample: then lane 0 of
/// the four arrays holds the accumulated sample and lane 1 of the first the number of samples
/// composited. (Not inlined: its four instances
/// inlined into `march8` slowed the reuse by about a tenth in a probe, 5.7 against 5.15
/// ns/sample. Not returning the vectors themselves: returned through memory, they kept the
/// accumulator there across the loop, which took the `ExtinctionWeightedU8` packets from 7.1
/// to 8.6 ns/sample.)
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
pub(super) fn march8_avx2<
    V: Voxel,
    const MODE: u8,
    const A: usize,
    const REUSE: bool,
    const ONE: bool,
>(
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    ranges: &[(f32, u32); LANES],
    d: f32,
    a_stop: f32,
    taus: &[f32; 256],
) -> [[i32; LANES]; 4] {
    let data = vol.data();
    let [nx, ny, nz] = vol.dims().map(|n| n as i32);
    // Per axis: (origin, direction, last voxel index, `n` as `f32`).
    let (org, dir) = (
        rays.each_ref().map(Ray::origin),
        rays.each_ref().map(Ray::dir),
    );
    let lead = PREFETCH_STEPS * d;
    let axis = |o: [f32; LANES], d: [f32; LANES], n: i32| {
        (
            lanes(o),
            lanes(d),
            _mm256_set1_epi32(n - 1),
            _mm256_set1_ps(n as f32),
            _mm256_mul_ps(lanes(d), _mm256_set1_ps(lead)),
        )
    };
    let axes = [
        axis(org.map(|o| o[0]), dir.map(|d| d[0]), nx),
        axis(org.map(|o| o[1]), dir.map(|d| d[1]), ny),
        axis(org.map(|o| o[2]), dir.map(|d| d[2]), nz),
    ];
    let t0 = lanes(ranges.map(|r| r.0));
    let count = ranges.map(|r| r.1);
    // (With `ONE`, every range is the one ray's.)
    let [(_, samples), ..] = *ranges;
    let steps = if ONE {
        samples.div_ceil(LANES as u32)
    } else {
        count.iter().copied().max().unwrap_or(0)
    };
    let [c0, c1, c2, c3, c4, c5, c6, c7] = count.map(|c| c as i32);
    let count = _mm256_setr_epi32(c0, c1, c2, c3, c4, c5, c6, c7);

    let dv = _mm256_set1_ps(d);
    let stop = _mm256_set1_ps(a_stop);
    let one = _mm256_set1_ps(1.0);
    let zf = _mm256_setzero_ps();
    let zero = _mm256_setzero_si256();
    // `⌊p⌋` is limited to `[−1, n]` before the conversion (the clamp below maps both ends to
    // the edge), so no coordinate overflows an `i32` lane.
    let lo_f = _mm256_set1_ps(-1.0);
    let ione = _mm256_set1_epi32(1);
    let (sx, sy) = (_mm256_set1_epi32(nx), _mm256_set1_epi32(nx * ny));

    // The sample of the sums `s`: the mode's `finish_in` in `F32x8` lanes (`Sample::clamped`
    // of the sums for `OpacityWeighted`; `Separate` first weights the colors by the clamped
    // `α`; the extinction modes integrate the step, `integrate_in`).
    let finish = |s: [__m256; 4]| {
        if MODE == INTEGER_OW {
            // (The sample itself.)
            return s;
        }
        let i = interp(s);
        let i = if extinction(MODE) {
            integrate_in(i, d)
        } else if MODE == SEPARATE {
            <Separate as Mode<StraightU8>>::finish_in(&Separate, i, d)
        } else {
            <OpacityWeighted as Mode<StraightU8>>::finish_in(&OpacityWeighted, i, d)
        };
        vectors(i)
    };
    // `front_to_back` of sample `[cr, cg, cb, a]` onto `acc`, kept in the live lanes only.
    let over = |acc: [__m256; 4], s: [__m256; 4], live: __m256| {
        if MODE == INTEGER_OW {
            let [ar, ag, ab, aa] = acc;
            let [cr, cg, cb, a] = s;
            // `fixed_point::front_to_back`: `T = ONE − A`, each channel plus
            // `⌊(T·x + ONE/2)/ONE⌋` (`T·x + ONE/2 < 2^32`: the wrapping `i32` product is the
            // `u32` one). A lane that is not live takes `T = 0`, whose increments are
            // `⌊(ONE/2)/ONE⌋ = 0`.
            let int = _mm256_castps_si256;
            let t = _mm256_sub_epi32(_mm256_set1_epi32(INT_ONE), int(aa));
            let t = _mm256_and_si256(t, int(live));
            let half = _mm256_set1_epi32(INT_ONE / 2);
            let step = |acc: __m256, x: __m256| {
                let n = _mm256_add_epi32(_mm256_mullo_epi32(t, int(x)), half);
                _mm256_castsi256_ps(_mm256_add_epi32(int(acc), div65280(n)))
            };
            return [step(ar, cr), step(ag, cg), step(ab, cb), step(aa, a)];
        }
        vectors(front_to_back_in(interp(acc), interp(s), Mask8(live)))
    };

    // The lanes still live after sample `i` has been composited onto `acc`: a lane stops
    // after its last sample, or once `A ≥ A_stop` (`Termination::done`).
    let still = |acc: &[__m256; 4], live: __m256, i: u32| {
        let more = _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, _mm256_set1_epi32(i as i32 + 1)));
        let done = if MODE == INTEGER_OW {
            // `A ≥ a_stop` as `A > a_stop − 1` (`1 ≤ a_stop ≤ ONE`).
            let below = _mm256_set1_epi32(a_stop as i32 - 1);
            _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_castps_si256(acc[3]), below))
        } else {
            _mm256_cmp_ps::<_CMP_GE_OQ>(acc[3], stop)
        };
        _mm256_andnot_ps(done, _mm256_and_ps(live, more))
    };

    // With `ONE`: the eight samples of step `i` (sample `8i + l` in lane `l`) composited in
    // order onto `acc` by `composite::front_to_back`; `Some` of the number of samples
    // composited once the ray ends or `A ≥ a_stop` (`Termination::done`).
    let serial = |acc: &mut Sample, [r, g, b, a]: [__m256; 4], i: u32| {
        let [r, g, b, a] = map4([r, g, b, a], |v| array(v));
        let lanes = r.into_iter().zip(g).zip(b).zip(a);
        for (k, (((r, g), b), a)) in (i * LANES as u32..).zip(lanes) {
            if k >= samples {
                return Some(samples);
            }
            *acc = front_to_back(*acc, Sample { c: [r, g, b], a });
            if acc.a >= a_stop {
                return Some(k + 1);
            }
        }
        None
    };
    let one_result = |s: Sample, n: u32| {
        let bits = |x: f32| x.to_bits() as i32;
        let mut out = [[0i32; LANES]; 4];
        let [or, og, ob, oa] = &mut out;
        [or[0], or[1], og[0], ob[0], oa[0]] = [
            bits(s.c[0]),
            n as i32,
            bits(s.c[1]),
            bits(s.c[2]),
            bits(s.a),
        ];
        out
    };
    let mut one_acc = Sample::TRANSPARENT;
    // The same for `INTEGER_OW`: `fixed_point::front_to_back` of each sample, stopping before
    // a sample once `A ≥ a_stop` (as `IntRayMarcher::cast` does).
    let int_serial = |acc: &mut IntSample, [r, g, b, a]: [__m256; 4], i: u32| {
        let [r, g, b, a] = map4([r, g, b, a], |v| to_i32s(_mm256_castps_si256(v)));
        let lanes = r.into_iter().zip(g).zip(b).zip(a);
        // Every lane holds `C ≤ A ≤ ONE` (`IntMode::combine`'s invariant, whose integer
        // arithmetic the kernel performs).
        let narrow = |x: i32| u16::try_from(x).unwrap_or(u16::MAX);
        for (k, (((r, g), b), a)) in (i * LANES as u32..).zip(lanes) {
            if k >= samples {
                return Some(samples);
            }
            if f32::from(acc.a()) >= a_stop {
                return Some(k);
            }
            let s = IntSample::from_valid([narrow(r), narrow(g), narrow(b)], narrow(a));
            *acc = int_front_to_back(*acc, s);
        }
        None
    };
    let int_result = |s: IntSample, n: u32| {
        let [r, g, b] = s.c().map(i32::from);
        let mut out = [[0i32; LANES]; 4];
        let [or, og, ob, oa] = &mut out;
        [or[0], or[1], og[0], ob[0], oa[0]] = [r, n as i32, g, b, i32::from(s.a())];
        out
    };
    let mut int_acc = IntSample::TRANSPARENT;
    // The accumulated result of the one ray, once it ends or stops at step `i`.
    let mut one_ray = |s: [__m256; 4], i: u32| {
        if MODE == INTEGER_OW {
            let n = int_serial(&mut int_acc, s, i)?;
            Some(int_result(int_acc, n))
        } else {
            let n = serial(&mut one_acc, s, i)?;
            Some(one_result(one_acc, n))
        }
    };

    let mut acc = [zf; 4];
    // Lanes still compositing: before their last sample and not yet stopped (with `ONE`,
    // all of them while the ray has samples; `serial` stops it).
    let mut live = if ONE {
        _mm256_castsi256_ps(_mm256_set1_epi32(if samples > 0 { -1 } else { 0 }))
    } else {
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, zero))
    };
    let mut cell = Cell::<A>::new();
    // The extinction modes only: the sums of the [`LAG`] steps before, finished and
    // composited after this step's sums, oldest first (software pipelining: the step's long
    // chain of dependent operations, two divisions among them, then overlaps the next
    // samples' work; same operations, same order of compositing, so the same results).
    let lag = if extinction(MODE) { LAG } else { 0 };
    let mut pending = [[zf; 4]; LAG as usize];
    let mut j = 0u32;
    while j < steps && _mm256_movemask_ps(live) != 0 {
        // The sample position, as `Ray::at(t_first + j·d)` (with `ONE`, of sample `8j + l` in
        // lane `l`: every index below `2^24`, `MAX_SAMPLES_PER_RAY`, so exact as an `f32`).
        let t = if ONE {
            let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
            let jv = _mm256_add_epi32(_mm256_set1_epi32((j * LANES as u32) as i32), lane);
            _mm256_add_ps(t0, _mm256_mul_ps(_mm256_cvtepi32_ps(jv), dv))
        } else {
            _mm256_add_ps(t0, _mm256_mul_ps(_mm256_set1_ps(j as f32), dv))
        };
        // Per axis: the fraction `p − ⌊p⌋`, the two tap coordinates clamped into the grid, and
        // the coordinate `PREFETCH_STEPS` steps ahead (truncated: only a prefetch address).
        let split = |(o, d, last, n, ahead): (__m256, __m256, __m256i, __m256, __m256)| {
            let p = _mm256_add_ps(o, _mm256_mul_ps(d, t));
            let next = _mm256_cvttps_epi32(_mm256_add_ps(p, ahead));
            if MODE == INTEGER_OW {
                // `IntRayMarcher::quantize`: `p` clamped into `[0, n − 1]` (NaN to 0: `max`
                // returns its second operand then), `raw = ⌊256·p + ½⌋` (`quantize8`), then
                // the index `raw >> 8` and the fraction `raw & 255` (an `i32` bit pattern);
                // the index is at most `n − 1`, the second tap clamped to it.
                let p = _mm256_min_ps(_mm256_max_ps(p, zf), _mm256_sub_ps(n, one));
                let raw = quantize8(p);
                let i = _mm256_srli_epi32::<8>(raw);
                let f = _mm256_and_si256(raw, _mm256_set1_epi32(0xff));
                return (
                    _mm256_castsi256_ps(f),
                    i,
                    _mm256_min_epi32(_mm256_add_epi32(i, ione), last),
                    next,
                );
            }
            let fl = _mm256_floor_ps(p);
            let i = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(fl, lo_f), n));
            let c = |i| _mm256_min_epi32(_mm256_max_epi32(i, zero), last);
            (
                _mm256_sub_ps(p, fl),
                c(i),
                c(_mm256_add_epi32(i, ione)),
                next,
            )
        };
        let [(fx, x0, x1, qx), (fy, y0, y1, qy), (fz, z0, z1, qz)] = map3(axes, split);
        let row = |y, z| _mm256_add_epi32(_mm256_mullo_epi32(y, sx), _mm256_mullo_epi32(z, sy));
        // The prefetch (with the reuse, whose branches would otherwise leave the remaining
        // reads waiting on memory): lanes 0 and 7 of the four tap rows ahead. Its addresses
        // may lie outside the data (`wrapping_offset`, never dereferenced).
        if REUSE {
            let q = _mm256_add_epi32(qx, row(qy, qz));
            // Along y or z, the two rows on the near side of the major axis (a far row ahead
            // is a near row of a sample a cell further on, prefetched by a later step); along
            // x, all four.
            let rows = match A {
                2 => [zero, sx, sy, sy],
                1 => [zero, sy, sx, sx],
                _ => [zero, sx, sy, _mm256_add_epi32(sx, sy)],
            };
            for r in rows.into_iter().take(if A == 0 { 4 } else { 2 }) {
                let [a0, .., a7] = to_i32s(_mm256_add_epi32(q, r));
                for l in [a0, a7] {
                    let p = data.as_ptr().wrapping_offset(l as isize);
                    _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>());
                }
            }
        }
        let (r00, r10, r01, r11) = (row(y0, z0), row(y1, z0), row(y0, z1), row(y1, z1));
        let at = [
            _mm256_add_epi32(x0, r00),
            _mm256_add_epi32(x1, r00),
            _mm256_add_epi32(x0, r10),
            _mm256_add_epi32(x1, r10),
            _mm256_add_epi32(x0, r01),
            _mm256_add_epi32(x1, r01),
            _mm256_add_epi32(x0, r11),
            _mm256_add_epi32(x1, r11),
        ];

        // `filter::trilinear_weights` in `F32x8` lanes.
        let w = trilinear_weights([F32x8(fx), F32x8(fy), F32x8(fz)]);

        // The taps' channels, then the sums from the last tap down (`mode::weighted_sums`). With the
        // reuse, the channels are read only where the packet has moved on (here rather than in
        // a `Cell` method: a `target_feature` function was not inlined into its caller, and
        // the call cost about 5 % of the kernel's time). The branch on `inside` is taken once
        // per step or face, outside the taps' loop.
        let s = if REUSE {
            let same = |a: __m256i, b: __m256i, c: __m256i, d: __m256i| {
                let eq = _mm256_and_si256(_mm256_cmpeq_epi32(a, b), _mm256_cmpeq_epi32(c, d));
                _mm256_movemask_epi8(eq) == -1
            };
            let [c0, c7, far0] = cell.at;
            if !same(at[0], c0, at[7], c7) {
                let taps = Taps::new(data, at);
                if same(at[0], far0, Cell::<A>::near7(&at), c7) {
                    cell.near ^= 1;
                } else {
                    cell.read::<V, MODE, 0>(&taps, taus);
                }
                cell.read::<V, MODE, 1>(&taps, taus);
                cell.at = [at[0], at[7], Cell::<A>::far0(&at)];
            }
            if MODE == INTEGER_OW {
                // The packed pairs along x, or along y for faces across x (`Cell::read`),
                // held at the place of their first tap; the fractions in that order.
                let ([b0, b1, b2, b3], f) = if A == 0 {
                    ([0, 1, 4, 5], [fy, fx, fz])
                } else {
                    ([0, 2, 4, 6], [fx, fy, fz])
                };
                let first = |j: usize| match j {
                    0 => b0,
                    1 => b1,
                    2 => b2,
                    _ => b3,
                };
                int_sums(|j| cell.tap(first(j)), map3(f, |v| _mm256_castps_si256(v)))
            } else {
                mode_sums::<MODE>(|k| cell.tap(k), &w)
            }
        } else {
            let taps = Taps::new(data, at);
            if MODE == INTEGER_OW {
                // Pairs along x: taps `2j` and `2j + 1`.
                let f = map3([fx, fy, fz], |v| _mm256_castps_si256(v));
                if taps.pairs() {
                    int_sums(|j| int_pair_of(taps.load_pair(2 * j)), f)
                } else if taps.inside() {
                    let load = |k| taps.load::<true>(k);
                    int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
                } else {
                    let load = |k| taps.load::<false>(k);
                    int_sums(|j| int_pair(load(2 * j), load(2 * j + 1)), f)
                }
            } else if taps.pairs() {
                // The four pairs' words first (eight registers), then each tap's channels when
                // the sums come to it.
                let [[w0, w1], [w2, w3], [w4, w5], [w6, w7]] =
                    map4([0, 2, 4, 6], |k| taps.load_pair(k));
                let words = [w0, w1, w2, w3, w4, w5, w6, w7];
                let word = |k: usize| words.get(k).copied().unwrap_or(zero);
                mode_sums::<MODE>(|k| channels::<MODE>(word(k), taus), &w)
            } else if taps.inside() {
                let c = taps.all_channels::<MODE, true>(taus);
                mode_sums::<MODE>(|k| c.get(k).copied().unwrap_or([zf; 4]), &w)
            } else {
                let c = taps.all_channels::<MODE, false>(taus);
                mode_sums::<MODE>(|k| c.get(k).copied().unwrap_or([zf; 4]), &w)
            }
        };
        // The sums to composite now, of sample `j − lag`: this step's, or (pipelined) the
        // oldest pending.
        let s = if lag > 0 {
            let oldest = pending[0];
            pending.rotate_left(1);
            if let Some(newest) = pending.last_mut() {
                *newest = s;
            }
            if j < lag {
                j += 1;
                continue;
            }
            oldest
        } else {
            s
        };
        if ONE {
            if let Some(out) = one_ray(finish(s), j - lag) {
                return out;
            }
        } else {
            acc = over(acc, finish(s), live);
            live = still(&acc, live, j - lag);
        }
        j += 1;
    }
    // The pipelined samples left (`j − lag` to `j − 1`, of those that exist), where a lane is
    // still live.
    if lag > 0 {
        let first = j.saturating_sub(lag);
        let left = pending.iter().skip((LAG - (j - first)) as usize);
        for (i, s) in (first..j).zip(left) {
            if ONE {
                if let Some(out) = one_ray(finish(*s), i) {
                    return out;
                }
            } else if _mm256_movemask_ps(live) != 0 {
                acc = over(acc, finish(*s), live);
                live = still(&acc, live, i);
            }
        }
    }
    if ONE {
        return if MODE == INTEGER_OW {
            int_result(int_acc, samples)
        } else {
            one_result(one_acc, samples)
        };
    }
    let [r, g, b, a] = acc;
    let bits = |v: __m256| to_i32s(_mm256_castps_si256(v));
    [bits(r), bits(g), bits(b), bits(a)]
}
