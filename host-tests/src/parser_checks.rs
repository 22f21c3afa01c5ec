//! Checks of the file parsers (`scene::load`), run by the parser fuzz targets
//! (`fuzz/fuzz_targets/load_*.rs`) and, on stable, by the corpus replay test
//! (`tests/parser_corpus_replay.rs`) on the checked-in corpus.
//!
//! The loaders read files, so each input is written to a scratch folder of its own (one per
//! thread) and read back with a memory cap of [`CAP`] bytes. Every target's oracle:
//! - no panic (a panic is the fuzz target's crash);
//! - a loaded volume has `dims[0]·dims[1]·dims[2]` samples, at most [`CAP`] bytes of them, and
//!   only finite floats; a header asking for more than the cap is an error (the fuzz runs add
//!   `-malloc_limit_mb` so an allocation past it is a crash too);
//! - round trips, with writers written here from the format descriptions (not the loaders'
//!   code): a loaded volume written as a raw NRRD reads back to the same samples; generated
//!   raw and NRRD files (every encoding) read back to the values they were written from; a
//!   NIfTI file and its gzip compression load alike; a transfer function written as text and
//!   as JSON reads back to the same points.

use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use arbitrary::Unstructured;
use volsample::ControlPoint;

use crate::scene::load::{
    check_points, load_transfer_function, read_nifti, read_nrrd, read_raw, read_tiff, read_volume,
    LoadedVolume, ScalarType, Scalars,
};

/// The parser fuzz targets, each with a corpus folder `fuzz/corpus/<name>`.
pub const TARGETS: [&str; 5] = [
    "load_raw",
    "load_nrrd",
    "load_nifti",
    "load_tiff",
    "load_tf",
];

/// The memory cap the checks pass to the loaders: 1 MiB of samples.
pub const CAP: u64 = 1 << 20;

/// Every scalar type, in the order the inputs' selector bytes pick them.
const TYPES: [ScalarType; 8] = [
    ScalarType::U8,
    ScalarType::I8,
    ScalarType::U16,
    ScalarType::I16,
    ScalarType::U32,
    ScalarType::I32,
    ScalarType::F32,
    ScalarType::F64,
];

/// Decodes `data` as the fuzz target `target` does and runs its check.
///
/// # Errors
/// The check's description of a broken promise, or an unknown target name. Input the loaders
/// refuse is not a failure: refusing bad input is what they must do.
pub fn run(target: &str, data: &[u8]) -> Result<(), String> {
    run_loaded(target, data).map(|_| ())
}

/// [`run`], telling also whether the input loaded (and its loaded volume or points went
/// through the oracle) rather than being refused.
///
/// # Errors
/// Those of [`run`].
pub fn run_loaded(target: &str, data: &[u8]) -> Result<bool, String> {
    let dir = Scratch::new()?;
    let r = match target {
        "load_raw" => raw(&dir.0, data),
        "load_nrrd" => nrrd(&dir.0, data),
        "load_nifti" => nifti(&dir.0, data),
        "load_tiff" => tiff(&dir.0, data),
        "load_tf" => tf(&dir.0, data),
        _ => Err(format!("unknown fuzz target {target}")),
    };
    drop(dir);
    r
}

/// A scratch folder for one input, emptied when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> Result<Self, String> {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        thread_local! {
            static DIR: RefCell<Option<PathBuf>> = const { RefCell::new(None) };
        }
        let dir = DIR.with(|d| {
            d.borrow_mut()
                .get_or_insert_with(|| {
                    std::env::temp_dir().join(format!(
                        "volsample-parser-checks-{}-{}",
                        std::process::id(),
                        NEXT.fetch_add(1, Ordering::Relaxed)
                    ))
                })
                .clone()
        });
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(Scratch(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The promises every loaded volume keeps.
fn invariants(what: &str, v: &LoadedVolume) -> Result<(), String> {
    let count = v.dims.iter().try_fold(1usize, |p, &d| p.checked_mul(d));
    if v.dims.contains(&0) || count != Some(v.data.len()) {
        return Err(format!(
            "{what}: dims {:?} but {} samples",
            v.dims,
            v.data.len()
        ));
    }
    if v.data.byte_len() as u64 > CAP {
        return Err(format!(
            "{what}: {} bytes of samples, over the cap of {CAP}",
            v.data.byte_len()
        ));
    }
    if let Some(i) = (0..v.data.len()).find(|&i| !v.data.get(i).is_some_and(f64::is_finite)) {
        return Err(format!("{what}: sample {i} is not finite"));
    }
    Ok(())
}

/// One sample of `ty` decoded from its bytes (independently of the loaders' decoder).
fn decode(ty: ScalarType, b: &[u8], big: bool) -> f64 {
    let mut a = [0u8; 8];
    let n = ty.size();
    a[..n].copy_from_slice(&b[..n]);
    if big {
        a[..n].reverse();
    }
    let [b0, b1, b2, b3, ..] = a;
    match ty {
        ScalarType::U8 => f64::from(b0),
        ScalarType::I8 => f64::from(b0 as i8),
        ScalarType::U16 => f64::from(u16::from_le_bytes([b0, b1])),
        ScalarType::I16 => f64::from(i16::from_le_bytes([b0, b1])),
        ScalarType::U32 => f64::from(u32::from_le_bytes([b0, b1, b2, b3])),
        ScalarType::I32 => f64::from(i32::from_le_bytes([b0, b1, b2, b3])),
        ScalarType::F32 => f64::from(f32::from_le_bytes([b0, b1, b2, b3])),
        ScalarType::F64 => f64::from_le_bytes(a),
    }
}

/// The bytes of the value `v` (exact in `ty`) in `ty`.
fn encode(ty: ScalarType, v: f64, big: bool) -> Vec<u8> {
    let mut b = match ty {
        ScalarType::U8 => vec![v as u8],
        ScalarType::I8 => (v as i8).to_le_bytes().to_vec(),
        ScalarType::U16 => (v as u16).to_le_bytes().to_vec(),
        ScalarType::I16 => (v as i16).to_le_bytes().to_vec(),
        ScalarType::U32 => (v as u32).to_le_bytes().to_vec(),
        ScalarType::I32 => (v as i32).to_le_bytes().to_vec(),
        ScalarType::F32 => (v as f32).to_le_bytes().to_vec(),
        ScalarType::F64 => v.to_le_bytes().to_vec(),
    };
    if big {
        b.reverse();
    }
    b
}

/// The loaded samples as `f64` (exact for every type).
fn values(d: &Scalars) -> Vec<f64> {
    (0..d.len()).filter_map(|i| d.get(i)).collect()
}

/// Compares loaded samples with the expected ones, bit for bit (as `f64`, so `-0.0` differs
/// from `0.0`).
fn same_values(what: &str, got: &Scalars, ty: ScalarType, want: &[f64]) -> Result<(), String> {
    if got.scalar_type() != ty {
        return Err(format!("{what}: type {:?}, want {ty:?}", got.scalar_type()));
    }
    let got = values(got);
    if got.len() != want.len() {
        return Err(format!(
            "{what}: {} samples, want {}",
            got.len(),
            want.len()
        ));
    }
    match got
        .iter()
        .zip(want)
        .position(|(a, b)| a.to_bits() != b.to_bits())
    {
        Some(i) => Err(format!(
            "{what}: sample {i} is {}, want {}",
            got[i], want[i]
        )),
        None => Ok(()),
    }
}

/// The NRRD encodings the loader reads.
#[derive(Debug, Clone, Copy)]
enum Encoding {
    Raw,
    Gzip,
    Bzip2,
    Ascii,
    Hex,
}

/// Writes `values` of `ty` as a NRRD (attached, or a detached header `in.nhdr` with
/// `data.bin`), following the NRRD0004 format description; returns the header's path.
fn write_nrrd(
    dir: &Path,
    dims: [usize; 3],
    ty: ScalarType,
    vals: &[f64],
    enc: Encoding,
    big: bool,
    detached: bool,
) -> Result<PathBuf, String> {
    let mut payload = Vec::new();
    match enc {
        Encoding::Ascii => {
            for v in vals {
                // `{:?}` of an f64 reads back exactly; f32 values are exact in f64.
                match ty {
                    ScalarType::F32 | ScalarType::F64 => payload.extend(format!("{v:?}\n").bytes()),
                    _ => payload.extend(format!("{}\n", *v as i64).bytes()),
                }
            }
        }
        _ => {
            let bytes: Vec<u8> = vals.iter().flat_map(|&v| encode(ty, v, big)).collect();
            payload = match enc {
                Encoding::Raw => bytes,
                Encoding::Hex => bytes
                    .chunks(16)
                    .flat_map(|c| {
                        let mut l: String = c.iter().map(|b| format!("{b:02x}")).collect();
                        l.push('\n');
                        l.into_bytes()
                    })
                    .collect(),
                Encoding::Gzip => {
                    let mut z = flate2::write::GzEncoder::new(Vec::new(), Default::default());
                    z.write_all(&bytes).map_err(|e| e.to_string())?;
                    z.finish().map_err(|e| e.to_string())?
                }
                Encoding::Bzip2 => {
                    let mut z = bzip2::write::BzEncoder::new(Vec::new(), Default::default());
                    z.write_all(&bytes).map_err(|e| e.to_string())?;
                    z.finish().map_err(|e| e.to_string())?
                }
                Encoding::Ascii => unreachable!("handled above"),
            };
        }
    }
    let mut header = format!(
        "NRRD0004\ntype: {}\ndimension: 3\nsizes: {} {} {}\nencoding: {}\nendian: {}\n",
        ty.name(),
        dims[0],
        dims[1],
        dims[2],
        format!("{enc:?}").to_ascii_lowercase(),
        if big { "big" } else { "little" },
    );
    let path = if detached {
        header.push_str("data file: data.bin\n");
        write(&dir.join("data.bin"), &payload)?;
        let p = dir.join("in.nhdr");
        write(&p, header.as_bytes())?;
        p
    } else {
        header.push('\n');
        let mut f = header.into_bytes();
        f.extend(payload);
        let p = dir.join("out.nrrd");
        write(&p, &f)?;
        p
    };
    Ok(path)
}

/// A loaded volume written as an attached raw NRRD reads back to the same samples.
fn round_trip(dir: &Path, what: &str, v: &LoadedVolume) -> Result<(), String> {
    let ty = v.data.scalar_type();
    let p = write_nrrd(
        dir,
        v.dims,
        ty,
        &values(&v.data),
        Encoding::Raw,
        false,
        false,
    )?;
    let back = read_nrrd(&p, CAP).map_err(|e| format!("{what}: written back as NRRD: {e}"))?;
    if back.dims != v.dims {
        return Err(format!(
            "{what}: written back as NRRD: dims {:?}, want {:?}",
            back.dims, v.dims
        ));
    }
    same_values(
        &format!("{what}: written back as NRRD"),
        &back.data,
        ty,
        &values(&v.data),
    )
}

/// `load_raw`: a raw file of the input's bytes, read with the input's dims, type, byte order
/// and spacing. It loads exactly when the size matches, the spacing is finite and non-zero and
/// every float is finite, and then to the values decoded here.
#[derive(Debug)]
struct RawInput<'a> {
    dims: [u16; 3],
    ty: u8,
    big: bool,
    spacing: Option<[f64; 3]>,
    bytes: &'a [u8],
}

impl<'a> RawInput<'a> {
    /// The fields with `arbitrary` (little-endian integers, a bool and an option each a
    /// byte), then the file's bytes: all the rest, as they are.
    fn decode(data: &'a [u8]) -> arbitrary::Result<Self> {
        let mut u = Unstructured::new(data);
        Ok(RawInput {
            dims: u.arbitrary()?,
            ty: u.arbitrary()?,
            big: u.arbitrary()?,
            spacing: u.arbitrary()?,
            bytes: u.take_rest(),
        })
    }
}

fn raw(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let Ok(i) = RawInput::decode(data) else {
        return Ok(false);
    };
    let ty = TYPES[usize::from(i.ty) % TYPES.len()];
    let dims = i.dims.map(usize::from);
    let p = dir.join("in.raw");
    write(&p, i.bytes)?;
    let got = read_raw(&p, dims, ty, i.big, i.spacing, CAP);
    let count = dims[0] * dims[1] * dims[2];
    let want: Vec<f64> = i
        .bytes
        .chunks_exact(ty.size())
        .map(|c| decode(ty, c, i.big))
        .collect();
    let fits = count > 0
        && (count * ty.size()) as u64 <= CAP
        && count * ty.size() == i.bytes.len()
        && i.spacing
            .is_none_or(|s| s.iter().all(|v| v.is_finite() && *v != 0.0))
        && want.iter().all(|v| v.is_finite());
    match (got, fits) {
        (Ok(v), true) => {
            invariants("raw", &v)?;
            if v.dims != dims {
                return Err(format!("raw: dims {:?}, want {dims:?}", v.dims));
            }
            let s = i.spacing.map_or([1.0; 3], |s| s.map(f64::abs));
            if v.space.spacing != s {
                return Err(format!("raw: spacing {:?}, want {s:?}", v.space.spacing));
            }
            same_values("raw", &v.data, ty, &want)?;
            round_trip(dir, "raw", &v)?;
            Ok(true)
        }
        (Err(_), false) => Ok(false),
        (Ok(_), false) => Err(format!(
            "raw: {dims:?} {ty:?} from {} bytes (spacing {:?}) loaded but should be refused",
            i.bytes.len(),
            i.spacing
        )),
        (Err(e), true) => Err(format!("raw: a well-formed file was refused: {e}")),
    }
}

/// `load_nrrd`, by the first byte: (0) the rest is an attached NRRD file; (1) a detached
/// header and its data file `data.bin`, split at a little-endian `u16` header length (the
/// header's own `data file` line names the file; inputs with `/` in them are skipped, so no
/// file outside the scratch folder is read); (2) generated values written as a NRRD in every
/// encoding, byte order, attached or detached, which must read back to those values.
fn nrrd(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let Some((&mode, rest)) = data.split_first() else {
        return Ok(false);
    };
    match mode % 3 {
        0 => {
            let p = dir.join("in.nrrd");
            write(&p, rest)?;
            loaded(dir, "nrrd", read_nrrd(&p, CAP))
        }
        1 => {
            if rest.contains(&b'/') || rest.len() < 2 {
                return Ok(false);
            }
            let n = usize::from(u16::from_le_bytes([rest[0], rest[1]])).min(rest.len() - 2);
            let (header, body) = rest[2..].split_at(n);
            let p = dir.join("in.nhdr");
            write(&p, header)?;
            write(&dir.join("data.bin"), body)?;
            loaded(dir, "nrrd (detached)", read_nrrd(&p, CAP))
        }
        _ => nrrd_written(dir, rest),
    }
}

/// What a successful load of fuzzed bytes must satisfy; a refusal is fine.
fn loaded(
    dir: &Path,
    what: &str,
    r: Result<LoadedVolume, crate::scene::load::LoadError>,
) -> Result<bool, String> {
    match r {
        Ok(v) => {
            invariants(what, &v)?;
            round_trip(dir, what, &v)?;
            Ok(true)
        }
        Err(_) => Ok(false),
    }
}

/// `load_nrrd` mode 2: dims, type, encoding, byte order and attached or detached, one byte
/// each, then the bytes the values are decoded from (cycled).
#[derive(Debug)]
struct NrrdInput<'a> {
    dims: [u8; 3],
    ty: u8,
    enc: u8,
    big: bool,
    detached: bool,
    bytes: &'a [u8],
}

impl<'a> NrrdInput<'a> {
    fn decode(data: &'a [u8]) -> arbitrary::Result<Self> {
        let mut u = Unstructured::new(data);
        Ok(NrrdInput {
            dims: u.arbitrary()?,
            ty: u.arbitrary()?,
            enc: u.arbitrary()?,
            big: u.arbitrary()?,
            detached: u.arbitrary()?,
            bytes: u.take_rest(),
        })
    }
}

fn nrrd_written(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let Ok(i) = NrrdInput::decode(data) else {
        return Ok(false);
    };
    let ty = TYPES[usize::from(i.ty) % TYPES.len()];
    let dims = i.dims.map(|d| usize::from(d % 8) + 1);
    let count = dims[0] * dims[1] * dims[2];
    let enc = [
        Encoding::Raw,
        Encoding::Gzip,
        Encoding::Bzip2,
        Encoding::Ascii,
        Encoding::Hex,
    ][usize::from(i.enc) % 5];
    // The values: the input's bytes, cycled, decoded as `ty`.
    let bytes = if i.bytes.is_empty() {
        &[0][..]
    } else {
        i.bytes
    };
    let want: Vec<f64> = bytes
        .iter()
        .copied()
        .cycle()
        .take(count * ty.size())
        .collect::<Vec<u8>>()
        .chunks_exact(ty.size())
        .map(|c| decode(ty, c, false))
        .collect();
    let p = write_nrrd(dir, dims, ty, &want, enc, i.big, i.detached)?;
    let what = format!(
        "nrrd {dims:?} {ty:?} {enc:?} big {} detached {}",
        i.big, i.detached
    );
    match read_nrrd(&p, CAP) {
        Ok(v) => {
            if !want.iter().all(|v| v.is_finite()) {
                return Err(format!("{what}: non-finite floats were accepted"));
            }
            invariants(&what, &v)?;
            if v.dims != dims {
                return Err(format!("{what}: dims {:?}", v.dims));
            }
            same_values(&what, &v.data, ty, &want)?;
            Ok(true)
        }
        Err(_) if !want.iter().all(|v| v.is_finite()) => Ok(false),
        Err(e) => Err(format!("{what}: refused: {e}")),
    }
}

/// `load_nifti`: the input as a `.nii` file and gzip-compressed as a `.nii.gz`; the two load
/// alike (both refused, or the same volume), and `read_volume` (which picks the loader by the
/// magic bytes) agrees.
fn nifti(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let plain = dir.join("in.nii");
    write(&plain, data)?;
    let mut z = flate2::write::GzEncoder::new(Vec::new(), Default::default());
    z.write_all(data).map_err(|e| e.to_string())?;
    let gz = dir.join("in.nii.gz");
    write(&gz, &z.finish().map_err(|e| e.to_string())?)?;
    let a = read_nifti(&plain, CAP);
    let b = read_nifti(&gz, CAP);
    match (&a, &b) {
        (Ok(x), Ok(y)) if x == y => {}
        (Err(_), Err(_)) => {}
        _ => {
            return Err(format!(
                "nifti: plain and gzip differ: {:?} vs {:?}",
                a.as_ref().map(|v| v.dims),
                b.as_ref().map(|v| v.dims)
            ))
        }
    }
    if let Ok(v) = &b {
        // A gzip file is a NIfTI file to `read_volume`.
        match read_volume(&gz, CAP) {
            Ok(w) if &w == v => {}
            _ => return Err("nifti: read_volume differs from read_nifti".into()),
        }
    }
    loaded(dir, "nifti", a)
}

/// `load_tiff`: the input as a TIFF stack; a load keeps the invariants and round-trips.
fn tiff(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let p = dir.join("in.tif");
    write(&p, data)?;
    loaded(dir, "tiff", read_tiff(&p, CAP))
}

/// `load_tf`: the input as a transfer function file (JSON or text, as the loader decides). A
/// loaded one passes `check_points`, and written back as text and as JSON it reads back to
/// the same points.
fn tf(dir: &Path, data: &[u8]) -> Result<bool, String> {
    let p = dir.join("in.tf");
    write(&p, data)?;
    let Ok(points) = load_transfer_function(&p) else {
        return Ok(false);
    };
    check_points(&points).map_err(|e| format!("tf: a loaded function fails: {e}"))?;
    // `{:?}` of an f64 reads back exactly, and f32 values are exact in f64.
    let row = |q: &ControlPoint| {
        [q.s, q.c[0], q.c[1], q.c[2], q.a]
            .map(|v| format!("{:?}", f64::from(v)))
            .join(" ")
    };
    let text: String = points.iter().map(|q| row(q) + "\n").collect();
    let json = format!(
        "{{\"points\": [{}]}}",
        points
            .iter()
            .map(|q| format!("[{}]", row(q).replace(' ', ", ")))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for (name, body) in [("tf.txt", text), ("tf.json", json)] {
        let q = dir.join(name);
        write(&q, body.as_bytes())?;
        let back = load_transfer_function(&q).map_err(|e| format!("tf: {name} refused: {e}"))?;
        let bits = |v: &[ControlPoint]| -> Vec<[u32; 5]> {
            v.iter()
                .map(|q| [q.s, q.c[0], q.c[1], q.c[2], q.a].map(f32::to_bits))
                .collect()
        };
        if bits(&back) != bits(&points) {
            return Err(format!("tf: {name} reads back to other points"));
        }
    }
    Ok(true)
}
