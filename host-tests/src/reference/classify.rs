//! Levoy's isosurface classifier (Levoy 1988), gradient by central differences.

use super::volume::{linear_index, RefScalarVolume, RefVolume, RefVoxel};

/// Parameters of Levoy's isosurface opacity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefIsosurface {
    /// Isovalue `f_v`.
    pub f_v: f64,
    /// Opacity `α_v` at the isovalue.
    pub alpha_v: f64,
    /// Thickness `r` of the transition region, in voxels.
    pub r: f64,
}

impl RefIsosurface {
    /// Opacity for value `f` and gradient magnitude `g ≥ 0`:
    /// `α_v·(1 − |f_v − f|/(r·g))` when `g > 0` and `|f_v − f| ≤ r·g`; `α_v` when `f = f_v`
    /// (whatever `g` and `r`); otherwise `0`.
    pub fn opacity(&self, f: f64, g: f64) -> f64 {
        let diff = (self.f_v - f).abs();
        if diff == 0.0 {
            self.alpha_v
        } else if g > 0.0 && diff <= self.r * g {
            self.alpha_v * (1.0 - diff / (self.r * g))
        } else {
            0.0
        }
    }
}

/// Difference quotient of `scalars` along one axis at coordinate `c` of `n`: central
/// `(f[c+1] − f[c−1])/2` inside, one-sided `f[1] − f[0]` and `f[n−1] − f[n−2]` at the edges,
/// `0` when `n = 1`. `at(k)` reads the value at coordinate `k` on this axis.
fn axis_derivative(n: usize, c: usize, at: impl Fn(usize) -> f64) -> f64 {
    if n < 2 {
        0.0
    } else if c == 0 {
        at(1) - at(0)
    } else if c == n - 1 {
        at(n - 1) - at(n - 2)
    } else {
        (at(c + 1) - at(c - 1)) / 2.0
    }
}

/// Gradient of a scalar field (storage order, dimensions `dims`) at voxel `(x, y, z)`, in units
/// per voxel: central differences inside, one-sided at the faces, `0` on an axis of length 1.
///
/// # Panics
/// If the voxel is outside the volume or `scalars` is too short.
pub fn central_gradient(dims: [usize; 3], scalars: &[f64], voxel: [usize; 3]) -> [f64; 3] {
    assert!((0..3).all(|k| voxel[k] < dims[k]), "voxel outside volume");
    let [x, y, z] = voxel;
    let f = |p: [usize; 3]| scalars[linear_index(dims, p)];
    [
        axis_derivative(dims[0], x, |k| f([k, y, z])),
        axis_derivative(dims[1], y, |k| f([x, k, z])),
        axis_derivative(dims[2], z, |k| f([x, y, k])),
    ]
}

/// Levoy opacity of every voxel of `vol` (storage order), with `g = |∇f|` from
/// [`central_gradient`].
pub fn levoy_opacities(vol: &RefScalarVolume, iso: RefIsosurface) -> Vec<f64> {
    let mut out = Vec::with_capacity(vol.scalars.len());
    for z in 0..vol.dims[2] {
        for y in 0..vol.dims[1] {
            for x in 0..vol.dims[0] {
                let g = central_gradient(vol.dims, &vol.scalars, [x, y, z]);
                let mag = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
                let f = vol.scalars[linear_index(vol.dims, [x, y, z])];
                out.push(iso.opacity(f, mag));
            }
        }
    }
    out
}

/// Pre-classifies `vol` with Levoy's opacity and one straight `color` for every voxel
/// (same dims and `d_ref`).
pub fn levoy_classify(vol: &RefScalarVolume, iso: RefIsosurface, color: [f64; 3]) -> RefVolume {
    RefVolume {
        dims: vol.dims,
        voxels: levoy_opacities(vol, iso)
            .into_iter()
            .map(|a| RefVoxel::new(color, a))
            .collect(),
        d_ref: vol.d_ref,
    }
}

/// The exact light factor of the shading pre-pass, `min(1, k_a + k_d·|n·L|)`, for the
/// gradient `g` and the light direction `dir` as given (both normalised here; `|n·L| = 1`
/// where `g = 0`). Lengths are scaled by their largest component, so that `f64` does not
/// overflow for `f32::MAX` components either.
pub fn shade_factor(g: [f64; 3], dir: [f32; 3], ka: f32, kd: f32) -> f64 {
    let len = |v: [f64; 3]| {
        let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if m == 0.0 {
            0.0
        } else {
            m * v.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
        }
    };
    let d = dir.map(f64::from);
    let (lg, ld) = (len(g), len(d));
    let cos = if lg == 0.0 {
        1.0
    } else {
        let dot: f64 = g.iter().zip(d).map(|(a, b)| (a / lg) * (b / ld)).sum();
        dot.abs().min(1.0)
    };
    (f64::from(ka) + f64::from(kd) * cos).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_of_linear_field_is_exact_everywhere() {
        let dims = [4, 3, 2];
        let vol = RefScalarVolume::from_fn(dims, 1.0, |[x, y, z]| {
            1.0 + 2.0 * x as f64 - 0.5 * y as f64 + 3.0 * z as f64
        });
        for z in 0..2 {
            for y in 0..3 {
                for x in 0..4 {
                    assert_eq!(
                        central_gradient(dims, &vol.scalars, [x, y, z]),
                        [2.0, -0.5, 3.0]
                    );
                }
            }
        }
    }

    #[test]
    fn gradient_one_sided_and_flat_axis() {
        // f = x² on 4 voxels: 0 1 4 9. Edges one-sided, inside central.
        let dims = [4, 1, 1];
        let s = [0.0, 1.0, 4.0, 9.0];
        assert_eq!(central_gradient(dims, &s, [0, 0, 0]), [1.0, 0.0, 0.0]);
        assert_eq!(central_gradient(dims, &s, [1, 0, 0]), [2.0, 0.0, 0.0]);
        assert_eq!(central_gradient(dims, &s, [2, 0, 0]), [4.0, 0.0, 0.0]);
        assert_eq!(central_gradient(dims, &s, [3, 0, 0]), [5.0, 0.0, 0.0]);
    }

    #[test]
    fn levoy_opacity_closed_forms() {
        let iso = RefIsosurface {
            f_v: 100.0,
            alpha_v: 0.8,
            r: 2.0,
        };
        assert_eq!(iso.opacity(100.0, 10.0), 0.8);
        assert_eq!(iso.opacity(110.0, 10.0), 0.4);
        assert_eq!(iso.opacity(90.0, 10.0), 0.4);
        assert_eq!(iso.opacity(120.0, 10.0), 0.0);
        assert_eq!(iso.opacity(121.0, 10.0), 0.0);
        assert_eq!(iso.opacity(100.0, 0.0), 0.8);
        assert_eq!(iso.opacity(100.5, 0.0), 0.0);
        let thin = RefIsosurface { r: 0.0, ..iso };
        assert_eq!(thin.opacity(100.0, 5.0), 0.8);
        assert_eq!(thin.opacity(100.1, 5.0), 0.0);
    }

    #[test]
    fn classify_ramp() {
        // f = 10·x: g = 10 everywhere; isovalue 20, r = 1 → opacity 1 − |20 − 10x|/10.
        let vol = RefScalarVolume::from_fn([5, 1, 1], 1.0, |[x, _, _]| 10.0 * x as f64);
        let iso = RefIsosurface {
            f_v: 20.0,
            alpha_v: 1.0,
            r: 1.0,
        };
        assert_eq!(levoy_opacities(&vol, iso), vec![0.0, 0.0, 1.0, 0.0, 0.0]);
        let iso = RefIsosurface { r: 1.5, ..iso };
        let a = levoy_opacities(&vol, iso);
        let expect = [0.0, 1.0 - 10.0 / 15.0, 1.0, 1.0 - 10.0 / 15.0, 0.0];
        for (g, e) in a.iter().zip(expect) {
            assert!((g - e).abs() < 1e-15);
        }
        let v = levoy_classify(&vol, iso, [1.0, 0.0, 0.0]);
        assert_eq!(v.voxels[2], RefVoxel::new([1.0, 0.0, 0.0], 1.0));
    }
}
