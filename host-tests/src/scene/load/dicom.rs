//! DICOM series: the image files of one folder, one slice per file, as one volume.
//!
//! Each file is walked with the lazy reader of `dicom-parser` (element headers first, values on
//! demand): every element's length is checked against the bytes left in the file before its
//! value is read, and the pixel data are not read by the parser at all, only located. The
//! samples are read here, after the whole series was checked and its size held against the
//! memory cap.
//!
//! # Space: DICOM's LPS patient coordinates to RAS+
//!
//! DICOM places a slice by `ImagePositionPatient` (the centre of its first pixel) and
//! `ImageOrientationPatient` (two unit vectors: the direction of a row, in which the column
//! index grows, then the direction of a column, in which the row index grows), in LPS
//! millimetres (`+x` left, `+y` posterior, `+z` superior). With `PixelSpacing = [Δrow, Δcol]`
//! (the distance between rows, then between columns) the index-to-LPS affine of voxel
//! `(i, j, k)` = (column, row, slice) is
//!
//! ```text
//! [ r·Δcol | c·Δrow | s | P₀ ]     r, c: the two direction cosines, P₀: the first slice's position
//! ```
//!
//! where `s` is the step from slice to slice: `(P_last − P₀)/(n − 1)` over the sorted slices
//! (for one slice: the normal `r × c` times `SpacingBetweenSlices`, else `SliceThickness`, else
//! 1 mm). Negating its first two rows gives the RAS+ [`Space`] (source
//! [`SpaceSource::DicomPatient`]).
//!
//! Slices are sorted by their position along the normal `r × c`; the gaps between neighbours
//! must agree (within 1 % of the median gap plus 0.01 mm), and every position must lie on the line
//! from the first to the last (no missing, doubled or shifted slice).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry};
use dicom_core::{PrimitiveValue, Tag};
use dicom_dictionary_std::tags;
use dicom_encoding::Endianness;
use dicom_parser::dataset::lazy_read::LazyDataSetReader;
use dicom_parser::dataset::LazyDataToken;
use dicom_parser::StatefulDecode;
use dicom_transfer_syntax_registry::{TransferSyntaxIndex, TransferSyntaxRegistry};

use crate::view::{cross, dot};

use super::{
    bad, checked_size, io_err, progress_inc, progress_start, read_full, LoadError, LoadedVolume,
    ScalarType, Scalars, Space, SpaceSource,
};

/// Explicit VR Little Endian: the file meta group's encoding in every DICOM file.
const EXPLICIT_VR_LE: &str = "1.2.840.10008.1.2.1";
/// The Media Storage SOP Class of a DICOMDIR (a directory record, not an image).
const DICOMDIR_CLASS: &str = "1.2.840.10008.1.3.10";

/// The attributes read from each file (all in the root data set).
const WANTED: [Tag; 17] = [
    tags::SERIES_INSTANCE_UID,
    tags::SAMPLES_PER_PIXEL,
    tags::PHOTOMETRIC_INTERPRETATION,
    tags::NUMBER_OF_FRAMES,
    tags::ROWS,
    tags::COLUMNS,
    tags::BITS_ALLOCATED,
    tags::BITS_STORED,
    tags::HIGH_BIT,
    tags::PIXEL_REPRESENTATION,
    tags::IMAGE_POSITION_PATIENT,
    tags::IMAGE_ORIENTATION_PATIENT,
    tags::PIXEL_SPACING,
    tags::RESCALE_SLOPE,
    tags::RESCALE_INTERCEPT,
    tags::SPACING_BETWEEN_SLICES,
    tags::SLICE_THICKNESS,
];

/// One image file of a series: what its header says and where its pixels are.
struct Slice {
    path: PathBuf,
    series: String,
    rows: usize,
    cols: usize,
    bits: u16,
    bits_stored: u16,
    high_bit: u16,
    signed: bool,
    position: [f64; 3],
    orientation: [f64; 6],
    pixel_spacing: [f64; 2],
    slope: f64,
    intercept: f64,
    /// `SpacingBetweenSlices`, else `SliceThickness` (used for a single slice only).
    thickness: Option<f64>,
    big_endian: bool,
    /// File offset of the first pixel byte.
    data_offset: u64,
}

impl Slice {
    fn bytes_per_sample(&self) -> usize {
        usize::from(self.bits / 8)
    }

    /// The smallest and largest stored value `BitsStored` allows.
    fn stored_range(&self) -> (i64, i64) {
        let b = u32::from(self.bits_stored);
        if self.signed {
            (-(1i64 << (b - 1)), (1i64 << (b - 1)) - 1)
        } else {
            (0, (1i64 << b) - 1)
        }
    }

    fn name(&self) -> String {
        self.path.file_name().map_or_else(
            || self.path.display().to_string(),
            |n| n.to_string_lossy().into(),
        )
    }
}

/// `(gggg,eeee)`.
fn tag_name(t: Tag) -> String {
    format!("({:04X},{:04X})", t.0, t.1)
}

/// The file meta group: transfer syntax and SOP class UIDs, and where the data set starts.
struct Meta {
    transfer_syntax: String,
    sop_class: String,
    end: u64,
}

/// Checks that an element of `len` bytes at `pos` fits in the file.
fn fits(path: &Path, tag: Option<Tag>, len: u32, pos: u64, file_len: u64) -> Result<(), LoadError> {
    let left = file_len.saturating_sub(pos);
    if u64::from(len) > left {
        let what = tag.map_or_else(
            || "an item".to_string(),
            |t| format!("element {}", tag_name(t)),
        );
        return Err(bad(
            path,
            format!(
                "{what} at byte {pos} claims {len} bytes, but the file has only {left} bytes left"
            ),
        ));
    }
    Ok(())
}

/// A UID or code string without DICOM's padding.
fn text(v: &PrimitiveValue) -> String {
    v.to_str()
        .trim_matches(|c: char| c == '\0' || c.is_whitespace())
        .to_string()
}

/// Reads the file meta group (always Explicit VR Little Endian) after the preamble.
fn read_meta(path: &Path, f: &mut BufReader<File>, file_len: u64) -> Result<Meta, LoadError> {
    let ts = TransferSyntaxRegistry
        .get(EXPLICIT_VR_LE)
        .ok_or_else(|| bad(path, "the DICOM registry lacks Explicit VR Little Endian"))?;
    let meta_err = |e: &dyn std::fmt::Display| bad(path, format!("malformed file meta group: {e}"));
    let mut rd = LazyDataSetReader::new_with_ts(&mut *f, ts).map_err(|e| meta_err(&e))?;
    let mut end = None;
    let mut transfer_syntax = None;
    let mut sop_class = String::new();
    loop {
        let tok = match rd.advance() {
            None => break,
            Some(t) => t.map_err(|e| meta_err(&e))?,
        };
        let (header, decoder) = match tok {
            // A value's header comes first, then the value.
            LazyDataToken::ElementHeader(_) => continue,
            LazyDataToken::LazyValue { header, decoder } => (header, decoder),
            _ => {
                return Err(bad(
                    path,
                    "malformed file meta group: a sequence in group 0002",
                ))
            }
        };
        let pos = decoder.position();
        let len = header
            .len
            .get()
            .ok_or_else(|| bad(path, "malformed file meta group: an undefined length"))?;
        fits(path, Some(header.tag), len, pos, file_len)?;
        let tok = LazyDataToken::LazyValue { header, decoder };
        let value = tok.into_value().map_err(|e| meta_err(&e))?;
        let next = pos + u64::from(len);
        match header.tag {
            tags::FILE_META_INFORMATION_GROUP_LENGTH => {
                let gl: u32 = value.to_int().map_err(|e| meta_err(&e))?;
                end = Some(next + u64::from(gl));
            }
            tags::TRANSFER_SYNTAX_UID => transfer_syntax = Some(text(&value)),
            tags::MEDIA_STORAGE_SOP_CLASS_UID => sop_class = text(&value),
            _ => {}
        }
        let Some(end) = end else {
            return Err(bad(
                path,
                "the file meta group does not start with its group length (0002,0000)",
            ));
        };
        if next >= end {
            break;
        }
    }
    let end = end.ok_or_else(|| bad(path, "empty file meta group"))?;
    if end > file_len {
        return Err(bad(
            path,
            format!("the file meta group claims to end at byte {end}, past the end of the {file_len}-byte file"),
        ));
    }
    let transfer_syntax = transfer_syntax.ok_or_else(|| {
        bad(
            path,
            "the file meta group has no transfer syntax (0002,0010)",
        )
    })?;
    Ok(Meta {
        transfer_syntax,
        sop_class,
        end,
    })
}

/// Whether `path` starts like a DICOM file: a 128-byte preamble, then `DICM`.
fn is_dicom(path: &Path) -> Result<bool, LoadError> {
    let mut f = File::open(path).map_err(io_err(path))?;
    let mut head = [0u8; 132];
    let n = read_full(&mut f, &mut head).map_err(io_err(path))?;
    Ok(n == 132 && &head[128..] == b"DICM")
}

/// Reads one file's header: `None` for a DICOMDIR.
fn read_header(path: &Path) -> Result<Option<Slice>, LoadError> {
    let file = File::open(path).map_err(io_err(path))?;
    let file_len = file.metadata().map_err(io_err(path))?.len();
    let mut f = BufReader::new(file);
    f.seek(SeekFrom::Start(132)).map_err(io_err(path))?;
    let meta = read_meta(path, &mut f, file_len)?;
    if meta.sop_class == DICOMDIR_CLASS {
        return Ok(None);
    }
    let uid = meta.transfer_syntax.as_str();
    let ts = TransferSyntaxRegistry
        .get(uid)
        .ok_or_else(|| bad(path, format!("unknown transfer syntax {uid}")))?;
    if !ts.is_codec_free() {
        return Err(bad(
            path,
            format!(
                "transfer syntax {} ({uid}) is compressed; only uncompressed data are read \
                 (Implicit VR Little Endian, Explicit VR Little or Big Endian)",
                ts.name()
            ),
        ));
    }
    let big_endian = ts.endianness() == Endianness::Big;
    f.seek(SeekFrom::Start(meta.end)).map_err(io_err(path))?;
    let ds_err = |e: &dyn std::fmt::Display| bad(path, format!("malformed data set: {e}"));
    let mut rd = LazyDataSetReader::new_with_ts(&mut f, ts).map_err(|e| ds_err(&e))?;
    let mut values: BTreeMap<Tag, PrimitiveValue> = BTreeMap::new();
    let mut pixels: Option<(u64, u32)> = None;
    let mut depth = 0usize;
    while let Some(tok) = rd.advance() {
        match tok.map_err(|e| ds_err(&e))? {
            LazyDataToken::PixelSequenceStart => {
                return Err(bad(
                    path,
                    format!(
                        "encapsulated (compressed) pixel data under transfer syntax {} ({uid})",
                        ts.name()
                    ),
                ))
            }
            LazyDataToken::SequenceStart { .. } => depth += 1,
            LazyDataToken::SequenceEnd => depth = depth.saturating_sub(1),
            LazyDataToken::ItemStart { .. }
            | LazyDataToken::ItemEnd
            | LazyDataToken::ElementHeader(_) => {}
            LazyDataToken::LazyItemValue { len, decoder } => {
                fits(path, None, len, decoder.position(), file_len)?;
                LazyDataToken::LazyItemValue { len, decoder }
                    .skip()
                    .map_err(|e| ds_err(&e))?;
            }
            LazyDataToken::LazyValue { header, decoder } => {
                let pos = decoder.position();
                let len = header.len.get().ok_or_else(|| {
                    bad(
                        path,
                        format!("element {} has an undefined length", tag_name(header.tag)),
                    )
                })?;
                fits(path, Some(header.tag), len, pos, file_len)?;
                let tok = LazyDataToken::LazyValue { header, decoder };
                if depth == 0 && header.tag == tags::PIXEL_DATA {
                    pixels = Some((pos, len));
                    break;
                } else if depth == 0 && WANTED.contains(&header.tag) {
                    values.insert(header.tag, tok.into_value().map_err(|e| ds_err(&e))?);
                } else {
                    tok.skip().map_err(|e| ds_err(&e))?;
                }
            }
            other => {
                return Err(bad(
                    path,
                    format!("malformed data set: unexpected {other:?}"),
                ))
            }
        }
    }
    let slice = slice_of(path, &values, pixels, big_endian)?;
    Ok(Some(slice))
}

/// The slice a file's attributes describe, or why it cannot be one.
fn slice_of(
    path: &Path,
    values: &BTreeMap<Tag, PrimitiveValue>,
    pixels: Option<(u64, u32)>,
    big_endian: bool,
) -> Result<Slice, LoadError> {
    let name = |t: Tag| {
        dicom_dictionary_std::StandardDataDictionary
            .by_tag(t)
            .map_or_else(|| tag_name(t), |e| format!("{} {}", e.alias(), tag_name(t)))
    };
    let missing = |t: Tag| bad(path, format!("no {} (needed to place the slice)", name(t)));
    let unreadable = |t: Tag, v: &PrimitiveValue| {
        bad(
            path,
            format!("{} is '{}', not a valid value", name(t), v.to_str()),
        )
    };
    let int = |t: Tag| -> Result<Option<i64>, LoadError> {
        values
            .get(&t)
            .map(|v| v.to_int::<i64>().map_err(|_| unreadable(t, v)))
            .transpose()
    };
    let floats = |t: Tag, n: usize| -> Result<Option<Vec<f64>>, LoadError> {
        let Some(v) = values.get(&t) else {
            return Ok(None);
        };
        match v.to_multi_float64() {
            Ok(f) if f.len() == n && f.iter().all(|x| x.is_finite()) => Ok(Some(f)),
            _ => Err(bad(
                path,
                format!("{} is '{}': need {n} finite numbers", name(t), v.to_str()),
            )),
        }
    };
    let need_int = |t: Tag| int(t)?.ok_or_else(|| missing(t));
    let samples = int(tags::SAMPLES_PER_PIXEL)?.unwrap_or(1);
    let photometric = values
        .get(&tags::PHOTOMETRIC_INTERPRETATION)
        .map(text)
        .unwrap_or_else(|| "MONOCHROME2".into());
    if samples != 1 || !photometric.starts_with("MONOCHROME") {
        return Err(bad(
            path,
            format!(
                "{samples} samples per pixel, photometric interpretation {photometric}: only \
                 grayscale images (one sample, MONOCHROME1 or MONOCHROME2) are read"
            ),
        ));
    }
    if let Some(frames) = int(tags::NUMBER_OF_FRAMES)? {
        if frames != 1 {
            return Err(bad(
                path,
                format!("{frames} frames in one file: only single-frame files are read"),
            ));
        }
    }
    let rows = need_int(tags::ROWS)?;
    let cols = need_int(tags::COLUMNS)?;
    let bits = need_int(tags::BITS_ALLOCATED)?;
    let bits_stored = int(tags::BITS_STORED)?.unwrap_or(bits);
    let high_bit = int(tags::HIGH_BIT)?.unwrap_or(bits_stored - 1);
    let signed = match need_int(tags::PIXEL_REPRESENTATION)? {
        0 => false,
        1 => true,
        p => return Err(bad(path, format!("pixel representation {p} (need 0 or 1)"))),
    };
    if !matches!(bits, 8 | 16 | 32) {
        return Err(bad(
            path,
            format!("{bits} bits allocated per sample: only 8, 16 and 32 are read"),
        ));
    }
    if !(1..=bits).contains(&bits_stored) || !(bits_stored - 1..bits).contains(&high_bit) {
        return Err(bad(
            path,
            format!(
                "bits stored {bits_stored}, high bit {high_bit} do not fit in {bits} bits \
                 allocated"
            ),
        ));
    }
    if rows <= 0 || cols <= 0 {
        return Err(bad(
            path,
            format!("{cols}×{rows} pixels: need at least 1×1"),
        ));
    }
    let (Ok(rows), Ok(cols)) = (usize::try_from(rows), usize::try_from(cols)) else {
        return Err(bad(path, "rows or columns out of range"));
    };
    let position = floats(tags::IMAGE_POSITION_PATIENT, 3)?
        .ok_or_else(|| missing(tags::IMAGE_POSITION_PATIENT))?;
    let orientation = floats(tags::IMAGE_ORIENTATION_PATIENT, 6)?
        .ok_or_else(|| missing(tags::IMAGE_ORIENTATION_PATIENT))?;
    let pixel_spacing =
        floats(tags::PIXEL_SPACING, 2)?.ok_or_else(|| missing(tags::PIXEL_SPACING))?;
    let (r, c) = (&orientation[..3], &orientation[3..]);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot: f64 = r.iter().zip(c).map(|(a, b)| a * b).sum();
    if (norm(r) - 1.0).abs() > 1e-3 || (norm(c) - 1.0).abs() > 1e-3 || dot.abs() > 1e-3 {
        return Err(bad(
            path,
            format!(
                "image orientation {orientation:?}: need two orthogonal unit vectors \
                 (row and column direction cosines)"
            ),
        ));
    }
    if pixel_spacing.iter().any(|s| *s <= 0.0) {
        return Err(bad(
            path,
            format!("pixel spacing {pixel_spacing:?}: need positive values"),
        ));
    }
    let slope = floats(tags::RESCALE_SLOPE, 1)?.map_or(1.0, |v| v[0]);
    let intercept = floats(tags::RESCALE_INTERCEPT, 1)?.map_or(0.0, |v| v[0]);
    let thickness = [tags::SPACING_BETWEEN_SLICES, tags::SLICE_THICKNESS]
        .into_iter()
        .find_map(|t| values.get(&t).and_then(|v| v.to_float64().ok()))
        .filter(|t| t.is_finite() && *t > 0.0);
    let (data_offset, len) = pixels.ok_or_else(|| bad(path, "no pixel data (7FE0,0010)"))?;
    // Sizes checked against the element's length, itself checked against the file's.
    // At most 2³² · 2³² · 4 for absurd values: saturate rather than overflow.
    let need = (rows as u64)
        .saturating_mul(cols as u64)
        .saturating_mul(bits as u64 / 8);
    let len = u64::from(len);
    if len < need || len > need.saturating_add(need % 2) {
        return Err(bad(
            path,
            format!(
                "pixel data hold {len} bytes, but {cols}×{rows} pixels of {bits} bits need {need}"
            ),
        ));
    }
    let to_u16 = |v: i64| u16::try_from(v).unwrap_or(0);
    Ok(Slice {
        path: path.to_path_buf(),
        series: values
            .get(&tags::SERIES_INSTANCE_UID)
            .map(text)
            .unwrap_or_default(),
        rows,
        cols,
        bits: to_u16(bits),
        bits_stored: to_u16(bits_stored),
        high_bit: to_u16(high_bit),
        signed,
        position: [position[0], position[1], position[2]],
        orientation: std::array::from_fn(|k| orientation[k]),
        pixel_spacing: [pixel_spacing[0], pixel_spacing[1]],
        slope,
        intercept,
        thickness,
        big_endian,
        data_offset,
    })
}

/// The image files of `dir` (the DICOM files, DICOMDIRs left out), sorted by name.
fn series_files(dir: &Path) -> Result<Vec<Slice>, LoadError> {
    let entries = std::fs::read_dir(dir).map_err(io_err(dir))?;
    let mut paths = Vec::new();
    for e in entries {
        let p = e.map_err(io_err(dir))?.path();
        if p.is_file() {
            paths.push(p);
        }
    }
    paths.sort();
    let mut out = Vec::new();
    for p in paths {
        if is_dicom(&p)? {
            if let Some(s) = read_header(&p)? {
                out.push(s);
            }
        }
    }
    Ok(out)
}

/// The files of the chosen series, or why there is no single series.
fn choose_series(
    dir: &Path,
    all: Vec<Slice>,
    series: Option<&str>,
) -> Result<Vec<Slice>, LoadError> {
    if all.is_empty() {
        return Err(bad(
            dir,
            "no DICOM image files (a DICOM file has 'DICM' after a 128-byte preamble)",
        ));
    }
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for s in &all {
        *counts.entry(s.series.as_str()).or_default() += 1;
    }
    let list = || {
        counts
            .iter()
            .map(|(uid, n)| {
                let uid = if uid.is_empty() { "(none)" } else { uid };
                format!("{uid} ({n} file{})", if *n == 1 { "" } else { "s" })
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let chosen = match series {
        Some(uid) if counts.contains_key(uid) => uid.to_string(),
        Some(uid) => {
            return Err(bad(
                dir,
                format!("no files of series {uid}; the folder holds {}", list()),
            ))
        }
        None if counts.len() > 1 => {
            return Err(bad(
                dir,
                format!(
                    "{} series in one folder: {}; choose one by its SeriesInstanceUID (the CLI's \
                     --dicom-series)",
                    counts.len(),
                    list()
                ),
            ))
        }
        None => all[0].series.clone(),
    };
    Ok(all.into_iter().filter(|s| s.series == chosen).collect())
}

/// Checks that every slice matches the first in size, sample format, orientation and spacing.
fn check_alike(slices: &[Slice]) -> Result<(), LoadError> {
    let Some(first) = slices.first() else {
        return Ok(());
    };
    for s in &slices[1..] {
        let differ = |what: &str, a: String, b: String| {
            Err(bad(
                &s.path,
                format!(
                    "{what} {b} differs from {a} in {} of the same series",
                    first.name()
                ),
            ))
        };
        if (s.cols, s.rows) != (first.cols, first.rows) {
            return differ(
                "size",
                format!("{}×{}", first.cols, first.rows),
                format!("{}×{}", s.cols, s.rows),
            );
        }
        let fmt = |s: &Slice| {
            format!(
                "{} bits allocated, {} stored, high bit {}, {}",
                s.bits,
                s.bits_stored,
                s.high_bit,
                if s.signed { "signed" } else { "unsigned" }
            )
        };
        if (s.bits, s.bits_stored, s.high_bit, s.signed)
            != (first.bits, first.bits_stored, first.high_bit, first.signed)
        {
            return differ("sample format", fmt(first), fmt(s));
        }
        let far =
            |a: &[f64], b: &[f64], tol: f64| a.iter().zip(b).any(|(x, y)| (x - y).abs() > tol);
        if far(&s.orientation, &first.orientation, 1e-4) {
            return differ(
                "image orientation",
                format!("{:?}", first.orientation),
                format!("{:?}", s.orientation),
            );
        }
        if far(&s.pixel_spacing, &first.pixel_spacing, 1e-4) {
            return differ(
                "pixel spacing",
                format!("{:?}", first.pixel_spacing),
                format!("{:?}", s.pixel_spacing),
            );
        }
    }
    Ok(())
}

/// Sorts the slices along the normal and returns the LPS step from one slice to the next.
fn sort_and_step(dir: &Path, slices: &mut [Slice]) -> Result<[f64; 3], LoadError> {
    let Some(first) = slices.first() else {
        return Err(bad(dir, "no slices"));
    };
    let o = first.orientation;
    let normal = cross([o[0], o[1], o[2]], [o[3], o[4], o[5]]);
    if slices.len() == 1 {
        let t = first.thickness.unwrap_or(1.0);
        return Ok(normal.map(|n| n * t));
    }
    slices.sort_by(|a, b| dot(a.position, normal).total_cmp(&dot(b.position, normal)));
    let d: Vec<f64> = slices.iter().map(|s| dot(s.position, normal)).collect();
    let n = slices.len();
    let gaps: Vec<f64> = d.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted = gaps.clone();
    sorted.sort_by(f64::total_cmp);
    // The lower median: with a missing slice among many, the others' gap.
    let typical = sorted[(sorted.len() - 1) / 2];
    let tol = 0.01 + 0.01 * typical.abs();
    for (pair, &gap) in slices.windows(2).zip(&gaps) {
        if gap <= tol || (gap - typical).abs() > tol {
            let why = if gap <= tol {
                "at the same position (a doubled slice)".to_string()
            } else {
                format!(
                    "{gap:.4} mm apart along the slice normal, but the series' median gap is \
                     {typical:.4} mm (uneven spacing or a missing slice)"
                )
            };
            return Err(bad(
                dir,
                format!("slices {} and {} are {why}", pair[0].name(), pair[1].name()),
            ));
        }
    }
    let p0 = slices[0].position;
    let pn = slices[n - 1].position;
    let step = [0, 1, 2].map(|a| (pn[a] - p0[a]) / (n - 1) as f64);
    for (k, s) in slices.iter().enumerate() {
        let off = [0, 1, 2].map(|a| s.position[a] - p0[a] - k as f64 * step[a]);
        if dot(off, off).sqrt() > tol {
            return Err(bad(
                dir,
                format!(
                    "slice {} at {:?} is off the line from {} to {} (by {:.4} mm)",
                    s.name(),
                    s.position,
                    slices[0].name(),
                    slices[n - 1].name(),
                    dot(off, off).sqrt()
                ),
            ));
        }
    }
    Ok(step)
}

/// Reads the `Rows × Columns` stored values of a slice, each masked to `BitsStored` (from
/// `HighBit` down) and sign-extended when signed, and hands them to `emit` in file order (a
/// row at a time, columns fastest). Reads nothing past them.
fn read_slice(s: &Slice, mut emit: impl FnMut(i64)) -> Result<(), LoadError> {
    let path = s.path.as_path();
    let mut f = File::open(path).map_err(io_err(path))?;
    f.seek(SeekFrom::Start(s.data_offset))
        .map_err(io_err(path))?;
    let bps = s.bytes_per_sample();
    let total = s.rows * s.cols * bps;
    let mut r = f.take(total as u64);
    let mut buf = vec![0u8; (1 << 16).min(total)];
    let shift = u32::from(s.high_bit + 1 - s.bits_stored);
    let stored = u32::from(s.bits_stored);
    let mask = (1u64 << stored) - 1;
    let sign = 1u64 << (stored - 1);
    let mut done = 0;
    while done < total {
        let want = (total - done).min(buf.len());
        let got = read_full(&mut r, &mut buf[..want]).map_err(io_err(path))?;
        if got < want {
            return Err(LoadError::Io(
                path.to_path_buf(),
                io::Error::new(
                    io::ErrorKind::UnexpectedEof,
                    "the file shrank while being read",
                ),
            ));
        }
        for w in buf[..got].chunks_exact(bps) {
            let raw = w.iter().enumerate().fold(0u64, |acc, (i, &b)| {
                let at = if s.big_endian { bps - 1 - i } else { i };
                acc | (u64::from(b) << (8 * at))
            });
            let v = (raw >> shift) & mask;
            let v = if s.signed && v & sign != 0 {
                v as i64 - (1i64 << stored)
            } else {
                v as i64
            };
            emit(v);
        }
        done += got;
    }
    Ok(())
}

/// The sample type of stored values of `bits` bits with no rescaling.
fn native_type(bits: u16, signed: bool) -> ScalarType {
    match (bits, signed) {
        (8, false) => ScalarType::U8,
        (8, true) => ScalarType::I8,
        (16, false) => ScalarType::U16,
        (16, true) => ScalarType::I16,
        (_, false) => ScalarType::U32,
        (_, true) => ScalarType::I32,
    }
}

/// The smallest integer type that holds `lo..=hi`: `i16`, `i32`, else `f64`.
fn integer_type(lo: i64, hi: i64) -> ScalarType {
    if lo >= i64::from(i16::MIN) && hi <= i64::from(i16::MAX) {
        ScalarType::I16
    } else if lo >= i64::from(i32::MIN) && hi <= i64::from(i32::MAX) {
        ScalarType::I32
    } else {
        ScalarType::F64
    }
}

/// Reads a DICOM series from the files of one folder (not its subfolders) into one volume:
/// one single-frame grayscale image per file, uncompressed (Implicit VR Little Endian,
/// Explicit VR Little Endian or Explicit VR Big Endian).
///
/// Files: every regular file of `dir` with `DICM` after a 128-byte preamble is read; others
/// (no preamble, such as text or hidden notes) are skipped, and so is a DICOMDIR (Media
/// Storage SOP Class `1.2.840.10008.1.3.10`). With more than one `SeriesInstanceUID` among
/// them, `series` chooses one; without it that is an error listing the series.
///
/// Samples: `BitsAllocated` 8, 16 or 32, `PixelRepresentation` unsigned or signed, each value
/// masked to `BitsStored` below `HighBit` (and sign-extended). Types:
/// - no rescaling (`RescaleSlope` 1 and `RescaleIntercept` 0, or absent, in every file): the
///   stored type, `u8`, `i8`, `u16`, `i16`, `u32` or `i32`;
/// - slope 1 and whole-number intercepts (CT in Hounsfield units): `stored + intercept` as
///   `i16` when every such value fits in `i16` (checked from `BitsStored`, else from the data),
///   else `i32` (else `f64`);
/// - any other slope or intercept: `slope · stored + intercept` computed in `f64`, stored as
///   `f32` (`f64` for 32-bit data).
///
/// `MONOCHROME1` values are kept as they are (not inverted: they are data, not display gray).
/// The [`Space`] is described in this module's documentation (LPS converted to RAS+).
///
/// # Errors
/// An unreadable folder or file; a DICOM file with a malformed meta group or data set, an
/// element claiming more bytes than the file has left (checked before its value is read), an
/// unknown or compressed transfer syntax (named with its UID), encapsulated pixel data,
/// several samples per pixel or a colour interpretation, several frames, other than 8, 16 or
/// 32 bits allocated, no pixel data, pixel data shorter (or longer) than `Rows × Columns` need,
/// no `ImagePositionPatient`, `ImageOrientationPatient` or `PixelSpacing`; no DICOM image in
/// the folder; several series and no `series` (or one not present); files of one series that
/// differ in size, sample format, orientation or pixel spacing; slices at one position,
/// unevenly spaced, or off the line of the others (both files named); more than `cap` bytes of
/// samples, checked before anything is allocated; NaN/∞ after rescaling.
pub fn read_dicom_series(
    dir: &Path,
    series: Option<&str>,
    cap: u64,
) -> Result<LoadedVolume, LoadError> {
    if !dir.is_dir() {
        return Err(bad(
            dir,
            "not a folder (a DICOM series is read from its folder)",
        ));
    }
    let all = series_files(dir)?;
    let mut slices = choose_series(dir, all, series)?;
    check_alike(&slices)?;
    let step = sort_and_step(dir, &mut slices)?;
    let Some(first) = slices.first() else {
        return Err(bad(dir, "no slices"));
    };
    let dims = [first.cols, first.rows, slices.len()];
    let stored_type = native_type(first.bits, first.signed);
    // Every output type is at least as wide as the stored one: refuse early, before any pass.
    checked_size(dir, dims, stored_type, cap)?;
    let identity = slices.iter().all(|s| s.slope == 1.0 && s.intercept == 0.0);
    let integral = slices
        .iter()
        .all(|s| s.slope == 1.0 && s.intercept.fract() == 0.0 && s.intercept.abs() < 2f64.powi(40));
    let ty = if identity {
        stored_type
    } else if integral {
        let (lo, hi) = first.stored_range();
        let b_lo = slices.iter().map(|s| s.intercept as i64).min().unwrap_or(0);
        let b_hi = slices.iter().map(|s| s.intercept as i64).max().unwrap_or(0);
        match integer_type(lo + b_lo, hi + b_hi) {
            ScalarType::I16 => ScalarType::I16,
            _ => {
                // The stored range does not fit in i16: look at the values themselves.
                let (mut vlo, mut vhi) = (i64::MAX, i64::MIN);
                for s in &slices {
                    let b = s.intercept as i64;
                    read_slice(s, |v| {
                        vlo = vlo.min(v + b);
                        vhi = vhi.max(v + b);
                    })?;
                }
                integer_type(vlo, vhi)
            }
        }
    } else if first.bits == 32 {
        ScalarType::F64
    } else {
        ScalarType::F32
    };
    let (count, _) = checked_size(dir, dims, ty, cap)?;
    // The progress bar of `show_progress` over the pixel bytes of the slices.
    let slice_bytes = (first.rows * first.cols * first.bytes_per_sample()) as u64;
    progress_start(slice_bytes * slices.len() as u64);
    macro_rules! fill {
        ($var:ident, $t:ty, |$v:ident, $s:ident| $e:expr) => {{
            let mut out: Vec<$t> = Vec::with_capacity(count);
            for $s in &slices {
                read_slice($s, |$v| out.push($e))?;
                progress_inc(slice_bytes);
            }
            Scalars::$var(out)
        }};
    }
    // The casts are exact: the masked stored values fit the native types, and the shifted ones
    // were checked against the chosen type above.
    let data = match ty {
        _ if identity => match ty {
            ScalarType::U8 => fill!(U8, u8, |v, _s| v as u8),
            ScalarType::I8 => fill!(I8, i8, |v, _s| v as i8),
            ScalarType::U16 => fill!(U16, u16, |v, _s| v as u16),
            ScalarType::I16 => fill!(I16, i16, |v, _s| v as i16),
            ScalarType::U32 => fill!(U32, u32, |v, _s| v as u32),
            _ => fill!(I32, i32, |v, _s| v as i32),
        },
        ScalarType::I16 if integral => fill!(I16, i16, |v, s| (v + s.intercept as i64) as i16),
        ScalarType::I32 if integral => fill!(I32, i32, |v, s| (v + s.intercept as i64) as i32),
        ScalarType::F32 => fill!(F32, f32, |v, s| (s.slope * v as f64 + s.intercept) as f32),
        _ => fill!(F64, f64, |v, s| s.slope * v as f64 + s.intercept),
    };
    if let Scalars::F32(v) = &data {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(bad(
                dir,
                format!("value {i} is NaN or infinite after RescaleSlope and RescaleIntercept"),
            ));
        }
    }
    if let Scalars::F64(v) = &data {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(bad(
                dir,
                format!("value {i} is NaN or infinite after RescaleSlope and RescaleIntercept"),
            ));
        }
    }
    let o = first.orientation;
    let [dr, dc] = first.pixel_spacing;
    let p0 = first.position;
    // LPS index-to-world columns: along a row (column index i), down a column (row index j),
    // slice to slice (k); then the origin. RAS+ negates the x and y rows.
    let cols = [
        [o[0] * dc, o[1] * dc, o[2] * dc],
        [o[3] * dr, o[4] * dr, o[5] * dr],
        step,
        p0,
    ];
    let mut affine = [[0.0; 4]; 4];
    for (r, sign) in [-1.0, -1.0, 1.0].into_iter().enumerate() {
        for (c, col) in cols.iter().enumerate() {
            affine[r][c] = sign * col[r];
        }
    }
    affine[3][3] = 1.0;
    Ok(LoadedVolume {
        dims,
        data,
        space: Space::from_affine(affine, SpaceSource::DicomPatient),
    })
}
