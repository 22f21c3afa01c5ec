//! Loading a user's volume (raw, NRRD, NIfTI-1/-2, a multi-page TIFF stack or a folder of
//! DICOM slices) and transfer function (JSON or text).
//!
//! The `read_*` functions return a [`LoadedVolume`]: the dimensions, the samples in the file's
//! own type ([`Scalars`]: a `u8` volume takes one byte per voxel) and the index-to-world
//! [`Space`] in **RAS+** millimetres, the convention of NIfTI and nibabel (`+x` right, `+y`
//! anterior, `+z` superior); NRRD's LPS and LAS spaces and DICOM's LPS patient coordinates are
//! converted to it. The older `load_*`
//! functions return the same samples as `f32`.
//!
//! Safety: nothing panics on bad input. Every failure is a [`LoadError`] that names the file
//! and the problem. A header whose data would need more than the memory cap (a parameter,
//! [`DEFAULT_MEMORY_CAP`] by default) is refused before anything is allocated; a plain file
//! shorter than its header claims is refused before its data are read; compressed data are
//! read only up to the size the header claims plus one byte (so a decompression bomb cannot
//! allocate more than the claimed size), and memory for them grows with what actually arrives.
//! Floating-point data with NaN or infinite values are refused.

use std::cell::RefCell;
use std::fmt;
use std::io::{self, BufRead, Read, Seek};
use std::path::{Path, PathBuf};

#[cfg(feature = "app")]
use indicatif::ProgressBar;

/// Without the feature `app` (the parser fuzz targets' build) there is no progress bar: a type
/// with no values, so every use of one is statically unreachable.
#[cfg(not(feature = "app"))]
#[derive(Debug, Clone)]
pub enum ProgressBar {}

#[cfg(not(feature = "app"))]
impl ProgressBar {
    fn inc(&self, _: u64) {
        match *self {}
    }
    fn set_length(&self, _: u64) {
        match *self {}
    }
    fn set_position(&self, _: u64) {
        match *self {}
    }
}

use volsample::ControlPoint;

#[cfg(feature = "app")]
mod dicom;
mod nifti;
mod nrrd;
mod tiff;

#[cfg(feature = "app")]
pub use self::dicom::read_dicom_series;
pub use self::nifti::read_nifti;
pub use self::nrrd::read_nrrd;
pub use self::tiff::read_tiff;

/// The memory cap of the CLI and of the `load_*` functions: 8 GiB of samples in their own type.
pub const DEFAULT_MEMORY_CAP: u64 = 8 << 30;

/// Scalar sample types a raw, NRRD, NIfTI or TIFF file may hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarType {
    /// Unsigned 8-bit.
    U8,
    /// Signed 8-bit.
    I8,
    /// Unsigned 16-bit.
    U16,
    /// Signed 16-bit (CT data in Hounsfield units).
    I16,
    /// Unsigned 32-bit.
    U32,
    /// Signed 32-bit.
    I32,
    /// IEEE 32-bit float.
    F32,
    /// IEEE 64-bit float.
    F64,
}

impl ScalarType {
    /// Bytes per value.
    pub fn size(self) -> usize {
        match self {
            ScalarType::U8 | ScalarType::I8 => 1,
            ScalarType::U16 | ScalarType::I16 => 2,
            ScalarType::U32 | ScalarType::I32 | ScalarType::F32 => 4,
            ScalarType::F64 => 8,
        }
    }

    /// Short name: `u8`, `i8`, `u16`, `i16`, `u32`, `i32`, `f32`, `f64`.
    pub fn name(self) -> &'static str {
        match self {
            ScalarType::U8 => "u8",
            ScalarType::I8 => "i8",
            ScalarType::U16 => "u16",
            ScalarType::I16 => "i16",
            ScalarType::U32 => "u32",
            ScalarType::I32 => "i32",
            ScalarType::F32 => "f32",
            ScalarType::F64 => "f64",
        }
    }

    /// Parses the short names (`u8` … `f64`), numpy's (`uint8`, `int16`, `float32`, …) and
    /// every NRRD spelling (`uchar`, `signed char`, `short`, `unsigned short int`, `int`,
    /// `uint`, `float`, `double`, `int16_t`, …), case-insensitively. 64-bit integers and
    /// NRRD's `block` are not scalar types here (`None`).
    pub fn parse(s: &str) -> Option<Self> {
        let s = s.trim().to_ascii_lowercase();
        let s = s.split_whitespace().collect::<Vec<_>>().join(" ");
        Some(match s.as_str() {
            "u8" | "uint8" | "uchar" | "unsigned char" | "uint8_t" => ScalarType::U8,
            "i8" | "int8" | "signed char" | "int8_t" => ScalarType::I8,
            "u16" | "uint16" | "ushort" | "unsigned short" | "unsigned short int" | "uint16_t" => {
                ScalarType::U16
            }
            "i16" | "int16" | "short" | "short int" | "signed short" | "signed short int"
            | "int16_t" => ScalarType::I16,
            "u32" | "uint32" | "uint" | "unsigned int" | "uint32_t" => ScalarType::U32,
            "i32" | "int32" | "int" | "signed int" | "int32_t" => ScalarType::I32,
            "f32" | "float" | "float32" => ScalarType::F32,
            "f64" | "double" | "float64" => ScalarType::F64,
            _ => return None,
        })
    }
}

/// A volume's samples in the file's own type, `x` fastest, then `y`, then `z`.
#[derive(Debug, Clone, PartialEq)]
pub enum Scalars {
    /// Unsigned 8-bit samples.
    U8(Vec<u8>),
    /// Signed 8-bit samples.
    I8(Vec<i8>),
    /// Unsigned 16-bit samples.
    U16(Vec<u16>),
    /// Signed 16-bit samples.
    I16(Vec<i16>),
    /// Unsigned 32-bit samples.
    U32(Vec<u32>),
    /// Signed 32-bit samples.
    I32(Vec<i32>),
    /// 32-bit float samples (all finite).
    F32(Vec<f32>),
    /// 64-bit float samples (all finite).
    F64(Vec<f64>),
}

/// Applies `$body` to the vector inside any [`Scalars`] variant.
macro_rules! each {
    ($s:expr, $v:ident => $body:expr) => {
        match $s {
            Scalars::U8($v) => $body,
            Scalars::I8($v) => $body,
            Scalars::U16($v) => $body,
            Scalars::I16($v) => $body,
            Scalars::U32($v) => $body,
            Scalars::I32($v) => $body,
            Scalars::F32($v) => $body,
            Scalars::F64($v) => $body,
        }
    };
}

impl Scalars {
    /// Number of samples.
    pub fn len(&self) -> usize {
        each!(self, v => v.len())
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The sample type.
    pub fn scalar_type(&self) -> ScalarType {
        match self {
            Scalars::U8(_) => ScalarType::U8,
            Scalars::I8(_) => ScalarType::I8,
            Scalars::U16(_) => ScalarType::U16,
            Scalars::I16(_) => ScalarType::I16,
            Scalars::U32(_) => ScalarType::U32,
            Scalars::I32(_) => ScalarType::I32,
            Scalars::F32(_) => ScalarType::F32,
            Scalars::F64(_) => ScalarType::F64,
        }
    }

    /// Sample `i` as `f64` (exact for every type), or `None` past the end.
    #[allow(clippy::useless_conversion)] // `f64::from` of the `F64` variant
    pub fn get(&self, i: usize) -> Option<f64> {
        each!(self, v => v.get(i).map(|&x| f64::from(x)))
    }

    /// Every sample as `f32` (rounded to nearest for 32-bit integers and `f64`).
    #[allow(clippy::useless_conversion)] // `f64::from` of the `F64` variant
    pub fn to_f32(&self) -> Vec<f32> {
        match self {
            Scalars::F32(v) => v.clone(),
            _ => each!(self, v => v.iter().map(|&x| f64::from(x) as f32).collect()),
        }
    }

    /// The smallest and largest sample, or `None` when there are none.
    #[allow(clippy::useless_conversion)] // `f64::from` of the `F64` variant
    pub fn range(&self) -> Option<(f64, f64)> {
        each!(self, v => v.iter().map(|&x| f64::from(x)).fold(None, |r, x| {
            Some(match r {
                None => (x, x),
                Some((lo, hi)) => (x.min(lo), x.max(hi)),
            })
        }))
    }

    /// Bytes the samples take in memory.
    pub fn byte_len(&self) -> usize {
        self.len() * self.scalar_type().size()
    }
}

/// Where a [`Space`] came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpaceSource {
    /// Nothing in the file: the identity (1 mm voxels at the origin; raw files, TIFF stacks).
    Identity,
    /// Voxel spacing given by the caller (raw files), origin at zero.
    Given,
    /// NIfTI `srow_x/y/z` (used whenever `sform_code > 0`), with that code.
    NiftiSform(i32),
    /// NIfTI quaternion, `qoffset_*` and `pixdim` (used when `sform_code` is 0 and
    /// `qform_code > 0`), with that code.
    NiftiQform(i32),
    /// NIfTI `pixdim[1..=3]` alone (both codes 0: the specification's "method 1", a diagonal
    /// scaling with origin zero; nibabel's `img.affine` centres and flips such files instead).
    NiftiPixdim,
    /// NRRD `space directions` and `space origin`, converted to RAS.
    NrrdSpaceDirections,
    /// NRRD `spacings` alone (diagonal, origin zero).
    NrrdSpacings,
    /// DICOM `ImagePositionPatient`, `ImageOrientationPatient` and `PixelSpacing` of the sorted
    /// slices, converted from LPS to RAS.
    DicomPatient,
}

/// The index-to-world mapping of a volume in RAS+ millimetres.
///
/// `affine` is row-major: world `[x, y, z, 1]ᵀ = affine · [i, j, k, 1]ᵀ` for voxel index
/// `(i, j, k)` (`i` the fastest axis). `+x` is right, `+y` anterior, `+z` superior (NIfTI's and
/// nibabel's convention; a NRRD in `left-posterior-superior` has its first two world rows
/// negated). `spacing` holds the lengths of the first three columns: the voxel size along each
/// index axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Space {
    /// Row-major 4×4 index-to-world (RAS+) matrix; the last row is `[0, 0, 0, 1]`.
    pub affine: [[f64; 4]; 4],
    /// Voxel size along each index axis (norms of the affine's first three columns).
    pub spacing: [f64; 3],
    /// Which header fields gave the affine.
    pub source: SpaceSource,
}

impl Space {
    /// The identity: 1 mm voxels, index = world.
    pub fn identity() -> Self {
        Self::diagonal([1.0; 3], SpaceSource::Identity)
    }

    /// A diagonal scaling by `spacing` with origin zero.
    pub fn diagonal(spacing: [f64; 3], source: SpaceSource) -> Self {
        let mut a = [[0.0; 4]; 4];
        for k in 0..3 {
            a[k][k] = spacing[k];
        }
        a[3][3] = 1.0;
        Self::from_affine(a, source)
    }

    /// The space of `affine` (its last row is taken as `[0, 0, 0, 1]`); the spacing is computed:
    /// each column's length, `√(Σ a²)`, or where the squares underflow or overflow (a column
    /// of lengths below about `10⁻¹⁵⁴` or above `10¹⁵⁴`), the same scaled by the column's
    /// largest entry, so that no finite non-zero column has length zero or infinity.
    pub fn from_affine(mut affine: [[f64; 4]; 4], source: SpaceSource) -> Self {
        affine[3] = [0.0, 0.0, 0.0, 1.0];
        let spacing = [0, 1, 2].map(|c| {
            let col = [0, 1, 2].map(|r| affine[r][c]);
            let squares = col.iter().map(|x| x * x).sum::<f64>();
            let m = col.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            if squares.is_normal() || m == 0.0 || !m.is_finite() {
                squares.sqrt()
            } else {
                m * col.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
            }
        });
        Space {
            affine,
            spacing,
            source,
        }
    }

    /// World (RAS+) position of the continuous voxel index `ijk`.
    pub fn index_to_world(&self, ijk: [f64; 3]) -> [f64; 3] {
        let a = &self.affine;
        [0, 1, 2].map(|r| a[r][0] * ijk[0] + a[r][1] * ijk[1] + a[r][2] * ijk[2] + a[r][3])
    }
}

/// A loaded volume: dimensions, samples in the file's type, and its place in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedVolume {
    /// Samples along `x`, `y`, `z` (`x` fastest in `data`).
    pub dims: [usize; 3],
    /// The samples, `dims[0] · dims[1] · dims[2]` of them.
    pub data: Scalars,
    /// Index-to-world mapping in RAS+.
    pub space: Space,
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

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> LoadError + '_ {
    move |e| LoadError::Io(path.to_path_buf(), e)
}

/// The window `[center − width/2, center + width/2]` in data units (e.g. Hounsfield units for
/// CT: `window(40.0, 400.0)` is the usual soft-tissue window, −160 to 240). The CLI's default
/// ramp runs from transparent at `lo` to its full opacity at `hi`; values below and above are
/// clamped to the ends, as a transfer function does. This is the continuous form; DICOM's
/// integer rule (`center − 0.5`, `width − 1`) differs by under one unit.
///
/// # Errors
/// A non-finite center or a width that is not finite and positive.
pub fn window(center: f64, width: f64) -> Result<(f64, f64), String> {
    if !(center.is_finite() && width.is_finite() && width > 0.0) {
        return Err(format!(
            "window center {center}, width {width}: need a finite center and a positive width"
        ));
    }
    Ok((center - width / 2.0, center + width / 2.0))
}

/// Voxel count and byte size of `dims` samples of `ty`, refused past `cap` bytes.
fn checked_size(
    path: &Path,
    dims: [usize; 3],
    ty: ScalarType,
    cap: u64,
) -> Result<(usize, usize), LoadError> {
    if dims.contains(&0) {
        return Err(bad(path, "a dimension is zero"));
    }
    let count = dims[0]
        .checked_mul(dims[1])
        .and_then(|p| p.checked_mul(dims[2]))
        .ok_or_else(|| bad(path, "dimensions overflow"))?;
    let need = count
        .checked_mul(ty.size())
        .ok_or_else(|| bad(path, "dimensions overflow"))?;
    if need as u64 > cap {
        return Err(bad(
            path,
            format!(
                "{}×{}×{} {} samples need {need} bytes, over the memory cap of {cap} bytes",
                dims[0],
                dims[1],
                dims[2],
                ty.name()
            ),
        ));
    }
    Ok((count, need))
}

/// Why reading samples from a stream stopped.
enum DataError {
    /// The stream ended after this many bytes.
    Short(u64),
    /// The stream holds more than the samples.
    Long,
    /// A read failed (for a decompressor: a corrupt stream).
    Io(io::Error),
}

/// Reads until `buf` is full or the stream ends; returns the bytes read.
fn read_full<R: Read + ?Sized>(r: &mut R, buf: &mut [u8]) -> io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// Skips `n` bytes; returns how many there were (fewer at the end of the stream).
fn skip<R: Read + ?Sized>(r: &mut R, n: u64) -> io::Result<u64> {
    io::copy(&mut r.take(n), &mut io::sink())
}

/// Reads `count` values of `N` bytes each, decoded by `conv`, in 64 KiB pieces. `reserve`
/// allocates all of them at once (for data whose length was checked); otherwise memory grows
/// with what arrives. With `check_end`, one more byte is read to make sure the stream ends.
fn read_array<R: Read + ?Sized, T, const N: usize>(
    r: &mut R,
    count: usize,
    reserve: bool,
    check_end: bool,
    conv: impl Fn([u8; N]) -> T,
) -> Result<Vec<T>, DataError> {
    let mut out = Vec::with_capacity(if reserve { count } else { count.min(1 << 16) });
    let mut buf = vec![0u8; (1 << 16) / N * N];
    while out.len() < count {
        let want = ((count - out.len()) * N).min(buf.len());
        let got = read_full(r, &mut buf[..want]).map_err(DataError::Io)?;
        for c in buf[..got - got % N].chunks_exact(N) {
            let mut a = [0u8; N];
            a.copy_from_slice(c);
            out.push(conv(a));
        }
        if got < want {
            return Err(DataError::Short((out.len() * N + got % N) as u64));
        }
    }
    if check_end {
        let mut one = [0u8; 1];
        if read_full(r, &mut one).map_err(DataError::Io)? != 0 {
            return Err(DataError::Long);
        }
    }
    Ok(out)
}

/// Reads `count` samples of `ty` in the given byte order (see [`read_array`]).
fn read_scalars<R: Read + ?Sized>(
    r: &mut R,
    ty: ScalarType,
    count: usize,
    big: bool,
    reserve: bool,
    check_end: bool,
) -> Result<Scalars, DataError> {
    macro_rules! num {
        ($t:ty, $var:ident) => {
            Scalars::$var(read_array(r, count, reserve, check_end, |a| {
                if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }
            })?)
        };
    }
    Ok(match ty {
        ScalarType::U8 => Scalars::U8(read_array(r, count, reserve, check_end, |[b]| b)?),
        ScalarType::I8 => Scalars::I8(read_array(r, count, reserve, check_end, |a| {
            i8::from_le_bytes(a)
        })?),
        ScalarType::U16 => num!(u16, U16),
        ScalarType::I16 => num!(i16, I16),
        ScalarType::U32 => num!(u32, U32),
        ScalarType::I32 => num!(i32, I32),
        ScalarType::F32 => num!(f32, F32),
        ScalarType::F64 => num!(f64, F64),
    })
}

/// Refuses NaN and infinite floats.
fn check_finite(path: &Path, data: &Scalars) -> Result<(), LoadError> {
    let bad_at = match data {
        Scalars::F32(v) => v.iter().position(|x| !x.is_finite()),
        Scalars::F64(v) => v.iter().position(|x| !x.is_finite()),
        _ => None,
    };
    match bad_at {
        Some(i) => Err(bad(path, format!("value {i} is NaN or infinite"))),
        None => Ok(()),
    }
}

/// The message for data of the wrong length: `have` bytes (`None`: more than `need`).
fn size_message(have: Option<u64>, count: usize, ty: ScalarType, need: usize) -> String {
    match have {
        Some(h) => format!("holds {h} data bytes, but {count} {ty:?} values need {need}"),
        None => format!("holds more than {need} data bytes, but {count} {ty:?} values need {need}"),
    }
}

thread_local! {
    /// The bar of [`show_progress`]: advanced by the bytes the loaders read on this thread.
    static PROGRESS: RefCell<Option<ProgressBar>> = const { RefCell::new(None) };
}

/// Sets (`Some`) or clears (`None`) a progress bar that the loaders on this thread advance
/// by the bytes they read from each file (compressed bytes for compressed data): each file
/// they open sets its length to the file's size and its position to 0. The CLI shows one
/// while it loads a volume.
pub fn show_progress(bar: Option<ProgressBar>) {
    PROGRESS.with(|p| *p.borrow_mut() = bar);
}

/// Sets the length of the bar of [`show_progress`], if any, and its position to 0 (for
/// loaders that read many files, such as a DICOM series).
#[cfg(feature = "app")]
pub(crate) fn progress_start(len: u64) {
    PROGRESS.with(|p| {
        if let Some(bar) = &*p.borrow() {
            bar.set_length(len);
            bar.set_position(0);
        }
    });
}

/// Advances the bar of [`show_progress`], if any, by `n`.
#[cfg(feature = "app")]
pub(crate) fn progress_inc(n: u64) {
    PROGRESS.with(|p| {
        if let Some(bar) = &*p.borrow() {
            bar.inc(n);
        }
    });
}

/// A file whose reads and seeks move the bar of [`show_progress`], if one was set when it
/// was opened.
pub(crate) struct Tracked {
    file: std::fs::File,
    bar: Option<ProgressBar>,
}

impl Read for Tracked {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.file.read(buf)?;
        if let Some(bar) = &self.bar {
            bar.inc(n as u64);
        }
        Ok(n)
    }
}

impl Seek for Tracked {
    fn seek(&mut self, pos: io::SeekFrom) -> io::Result<u64> {
        let at = self.file.seek(pos)?;
        if let Some(bar) = &self.bar {
            bar.set_position(at);
        }
        Ok(at)
    }
}

/// Opens `path` for buffered reading, with its length (the progress bar of
/// [`show_progress`] follows the reads).
fn open(path: &Path) -> Result<(io::BufReader<Tracked>, u64), LoadError> {
    let file = std::fs::File::open(path).map_err(io_err(path))?;
    let len = file.metadata().map_err(io_err(path))?.len();
    let bar = PROGRESS.with(|p| p.borrow().clone());
    if let Some(bar) = &bar {
        bar.set_length(len);
        bar.set_position(0);
    }
    Ok((io::BufReader::new(Tracked { file, bar }), len))
}

/// Reads a headerless raw volume: `dims` samples of `ty`, `x` fastest, in the given byte
/// order; `spacing` (voxel size per axis) gives a diagonal [`Space`], else the identity.
///
/// # Errors
/// Unreadable file, zero dimensions, more than `cap` bytes of samples, a file size other than
/// `dims × ty` (checked before reading), NaN/∞ floats, a non-finite or zero spacing.
pub fn read_raw(
    path: &Path,
    dims: [usize; 3],
    ty: ScalarType,
    big_endian: bool,
    spacing: Option<[f64; 3]>,
    cap: u64,
) -> Result<LoadedVolume, LoadError> {
    let (count, need) = checked_size(path, dims, ty, cap)?;
    let space = match spacing {
        None => Space::identity(),
        Some(s) if s.iter().all(|v| v.is_finite() && *v != 0.0) => {
            Space::diagonal(s, SpaceSource::Given)
        }
        Some(s) => {
            return Err(bad(
                path,
                format!("spacing {s:?}: need finite non-zero values"),
            ))
        }
    };
    let (mut r, len) = open(path)?;
    if len != need as u64 {
        return Err(bad(path, size_message(Some(len), count, ty, need)));
    }
    let data = read_scalars(&mut r, ty, count, big_endian, true, true).map_err(|e| match e {
        DataError::Io(e) => LoadError::Io(path.to_path_buf(), e),
        DataError::Short(h) => bad(path, size_message(Some(h), count, ty, need)),
        DataError::Long => bad(path, size_message(None, count, ty, need)),
    })?;
    check_finite(path, &data)?;
    Ok(LoadedVolume { dims, data, space })
}

/// Reads a NRRD, NIfTI-1/-2 (plain or gzip) or TIFF file, chosen by its first bytes, or the
/// DICOM series in a folder ([`read_dicom_series`], which must hold one series).
///
/// # Errors
/// Those of [`read_nrrd`], [`read_nifti`], [`read_tiff`] and [`read_dicom_series`]; a file that
/// is none of them (a single DICOM file is refused: its folder holds the series).
pub fn read_volume(path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    if path.is_dir() {
        #[cfg(feature = "app")]
        return read_dicom_series(path, None, cap);
        #[cfg(not(feature = "app"))]
        return Err(bad(path, "a folder: DICOM series need the feature `app`"));
    }
    let (mut r, _) = open(path)?;
    let head = r.fill_buf().map_err(io_err(path))?;
    let mut magic = [0u8; 348];
    let n = head.len().min(348);
    magic[..n].copy_from_slice(&head[..n]);
    if magic.starts_with(b"NRRD") {
        read_nrrd(path, cap)
    } else if magic.starts_with(b"II*\0") || magic.starts_with(b"MM\0*") {
        read_tiff(path, cap)
    } else if magic.starts_with(&[0x1f, 0x8b])
        || &magic[4..8] == b"n+2\0"
        || &magic[344..348] == b"n+1\0"
    {
        read_nifti(path, cap)
    } else if &magic[128..132] == b"DICM" {
        Err(bad(
            path,
            "a DICOM file: give its folder, which holds the series of slices",
        ))
    } else {
        Err(bad(
            path,
            "not a NRRD, NIfTI or TIFF file (for headerless data give its dims and type)",
        ))
    }
}

/// Loads a headerless little-endian raw volume of `dims` values of `ty` as `f32`
/// ([`read_raw`] with the [`DEFAULT_MEMORY_CAP`]).
///
/// # Errors
/// Those of [`read_raw`].
pub fn load_raw(path: &Path, dims: [usize; 3], ty: ScalarType) -> Result<Vec<f32>, LoadError> {
    Ok(read_raw(path, dims, ty, false, None, DEFAULT_MEMORY_CAP)?
        .data
        .to_f32())
}

/// Loads a 3D scalar NRRD file as `f32`: its dimensions and values ([`read_nrrd`] with the
/// [`DEFAULT_MEMORY_CAP`]).
///
/// # Errors
/// Those of [`read_nrrd`].
pub fn load_nrrd(path: &Path) -> Result<([usize; 3], Vec<f32>), LoadError> {
    let v = read_nrrd(path, DEFAULT_MEMORY_CAP)?;
    Ok((v.dims, v.data.to_f32()))
}

/// Loads a NIfTI-1 or NIfTI-2 volume (`.nii` or `.nii.gz`) as `f32`: its dimensions and
/// (scaled) values ([`read_nifti`] with the [`DEFAULT_MEMORY_CAP`]).
///
/// # Errors
/// Those of [`read_nifti`].
pub fn load_nifti(path: &Path) -> Result<([usize; 3], Vec<f32>), LoadError> {
    let v = read_nifti(path, DEFAULT_MEMORY_CAP)?;
    Ok((v.dims, v.data.to_f32()))
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
