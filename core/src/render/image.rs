//! The pixel loops and image checks shared by the float and the integer ray marchers.

use crate::arch::InIsa;
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

/// Checks a band of image rows: [`Error::EmptyImage`] for a zero width or height,
/// [`Error::ImageSizeMismatch`] unless `len` is a whole number of rows, and
/// [`Error::RowsOutsideImage`] unless rows `first .. first + len / width` lie in the image.
/// Returns the number of rows.
fn check_rows(width: usize, height: usize, first: usize, len: usize) -> Result<usize, Error> {
    if width == 0 || height == 0 {
        return Err(Error::EmptyImage);
    }
    let rows = len / width;
    if rows * width != len {
        return Err(Error::ImageSizeMismatch {
            expected: (rows + 1).saturating_mul(width),
            actual: len,
        });
    }
    match first.checked_add(rows) {
        Some(end) if end <= height => Ok(rows),
        _ => Err(Error::RowsOutsideImage {
            first,
            rows,
            height,
        }),
    }
}

/// Checks a whole image: as [`check_rows`] from row 0, but [`Error::ImageSizeMismatch`]
/// unless `len == width·height`.
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

/// Fills rows `first ..` of a `width × height` image (row-major, row 0 at the top; `image`
/// holds the band's rows) by `cast8` of eight pixels of a row at a time: the eight-ray
/// packets' pixel loop of both ray marchers. A short last chunk of a row fills the lanes by
/// repeating its last pixel's ray and keeps only its own pixels (each lane's result is that
/// of its ray alone, so the repeats change nothing).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn trace_rows8<P: Copy, Cam: Camera>(
    camera: &Cam,
    (width, height): (usize, usize),
    first: usize,
    image: &mut [P],
    mut cast8: impl FnMut(&[Ray; 8], &mut [P; 8]),
) {
    for (j, row) in image.chunks_exact_mut(width).enumerate() {
        let j = first + j;
        for (k, px) in row.chunks_mut(8).enumerate() {
            let i0 = 8 * k;
            let rays: [Ray; 8] =
                crate::each::build(|l| camera.ray((i0 + l).min(width - 1), j, width, height));
            let Some(&p0) = px.first() else {
                continue;
            };
            let mut out = [p0; 8];
            cast8(&rays, &mut out);
            for (p, o) in px.iter_mut().zip(out) {
                *p = o;
            }
        }
    }
}

/// Fills rows `first ..` of a `width × height` image (`image` holds the band's rows) with
/// `cast` of each pixel's ray: the pixel loop shared by the float and the integer ray
/// marchers.
fn trace_image<P, Cam: Camera>(
    camera: &Cam,
    (width, height): (usize, usize),
    first: usize,
    image: &mut [P],
    cast: impl Fn(&Ray) -> P,
) {
    for (j, row) in image.chunks_exact_mut(width).enumerate() {
        for (i, px) in row.iter_mut().enumerate() {
            *px = cast(&camera.ray(i, first + j, width, height));
        }
    }
}

/// Checks the image of both ray marchers' `render_into` (`rows: None`, the whole image) and
/// `render_rows_into` (`rows: Some(first)`, the band of rows from `first` that `image`
/// holds) and returns its first row.
///
/// # Errors
/// [`Error::EmptyImage`] for a zero width or height; [`Error::ImageSizeMismatch`] unless
/// `image.len()` is `width·height` (whole image) or a multiple of `width` (band);
/// [`Error::RowsOutsideImage`] for a band that does not lie in the image.
fn first_row(
    (width, height): (usize, usize),
    rows: Option<usize>,
    len: usize,
) -> Result<usize, Error> {
    match rows {
        None => check_image(width, height, len).map(|()| 0),
        Some(first) => check_rows(width, height, first, len).map(|_| first),
    }
}

/// The body of both ray marchers' `render_into` (`rows: None`) and `render_rows_into`
/// (`rows: Some(first)`) for the marcher `m`, on the image (or band) that [`first_row`]
/// checks. Where `packets` holds (the marcher's eight-ray kernel applies: its instruction
/// set is AVX2 and its types have the kernel), eight pixels of a row at a time
/// ([`trace_rows8`]) inside the marcher's AVX2 entry ([`InIsa::in_avx2`]) by `cast_rays8`,
/// which casts the leading multiple of eight rays and returns the rest, and `cast` of each
/// ray of the rest (none while the kernel applies); otherwise each pixel by `cast`
/// ([`trace_image`]), which enters the marcher's instruction set per ray: the one-ray march
/// is compiled once per instance of the marcher, shared with `cast`, and only the AVX2
/// instance with the packets. Every pixel is the same either way, and the same in the whole
/// image or a band.
///
/// # Errors
/// Those of [`first_row`].
#[inline(always)]
pub(crate) fn render_band<M: InIsa, P: Copy, Cam: Camera>(
    (m, packets): (&M, bool),
    (camera, size, rows): (&Cam, (usize, usize), Option<usize>),
    image: &mut [P],
    (cast_rays8, cast): (
        impl for<'r, 'o> Fn(&M, &'r [Ray], &'o mut [P]) -> (&'r [Ray], &'o mut [P]),
        impl Fn(&M, &Ray) -> P,
    ),
) -> Result<(), Error> {
    let first = first_row(size, rows, image.len())?;
    #[cfg(target_arch = "x86_64")]
    if let Some(cpu) = m.isa_of().avx2_token().filter(|_| packets) {
        // The closure inlined into the AVX2 entry, as `in_isa!`'s. `Err` (no AVX2 instance)
        // only where `packets` is false, by type.
        let eight = m.in_avx2(
            cpu,
            #[inline(always)]
            || {
                trace_rows8(camera, size, first, &mut *image, |rays, out| {
                    let (rest, out) = cast_rays8(m, rays, out);
                    for (r, o) in rest.iter().zip(out) {
                        *o = cast(m, r);
                    }
                });
            },
        );
        if eight.is_ok() {
            return Ok(());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (packets, cast_rays8);
    trace_image(camera, size, first, image, |ray| cast(m, ray));
    Ok(())
}
