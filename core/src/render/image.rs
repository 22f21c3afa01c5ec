//! The pixel loops and image checks shared by the float and the integer ray marchers.

use crate::error::Error;
use crate::ray::{Camera, Ray};

/// [`Error::ImageSizeMismatch`] unless `actual == expected`.
pub(crate) fn check_len(expected: usize, actual: usize) -> Result<(), Error> {
    if actual == expected {
        Ok(())
    } else {
        Err(Error::ImageSizeMismatch { expected, actual })
    }
}

/// Checks an image buffer: [`Error::EmptyImage`] for a zero width or height,
/// [`Error::ImageSizeMismatch`] unless `len == width·height`.
fn check_image(width: usize, height: usize, len: usize) -> Result<(), Error> {
    if width == 0 || height == 0 {
        return Err(Error::EmptyImage);
    }
    let expected = width.checked_mul(height).ok_or(Error::ImageSizeMismatch {
        expected: usize::MAX,
        actual: len,
    })?;
    if len != expected {
        return Err(Error::ImageSizeMismatch {
            expected,
            actual: len,
        });
    }
    Ok(())
}

/// Fills a `width × height` image (row-major, row 0 at the top) by `cast_rays` of eight
/// pixels of a row at a time (a short last chunk of a row: its own pixels only), after
/// checking the image size: the eight-ray packets' pixel loop of both ray marchers.
///
/// # Errors
/// As [`trace_image`], and those of `cast_rays`.
fn trace_rows8<P, Cam: Camera>(
    camera: &Cam,
    width: usize,
    height: usize,
    image: &mut [P],
    mut cast_rays: impl FnMut(&[Ray], &mut [P]) -> Result<(), Error>,
) -> Result<(), Error> {
    check_image(width, height, image.len())?;
    for (j, row) in image.chunks_exact_mut(width).enumerate() {
        for (k, px) in row.chunks_mut(8).enumerate() {
            let i0 = 8 * k;
            // A short last chunk repeats its last pixel's ray; only `px.len()` are cast.
            let rays: [Ray; 8] =
                core::array::from_fn(|l| camera.ray((i0 + l).min(width - 1), j, width, height));
            let rays = rays.get(..px.len()).unwrap_or(&rays);
            cast_rays(rays, px)?;
        }
    }
    Ok(())
}

/// Fills a `width × height` image (row-major, row 0 at the top) with `cast` of each pixel's
/// ray, after checking the image size: the pixel loop shared by the float and the integer
/// ray marchers.
///
/// # Errors
/// [`Error::EmptyImage`] for a zero width or height, [`Error::ImageSizeMismatch`] unless
/// `image.len() == width·height`.
fn trace_image<P, Cam: Camera>(
    camera: &Cam,
    width: usize,
    height: usize,
    image: &mut [P],
    cast: impl Fn(&Ray) -> P,
) -> Result<(), Error> {
    check_image(width, height, image.len())?;
    for (j, row) in image.chunks_exact_mut(width).enumerate() {
        for (i, px) in row.iter_mut().enumerate() {
            *px = cast(&camera.ray(i, j, width, height));
        }
    }
    Ok(())
}

/// The image of both ray marchers' `render_into`: where `packets`, eight pixels of a row at a
/// time by `cast_rays` (as many rays as outputs; [`trace_rows8`]), else each pixel by
/// `cast` ([`trace_image`]).
///
/// # Errors
/// As [`trace_image`].
#[inline(always)]
pub(crate) fn render_image<P, Cam: Camera>(
    camera: &Cam,
    (width, height): (usize, usize),
    image: &mut [P],
    packets: bool,
    mut cast_rays: impl FnMut(&[Ray], &mut [P]),
    cast: impl Fn(&Ray) -> P,
) -> Result<(), Error> {
    if packets {
        trace_rows8(camera, width, height, image, |rays, px| {
            check_len(rays.len(), px.len())?;
            cast_rays(rays, px);
            Ok(())
        })
    } else {
        trace_image(camera, width, height, image, cast)
    }
}
