//! Rays: clipping to the volume box and the sample positions along them.

/// A ray `origin + t·dir`; `dir` is normalized by the caller (the camera).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefRay {
    /// Start point, in voxel units.
    pub origin: [f64; 3],
    /// Unit direction.
    pub dir: [f64; 3],
}

impl RefRay {
    /// Builds a ray (no normalization).
    pub fn new(origin: [f64; 3], dir: [f64; 3]) -> Self {
        Self { origin, dir }
    }

    /// Point at parameter `t`: `origin + t·dir`, per component.
    pub fn at(&self, t: f64) -> [f64; 3] {
        [
            self.origin[0] + t * self.dir[0],
            self.origin[1] + t * self.dir[1],
            self.origin[2] + t * self.dir[2],
        ]
    }
}

/// Clips `ray` to the volume box `[−½, n − ½]` per axis (slab method).
///
/// Returns `[t0, t1]` with `t0` raised to `0` for rays that start inside, or `None` when the
/// interval is empty or a single point (`t0 ≥ t1`), when the ray misses or points away, or when
/// a dimension is zero. An axis with `dir = 0` keeps the ray when the origin lies in the slab,
/// faces included.
pub fn clip_ray(dims: [usize; 3], ray: &RefRay) -> Option<(f64, f64)> {
    if dims.contains(&0) {
        return None;
    }
    let mut t0 = f64::NEG_INFINITY;
    let mut t1 = f64::INFINITY;
    for (k, &n) in dims.iter().enumerate() {
        let lo = -0.5;
        let hi = n as f64 - 0.5;
        let (o, v) = (ray.origin[k], ray.dir[k]);
        if v == 0.0 {
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let ta = (lo - o) / v;
        let tb = (hi - o) / v;
        t0 = t0.max(ta.min(tb));
        t1 = t1.min(ta.max(tb));
    }
    let t0 = t0.max(0.0);
    if t0 < t1 {
        Some((t0, t1))
    } else {
        None
    }
}

/// Sample parameters `t_k = (k + phase)·d` for every integer `k` with `t0 ≤ t_k < t1`, in
/// increasing order (`d > 0`, `phase ∈ [0, 1)`). Each `t_k` is computed by that formula (not
/// by accumulation), so tests can reproduce it exactly. Empty when `t0 ≥ t1`, `d ≤ 0`, or a
/// bound is not finite.
pub fn sample_times(t0: f64, t1: f64, d: f64, phase: f64) -> Vec<f64> {
    let mut out = Vec::new();
    // Written positively so that NaN input also yields no samples; infinite bounds would
    // never end.
    let valid = t0 < t1 && d > 0.0 && t0.is_finite() && t1.is_finite();
    if !valid {
        return out;
    }
    let t_of = |k: f64| (k + phase) * d;
    let mut k = (t0 / d - phase).ceil();
    while t_of(k) < t0 {
        k += 1.0;
    }
    while t_of(k - 1.0) >= t0 {
        k -= 1.0;
    }
    loop {
        let t = t_of(k);
        if t >= t1 {
            break;
        }
        out.push(t);
        k += 1.0;
    }
    out
}

/// Sample positions along `ray` through a volume of dimensions `dims`: `ray.at(t_k)` for the
/// [`sample_times`] of the clipped interval ([`clip_ray`]); empty when the ray misses.
pub fn sample_positions(dims: [usize; 3], ray: &RefRay, d: f64, phase: f64) -> Vec<[f64; 3]> {
    match clip_ray(dims, ray) {
        Some((t0, t1)) => sample_times(t0, t1, d, phase)
            .into_iter()
            .map(|t| ray.at(t))
            .collect(),
        None => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_aligned_from_outside() {
        let ray = RefRay::new([-3.0, 1.0, 1.0], [1.0, 0.0, 0.0]);
        assert_eq!(clip_ray([4, 4, 4], &ray), Some((2.5, 6.5)));
        let back = RefRay::new([10.0, 1.0, 1.0], [-1.0, 0.0, 0.0]);
        assert_eq!(clip_ray([4, 4, 4], &back), Some((6.5, 10.5)));
    }

    #[test]
    fn starting_inside_clamps_t0() {
        let ray = RefRay::new([1.0, 1.0, 1.0], [0.0, 0.0, 1.0]);
        assert_eq!(clip_ray([4, 4, 4], &ray), Some((0.0, 2.5)));
    }

    #[test]
    fn misses() {
        let dims = [4, 4, 4];
        // Parallel, outside the slab.
        assert_eq!(
            clip_ray(dims, &RefRay::new([-1.0, 5.0, 1.0], [1.0, 0.0, 0.0])),
            None
        );
        // Pointing away.
        assert_eq!(
            clip_ray(dims, &RefRay::new([-1.0, 1.0, 1.0], [-1.0, 0.0, 0.0])),
            None
        );
        // Diagonal passing beside the box.
        let s = 0.5f64.sqrt();
        assert_eq!(
            clip_ray(dims, &RefRay::new([-5.0, 3.0, 1.0], [s, s, 0.0])),
            None
        );
        // Empty volume.
        assert_eq!(
            clip_ray([0, 4, 4], &RefRay::new([-1.0, 1.0, 1.0], [1.0, 0.0, 0.0])),
            None
        );
    }

    #[test]
    fn grazing_face_is_inside() {
        let ray = RefRay::new([-1.0, -0.5, 3.5], [1.0, 0.0, 0.0]);
        assert_eq!(clip_ray([4, 4, 4], &ray), Some((0.5, 4.5)));
    }

    #[test]
    fn diagonal_length() {
        let s = 1.0 / 3.0f64.sqrt();
        let ray = RefRay::new([-1.5, -1.5, -1.5], [s, s, s]);
        let (t0, t1) = clip_ray([2, 2, 2], &ray).unwrap();
        assert!((t0 - 3.0f64.sqrt()).abs() < 1e-15);
        assert!((t1 - t0 - 2.0 * 3.0f64.sqrt()).abs() < 1e-14);
    }

    #[test]
    fn sample_times_half_open() {
        assert_eq!(sample_times(0.0, 3.0, 1.0, 0.0), vec![0.0, 1.0, 2.0]);
        assert_eq!(sample_times(0.0, 3.0, 1.0, 0.5), vec![0.5, 1.5, 2.5]);
        assert_eq!(sample_times(2.5, 6.5, 1.0, 0.5), vec![2.5, 3.5, 4.5, 5.5]);
        assert_eq!(
            sample_times(2.5, 6.5, 0.5, 0.0),
            vec![2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0]
        );
        assert_eq!(sample_times(2.6, 2.9, 1.0, 0.0), Vec::<f64>::new());
        assert_eq!(sample_times(1.0, 1.0, 1.0, 0.0), Vec::<f64>::new());
        assert_eq!(
            sample_times(0.1, 1.0, 0.25, 0.5),
            vec![0.125, 0.375, 0.625, 0.875]
        );
    }

    #[test]
    fn sample_times_are_exactly_the_grid_points_in_range() {
        let mut state = 3u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let t0 = next() * 50.0;
            let t1 = t0 + next() * 10.0;
            let d = 0.05 + next() * 2.0;
            let phase = next();
            let ts = sample_times(t0, t1, d, phase);
            let t_of = |k: f64| (k + phase) * d;
            let k_first = match ts.first() {
                Some(&t) => (t / d - phase).round(),
                None => (t0 / d - phase).ceil(),
            };
            assert!(t_of(k_first - 1.0) < t0);
            for (n, &t) in ts.iter().enumerate() {
                assert_eq!(t, t_of(k_first + n as f64));
                assert!(t0 <= t && t < t1);
            }
            assert!(t_of(k_first + ts.len() as f64) >= t1 || ts.is_empty());
        }
        assert!(sample_times(0.0, f64::INFINITY, 1.0, 0.0).is_empty());
        assert!(sample_times(f64::NAN, 1.0, 1.0, 0.0).is_empty());
    }

    #[test]
    fn positions_along_axis() {
        let ray = RefRay::new([-3.0, 1.0, 2.0], [1.0, 0.0, 0.0]);
        let p = sample_positions([4, 4, 4], &ray, 1.0, 0.5);
        assert_eq!(
            p,
            vec![
                [-0.5, 1.0, 2.0],
                [0.5, 1.0, 2.0],
                [1.5, 1.0, 2.0],
                [2.5, 1.0, 2.0]
            ]
        );
    }
}
