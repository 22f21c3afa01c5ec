//! NIfTI-1 and NIfTI-2 single files (`.nii`, `.nii.gz`), headers parsed from the
//! specifications (`nifti1.h`, `nifti2.h`).

use std::io::{self, BufRead, Read};
use std::path::Path;

use super::{
    bad, check_finite, checked_size, open, read_full, read_scalars, size_message, skip, DataError,
    LoadError, LoadedVolume, ScalarType, Scalars, Space, SpaceSource,
};

/// `sizeof_hdr` of NIfTI-1 and of NIfTI-2.
const NIFTI1_HEADER: usize = 348;
const NIFTI2_HEADER: usize = 540;

/// Shows header bytes such as a magic code readably (`n+1\0`, `\x89PN`).
fn escaped(bytes: &[u8]) -> String {
    bytes
        .iter()
        .flat_map(|&b| std::ascii::escape_default(b))
        .map(char::from)
        .collect()
}

/// Header bytes in one byte order.
struct Fields<'a> {
    b: &'a [u8],
    big: bool,
}

impl Fields<'_> {
    fn get<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut a = [0u8; N];
        a.copy_from_slice(&self.b[at..at + N]);
        if self.big {
            a.reverse();
        }
        a
    }
    fn i16(&self, at: usize) -> i64 {
        i16::from_le_bytes(self.get(at)).into()
    }
    fn i32(&self, at: usize) -> i64 {
        i32::from_le_bytes(self.get(at)).into()
    }
    fn i64(&self, at: usize) -> i64 {
        i64::from_le_bytes(self.get(at))
    }
    fn f32(&self, at: usize) -> f64 {
        f32::from_le_bytes(self.get(at)).into()
    }
    fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.get(at))
    }
}

/// The header fields this loader uses, widened to NIfTI-2's types.
struct Header {
    dim: [i64; 8],
    datatype: i64,
    bitpix: i64,
    pixdim: [f64; 8],
    vox_offset: f64,
    slope: f64,
    inter: f64,
    qform_code: i64,
    sform_code: i64,
    quatern: [f64; 3],
    qoffset: [f64; 3],
    srow: [[f64; 4]; 3],
}

impl Header {
    fn nifti1(f: &Fields) -> Self {
        Header {
            dim: std::array::from_fn(|k| f.i16(40 + 2 * k)),
            datatype: f.i16(70),
            bitpix: f.i16(72),
            pixdim: std::array::from_fn(|k| f.f32(76 + 4 * k)),
            vox_offset: f.f32(108),
            slope: f.f32(112),
            inter: f.f32(116),
            qform_code: f.i16(252),
            sform_code: f.i16(254),
            quatern: std::array::from_fn(|k| f.f32(256 + 4 * k)),
            qoffset: std::array::from_fn(|k| f.f32(268 + 4 * k)),
            srow: std::array::from_fn(|r| std::array::from_fn(|c| f.f32(280 + 16 * r + 4 * c))),
        }
    }

    fn nifti2(f: &Fields) -> Self {
        Header {
            dim: std::array::from_fn(|k| f.i64(16 + 8 * k)),
            datatype: f.i16(12),
            bitpix: f.i16(14),
            pixdim: std::array::from_fn(|k| f.f64(104 + 8 * k)),
            vox_offset: f.i64(168) as f64,
            slope: f.f64(176),
            inter: f.f64(184),
            qform_code: f.i32(344),
            sform_code: f.i32(348),
            quatern: std::array::from_fn(|k| f.f64(352 + 8 * k)),
            qoffset: std::array::from_fn(|k| f.f64(376 + 8 * k)),
            srow: std::array::from_fn(|r| std::array::from_fn(|c| f.f64(400 + 32 * r + 8 * c))),
        }
    }

    /// The sform when `sform_code > 0`, else the qform when `qform_code > 0`, else `pixdim`.
    fn space(&self, path: &Path) -> Result<Space, LoadError> {
        // Non-positive or non-finite voxel sizes count as 1, as niftilib does.
        let pix = |k: usize| {
            let d = self.pixdim[k];
            if d.is_finite() && d > 0.0 {
                d
            } else {
                1.0
            }
        };
        if self.sform_code > 0 {
            let mut a = [[0.0; 4]; 4];
            a[..3].copy_from_slice(&self.srow);
            if !a.iter().flatten().all(|v| v.is_finite()) {
                return Err(bad(path, "sform (srow_x/y/z) has NaN or infinite entries"));
            }
            return Ok(Space::from_affine(
                a,
                SpaceSource::NiftiSform(self.sform_code as i32),
            ));
        }
        if self.qform_code > 0 {
            let [b, c, d] = self.quatern;
            if !self
                .quatern
                .iter()
                .chain(&self.qoffset)
                .all(|v| v.is_finite())
            {
                return Err(bad(
                    path,
                    "qform quaternion or offset has NaN or infinite entries",
                ));
            }
            // a = sqrt(1 − b² − c² − d²); a rounding excess over 1 means a 180° turn (a = 0).
            let s = 1.0 - (b * b + c * c + d * d);
            let (a, b, c, d) = if s > 1e-7 {
                (s.sqrt(), b, c, d)
            } else {
                let n = (b * b + c * c + d * d).sqrt();
                if n == 0.0 {
                    (1.0, 0.0, 0.0, 0.0)
                } else {
                    (0.0, b / n, c / n, d / n)
                }
            };
            let r = [
                [
                    a * a + b * b - c * c - d * d,
                    2.0 * (b * c - a * d),
                    2.0 * (b * d + a * c),
                ],
                [
                    2.0 * (b * c + a * d),
                    a * a + c * c - b * b - d * d,
                    2.0 * (c * d - a * b),
                ],
                [
                    2.0 * (b * d - a * c),
                    2.0 * (c * d + a * b),
                    a * a + d * d - c * c - b * b,
                ],
            ];
            let qfac = if self.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
            let zoom = [pix(1), pix(2), qfac * pix(3)];
            let mut m = [[0.0; 4]; 4];
            for i in 0..3 {
                for j in 0..3 {
                    m[i][j] = r[i][j] * zoom[j];
                }
                m[i][3] = self.qoffset[i];
            }
            return Ok(Space::from_affine(
                m,
                SpaceSource::NiftiQform(self.qform_code as i32),
            ));
        }
        Ok(Space::diagonal(
            [pix(1), pix(2), pix(3)],
            SpaceSource::NiftiPixdim,
        ))
    }
}

/// The scalar type of a NIfTI datatype code, or why it is refused.
fn datatype(code: i64) -> Result<ScalarType, String> {
    Ok(match code {
        2 => ScalarType::U8,
        4 => ScalarType::I16,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        768 => ScalarType::U32,
        _ => {
            let name = match code {
                1 => "BINARY",
                32 => "COMPLEX64",
                128 => "RGB24 (colour, not scalar samples)",
                1024 => "INT64",
                1280 => "UINT64",
                1536 => "FLOAT128",
                1792 => "COMPLEX128",
                2048 => "COMPLEX256",
                2304 => "RGBA32 (colour, not scalar samples)",
                _ => return Err(format!("unknown datatype code {code}")),
            };
            return Err(format!(
                "unsupported datatype {name} (code {code}); supported: uint8 (2), int8 (256), \
                 int16 (4), uint16 (512), int32 (8), uint32 (768), float32 (16), float64 (64)"
            ));
        }
    })
}

/// `slope · v + inter` for every sample: `f32` results for 8- and 16-bit integers and `f32`,
/// `f64` for 32-bit integers and `f64` (computed in `f64` either way).
fn scaled(data: &Scalars, slope: f64, inter: f64) -> Scalars {
    let f = |i: usize| slope * data.get(i).unwrap_or(0.0) + inter;
    match data.scalar_type() {
        ScalarType::U32 | ScalarType::I32 | ScalarType::F64 => {
            Scalars::F64((0..data.len()).map(f).collect())
        }
        _ => Scalars::F32((0..data.len()).map(|i| f(i) as f32).collect()),
    }
}

/// Reads a single-file NIfTI-1 or NIfTI-2 volume, `.nii` or gzip-compressed `.nii.gz`
/// (recognised by content, not name), either byte order (found from `sizeof_hdr`).
///
/// Datatypes: `uint8`, `int8`, `int16`, `uint16`, `int32`, `uint32`, `float32`, `float64`
/// (`RGB24`, `RGBA32`, complex, 64-bit integer and `float128` data are refused). The volume
/// must be 3-D: `dim[0]` of 3, or more with every `dim[4..]` equal to 1. The data start at
/// `vox_offset`; extensions and padding before it are skipped.
///
/// Scaling: when `scl_slope` is finite and non-zero and `(scl_slope, scl_inter)` is not
/// `(1, 0)`, each value becomes `scl_slope·v + scl_inter`, computed in `f64` and stored as
/// `f32` for 8/16-bit integer and `f32` data, as `f64` for 32-bit integer and `f64` data;
/// otherwise (a slope of 0 — NIfTI's "no scaling" — NaN or ∞ as nibabel writes, or 1 and 0)
/// the samples keep their own type.
///
/// Space (RAS+, see [`Space`]): the sform (`srow_x/y/z`) when `sform_code > 0`; else the
/// qform (quaternion `b, c, d`, `qoffset`, `pixdim[1..=3]` and `qfac = pixdim[0]`) when
/// `qform_code > 0`; else `pixdim[1..=3]` on the diagonal with origin zero. Non-positive or
/// non-finite `pixdim`s count as 1.
///
/// # Errors
/// Unreadable file or corrupt gzip stream; not a NIfTI `.nii` (no `n+1`/`n+2` magic: a
/// header-only `.hdr` or another format); a `sizeof_hdr` other than 348/540; an unsupported or
/// unknown `datatype`, or a `bitpix` that does not match it; 2-D data or more than one
/// volume; a non-positive dimension; a bad `vox_offset`; more than `cap` bytes of samples;
/// data shorter or longer than the dimensions need (checked against the size of a plain file
/// before reading); NaN/∞ values (before or after scaling); a valid `scl_slope` with a NaN/∞
/// `scl_inter`; NaN/∞ in the chosen sform or qform.
pub fn read_nifti(path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    let (mut file, file_len) = open(path)?;
    let gz = file
        .fill_buf()
        .map_err(|e| LoadError::Io(path.to_path_buf(), e))?
        .starts_with(&[0x1f, 0x8b]);
    let mut r: Box<dyn Read> = if gz {
        Box::new(flate2::bufread::MultiGzDecoder::new(file))
    } else {
        Box::new(file)
    };
    let read_err = |e: io::Error| {
        if gz {
            bad(path, format!("bad gzip stream: {e}"))
        } else {
            LoadError::Io(path.to_path_buf(), e)
        }
    };
    let mut bytes = vec![0u8; NIFTI2_HEADER];
    let mut have = read_full(&mut r, &mut bytes[..NIFTI1_HEADER]).map_err(read_err)?;
    let nifti2 = have >= 8 && &bytes[4..8] == b"n+2\0";
    if nifti2 {
        have += read_full(&mut r, &mut bytes[have..]).map_err(read_err)?;
    }
    let header_len = if nifti2 { NIFTI2_HEADER } else { NIFTI1_HEADER };
    if have < header_len {
        return Err(bad(
            path,
            format!(
                "{have} bytes is too short for a NIfTI-{} header ({header_len} bytes)",
                if nifti2 { 2 } else { 1 }
            ),
        ));
    }
    if !nifti2 {
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
                        "not a NIfTI-1 or NIfTI-2 file (magic at byte 344 is '{}', need \
                         'n+1\\0'; or 'n+2\\0' at byte 4)",
                        escaped(m)
                    ),
                ))
            }
        }
    }
    let head = [bytes[0], bytes[1], bytes[2], bytes[3]];
    let want = header_len as i32;
    let big = match (i32::from_le_bytes(head), i32::from_be_bytes(head)) {
        (le, _) if le == want => false,
        (_, be) if be == want => true,
        (le, _) => return Err(bad(path, format!("sizeof_hdr is {le}, need {want}"))),
    };
    let fields = Fields { b: &bytes, big };
    let h = if nifti2 {
        Header::nifti2(&fields)
    } else {
        Header::nifti1(&fields)
    };

    let code = h.datatype;
    let ty = datatype(code).map_err(|m| bad(path, m))?;
    let bits = 8 * ty.size() as i64;
    if h.bitpix != bits {
        return Err(bad(
            path,
            format!(
                "bitpix is {}, but datatype {ty:?} has {bits} bits",
                h.bitpix
            ),
        ));
    }
    let rank = h.dim[0];
    if !(3..=7).contains(&rank) {
        return Err(bad(
            path,
            format!("need a 3D volume, but dim[0] (the number of dimensions) is {rank}"),
        ));
    }
    let extra = &h.dim[4..=rank as usize];
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
        let v = h.dim[k + 1];
        *d = usize::try_from(v)
            .ok()
            .filter(|&d| d > 0)
            .ok_or_else(|| bad(path, format!("dim[{}] is {v}, must be positive", k + 1)))?;
    }
    let (count, need) = checked_size(path, dims, ty, cap)?;
    let space = h.space(path)?;

    let off = h.vox_offset;
    let min_off = header_len + 4;
    if !(off.is_finite() && off.fract() == 0.0 && off >= min_off as f64) {
        return Err(bad(
            path,
            format!("vox_offset is {off}, need a whole number ≥ {min_off}"),
        ));
    }
    let start = off as u64; // saturates: a huge offset is past the end below
    let truncated = |end: u64| {
        bad(
            path,
            format!("truncated: vox_offset is {start}, but the file holds {end} bytes"),
        )
    };
    if !gz {
        if start > file_len {
            return Err(truncated(file_len));
        }
        let have = file_len - start;
        if have != need as u64 {
            return Err(bad(path, size_message(Some(have), count, ty, need)));
        }
    }
    let gap = start - header_len as u64;
    let skipped = skip(&mut r, gap).map_err(read_err)?;
    if skipped < gap {
        return Err(truncated(header_len as u64 + skipped));
    }
    let data = read_scalars(&mut r, ty, count, big, !gz, true).map_err(|e| match e {
        DataError::Io(e) => read_err(e),
        DataError::Short(n) => bad(path, size_message(Some(n), count, ty, need)),
        DataError::Long => bad(path, size_message(None, count, ty, need)),
    })?;
    check_finite(path, &data)?;

    let (slope, inter) = (h.slope, h.inter);
    let data = if slope.is_finite() && slope != 0.0 && (slope, inter) != (1.0, 0.0) {
        if !inter.is_finite() {
            return Err(bad(
                path,
                format!("scl_slope is {slope} but scl_inter is {inter}"),
            ));
        }
        let s = scaled(&data, slope, inter);
        if check_finite(path, &s).is_err() {
            return Err(bad(
                path,
                format!(
                    "a value is infinite after scaling by scl_slope {slope}, scl_inter {inter}"
                ),
            ));
        }
        s
    } else {
        data
    };
    Ok(LoadedVolume { dims, data, space })
}
