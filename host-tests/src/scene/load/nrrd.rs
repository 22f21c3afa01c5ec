//! NRRD (`.nrrd` with attached data, `.nhdr` with a detached data file).

use std::io::{self, BufRead, Read, Seek, SeekFrom};
use std::path::Path;

use super::{
    bad, check_finite, checked_size, io_err, open, read_scalars, size_message, skip, DataError,
    LoadError, LoadedVolume, ScalarType, Scalars, Space, SpaceSource,
};

/// Longest header read before giving up on finding its end.
const MAX_HEADER: u64 = 1 << 20;

/// The fields of a NRRD header this loader uses.
#[derive(Default)]
struct Header {
    ty: Option<ScalarType>,
    dimension: Option<usize>,
    sizes: Option<Vec<usize>>,
    encoding: Option<String>,
    big_endian: bool,
    data_file: Option<String>,
    line_skip: u64,
    byte_skip: i64,
    space: Option<String>,
    directions: Option<Vec<Option<Vec<f64>>>>,
    origin: Option<Vec<f64>>,
    spacings: Option<Vec<f64>>,
}

/// Parses `(1,0,0)`-style vectors.
fn vector(s: &str) -> Option<Vec<f64>> {
    let inner = s.trim().strip_prefix('(')?.strip_suffix(')')?;
    inner.split(',').map(|t| t.trim().parse().ok()).collect()
}

/// Parses `space directions`: one vector or `none` per axis.
fn directions(s: &str) -> Option<Vec<Option<Vec<f64>>>> {
    let mut out = Vec::new();
    let mut rest = s.trim();
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("none") {
            out.push(None);
            rest = r.trim_start();
        } else {
            let end = rest.find(')')?;
            out.push(Some(vector(&rest[..=end])?));
            rest = rest[end + 1..].trim_start();
        }
    }
    Some(out)
}

/// Signs that take a NRRD space's first three axes to RAS, or `None` for an unknown space.
fn ras_signs(space: &str) -> Option<[f64; 3]> {
    let s = space.trim().to_ascii_lowercase();
    let s = s.strip_suffix("-time").unwrap_or(&s);
    Some(match s {
        "right-anterior-superior" | "ras" => [1.0, 1.0, 1.0],
        "left-anterior-superior" | "las" => [-1.0, 1.0, 1.0],
        "left-posterior-superior" | "lps" => [-1.0, -1.0, 1.0],
        // No anatomical meaning: taken as they are.
        "scanner-xyz" | "3d-right-handed" | "3d-left-handed" => [1.0, 1.0, 1.0],
        _ => return None,
    })
}

fn parse_header(path: &Path, text: &str) -> Result<Header, LoadError> {
    let mut h = Header::default();
    for line in text.lines().skip(1) {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some((key, value)) = line.split_once(':') else {
            continue;
        };
        if value.starts_with('=') {
            continue; // key:=value pairs carry nothing we need
        }
        let value = value.trim();
        let field = |what: &str| bad(path, format!("bad {what} '{value}'"));
        match key.trim().to_ascii_lowercase().as_str() {
            "type" => {
                h.ty = Some(ScalarType::parse(value).ok_or_else(|| {
                    bad(
                        path,
                        format!(
                            "unsupported type '{value}' (int8 to uint32, float or double; \
                             not 64-bit integers or block)"
                        ),
                    )
                })?)
            }
            "dimension" => h.dimension = Some(value.parse().map_err(|_| field("dimension"))?),
            "sizes" => {
                let v: Result<Vec<usize>, _> = value.split_whitespace().map(str::parse).collect();
                h.sizes = Some(v.map_err(|_| field("sizes"))?);
            }
            "encoding" => h.encoding = Some(value.to_ascii_lowercase()),
            "endian" => h.big_endian = value.eq_ignore_ascii_case("big"),
            "data file" | "datafile" => h.data_file = Some(value.to_string()),
            "line skip" | "lineskip" => {
                h.line_skip = value.parse().map_err(|_| field("line skip"))?
            }
            "byte skip" | "byteskip" => {
                h.byte_skip = value
                    .parse()
                    .ok()
                    .filter(|&b: &i64| b >= -1)
                    .ok_or_else(|| field("byte skip"))?
            }
            "space" => h.space = Some(value.to_string()),
            "space directions" => {
                h.directions = Some(directions(value).ok_or_else(|| field("space directions"))?)
            }
            "space origin" => h.origin = Some(vector(value).ok_or_else(|| field("space origin"))?),
            "spacings" => {
                let v: Result<Vec<f64>, _> = value.split_whitespace().map(str::parse).collect();
                h.spacings = Some(v.map_err(|_| field("spacings"))?);
            }
            _ => {}
        }
    }
    Ok(h)
}

/// The RAS space of the three kept axes `axes` of `h`.
fn space(path: &Path, h: &Header, axes: [usize; 3]) -> Result<Space, LoadError> {
    if let Some(dirs) = &h.directions {
        if Some(dirs.len()) != h.dimension {
            return Err(bad(
                path,
                format!(
                    "'space directions' has {} entries, 'dimension' is {:?}",
                    dirs.len(),
                    h.dimension
                ),
            ));
        }
        let signs = match &h.space {
            Some(s) => ras_signs(s).ok_or_else(|| {
                bad(
                    path,
                    format!(
                        "unknown space '{s}' (right-anterior-superior, left-anterior-superior, \
                         left-posterior-superior, scanner-xyz, 3D-right-handed, 3D-left-handed)"
                    ),
                )
            })?,
            None => [1.0; 3],
        };
        let mut a = [[0.0; 4]; 4];
        for (c, &axis) in axes.iter().enumerate() {
            let v = match &dirs[axis] {
                Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => v,
                Some(v) => {
                    return Err(bad(
                        path,
                        format!("space direction of axis {axis} is {v:?}, need 3 finite numbers"),
                    ))
                }
                None => return Err(bad(path, format!("axis {axis} has no space direction"))),
            };
            for r in 0..3 {
                a[r][c] = signs[r] * v[r];
            }
        }
        if let Some(o) = &h.origin {
            if o.len() != 3 || !o.iter().all(|x| x.is_finite()) {
                return Err(bad(
                    path,
                    format!("space origin {o:?}: need 3 finite numbers"),
                ));
            }
            for r in 0..3 {
                a[r][3] = signs[r] * o[r];
            }
        }
        return Ok(Space::from_affine(a, SpaceSource::NrrdSpaceDirections));
    }
    if let Some(sp) = &h.spacings {
        if Some(sp.len()) == h.dimension {
            let s = axes
                .map(|k| sp[k])
                .map(|v| if v.is_finite() && v != 0.0 { v } else { 1.0 });
            return Ok(Space::diagonal(s, SpaceSource::NrrdSpacings));
        }
    }
    Ok(Space::identity())
}

/// A reader that turns hexadecimal text (two digits per byte, whitespace ignored) into bytes.
struct Hex<R>(R);

impl<R: BufRead> Read for Hex<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        let mut n = 0;
        let mut hi: Option<u8> = None;
        while n < out.len() {
            let Some(&c) = self.0.fill_buf()?.first() else {
                break;
            };
            if c.is_ascii_whitespace() {
                self.0.consume(1);
                continue;
            }
            let d = (c as char).to_digit(16).ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!("'{}' is not hex", c as char),
                )
            })? as u8;
            self.0.consume(1);
            match hi.take() {
                None => hi = Some(d),
                Some(h) => {
                    out[n] = h << 4 | d;
                    n += 1;
                }
            }
        }
        if hi.is_some() {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "odd number of hex digits",
            ));
        }
        Ok(n)
    }
}

/// Reads the next whitespace-separated token of at most 64 bytes (`None` at the end).
fn token<R: BufRead>(r: &mut R) -> io::Result<Option<String>> {
    let mut t = Vec::new();
    while let Some(&c) = r.fill_buf()?.first() {
        r.consume(1);
        if c.is_ascii_whitespace() || c == b',' {
            if t.is_empty() {
                continue;
            }
            break;
        }
        if t.len() == 64 {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                "a value longer than 64 bytes",
            ));
        }
        t.push(c);
    }
    Ok((!t.is_empty()).then(|| String::from_utf8_lossy(&t).into_owned()))
}

/// Reads `count` ASCII values of `ty`; errors name the value's index.
fn read_ascii<R: BufRead>(
    path: &Path,
    r: &mut R,
    ty: ScalarType,
    count: usize,
) -> Result<Scalars, LoadError> {
    macro_rules! parse {
        ($t:ty, $var:ident) => {{
            let mut v: Vec<$t> = Vec::with_capacity(count.min(1 << 16));
            for i in 0..count {
                let t = token(r)
                    .map_err(|e| bad(path, format!("ASCII data: {e}")))?
                    .ok_or_else(|| {
                        bad(
                            path,
                            format!("ASCII data hold {i} values, but sizes need {count}"),
                        )
                    })?;
                v.push(t.parse::<$t>().map_err(|_| {
                    bad(
                        path,
                        format!("ASCII value {i} '{t}' is not a {}", ty.name()),
                    )
                })?);
            }
            Scalars::$var(v)
        }};
    }
    let data = match ty {
        ScalarType::U8 => parse!(u8, U8),
        ScalarType::I8 => parse!(i8, I8),
        ScalarType::U16 => parse!(u16, U16),
        ScalarType::I16 => parse!(i16, I16),
        ScalarType::U32 => parse!(u32, U32),
        ScalarType::I32 => parse!(i32, I32),
        ScalarType::F32 => parse!(f32, F32),
        ScalarType::F64 => parse!(f64, F64),
    };
    if token(r).ok().flatten().is_some() {
        return Err(bad(
            path,
            format!("ASCII data hold more than the {count} values sizes need"),
        ));
    }
    Ok(data)
}

/// Skips `n` lines; errors if the stream ends first.
fn skip_lines<R: BufRead>(path: &Path, r: &mut R, n: u64) -> Result<(), LoadError> {
    for i in 0..n {
        loop {
            let buf = r.fill_buf().map_err(io_err(path))?;
            if buf.is_empty() {
                return Err(bad(
                    path,
                    format!("line skip {n}: the data end after {i} lines"),
                ));
            }
            if let Some(p) = buf.iter().position(|&b| b == b'\n') {
                r.consume(p + 1);
                break;
            }
            let l = buf.len();
            r.consume(l);
        }
    }
    Ok(())
}

/// Reads a 3-D scalar NRRD file, attached (`.nrrd`) or detached (`.nhdr` whose `data file`
/// is relative to the header's folder, or absolute).
///
/// Supported: encodings `raw`, `gzip`/`gz`, `bzip2`/`bz2`, `ascii`/`text`/`txt` and `hex`;
/// every NRRD spelling of int8 to uint32, `float` and `double` (not 64-bit integers or
/// `block`); `endian` little or big (little when missing); `line skip` (lines of the data
/// file, before any decompression) and `byte skip` (after decompression; `-1`, the data at
/// the end of the file, with `raw` only); `dimension: 3`, or 4 with a leading (channel) or
/// trailing axis of size 1. The [`Space`] is `space directions` and `space origin`
/// converted to RAS (LPS and LAS spaces have their axes' signs flipped; `scanner-xyz` and
/// the `3D-*-handed` spaces are taken as they are), else `spacings` (diagonal), else the
/// identity. `kinds`, `centers` and key/value pairs are ignored.
///
/// # Errors
/// A missing `NRRD` magic; a header over 1 MiB; missing or bad `type`/`dimension`/`sizes`/
/// `encoding`; other dimensions; an unsupported encoding; multi-file data (`data file: LIST`
/// or a format pattern); an unreadable data file; more than `cap` bytes of samples; raw data
/// of another size than the header claims (checked before reading); compressed or text data
/// that end early, hold more than claimed, or are corrupt; NaN/∞ floats; bad space fields.
pub fn read_nrrd(path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    let (mut r, file_len) = open(path)?;
    // The header ends at the first empty line (or the end of a detached header).
    let mut header = Vec::new();
    let mut pos = 0u64;
    loop {
        let start = header.len();
        let n = (&mut r)
            .take(MAX_HEADER + 1 - pos.min(MAX_HEADER))
            .read_until(b'\n', &mut header)
            .map_err(io_err(path))?;
        pos += n as u64;
        if start == 0 && !header.starts_with(b"NRRD000") {
            return Err(bad(path, "not a NRRD file (no NRRD000x magic)"));
        }
        let line = &header[start..];
        if n == 0 || line == b"\n" || line == b"\r\n" {
            break;
        }
        if pos > MAX_HEADER {
            return Err(bad(
                path,
                "header longer than 1 MiB (no empty line ends it)",
            ));
        }
    }
    let text = std::str::from_utf8(&header).map_err(|_| bad(path, "header is not text"))?;
    let h = parse_header(path, text)?;
    let ty = h.ty.ok_or_else(|| bad(path, "missing 'type' field"))?;
    let dimension = h
        .dimension
        .ok_or_else(|| bad(path, "missing 'dimension' field"))?;
    let sizes = h
        .sizes
        .clone()
        .ok_or_else(|| bad(path, "missing 'sizes' field"))?;
    if sizes.len() != dimension {
        return Err(bad(
            path,
            format!(
                "'sizes' has {} entries, 'dimension' is {dimension}",
                sizes.len()
            ),
        ));
    }
    let axes = match (dimension, sizes.as_slice()) {
        (3, _) => [0, 1, 2],
        (4, [1, ..]) => [1, 2, 3],
        (4, [.., 1]) => [0, 1, 2],
        _ => {
            return Err(bad(
                path,
                format!(
                    "need a 3D volume, 'dimension' is {dimension} with sizes {sizes:?} \
                     (4-D only with a first or last axis of size 1)"
                ),
            ))
        }
    };
    let dims = axes.map(|k| sizes[k]);
    let (count, need) = checked_size(path, dims, ty, cap)?;
    let space = space(path, &h, axes)?;

    let encoding = h
        .encoding
        .as_deref()
        .ok_or_else(|| bad(path, "missing 'encoding' field"))?;
    enum Enc {
        Raw,
        Gzip,
        Bzip2,
        Ascii,
        Hex,
    }
    let enc = match encoding {
        "raw" => Enc::Raw,
        "gzip" | "gz" => Enc::Gzip,
        "bzip2" | "bz2" => Enc::Bzip2,
        "ascii" | "text" | "txt" => Enc::Ascii,
        "hex" => Enc::Hex,
        e => {
            return Err(bad(
                path,
                format!("unsupported encoding '{e}' (raw, gzip, bzip2, ascii, hex)"),
            ))
        }
    };

    // The data: after the header, or in the data file.
    let (mut data, data_len, data_path) = match &h.data_file {
        None => (r, file_len, path.to_path_buf()),
        Some(f) => {
            let f = f.trim();
            if f.starts_with("LIST") || f.contains(char::is_whitespace) {
                return Err(bad(
                    path,
                    format!("multi-file data ('data file: {f}') are not supported"),
                ));
            }
            let p = path.parent().unwrap_or(Path::new(".")).join(f);
            let (d, len) = open(&p).map_err(|e| bad(path, format!("data file {e}")))?;
            (d, len, p)
        }
    };
    let dp = data_path.as_path();
    skip_lines(dp, &mut data, h.line_skip)?;
    let data_pos = data.stream_position().map_err(io_err(dp))?;
    if h.byte_skip == -1 && !matches!(enc, Enc::Raw) {
        return Err(bad(path, "byte skip -1 needs raw encoding"));
    }
    let named = |e: LoadError| match e {
        LoadError::Format(p, m) if p != path => LoadError::Format(
            path.to_path_buf(),
            format!("data file {}: {m}", p.display()),
        ),
        LoadError::Io(p, e) if p != path => LoadError::Format(
            path.to_path_buf(),
            format!("data file {}: {e}", p.display()),
        ),
        e => e,
    };
    let values = match enc {
        Enc::Raw => {
            let start = if h.byte_skip == -1 {
                file_len_minus(dp, data_len, need, count, ty).map_err(named)?
            } else {
                data_pos.saturating_add(h.byte_skip as u64)
            };
            let have = data_len.saturating_sub(start);
            if have != need as u64 {
                return Err(named(bad(dp, size_message(Some(have), count, ty, need))));
            }
            data.seek(SeekFrom::Start(start))
                .map_err(io_err(dp))
                .map_err(named)?;
            read_scalars(&mut data, ty, count, h.big_endian, true, true).map_err(|e| {
                named(match e {
                    DataError::Io(e) => LoadError::Io(dp.to_path_buf(), e),
                    DataError::Short(h) => bad(dp, size_message(Some(h), count, ty, need)),
                    DataError::Long => bad(dp, size_message(None, count, ty, need)),
                })
            })?
        }
        Enc::Gzip => decompressed(
            dp,
            "gzip",
            flate2::bufread::MultiGzDecoder::new(data),
            &h,
            ty,
            count,
            need,
        )
        .map_err(named)?,
        Enc::Bzip2 => decompressed(
            dp,
            "bzip2",
            bzip2::bufread::MultiBzDecoder::new(data),
            &h,
            ty,
            count,
            need,
        )
        .map_err(named)?,
        Enc::Ascii => {
            skip(&mut data, h.byte_skip as u64)
                .map_err(io_err(dp))
                .map_err(named)?;
            read_ascii(dp, &mut data, ty, count).map_err(named)?
        }
        Enc::Hex => {
            skip(&mut data, h.byte_skip as u64)
                .map_err(io_err(dp))
                .map_err(named)?;
            let mut hex = Hex(data);
            read_scalars(&mut hex, ty, count, h.big_endian, false, true).map_err(|e| {
                named(match e {
                    DataError::Io(e) => bad(dp, format!("hex data: {e}")),
                    DataError::Short(h) => bad(dp, size_message(Some(h), count, ty, need)),
                    DataError::Long => bad(dp, size_message(None, count, ty, need)),
                })
            })?
        }
    };
    check_finite(path, &values)?;
    Ok(LoadedVolume {
        dims,
        data: values,
        space,
    })
}

/// Start of the last `need` bytes of a file of `len` bytes (`byte skip: -1`).
fn file_len_minus(
    path: &Path,
    len: u64,
    need: usize,
    count: usize,
    ty: ScalarType,
) -> Result<u64, LoadError> {
    len.checked_sub(need as u64)
        .ok_or_else(|| bad(path, size_message(Some(len), count, ty, need)))
}

/// Reads `count` samples from a decompressor: `byte skip` decompressed bytes first, then
/// exactly the samples (one byte more is read to check that the stream ends there).
fn decompressed<R: Read>(
    path: &Path,
    name: &str,
    mut z: R,
    h: &Header,
    ty: ScalarType,
    count: usize,
    need: usize,
) -> Result<Scalars, LoadError> {
    let corrupt = |e: io::Error| bad(path, format!("bad {name} stream: {e}"));
    let skipped = skip(&mut z, h.byte_skip as u64).map_err(corrupt)?;
    if skipped < h.byte_skip as u64 {
        return Err(bad(
            path,
            format!(
                "byte skip {}: the {name} data hold only {skipped} bytes",
                h.byte_skip
            ),
        ));
    }
    read_scalars(&mut z, ty, count, h.big_endian, false, true).map_err(|e| match e {
        DataError::Io(e) => corrupt(e),
        DataError::Short(n) => bad(
            path,
            format!("{name} data {}", size_message(Some(n), count, ty, need)),
        ),
        DataError::Long => bad(
            path,
            format!("{name} data {}", size_message(None, count, ty, need)),
        ),
    })
}
