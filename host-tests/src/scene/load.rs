//! Loading a user's volume (raw, NRRD or NIfTI-1) and transfer function (JSON or text).
//!
//! Every failure is a [`LoadError`] that names the file and the problem; nothing panics on
//! bad input.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

use volsample::ControlPoint;

/// Scalar sample types a raw, NRRD or NIfTI file may hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarType {
    /// Unsigned 8-bit.
    U8,
    /// Unsigned 16-bit.
    U16,
    /// Signed 16-bit (NIfTI `int16` only so far; [`ScalarType::parse`] does not name it).
    I16,
    /// IEEE 32-bit float.
    F32,
}

impl ScalarType {
    /// Bytes per value.
    pub fn size(self) -> usize {
        match self {
            ScalarType::U8 => 1,
            ScalarType::U16 | ScalarType::I16 => 2,
            ScalarType::F32 => 4,
        }
    }

    /// Parses `u8`/`uint8`/`uchar`, `u16`/`uint16`/`ushort`, `f32`/`float`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "u8" | "uint8" | "uchar" | "unsigned char" | "uint8_t" => Some(ScalarType::U8),
            "u16" | "uint16" | "ushort" | "unsigned short" | "uint16_t" => Some(ScalarType::U16),
            "f32" | "float" | "float32" => Some(ScalarType::F32),
            _ => None,
        }
    }
}

/// Why a file could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// The file could not be read.
    Io(PathBuf, std::io::Error),
    /// The file is readable but malformed; the text says where and how.
    Format(PathBuf, String),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Io(p, e) => write!(f, "{}: {e}", p.display()),
            LoadError::Format(p, m) => write!(f, "{}: {m}", p.display()),
        }
    }
}

impl std::error::Error for LoadError {}

fn bad(path: &Path, msg: impl Into<String>) -> LoadError {
    LoadError::Format(path.to_path_buf(), msg.into())
}

/// Decodes `bytes` as `count` values of `ty`, little- or big-endian, into `f32`.
fn decode(
    path: &Path,
    bytes: &[u8],
    ty: ScalarType,
    count: usize,
    big_endian: bool,
) -> Result<Vec<f32>, LoadError> {
    let need = count
        .checked_mul(ty.size())
        .ok_or_else(|| bad(path, "dimensions overflow"))?;
    if bytes.len() != need {
        return Err(bad(
            path,
            format!(
                "holds {} data bytes, but {count} {ty:?} values need {need}",
                bytes.len()
            ),
        ));
    }
    let out: Vec<f32> = match ty {
        ScalarType::U8 => bytes.iter().map(|&b| f32::from(b)).collect(),
        ScalarType::U16 => bytes
            .chunks_exact(2)
            .map(|c| {
                let a = [c[0], c[1]];
                f32::from(if big_endian {
                    u16::from_be_bytes(a)
                } else {
                    u16::from_le_bytes(a)
                })
            })
            .collect(),
        ScalarType::I16 => bytes
            .chunks_exact(2)
            .map(|c| {
                let a = [c[0], c[1]];
                f32::from(if big_endian {
                    i16::from_be_bytes(a)
                } else {
                    i16::from_le_bytes(a)
                })
            })
            .collect(),
        ScalarType::F32 => bytes
            .chunks_exact(4)
            .map(|c| {
                let a = [c[0], c[1], c[2], c[3]];
                if big_endian {
                    f32::from_be_bytes(a)
                } else {
                    f32::from_le_bytes(a)
                }
            })
            .collect(),
    };
    if let Some(i) = out.iter().position(|v| !v.is_finite()) {
        return Err(bad(path, format!("value {i} is NaN or infinite")));
    }
    Ok(out)
}

/// Loads a headerless little-endian raw volume of `dims` values of `ty`.
///
/// # Errors
/// Unreadable file, a size that does not match `dims × ty`, zero dimensions, NaN/∞ floats.
pub fn load_raw(path: &Path, dims: [usize; 3], ty: ScalarType) -> Result<Vec<f32>, LoadError> {
    if dims.contains(&0) {
        return Err(bad(path, "a dimension is zero"));
    }
    let bytes = std::fs::read(path).map_err(|e| LoadError::Io(path.to_path_buf(), e))?;
    let count = dims[0]
        .checked_mul(dims[1])
        .and_then(|p| p.checked_mul(dims[2]))
        .ok_or_else(|| bad(path, "dimensions overflow"))?;
    decode(path, &bytes, ty, count, false)
}

/// Loads a 3D scalar NRRD file (`encoding: raw`, attached or detached data; types u8, u16,
/// f32). Returns the dimensions and the values.
///
/// # Errors
/// A missing `NRRD` magic, missing or bad `type`/`dimension`/`sizes`/`encoding` fields, an
/// unsupported encoding (gzip, ascii…), a data size that does not match, NaN/∞ floats.
pub fn load_nrrd(path: &Path) -> Result<([usize; 3], Vec<f32>), LoadError> {
    let bytes = std::fs::read(path).map_err(|e| LoadError::Io(path.to_path_buf(), e))?;
    if !bytes.starts_with(b"NRRD000") {
        return Err(bad(path, "not a NRRD file (no NRRD000x magic)"));
    }
    // The header ends at the first empty line.
    let mut end = None;
    let mut i = 0;
    while i + 1 < bytes.len() {
        if bytes[i] == b'\n' && bytes[i + 1] == b'\n' {
            end = Some((i, i + 2));
            break;
        }
        if i + 2 < bytes.len() && &bytes[i..i + 3] == b"\n\r\n" {
            end = Some((i, i + 3));
            break;
        }
        i += 1;
    }
    let (hdr_end, data_start) = end.unwrap_or((bytes.len(), bytes.len()));
    let header =
        std::str::from_utf8(&bytes[..hdr_end]).map_err(|_| bad(path, "header is not text"))?;
    let mut ty = None;
    let mut dimension = None;
    let mut sizes = None;
    let mut encoding = None;
    let mut big_endian = false;
    let mut data_file = None;
    for line in header.lines().skip(1) {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some((key, value)) = line.split_once(':') else {
            continue; // key:=value lines and others carry nothing we need
        };
        let value = value.trim_start_matches('=').trim();
        match key.trim().to_ascii_lowercase().as_str() {
            "type" => {
                ty = Some(ScalarType::parse(value).ok_or_else(|| {
                    bad(path, format!("unsupported type '{value}' (u8, u16, float)"))
                })?)
            }
            "dimension" => {
                dimension = Some(
                    value
                        .parse::<usize>()
                        .map_err(|_| bad(path, format!("bad dimension '{value}'")))?,
                )
            }
            "sizes" => {
                let v: Result<Vec<usize>, _> = value.split_whitespace().map(str::parse).collect();
                sizes = Some(v.map_err(|_| bad(path, format!("bad sizes '{value}'")))?);
            }
            "encoding" => encoding = Some(value.to_ascii_lowercase()),
            "endian" => big_endian = value.eq_ignore_ascii_case("big"),
            "data file" | "datafile" => data_file = Some(value.to_string()),
            _ => {}
        }
    }
    let ty = ty.ok_or_else(|| bad(path, "missing 'type' field"))?;
    if dimension != Some(3) {
        return Err(bad(
            path,
            format!("need a 3D volume, 'dimension' is {dimension:?}"),
        ));
    }
    let sizes = sizes.ok_or_else(|| bad(path, "missing 'sizes' field"))?;
    let dims: [usize; 3] = sizes
        .as_slice()
        .try_into()
        .map_err(|_| bad(path, format!("'sizes' has {} entries, need 3", sizes.len())))?;
    if dims.contains(&0) {
        return Err(bad(path, "a size is zero"));
    }
    match encoding.as_deref() {
        Some("raw") => {}
        Some(e) => return Err(bad(path, format!("unsupported encoding '{e}' (only raw)"))),
        None => return Err(bad(path, "missing 'encoding' field")),
    }
    let data = match data_file {
        Some(f) => {
            let p = path.parent().unwrap_or(Path::new(".")).join(f);
            std::fs::read(&p).map_err(|e| LoadError::Io(p, e))?
        }
        None => bytes[data_start.min(bytes.len())..].to_vec(),
    };
    let count = dims[0]
        .checked_mul(dims[1])
        .and_then(|p| p.checked_mul(dims[2]))
        .ok_or_else(|| bad(path, "sizes overflow"))?;
    Ok((dims, decode(path, &data, ty, count, big_endian)?))
}

/// Size of a NIfTI-1 header (`sizeof_hdr`); the data of a `.nii` file starts at 352 or later.
const NIFTI1_HEADER: usize = 348;

/// Shows header bytes such as a magic code readably (`n+1\0`, `\x89PN`).
fn escaped(bytes: &[u8]) -> String {
    bytes
        .iter()
        .flat_map(|&b| std::ascii::escape_default(b))
        .map(char::from)
        .collect()
}

/// Loads a single-file NIfTI-1 volume, `.nii` or gzip-compressed `.nii.gz` (recognised by its
/// content, not its name). Returns the dimensions `[dim[1], dim[2], dim[3]]` and the values,
/// `x` fastest as the file stores them.
///
/// The header is parsed by the `nifti` crate (either byte order). Supported `datatype`s:
/// `uint8` (2), `int16` (4), `uint16` (512), `float32` (16). The volume must be 3-D: `dim[0]`
/// of 3, or more with every `dim[4..]` equal to 1 (a single 3-D volume of a 4-D file). The data
/// start at `vox_offset`; extensions and padding before it are skipped. When `scl_slope` is
/// finite and non-zero each value becomes `scl_slope·v + scl_inter`; a `scl_slope` of 0 (the
/// NIfTI-1 rule), NaN or ∞ (nibabel's rule) means no scaling. Orientation (`qform`/`sform`)
/// and voxel spacing (`pixdim`) are ignored: the volume is sampled on its index grid.
///
/// # Errors
/// Unreadable file or gzip stream; not a NIfTI-1 `.nii` (no `n+1` magic: a header-only
/// `.hdr`, NIfTI-2 or another format); a `sizeof_hdr` other than 348; an unsupported or unknown
/// `datatype`, or a `bitpix` that does not match it; 2-D data or more than one volume; a
/// non-positive dimension; a bad `vox_offset`; data shorter or longer than the dimensions
/// need; NaN/∞ values (before or after scaling); a valid `scl_slope` with a NaN/∞ `scl_inter`.
pub fn load_nifti(path: &Path) -> Result<([usize; 3], Vec<f32>), LoadError> {
    let file = std::fs::read(path).map_err(|e| LoadError::Io(path.to_path_buf(), e))?;
    let bytes = if file.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(file.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| bad(path, format!("bad gzip stream: {e}")))?;
        out
    } else {
        file
    };
    if bytes.get(4..8) == Some(b"n+2\0") {
        return Err(bad(path, "a NIfTI-2 file; only NIfTI-1 is supported"));
    }
    if bytes.len() < NIFTI1_HEADER {
        return Err(bad(
            path,
            format!(
                "{} bytes is too short for a NIfTI-1 header ({NIFTI1_HEADER} bytes)",
                bytes.len()
            ),
        ));
    }
    match &bytes[344..348] {
        b"n+1\0" => {}
        b"ni1\0" => {
            return Err(bad(
                path,
                "a header-only NIfTI-1 .hdr (magic ni1); give the single-file .nii",
            ))
        }
        m => {
            return Err(bad(
                path,
                format!(
                    "not a NIfTI-1 file (magic at byte 344 is '{}', need 'n+1\\0')",
                    escaped(m)
                ),
            ))
        }
    }
    // sizeof_hdr = 348 gives the byte order; the crate finds it from dim[0] (1 to 7).
    let head = [bytes[0], bytes[1], bytes[2], bytes[3]];
    let big = match (i32::from_le_bytes(head), i32::from_be_bytes(head)) {
        (348, _) => false,
        (_, 348) => true,
        (le, _) => {
            return Err(bad(
                path,
                format!("sizeof_hdr is {le}, need {NIFTI1_HEADER}"),
            ))
        }
    };
    let header = nifti::NiftiHeader::from_reader(bytes.as_slice())
        .map_err(|e| bad(path, format!("bad NIfTI-1 header: {e}")))?;
    if (header.endianness == nifti::Endianness::Big) != big {
        let d = [bytes[40], bytes[41]];
        let d = if big {
            i16::from_be_bytes(d)
        } else {
            i16::from_le_bytes(d)
        };
        return Err(bad(
            path,
            format!("dim[0] (the number of dimensions) is {d}, must be 1 to 7"),
        ));
    }

    let code = header.datatype;
    let ty = match header.data_type() {
        Ok(nifti::NiftiType::Uint8) => ScalarType::U8,
        Ok(nifti::NiftiType::Int16) => ScalarType::I16,
        Ok(nifti::NiftiType::Uint16) => ScalarType::U16,
        Ok(nifti::NiftiType::Float32) => ScalarType::F32,
        Ok(t) => {
            return Err(bad(
                path,
                format!(
                    "unsupported datatype {t:?} (code {code}); \
                     supported: uint8 (2), int16 (4), uint16 (512), float32 (16)"
                ),
            ))
        }
        Err(_) => return Err(bad(path, format!("unknown datatype code {code}"))),
    };
    let bits = 8 * ty.size();
    if usize::try_from(header.bitpix) != Ok(bits) {
        return Err(bad(
            path,
            format!(
                "bitpix is {}, but datatype {ty:?} has {bits} bits",
                header.bitpix
            ),
        ));
    }

    // `dim` is `short[8]` in the specification; the crate reads it unsigned.
    let dim = header.dim.map(|d| d as i16);
    let rank = dim[0];
    if !(3..=7).contains(&rank) {
        return Err(bad(
            path,
            format!("need a 3D volume, but dim[0] (the number of dimensions) is {rank}"),
        ));
    }
    let extra = &dim[4..=rank as usize];
    if extra.iter().any(|&d| d != 1) {
        return Err(bad(
            path,
            format!(
                "need a single 3D volume, but the data are {rank}-D with dim[4..={rank}] = \
                 {extra:?}"
            ),
        ));
    }
    let mut dims = [0usize; 3];
    for (k, d) in dims.iter_mut().enumerate() {
        let v = dim[k + 1];
        *d = usize::try_from(v)
            .ok()
            .filter(|&d| d > 0)
            .ok_or_else(|| bad(path, format!("dim[{}] is {v}, must be positive", k + 1)))?;
    }

    let off = header.vox_offset;
    if !(off.is_finite() && off.fract() == 0.0 && off >= 352.0) {
        return Err(bad(
            path,
            format!("vox_offset is {off}, need a whole number ≥ 352"),
        ));
    }
    let start = off as usize; // saturates: a huge offset is past the end below
    if start > bytes.len() {
        return Err(bad(
            path,
            format!(
                "truncated: vox_offset is {start}, but the file holds {} bytes",
                bytes.len()
            ),
        ));
    }
    let count = dims[0]
        .checked_mul(dims[1])
        .and_then(|p| p.checked_mul(dims[2]))
        .ok_or_else(|| bad(path, "dimensions overflow"))?;
    // The data are sliced here rather than read by `nifti::ReaderOptions::read_file`: nifti
    // 0.18 starts them right after the extensions, not at `vox_offset`, so it misreads a file
    // with padding before the data (tested in tests/load.rs, `nifti_dims_and_order`).
    let mut values = decode(path, &bytes[start..], ty, count, big)?;

    let (slope, inter) = (header.scl_slope, header.scl_inter);
    if slope.is_finite() && slope != 0.0 {
        if !inter.is_finite() {
            return Err(bad(
                path,
                format!("scl_slope is {slope} but scl_inter is {inter}"),
            ));
        }
        if (slope, inter) != (1.0, 0.0) {
            for v in &mut values {
                *v = (f64::from(slope) * f64::from(*v) + f64::from(inter)) as f32;
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(bad(
                    path,
                    format!(
                        "value {i} is infinite after scaling by scl_slope {slope}, \
                         scl_inter {inter}"
                    ),
                ));
            }
        }
    }
    Ok((dims, values))
}

/// Loads a transfer function: JSON `{"points": [[s, r, g, b, a], ...]}` (or a bare array),
/// or text with one `s r g b a` line per point (`#` comments allowed). Points must be sorted
/// by `s`; colors and opacities in `[0, 1]`.
///
/// # Errors
/// Unreadable file, malformed JSON or lines (with the line number), values the core rejects.
pub fn load_transfer_function(path: &Path) -> Result<Vec<ControlPoint>, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|e| LoadError::Io(path.to_path_buf(), e))?;
    let rows: Vec<Vec<f64>> = if text.trim_start().starts_with(['{', '[']) {
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| bad(path, format!("bad JSON: {e}")))?;
        let arr = v
            .get("points")
            .unwrap_or(&v)
            .as_array()
            .ok_or_else(|| bad(path, "expected an array of points"))?;
        arr.iter()
            .enumerate()
            .map(|(i, p)| {
                p.as_array()
                    .and_then(|a| {
                        a.iter()
                            .map(serde_json::Value::as_f64)
                            .collect::<Option<Vec<f64>>>()
                    })
                    .ok_or_else(|| bad(path, format!("point {} is not an array of numbers", i + 1)))
            })
            .collect::<Result<_, _>>()?
    } else {
        text.lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
            .map(|(i, l)| {
                l.split_whitespace()
                    .map(|t| t.parse::<f64>())
                    .collect::<Result<Vec<f64>, _>>()
                    .map_err(|_| bad(path, format!("line {}: not numbers", i + 1)))
            })
            .collect::<Result<_, _>>()?
    };
    let points = rows
        .iter()
        .enumerate()
        .map(|(i, r)| match r.as_slice() {
            [s, cr, cg, cb, a] => Ok(ControlPoint {
                s: *s as f32,
                c: [*cr as f32, *cg as f32, *cb as f32],
                a: *a as f32,
            }),
            _ => Err(bad(
                path,
                format!("point {} has {} values, need 5 (s r g b a)", i + 1, r.len()),
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    check_points(&points).map_err(|e| bad(path, e))?;
    Ok(points)
}

/// Names the first bad control point of a transfer function, counting from 1 (the core
/// only says what is wrong, not where).
///
/// # Errors
/// The first point with a non-finite value, a color or opacity outside `[0, 1]`, or a
/// value not above the previous point's; more points than the core's 64.
pub fn check_points(points: &[volsample::ControlPoint]) -> Result<(), String> {
    if points.is_empty() {
        return Err("the transfer function has no points".into());
    }
    for (k, p) in points.iter().enumerate() {
        let n = k + 1;
        if !p.s.is_finite() {
            return Err(format!("point {n}: the scalar value {} is not finite", p.s));
        }
        for (name, v) in ["red", "green", "blue", "opacity"]
            .into_iter()
            .zip(p.c.iter().chain([&p.a]))
        {
            if !(0.0..=1.0).contains(v) {
                return Err(format!(
                    "point {n} (s = {}): {name} {v} is outside [0, 1]",
                    p.s
                ));
            }
        }
        if let Some(prev) = k.checked_sub(1).and_then(|j| points.get(j)) {
            if p.s <= prev.s {
                return Err(format!(
                    "point {n} (s = {}) does not follow point {k} (s = {}): the scalar values must increase",
                    p.s, prev.s
                ));
            }
        }
    }
    volsample::TransferFunction::<64>::new(points)
        .map(|_| ())
        .map_err(|e| e.to_string())
}
