//! Multi-page TIFF stacks: one grayscale page per z-slice.

use std::collections::HashSet;
use std::io::{self, Read, Seek, SeekFrom};
use std::path::Path;

use ::tiff::decoder::{Decoder, DecodingResult, Limits};
use ::tiff::tags::Tag;
use ::tiff::ColorType;

/// The most a compressed page may expand, per byte of the file: LZW codes of 9 bits stand for
/// at most 4096 bytes (Deflate's limit, 1032, is lower).
const MAX_EXPANSION: u64 = 4096;

use super::{bad, check_finite, io_err, open, LoadError, LoadedVolume, Scalars, Space};

/// The bytes one value of a TIFF field type takes in the file, `None` for a type the `tiff`
/// crate does not know (it skips such entries).
fn type_bytes(ty: u16) -> Option<u64> {
    match ty {
        1 | 2 | 6 | 7 => Some(1),              // BYTE, ASCII, SBYTE, UNDEFINED
        3 | 8 => Some(2),                      // SHORT, SSHORT
        4 | 9 | 11 | 13 => Some(4),            // LONG, SLONG, FLOAT, IFD
        5 | 10 | 12 | 16 | 17 | 18 => Some(8), // RATIONAL, SRATIONAL, DOUBLE, LONG8, SLONG8, IFD8
        _ => None,
    }
}

/// Walks the file's chain of image directories (IFDs) before the `tiff` crate reads any, and
/// refuses an entry whose values cannot lie in the file: more bytes than the file holds, or
/// out-of-line values that run past its end. The crate reserves memory for an entry's
/// declared count before it reads the values, and it reads the first directory before a
/// decoder's limits can be set; this check is what bounds that reservation by the file's size.
/// Sound: a well-formed file's values lie inside it. Returns `Ok` without judging what is not
/// a TIFF header, so the crate's own error reports it.
fn check_directories(path: &Path, file_len: u64) -> Result<(), LoadError> {
    let file = std::fs::File::open(path).map_err(io_err(path))?;
    let mut r = io::BufReader::new(file);
    let mut head = [0u8; 8];
    if r.read_exact(&mut head).is_err() {
        return Ok(());
    }
    let big_endian = match &head[..2] {
        b"II" => false,
        b"MM" => true,
        _ => return Ok(()),
    };
    let u16_of = |b: &[u8]| {
        let a = [b[0], b[1]];
        if big_endian {
            u16::from_be_bytes(a)
        } else {
            u16::from_le_bytes(a)
        }
    };
    let u32_of = |b: &[u8]| {
        let a = [b[0], b[1], b[2], b[3]];
        if big_endian {
            u32::from_be_bytes(a)
        } else {
            u32::from_le_bytes(a)
        }
    };
    let u64_of = |b: &[u8]| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&b[..8]);
        if big_endian {
            u64::from_be_bytes(a)
        } else {
            u64::from_le_bytes(a)
        }
    };
    let big_tiff = match u16_of(&head[2..4]) {
        42 => false,
        43 => true,
        _ => return Ok(()),
    };
    let mut next = if big_tiff {
        let mut b = [0u8; 8];
        if r.read_exact(&mut b).is_err() {
            return Ok(());
        }
        u64_of(&b)
    } else {
        u64::from(u32_of(&head[4..8]))
    };
    // Entry layout: tag u16, type u16, count (u32 | u64), value or offset (4 | 8 bytes).
    let (entry_len, inline) = if big_tiff { (20usize, 8u64) } else { (12, 4) };
    let mut seen = HashSet::new();
    let mut dir = 0usize;
    // A directory past the end, or one already seen, ends the walk; the crate reports it.
    while next != 0 && next < file_len && seen.insert(next) {
        dir += 1;
        if r.seek(SeekFrom::Start(next)).is_err() {
            return Ok(());
        }
        let mut b = [0u8; 8];
        let entries = if big_tiff {
            if r.read_exact(&mut b).is_err() {
                return Ok(());
            }
            u64_of(&b)
        } else {
            if r.read_exact(&mut b[..2]).is_err() {
                return Ok(());
            }
            u64::from(u16_of(&b))
        };
        let mut e = [0u8; 20];
        for _ in 0..entries {
            if r.read_exact(&mut e[..entry_len]).is_err() {
                return Ok(());
            }
            let tag = u16_of(&e[0..2]);
            let Some(size) = type_bytes(u16_of(&e[2..4])) else {
                continue;
            };
            let (count, offset) = if big_tiff {
                (u64_of(&e[4..12]), u64_of(&e[12..20]))
            } else {
                (u64::from(u32_of(&e[4..8])), u64::from(u32_of(&e[8..12])))
            };
            let bytes = count.checked_mul(size);
            let fits = match bytes {
                Some(n) if n <= inline => true,
                Some(n) => offset.checked_add(n).is_some_and(|end| end <= file_len),
                None => false,
            };
            if !fits {
                return Err(bad(
                    path,
                    format!(
                        "directory {dir}: tag {tag} declares {count} values of {size} bytes, \
                         more than the {file_len}-byte file holds at offset {offset}"
                    ),
                ));
            }
        }
        next = if big_tiff {
            if r.read_exact(&mut b).is_err() {
                return Ok(());
            }
            u64_of(&b)
        } else {
            if r.read_exact(&mut b[..4]).is_err() {
                return Ok(());
            }
            u64::from(u32_of(&b[..4]))
        };
    }
    Ok(())
}

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
/// before the page is decoded; a directory entry whose values cannot lie in the file, checked
/// for every directory before any is read; NaN/∞ floats.
pub fn read_tiff(path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    let (r, file_len) = open(path)?;
    check_directories(path, file_len)?;
    let tiff_err = |page: usize, e: ::tiff::TiffError| bad(path, format!("page {page}: {e}"));
    let mut limits = Limits::default();
    limits.decoding_buffer_size = usize::try_from(cap).unwrap_or(usize::MAX);
    // A strip or tile's compressed bytes lie in the file.
    limits.intermediate_buffer_size = usize::try_from(file_len).unwrap_or(usize::MAX);
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
