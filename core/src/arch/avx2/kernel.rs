//! The march's AVX2 instance: eight rays (or eight samples of one ray) in the lanes, step by
//! step, in the one march loop of `crate::march`.

use core::arch::x86_64::*;
use core::ops::ControlFlow;

use super::*;
use crate::each::Each;

/// [`march8`] in AVX2, of the kind `K` ([`Kind`]); where `REUSE` (parallel rays), the taps'
/// channels kept as faces across axis `A` ([`Cell`]) and the voxels ahead prefetched (with
/// `ONE`, the tap rows two steps ahead).
/// Returns the accumulated `[r, g, b, α]` lanes as bit patterns.
///
/// The lanes march their [`Samples`]: at step `j`, lane `l` is at sample `first + j`, at
/// `t₀ + (first + j)·d` as the one-ray march computes it, until its `end`.
///
/// Where `ONE` ([`march_one`]), the eight lanes are eight consecutive samples of one ray
/// instead (`rays[0]`, `ranges[0]`; lane `l` of step `j` is sample `first + 8j + l`, at
/// `t₀ + (first + 8j + l)·d`), composited in order, one lane after
/// the other, by `composite::front_to_back` until `A ≥ a_stop` after a sample: then lane 0 of
/// the four arrays holds the accumulated sample and lane 1 of the first the number of samples
/// composited. (Not inlined: its four instances
/// inlined into `march8` slowed the reuse by about a tenth in a probe, 5.7 against 5.15
/// ns/sample. Not returning the vectors themselves: returned through memory, they kept the
/// accumulator there across the loop, which took the `ExtinctionWeightedU8` packets from 7.1
/// to 8.6 ns/sample.)
#[inline(never)]
#[target_feature(enable = "avx2,fma")]
pub(super) fn march8_avx2<V: Voxel, K: Kind, const A: usize, const REUSE: bool, const ONE: bool>(
    cpu: Avx2,
    vol: &Volume<'_, V>,
    rays: &[Ray; LANES],
    samples: &Samples,
    stage: Stage<'_, K::Corr>,
) -> [[i32; LANES]; 4] {
    let Samples {
        ref ranges,
        first,
        total,
    } = *samples;
    let Stage {
        d,
        a_stop,
        taus,
        corr,
    } = stage;
    let taus = Taus {
        table: taus,
        gather: cpu.gathers(),
    };
    let data = vol.data();
    let [nx, ny, nz] = vol.dims().each(|n| n as i32);
    // Per axis: (origin, direction, last voxel index, `n` as `f32`).
    let (org, dir) = (
        rays.each_ref().each(Ray::origin),
        rays.each_ref().each(Ray::dir),
    );
    // With `ONE` a step is eight samples: the prefetch looks two steps ahead.
    let ahead = if ONE {
        2.0 * LANES as f32
    } else {
        PREFETCH_STEPS
    };
    let lead = ahead * d;
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
        axis(org.each(|o| o[0]), dir.each(|d| d[0]), nx),
        axis(org.each(|o| o[1]), dir.each(|d| d[1]), ny),
        axis(org.each(|o| o[2]), dir.each(|d| d[2]), nz),
    ];
    let t0 = lanes(ranges.each(|r| r.0));
    // Per lane, the steps it takes.
    let count = ranges.each(|r| r.1.saturating_sub(first));
    // (With `ONE`, every range is the one ray's: its last sample marched, and how many.)
    let [(_, end), ..] = *ranges;
    let samples = end.saturating_sub(first);
    let steps = if ONE {
        samples.div_ceil(LANES as u32)
    } else {
        count.iter().copied().max().unwrap_or(0)
    };
    let [c0, c1, c2, c3, c4, c5, c6, c7] = count.each(|c| c as i32);
    let count = _mm256_setr_epi32(c0, c1, c2, c3, c4, c5, c6, c7);

    let dv = _mm256_set1_ps(d);
    let zf = _mm256_setzero_ps();
    let zero = _mm256_setzero_si256();
    let plane = nx * ny;
    let (sx, sy) = (_mm256_set1_epi32(nx), _mm256_set1_epi32(plane));
    // The first byte of voxel `l`, and the prefetch of every cache line of the bytes from
    // `first` to `end` (where that span is over four lines, of its two ends only). The
    // addresses may lie outside the data (`wrapping_offset`, never dereferenced).
    let voxel = |l: i32| data.as_ptr().wrapping_offset(l as isize).cast::<i8>();
    let lines = |first: *const i8, end: *const i8| {
        let span = (end as usize).wrapping_sub(first as usize);
        _mm_prefetch::<_MM_HINT_T0>(first);
        if span <= 4 * 64 {
            for k in (64..span).step_by(64) {
                _mm_prefetch::<_MM_HINT_T0>(first.wrapping_add(k));
            }
        }
        _mm_prefetch::<_MM_HINT_T0>(end.wrapping_sub(1));
    };

    // The sample of the sums `s` (`Kind::finish`) composited onto `acc` in the live lanes.
    let over = |acc: [__m256; 4], s: [__m256; 4], live: __m256| {
        // SAFETY: the methods of `Kind` need AVX2 and FMA, which this function has (its
        // callers' `Avx2` token proves the CPU runs them); so in every `unsafe` block below.
        unsafe { K::over(acc, K::finish(s, d, corr), live) }
    };
    // The lanes still live after sample `i` has been composited onto `acc`: a lane stops
    // after its last sample, or once `A ≥ A_stop` (`Termination::done`).
    let still = |acc: &[__m256; 4], live: __m256, i: u32| {
        let more = _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, _mm256_set1_epi32(i as i32 + 1)));
        // SAFETY: as above.
        let done = unsafe { K::done(acc, a_stop) };
        _mm256_andnot_ps(done, _mm256_and_ps(live, more))
    };
    // With `ONE`, the result from the one ray's accumulated sample (bit patterns) once it ends
    // or stops: lane 0 of the four arrays the sample, lane 1 of the first the number of
    // samples composited.
    let one_result = |[r, g, b, a]: [i32; 4], n: u32| {
        let mut out = [[0i32; LANES]; 4];
        let [or, og, ob, oa] = &mut out;
        [or[0], or[1], og[0], ob[0], oa[0]] = [r, n as i32, g, b, a];
        out
    };

    // Lanes still compositing: before their last sample and not yet stopped (with `ONE`,
    // all of them while the ray has samples; `serial` stops it).
    let live = if ONE {
        _mm256_castsi256_ps(_mm256_set1_epi32(if samples > 0 { -1 } else { 0 }))
    } else {
        _mm256_castsi256_ps(_mm256_cmpgt_epi32(count, zero))
    };
    let mut st = State {
        acc: [zf; 4],
        live,
        cell: Cell::<A>::new(),
        one_acc: [0; 4],
    };
    // The sums of step `j` (`crate::march`, which composites them `K::LAG` steps later: for the
    // extinction modes the step's long chain of dependent operations, two divisions among
    // them, then overlaps the next samples' work).
    let steps = crate::march::march(
        &mut st,
        steps,
        K::LAG,
        [zf; 4],
        #[inline(always)]
        |st: &mut State<A>, _| _mm256_movemask_ps(st.live) != 0,
        #[inline(always)]
        |st: &mut State<A>, j: u32| {
            // The sample position, as `Ray::at(t_first + k·d)` of sample `k = first + j` (with
            // `ONE`, `first + 8j + l` in lane `l`: every index below `2^24`,
            // `MAX_SAMPLES_PER_RAY`, so exact as an `f32`).
            let t = if ONE {
                let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
                let k0 = first + j * LANES as u32;
                let jv = _mm256_add_epi32(_mm256_set1_epi32(k0 as i32), lane);
                _mm256_add_ps(t0, _mm256_mul_ps(_mm256_cvtepi32_ps(jv), dv))
            } else {
                _mm256_add_ps(t0, _mm256_mul_ps(_mm256_set1_ps((first + j) as f32), dv))
            };
            // Per axis: the fraction and the two tap coordinates clamped into the grid
            // (`Kind::split`), and the coordinate `PREFETCH_STEPS` steps ahead (truncated: only a
            // prefetch address).
            let split = |(o, d, last, n, ahead): (__m256, __m256, __m256i, __m256, __m256)| {
                let p = _mm256_add_ps(o, _mm256_mul_ps(d, t));
                let next = _mm256_cvttps_epi32(_mm256_add_ps(p, ahead));
                // SAFETY: as above.
                let (f, i0, i1) = unsafe { K::split(p, last, n) };
                (f, i0, i1, next)
            };
            let [(fx, x0, x1, qx), (fy, y0, y1, qy), (fz, z0, z1, qz)] = map3(axes, split);
            let row = |y, z| _mm256_add_epi32(_mm256_mullo_epi32(y, sx), _mm256_mullo_epi32(z, sy));
            // The prefetch (with the reuse, whose branches would otherwise leave the remaining
            // reads waiting on memory): the four tap rows ahead, from lane 0 to lane 7.
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
                    // Every line from lane 0's first tap to lane 7's second: one or two of
                    // RGBA8 voxels for a packet along a row of pixels, three or four of
                    // 16-byte ones (see the module docs). Lanes further apart (not a row) get
                    // the two ends only.
                    lines(voxel(a0), voxel(a7.wrapping_add(2)));
                }
            }
            // With `ONE`, the four tap rows of lanes 0 and 4 two steps ahead (along z, lane 0's
            // far rows are lane 2's near ones; the next step's lane 0 covers lane 6): each from
            // its first tap's line to its second's.
            if ONE {
                let [a0, _, _, _, a4, ..] = to_i32s(_mm256_add_epi32(qx, row(qy, qz)));
                for a in [a0, a4] {
                    for r in [0, nx, plane, plane.wrapping_add(nx)] {
                        let first = voxel(a.wrapping_add(r));
                        lines(first, first.wrapping_add(2 * size_of::<V>()));
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
            let f = [fx, fy, fz];

            // The taps' channels, then the sums (`Kind::cell_sums`, `Kind::tap_sums`). With the
            // reuse, the channels are read only where the packet has moved on (here rather than in
            // a `Cell` method: a `target_feature` function was not inlined into its caller, and
            // the call cost about 5 % of the kernel's time).
            if REUSE {
                let same = |a: __m256i, b: __m256i, c: __m256i, d: __m256i| {
                    let eq = _mm256_and_si256(_mm256_cmpeq_epi32(a, b), _mm256_cmpeq_epi32(c, d));
                    _mm256_movemask_epi8(eq) == -1
                };
                let cell = &mut st.cell;
                let [c0, c7, far0] = cell.at;
                if !same(at[0], c0, at[7], c7) {
                    let taps = Taps::new(data, at);
                    if same(at[0], far0, Cell::<A>::near7(&at), c7) {
                        cell.near ^= 1;
                    } else {
                        cell.read::<V, K, 0>(&taps, taus);
                    }
                    cell.read::<V, K, 1>(&taps, taus);
                    cell.at = [at[0], at[7], Cell::<A>::far0(&at)];
                }
                // SAFETY: as above.
                unsafe { K::cell_sums(cell, f) }
            } else {
                // SAFETY: as above.
                unsafe { K::tap_sums(&Taps::new(data, at), f, taus) }
            }
        },
        // The sums of step `i` composited: in order onto the one ray (`ONE`), ending the march
        // once it stops or its samples end; else onto each live lane's `acc`.
        #[inline(always)]
        |st: &mut State<A>, s: [__m256; 4], i: u32| {
            if ONE {
                // (Here rather than in a closure of its own, which LLVM did not always inline
                // into both of this closure's call sites of the pipelined march.)
                let k0 = first + i * LANES as u32;
                // SAFETY: as above.
                let n = unsafe {
                    K::serial(
                        &mut st.one_acc,
                        K::finish(s, d, corr),
                        k0,
                        (end, total),
                        a_stop,
                    )
                };
                match n {
                    Some(n) => ControlFlow::Break(one_result(st.one_acc, n)),
                    None => ControlFlow::Continue(()),
                }
            } else {
                st.acc = over(st.acc, s, st.live);
                st.live = still(&st.acc, st.live, i);
                ControlFlow::Continue(())
            }
        },
    );
    if let ControlFlow::Break(out) = steps {
        return out;
    }
    if ONE {
        return one_result(st.one_acc, K::ran_out(&st.one_acc, (end, total), a_stop));
    }
    let [r, g, b, a] = st.acc;
    let bits = |v: __m256| to_i32s(_mm256_castps_si256(v));
    [bits(r), bits(g), bits(b), bits(a)]
}

/// What [`march8_avx2`]'s steps carry from one to the next: the accumulated `[r, g, b, α]`
/// lanes, the lanes still live, (with the reuse) the taps' channels, and (with `ONE`) the one
/// ray's accumulated sample (bit patterns).
struct State<const A: usize> {
    acc: [__m256; 4],
    live: __m256,
    cell: Cell<A>,
    one_acc: [i32; 4],
}
