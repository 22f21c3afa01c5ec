//! Sampling modes: what is interpolated, and the associated sample for a step `d`.

use super::filter::{taps, RefFilter};
use super::opacity::{extinction_sample, opacity_correct};
use super::tf::RefTransferFunction;
use super::volume::{
    RefAssoc, RefAssocVolume, RefExtinction, RefScalarVolume, RefVolume, RefVoxel,
};

/// What is interpolated at a sample position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RefMode {
    /// Straight colors and opacities separately: `α = Σwα_i`, `C̃ = α·Σwc_i` (Levoy; flawed).
    Separate,
    /// Opacity-weighted colors: `ω_i = w_iα_i`, `α = Σω_i`, `C̃ = Σω_ic_i` (Wittenbrink).
    OpacityWeighted,
    /// Stored associated colors: `α = Σwα_i`, `C̃ = ΣwC̃_i` (Drebin).
    Preweighted,
    /// Extinction and extinction-weighted colors, converted exactly for the step (Kraus).
    ExtinctionWeighted,
    /// Interpolate the scalar, then classify with the transfer function.
    PostClassified,
}

impl RefMode {
    /// Every mode.
    pub const ALL: [RefMode; 5] = [
        RefMode::Separate,
        RefMode::OpacityWeighted,
        RefMode::Preweighted,
        RefMode::ExtinctionWeighted,
        RefMode::PostClassified,
    ];

    /// True for the modes that interpolate opacities and need opacity correction when
    /// `d ≠ d_ref` (all but `ExtinctionWeighted`).
    pub fn is_opacity_based(self) -> bool {
        !matches!(self, RefMode::ExtinctionWeighted)
    }
}

/// The data a sample is taken from.
///
/// Every mode but `PostClassified` accepts every source: straight voxels are premultiplied
/// exactly for `Preweighted`, associated voxels are divided back (`C̃/α`, `0` at `α = 0`) for
/// the straight modes, and scalar voxels are pre-classified voxel by voxel with the transfer
/// function. `PostClassified` needs `Scalar`.
#[derive(Clone, Copy, Debug)]
pub enum RefSource<'a> {
    /// Straight RGBA voxels.
    Straight(&'a RefVolume),
    /// Stored associated voxels.
    Associated(&'a RefAssocVolume),
    /// Scalars and the transfer function that classifies them.
    Scalar(&'a RefScalarVolume, &'a RefTransferFunction),
}

impl RefSource<'_> {
    /// Dimensions of the underlying volume.
    pub fn dims(&self) -> [usize; 3] {
        match self {
            RefSource::Straight(v) => v.dims,
            RefSource::Associated(v) => v.dims,
            RefSource::Scalar(v, _) => v.dims,
        }
    }

    /// Reference distance `d′` of the underlying volume.
    pub fn d_ref(&self) -> f64 {
        match self {
            RefSource::Straight(v) => v.d_ref,
            RefSource::Associated(v) => v.d_ref,
            RefSource::Scalar(v, _) => v.d_ref,
        }
    }

    /// Straight voxel at linear index `i`.
    fn straight(&self, i: usize) -> RefVoxel {
        match self {
            RefSource::Straight(v) => v.voxels[i],
            RefSource::Associated(v) => v.voxels[i].straight(),
            RefSource::Scalar(v, tf) => tf.eval(v.scalars[i]),
        }
    }

    /// Associated voxel at linear index `i`.
    fn associated(&self, i: usize) -> RefAssoc {
        match self {
            RefSource::Associated(v) => v.voxels[i],
            _ => self.straight(i).associated(),
        }
    }
}

/// `Separate` before opacity correction.
fn separate_raw(src: RefSource<'_>, t: &[(usize, f64)]) -> RefAssoc {
    let mut alpha = 0.0;
    let mut c = [0.0; 3];
    for &(i, w) in t {
        let v = src.straight(i);
        alpha += w * v.alpha;
        for (ck, vk) in c.iter_mut().zip(v.color) {
            *ck += w * vk;
        }
    }
    RefAssoc::new([alpha * c[0], alpha * c[1], alpha * c[2]], alpha)
}

/// `OpacityWeighted` before opacity correction.
fn opacity_weighted_raw(src: RefSource<'_>, t: &[(usize, f64)]) -> RefAssoc {
    let mut alpha = 0.0;
    let mut c = [0.0; 3];
    for &(i, w) in t {
        let v = src.straight(i);
        let omega = w * v.alpha;
        alpha += omega;
        for (ck, vk) in c.iter_mut().zip(v.color) {
            *ck += omega * vk;
        }
    }
    RefAssoc::new(c, alpha)
}

/// `Preweighted` before opacity correction.
fn preweighted_raw(src: RefSource<'_>, t: &[(usize, f64)]) -> RefAssoc {
    let mut alpha = 0.0;
    let mut c = [0.0; 3];
    for &(i, w) in t {
        let v = src.associated(i);
        alpha += w * v.alpha;
        for (ck, vk) in c.iter_mut().zip(v.color) {
            *ck += w * vk;
        }
    }
    RefAssoc::new(c, alpha)
}

/// Interpolated extinction `(Σwτ_i, ΣwC^τ_i)` of the voxels' (capped) extinction forms.
fn extinction_raw(src: RefSource<'_>, t: &[(usize, f64)]) -> RefExtinction {
    let d_ref = src.d_ref();
    let mut e = RefExtinction::default();
    for &(i, w) in t {
        let v = src.straight(i).extinction(d_ref);
        e.tau += w * v.tau;
        for (ck, vk) in e.color_tau.iter_mut().zip(v.color_tau) {
            *ck += w * vk;
        }
    }
    e
}

/// `PostClassified` before opacity correction.
///
/// # Panics
/// If `src` is not a scalar source.
fn post_classified_raw(src: RefSource<'_>, t: &[(usize, f64)]) -> RefAssoc {
    let RefSource::Scalar(vol, tf) = src else {
        panic!("PostClassified needs a RefSource::Scalar");
    };
    let s: f64 = t.iter().map(|&(i, w)| w * vol.scalars[i]).sum();
    tf.eval(s).associated()
}

/// Associated sample of `source` at `pos` with `mode` and `filter`, valid for the step `d`.
///
/// Opacity-based modes are opacity-corrected from `source.d_ref()` to `d`
/// ([`opacity_correct`]); `ExtinctionWeighted` uses `d` directly. Pass `d = d_ref` for the
/// uncorrected sample.
///
/// # Panics
/// If `mode` is `PostClassified` and `source` is not `Scalar`, or a dimension is zero.
pub fn sample(
    source: RefSource<'_>,
    mode: RefMode,
    filter: RefFilter,
    pos: [f64; 3],
    d: f64,
) -> RefAssoc {
    let t = taps(source.dims(), filter, pos);
    let raw = match mode {
        RefMode::Separate => separate_raw(source, &t),
        RefMode::OpacityWeighted => opacity_weighted_raw(source, &t),
        RefMode::Preweighted => preweighted_raw(source, &t),
        RefMode::PostClassified => post_classified_raw(source, &t),
        RefMode::ExtinctionWeighted => return extinction_sample(extinction_raw(source, &t), d),
    };
    opacity_correct(raw, d, source.d_ref())
}

/// `Separate` sample of straight voxels (see [`sample`]).
pub fn sample_separate(vol: &RefVolume, filter: RefFilter, pos: [f64; 3], d: f64) -> RefAssoc {
    sample(RefSource::Straight(vol), RefMode::Separate, filter, pos, d)
}

/// `OpacityWeighted` sample of straight voxels (see [`sample`]).
pub fn sample_opacity_weighted(
    vol: &RefVolume,
    filter: RefFilter,
    pos: [f64; 3],
    d: f64,
) -> RefAssoc {
    sample(
        RefSource::Straight(vol),
        RefMode::OpacityWeighted,
        filter,
        pos,
        d,
    )
}

/// `Preweighted` sample of stored associated voxels (see [`sample`]).
pub fn sample_preweighted(
    vol: &RefAssocVolume,
    filter: RefFilter,
    pos: [f64; 3],
    d: f64,
) -> RefAssoc {
    sample(
        RefSource::Associated(vol),
        RefMode::Preweighted,
        filter,
        pos,
        d,
    )
}

/// `ExtinctionWeighted` sample of straight voxels (see [`sample`]).
pub fn sample_extinction_weighted(
    vol: &RefVolume,
    filter: RefFilter,
    pos: [f64; 3],
    d: f64,
) -> RefAssoc {
    sample(
        RefSource::Straight(vol),
        RefMode::ExtinctionWeighted,
        filter,
        pos,
        d,
    )
}

/// `PostClassified` sample of scalars classified by `tf` (see [`sample`]).
pub fn sample_post_classified(
    vol: &RefScalarVolume,
    tf: &RefTransferFunction,
    filter: RefFilter,
    pos: [f64; 3],
    d: f64,
) -> RefAssoc {
    sample(
        RefSource::Scalar(vol, tf),
        RefMode::PostClassified,
        filter,
        pos,
        d,
    )
}

#[cfg(test)]
mod tests {
    use super::super::tf::RefControlPoint;
    use super::*;

    fn close(a: RefAssoc, b: RefAssoc, tol: f64) -> bool {
        (a.alpha - b.alpha).abs() <= tol && (0..3).all(|k| (a.color[k] - b.color[k]).abs() <= tol)
    }

    /// 2×1×1: an opaque white voxel next to a transparent red one ("red empty space").
    fn edge() -> RefVolume {
        RefVolume::new(
            [2, 1, 1],
            vec![
                RefVoxel::new([1.0, 1.0, 1.0], 1.0),
                RefVoxel::new([1.0, 0.0, 0.0], 0.0),
            ],
            1.0,
        )
    }

    #[test]
    fn uniform_volume_every_mode_returns_the_voxel() {
        let v = RefVoxel::new([0.2, 0.6, 1.0], 0.4);
        let vol = RefVolume::uniform([3, 3, 3], v, 1.0);
        let assoc = vol.to_associated();
        let scalars = RefScalarVolume::from_fn([3, 3, 3], 1.0, |_| 0.5);
        let tf = RefTransferFunction::new(vec![RefControlPoint::new(0.0, v.color, v.alpha)]);
        for filter in RefFilter::ALL {
            for mode in RefMode::ALL {
                let pos = [0.3, 1.7, 2.2];
                let s = match mode {
                    RefMode::Preweighted => {
                        sample(RefSource::Associated(&assoc), mode, filter, pos, 1.0)
                    }
                    RefMode::PostClassified => {
                        sample(RefSource::Scalar(&scalars, &tf), mode, filter, pos, 1.0)
                    }
                    _ => sample(RefSource::Straight(&vol), mode, filter, pos, 1.0),
                };
                assert!(close(s, v.associated(), 1e-15), "{mode:?} {filter:?} {s:?}");
            }
        }
    }

    #[test]
    fn separate_shows_the_color_bleeding_artifact() {
        let vol = edge();
        let p = [0.5, 0.0, 0.0];
        let sep = sample_separate(&vol, RefFilter::Trilinear, p, 1.0);
        assert_eq!(sep, RefAssoc::new([0.5, 0.25, 0.25], 0.5));
        let ow = sample_opacity_weighted(&vol, RefFilter::Trilinear, p, 1.0);
        assert_eq!(ow, RefAssoc::new([0.5, 0.5, 0.5], 0.5));
        let pw = sample_preweighted(&vol.to_associated(), RefFilter::Trilinear, p, 1.0);
        assert_eq!(pw, ow);
    }

    #[test]
    fn extinction_weighted_closed_form() {
        // τ = 4 and τ = 0 neighbours, halfway: τ = 2, α = 1 − e^(−2d).
        let a4 = 1.0 - (-4.0f64).exp();
        let vol = RefVolume::new(
            [2, 1, 1],
            vec![
                RefVoxel::new([1.0, 0.5, 0.0], a4),
                RefVoxel::new([0.0, 1.0, 0.0], 0.0),
            ],
            1.0,
        );
        for d in [0.25, 1.0, 3.0] {
            let s = sample_extinction_weighted(&vol, RefFilter::Trilinear, [0.5, 0.0, 0.0], d);
            let a = 1.0 - (-2.0 * d).exp();
            assert!((s.alpha - a).abs() < 1e-14, "{d}");
            // Only the τ = 4 voxel contributes color: C^τ/τ = its color.
            assert!((s.color[0] - a).abs() < 1e-14);
            assert!((s.color[1] - 0.5 * a).abs() < 1e-14);
        }
        // The same for d = d_ref on a uniform volume reproduces the voxel opacity.
        let v = RefVoxel::new([0.3, 0.3, 0.3], 0.6);
        let u = RefVolume::uniform([2, 2, 2], v, 2.0);
        let s = sample_extinction_weighted(&u, RefFilter::TriquadraticBSpline, [0.5; 3], 2.0);
        assert!(close(s, v.associated(), 1e-15));
    }

    #[test]
    fn extinction_weighted_opaque_voxel_is_capped() {
        let vol = RefVolume::uniform([1, 1, 1], RefVoxel::new([1.0, 0.0, 0.0], 1.0), 1.0);
        let s = sample_extinction_weighted(&vol, RefFilter::Nearest, [0.0; 3], 0.01);
        assert!((s.alpha - (1.0 - (-0.64f64).exp())).abs() < 1e-15);
        assert!((s.color[0] - s.alpha).abs() < 1e-15);
        assert!(s.color[1] == 0.0 && s.alpha.is_finite());
        // Transparent everywhere: transparent sample (τ = 0 limit).
        let empty = RefVolume::uniform([2, 2, 2], RefVoxel::new([1.0; 3], 0.0), 1.0);
        let s = sample_extinction_weighted(&empty, RefFilter::Trilinear, [0.5; 3], 1.0);
        assert_eq!(s, RefAssoc::TRANSPARENT);
    }

    #[test]
    fn opacity_based_modes_are_corrected() {
        let vol = edge();
        let raw = sample_opacity_weighted(&vol, RefFilter::Trilinear, [0.5, 0.0, 0.0], 1.0);
        let half = sample_opacity_weighted(&vol, RefFilter::Trilinear, [0.5, 0.0, 0.0], 0.5);
        assert!(close(half, opacity_correct(raw, 0.5, 1.0), 0.0));
        assert!((half.alpha - (1.0 - 0.5f64.sqrt())).abs() < 1e-15);
    }

    #[test]
    fn post_classified_linear_ramp_equals_opacity_weighted() {
        // Wittenbrink §4: with a linear opacity ramp and one material color, interpolating the
        // material and classifying equals opacity-weighted interpolation of classified voxels.
        let color = [0.9, 0.4, 0.1];
        let tf = RefTransferFunction::new(vec![
            RefControlPoint::new(0.0, color, 0.0),
            RefControlPoint::new(1.0, color, 1.0),
        ]);
        let scalars = RefScalarVolume::from_fn([3, 2, 2], 1.0, |[x, y, z]| {
            [0.0, 0.3, 1.0][x] * [1.0, 0.5][y] * [1.0, 0.8][z]
        });
        let classified = scalars.classify(&tf);
        for pos in [[0.5, 0.5, 0.5], [1.25, 0.1, 0.9], [1.9, 0.7, 0.3]] {
            let post = sample_post_classified(&scalars, &tf, RefFilter::Trilinear, pos, 1.0);
            let ow = sample_opacity_weighted(&classified, RefFilter::Trilinear, pos, 1.0);
            assert!(close(post, ow, 1e-15), "{pos:?}");
        }
    }

    #[test]
    #[should_panic(expected = "PostClassified needs")]
    fn post_classified_needs_scalars() {
        let vol = edge();
        let _ = sample(
            RefSource::Straight(&vol),
            RefMode::PostClassified,
            RefFilter::Nearest,
            [0.0; 3],
            1.0,
        );
    }
}
