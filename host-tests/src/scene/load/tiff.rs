//! Multi-page TIFF stacks: one grayscale page per z-slice.

use std::path::Path;

use ::tiff::decoder::{Decoder, DecodingResult, Limits};
use ::tiff::tags::Tag;
use ::tiff::ColorType;

/// The most a compressed page may expand, per byte of the file: LZW codes of 9 bits stand for
/// at most 4096 bytes (Deflate's limit, 1032, is lower).
const MAX_EXPANSION: u64 = 4096;

use super::{bad, check_finite, open, LoadError, LoadedVolume, Scalars, Space};

/// Reads a multi-page TIFF stack (the `tiff` crate): page `z` is slice `z`, its rows `y`, its
/// columns `x`. Pages must be single-channel grayscale of one sample type: 8, 16 or 32-bit
/// unsigned or signed integers, 32 or 64-bit floats (uncompressed, LZW or Deflate), and all of
/// one size. The [`Space`] is the identity (TIFF resolution tags are not read).
///
/// # Errors
/// Unreadable or malformed TIFF (including strips past the end of the file); a page that is
/// not grayscale, has another sample type than the first, or another size; 16-bit float or
/// 64-bit integer samples; more than `cap` bytes of samples in all, or an uncompressed page
/// larger than the file (a compressed one larger than 4096 times the file), both checked
/// before the page is decoded; NaN/∞ floats.
pub fn read_tiff(path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    let (r, file_len) = open(path)?;
    let tiff_err = |page: usize, e: ::tiff::TiffError| bad(path, format!("page {page}: {e}"));
    let mut limits = Limits::default();
    limits.decoding_buffer_size = usize::try_from(cap).unwrap_or(usize::MAX);
    let mut dec = Decoder::new(r)
        .map_err(|e| bad(path, format!("not a readable TIFF file: {e}")))?
        .with_limits(limits);
    let mut data: Option<Scalars> = None;
    let mut size = (0u32, 0u32);
    let mut bytes = 0u64;
    let mut pages = 0usize;
    loop {
        let page = pages + 1;
        let (w, h) = dec.dimensions().map_err(|e| tiff_err(page, e))?;
        let bits = match dec.colortype().map_err(|e| tiff_err(page, e))? {
            ColorType::Gray(b) => b,
            c => {
                return Err(bad(
                    path,
                    format!("page {page} is {c:?}; a stack needs grayscale (one sample) pages"),
                ))
            }
        };
        if pages == 0 {
            size = (w, h);
        } else if (w, h) != size {
            return Err(bad(
                path,
                format!(
                    "page {page} is {w}×{h} but page 1 is {}×{}: the pages of a stack must \
                     have one size",
                    size.0, size.1
                ),
            ));
        }
        let page_bytes = u64::from(w) * u64::from(h) * u64::from(bits.div_ceil(8));
        bytes = bytes.saturating_add(page_bytes);
        if bytes > cap {
            return Err(bad(
                path,
                format!(
                    "{page} pages of {w}×{h} {bits}-bit samples need {bytes} bytes or more, \
                     over the memory cap of {cap} bytes"
                ),
            ));
        }
        // An uncompressed page cannot hold more than the file; a compressed one no more than
        // MAX_EXPANSION times the file. Checked before the page's buffer is allocated.
        let compression: u16 = dec
            .find_tag_unsigned(Tag::Compression)
            .map_err(|e| tiff_err(page, e))?
            .unwrap_or(1);
        let room = if compression == 1 {
            file_len
        } else {
            file_len.saturating_mul(MAX_EXPANSION)
        };
        if page_bytes > room {
            return Err(bad(
                path,
                format!(
                    "page {page} claims {w}×{h} {bits}-bit samples ({page_bytes} bytes), more \
                     than the {file_len}-byte file can hold"
                ),
            ));
        }
        let img = dec.read_image().map_err(|e| tiff_err(page, e))?;
        let want = (w as usize) * (h as usize);
        macro_rules! append {
            ($v:ident, $var:ident) => {{
                if $v.len() != want {
                    return Err(bad(
                        path,
                        format!("page {page} decoded to {} samples, need {want}", $v.len()),
                    ));
                }
                match &mut data {
                    None => data = Some(Scalars::$var($v)),
                    Some(Scalars::$var(all)) => all.extend_from_slice(&$v),
                    Some(other) => {
                        return Err(bad(
                            path,
                            format!(
                                "page {page} holds {} samples but page 1 holds {}",
                                stringify!($var),
                                other.scalar_type().name()
                            ),
                        ))
                    }
                }
            }};
        }
        match img {
            DecodingResult::U8(v) => append!(v, U8),
            DecodingResult::I8(v) => append!(v, I8),
            DecodingResult::U16(v) => append!(v, U16),
            DecodingResult::I16(v) => append!(v, I16),
            DecodingResult::U32(v) => append!(v, U32),
            DecodingResult::I32(v) => append!(v, I32),
            DecodingResult::F32(v) => append!(v, F32),
            DecodingResult::F64(v) => append!(v, F64),
            DecodingResult::F16(_) | DecodingResult::U64(_) | DecodingResult::I64(_) => {
                return Err(bad(
                    path,
                    format!(
                        "page {page}: {bits}-bit samples of this kind are not supported \
                         (8/16/32-bit integers, 32/64-bit floats)"
                    ),
                ))
            }
        }
        pages += 1;
        if !dec.more_images() {
            break;
        }
        dec.next_image().map_err(|e| tiff_err(pages + 1, e))?;
    }
    let data = data.ok_or_else(|| bad(path, "no pages"))?;
    check_finite(path, &data)?;
    let dims = [size.0 as usize, size.1 as usize, pages];
    if dims.contains(&0) {
        return Err(bad(path, "a dimension is zero"));
    }
    Ok(LoadedVolume {
        dims,
        data,
        space: Space::identity(),
    })
}
