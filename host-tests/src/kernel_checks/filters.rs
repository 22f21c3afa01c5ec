//! `filters`: the float nearest and B-spline filters, every float mode, against the f64
//! reference.

use arbitrary::Arbitrary;
use volsample::ControlPoint;

use crate::float_checks::{max_abs_diff, FilterKind, FloatCase, ModeKind};
use crate::tolerance;

/// Input of the `filters` check: a [`FloatCase`] and a position, from integers.
#[derive(Debug, Clone, PartialEq, Eq, Default, Arbitrary)]
pub struct FilterInput {
    /// Dimensions, each `1 + x mod 5`.
    pub dims: [u8; 3],
    /// Straight voxels `[r, g, b, a]`, each `x/65535`; the voxels past the given ones follow a
    /// fixed pattern (`fill`), so that a short input is not a constant volume.
    pub voxels: Vec<[u16; 4]>,
    /// Scalars `255·x/65535`, the ones past the given ones from the same pattern.
    pub scalars: Vec<u16>,
    /// Control points `[s, r, g, b, a]`: `s = 255·x/65536`, the others `x/65535`; sorted,
    /// points closer than `10⁻³` in `s` to the one before dropped, at most 5 (one black
    /// transparent point at 0 when empty).
    pub tf: Vec<[u16; 5]>,
    /// `d′`: 1 for 0, else `0.25 + 3.75·x/65536`.
    pub d_ref: u16,
    /// Step of the extinction check at another distance: `10⁻³ + 8·x/65536`.
    pub d: u16,
    /// Position per axis, `−1.5 + (n + 2)·((x + 2^15) mod 2^16)/65536` (one voxel and a half
    /// past each face; `x = 0` is the middle).
    pub pos: [u16; 3],
    /// Or the position as `f32` bits (used when every coordinate is finite and within
    /// `±2^20`).
    pub pos_bits: Option<[u32; 3]>,
}

/// The voxel `i` of the fixed pattern that fills a volume past the input's voxels: a hash of
/// `i` per channel (full range, not smooth).
pub fn fill(i: usize) -> [u16; 4] {
    let h = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    [0, 16, 32, 48].map(|s| (h >> s) as u16)
}

impl FilterInput {
    /// The case and the position.
    pub fn case(&self) -> (FloatCase, [f32; 3]) {
        let dims = self.dims.map(|x| 1 + usize::from(x % 5));
        let n = dims[0] * dims[1] * dims[2];
        let unit = |x: u16| f32::from(x) / 65535.0;
        let voxels = (0..n)
            .map(|i| self.voxels.get(i).copied().unwrap_or_else(|| fill(i)))
            .map(|v| volsample::StraightF32 {
                c: [unit(v[0]), unit(v[1]), unit(v[2])],
                a: unit(v[3]),
            })
            .collect();
        let scalars = (0..n)
            .map(|i| 255.0 * unit(self.scalars.get(i).copied().unwrap_or(fill(i)[0])))
            .collect();
        let mut pts: Vec<ControlPoint> = self
            .tf
            .iter()
            .map(|p| ControlPoint {
                s: 255.0 * f32::from(p[0]) / 65536.0,
                c: [unit(p[1]), unit(p[2]), unit(p[3])],
                a: unit(p[4]),
            })
            .collect();
        pts.sort_by(|a, b| a.s.total_cmp(&b.s));
        pts.dedup_by(|a, b| a.s <= b.s + 1e-3);
        pts.truncate(5);
        if pts.is_empty() {
            pts.push(ControlPoint {
                s: 0.0,
                c: [0.0; 3],
                a: 0.0,
            });
        }
        let d_ref = if self.d_ref == 0 {
            1.0
        } else {
            0.25 + 3.75 * f32::from(self.d_ref) / 65536.0
        };
        let pos = match self.pos_bits.map(|b| b.map(f32::from_bits)) {
            Some(p) if p.iter().all(|x| x.is_finite() && x.abs() <= 1_048_576.0) => p,
            _ => std::array::from_fn(|k| {
                let x = self.pos[k].wrapping_add(1 << 15);
                -1.5 + (dims[k] as f32 + 2.0) * f32::from(x) / 65536.0
            }),
        };
        (
            FloatCase {
                dims,
                voxels,
                scalars,
                tf: pts,
                d_ref,
            },
            pos,
        )
    }
}

/// `filters`: every float mode with the nearest and the triquadratic B-spline filter at the
/// input's position is a valid sample within `tolerance::sample_bound` of the f64 reference
/// at `d = d′`, and the extinction mode also at the input's other step `d`. Returns the
/// number of samples compared.
///
/// # Errors
/// The first bound exceeded, with the values.
pub fn filters(inp: &FilterInput) -> Result<u64, String> {
    let (case, pos) = inp.case();
    let d = 1e-3 + 8.0 * f32::from(inp.d) / 65536.0;
    let mut compared = 0;
    for filter in [FilterKind::Nearest, FilterKind::BSpline] {
        let mut runs: Vec<(ModeKind, f32)> =
            ModeKind::ALL.iter().map(|&m| (m, case.d_ref)).collect();
        runs.push((ModeKind::ExtinctionWeighted, d));
        for (mode, d) in runs {
            let core = case.core_sample(mode, filter, pos, d);
            let r = case.reference_sample(mode, filter, pos, d);
            let bound = tolerance::sample_bound(mode, filter, &case, d);
            let err = max_abs_diff(core, r);
            compared += 1;
            if !core.is_valid() || err.is_nan() || err > bound {
                return Err(format!(
                    "{mode:?} {filter:?} at {pos:?}, d = {d}: core {core:?} vs reference {r:?}: \
                     error {err:e} > bound {bound:e} in {case:?}"
                ));
            }
        }
    }
    Ok(compared)
}
