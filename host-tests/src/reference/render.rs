//! Whole-image reference renderer and its ground-truth counterpart.

use super::camera::{camera_ray, RefCamera};
use super::composite::{composite_front_to_back, over_background};
use super::filter::RefFilter;
use super::mode::{sample, RefMode, RefSource};
use super::ray::sample_positions;
use super::truth::integrate_source_exact;
use super::volume::RefAssoc;

/// Everything but the camera and the volume that a reference rendering needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefRenderParams {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Sampling mode.
    pub mode: RefMode,
    /// Reconstruction filter.
    pub filter: RefFilter,
    /// Step `d` between samples, in voxel units.
    pub step: f64,
    /// Ray phase in `[0, 1)`: samples at `t = (k + phase)·step`.
    pub phase: f64,
    /// Associated background composited behind every pixel.
    pub background: RefAssoc,
    /// Early-termination opacity (`1.0`: composite every sample).
    pub a_stop: f64,
}

impl RefRenderParams {
    /// `width × height`, `OpacityWeighted`, `Trilinear`, step 1, phase 0, transparent
    /// background, no early stop.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            mode: RefMode::OpacityWeighted,
            filter: RefFilter::Trilinear,
            step: 1.0,
            phase: 0.0,
            background: RefAssoc::TRANSPARENT,
            a_stop: 1.0,
        }
    }
}

/// Pixel `(i, j)` of [`render_reference`]: the camera ray's samples ([`sample_positions`],
/// each sampled by [`sample`] with `params.step` as `d`), composited front to back with early
/// stop at `params.a_stop`, then over `params.background`.
pub fn render_pixel(
    camera: &RefCamera,
    source: RefSource<'_>,
    params: &RefRenderParams,
    i: usize,
    j: usize,
) -> RefAssoc {
    let ray = camera_ray(camera, params.width, params.height, i, j);
    let samples: Vec<RefAssoc> = sample_positions(source.dims(), &ray, params.step, params.phase)
        .into_iter()
        .map(|p| sample(source, params.mode, params.filter, p, params.step))
        .collect();
    over_background(
        composite_front_to_back(&samples, params.a_stop),
        params.background,
    )
}

/// Renders `source` seen by `camera`: `width·height` associated pixels, row-major, row 0 at
/// the top (pixel `(i, j)` at index `j·width + i`). The reference distance is the source's.
///
/// # Panics
/// As [`sample`] (e.g. `PostClassified` with a non-scalar source).
pub fn render_reference(
    camera: &RefCamera,
    source: RefSource<'_>,
    params: &RefRenderParams,
) -> Vec<RefAssoc> {
    let mut out = Vec::with_capacity(params.width * params.height);
    for j in 0..params.height {
        for i in 0..params.width {
            out.push(render_pixel(camera, source, params, i, j));
        }
    }
    out
}

/// Ground-truth image for the same camera and layout: each pixel is
/// [`integrate_source_exact`] with `params.filter` and substeps of at most `h`, over
/// `params.background`. Ignores `mode`, `step`, `phase` and `a_stop`.
pub fn render_exact(
    camera: &RefCamera,
    source: RefSource<'_>,
    params: &RefRenderParams,
    h: f64,
) -> Vec<RefAssoc> {
    let mut out = Vec::with_capacity(params.width * params.height);
    for j in 0..params.height {
        for i in 0..params.width {
            let ray = camera_ray(camera, params.width, params.height, i, j);
            let acc = integrate_source_exact(source, params.filter, &ray, h);
            out.push(over_background(acc, params.background));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::volume::{RefVolume, RefVoxel};
    use super::*;

    fn ortho_x(extent: f64) -> RefCamera {
        // Looks along +x at a volume centred at (1.5, 1.5, 1.5).
        RefCamera::Orthographic {
            eye: [-5.0, 1.5, 1.5],
            dir: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            extent,
        }
    }

    #[test]
    fn uniform_volume_closed_form() {
        let v = RefVoxel::new([1.0, 0.5, 0.0], 0.25);
        let vol = RefVolume::uniform([4, 4, 4], v, 1.0);
        let mut p = RefRenderParams::new(1, 1);
        p.phase = 0.5;
        // The box spans t ∈ [4.5, 8.5]; phase ½ puts samples at t = 4.5, 5.5, 6.5, 7.5.
        let img = render_reference(&ortho_x(2.0), RefSource::Straight(&vol), &p);
        let a = 1.0 - 0.75f64.powi(4);
        assert_eq!(img.len(), 1);
        assert!((img[0].alpha - a).abs() < 1e-15);
        assert!((img[0].color[1] - 0.5 * a).abs() < 1e-15);
        // Extinction truth: the same opacity for a homogeneous medium.
        let truth = render_exact(&ortho_x(2.0), RefSource::Straight(&vol), &p, 1.0 / 64.0);
        assert!((truth[0].alpha - a).abs() < 1e-14);
    }

    #[test]
    fn layout_background_and_misses() {
        let vol = RefVolume::uniform([4, 4, 4], RefVoxel::new([0.0, 1.0, 0.0], 1.0), 1.0);
        let mut p = RefRenderParams::new(3, 3);
        p.background = RefAssoc::new([1.0, 0.0, 0.0], 1.0);
        // Extent 12: pixel pitch 4, so only the centre pixel hits the 4³ box.
        let img = render_reference(&ortho_x(12.0), RefSource::Straight(&vol), &p);
        assert_eq!(img.len(), 9);
        for (n, px) in img.iter().enumerate() {
            if n == 4 {
                assert_eq!(*px, RefAssoc::new([0.0, 1.0, 0.0], 1.0));
            } else {
                assert_eq!(*px, p.background, "pixel {n} misses");
            }
        }
    }

    #[test]
    fn early_stop_changes_only_what_it_should() {
        let vol = RefVolume::uniform([8, 1, 1], RefVoxel::new([1.0; 3], 0.5), 1.0);
        let cam = RefCamera::Orthographic {
            eye: [-5.0, 0.0, 0.0],
            dir: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            extent: 0.5,
        };
        let mut p = RefRenderParams::new(1, 1);
        p.a_stop = 0.9;
        // 1 − 0.5ⁿ ≥ 0.9 first at n = 4.
        let img = render_reference(&cam, RefSource::Straight(&vol), &p);
        assert_eq!(img[0].alpha, 1.0 - 0.5f64.powi(4));
    }
}
