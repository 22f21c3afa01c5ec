//! Volume file formats against files written by numpy, pynrrd, nibabel and tifffile
//! (`tests/data/formats/make_fixtures.py`). Each fixture has a JSON file, written by that
//! script from the Python side, with the dimensions, sample type, values (x fastest) and
//! RAS+ affine a correct loader must return; or, for a file that must be refused, a piece of
//! the error. Then refusals: truncated and corrupted copies of every fixture, headers claiming
//! more than the file holds or more than the memory cap, bad compressed streams, unknown types.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use volsample_host::scene::load::{
    read_nifti, read_nrrd, read_raw, read_tiff, read_volume, window, LoadError, LoadedVolume,
    ScalarType, Scalars, SpaceSource, DEFAULT_MEMORY_CAP,
};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/formats")
}

fn tmp(name: &str, bytes: &[u8]) -> PathBuf {
    let d = std::env::temp_dir().join(format!("volsample-formats-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// Every fixture's JSON, parsed, sorted by file name.
fn fixtures() -> Vec<Value> {
    let mut out: Vec<(String, Value)> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .map(|p| {
            let v: Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
            (p.display().to_string(), v)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out.into_iter().map(|(_, v)| v).collect()
}

/// Loads `path` the way fixture `f` says (its reader, a raw file's dims and type).
fn load(f: &Value, path: &Path, cap: u64) -> Result<LoadedVolume, LoadError> {
    match f["reader"].as_str().unwrap() {
        "nrrd" => read_nrrd(path, cap),
        "nifti" => read_nifti(path, cap),
        "tiff" => read_tiff(path, cap),
        "raw" => {
            let dims: Vec<usize> = f["dims"]
                .as_array()
                .unwrap()
                .iter()
                .map(|d| d.as_u64().unwrap() as usize)
                .collect();
            let ty = ScalarType::parse(f["raw"]["type"].as_str().unwrap()).unwrap();
            let big = f["raw"]["big_endian"].as_bool().unwrap();
            read_raw(path, dims.try_into().unwrap(), ty, big, None, cap)
        }
        r => panic!("unknown reader {r}"),
    }
}

fn source_name(s: SpaceSource) -> &'static str {
    match s {
        SpaceSource::Identity => "identity",
        SpaceSource::Given => "given",
        SpaceSource::NiftiSform(_) => "sform",
        SpaceSource::NiftiQform(_) => "qform",
        SpaceSource::NiftiPixdim => "pixdim",
        SpaceSource::NrrdSpaceDirections => "nrrd-space",
        SpaceSource::NrrdSpacings => "nrrd-spacings",
        SpaceSource::DicomPatient => "dicom-patient",
    }
}

/// Checks a loaded volume against its fixture's JSON.
fn check(f: &Value, v: &LoadedVolume) {
    let name = f["file"].as_str().unwrap();
    let dims: Vec<usize> = f["dims"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_u64().unwrap() as usize)
        .collect();
    assert_eq!(v.dims.to_vec(), dims, "{name}: dims");
    assert_eq!(
        v.data.scalar_type().name(),
        f["type"].as_str().unwrap(),
        "{name}: sample type"
    );
    let want = f["values"].as_array().unwrap();
    assert_eq!(v.data.len(), want.len(), "{name}: count");
    let tol = f["rel_tol"].as_f64().unwrap();
    for (i, w) in want.iter().enumerate() {
        let got = v.data.get(i).unwrap();
        let w = w.as_f64().unwrap();
        if tol == 0.0 {
            assert_eq!(got, w, "{name}: value {i}");
        } else {
            assert!(
                (got - w).abs() <= tol * w.abs().max(1.0),
                "{name}: value {i}: {got} vs {w}"
            );
        }
    }
    let affine: Vec<Vec<f64>> = f["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            row.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect();
    assert_eq!(affine.len(), 4, "{name}");
    for (r, (row, want)) in v.space.affine.iter().zip(&affine).enumerate() {
        for (c, (got, w)) in row.iter().zip(want).enumerate() {
            assert!(
                (got - w).abs() <= 1e-6,
                "{name}: affine[{r}][{c}] {got} vs {w}: {:?}",
                v.space.affine
            );
        }
    }
    for (c, spacing) in v.space.spacing.iter().enumerate() {
        let norm = affine[..3]
            .iter()
            .map(|row| row[c] * row[c])
            .sum::<f64>()
            .sqrt();
        assert!((spacing - norm).abs() <= 1e-6, "{name}: spacing {c}");
    }
    assert_eq!(
        source_name(v.space.source),
        f["source"].as_str().unwrap(),
        "{name}: space source"
    );
}

#[test]
fn fixtures_load_as_python_wrote_them() {
    let all = fixtures();
    let mut loaded = 0;
    let mut refused = 0;
    let mut formats = std::collections::BTreeSet::new();
    for f in &all {
        let name = f["file"].as_str().unwrap();
        let path = dir().join(name);
        let r = load(f, &path, DEFAULT_MEMORY_CAP);
        if let Some(want) = f.get("error") {
            let e = r.expect_err(name).to_string();
            assert!(
                e.contains(name) && e.contains(want.as_str().unwrap()),
                "{name}: {e}"
            );
            refused += 1;
            continue;
        }
        let v = r.unwrap_or_else(|e| panic!("{e}"));
        check(f, &v);
        // The same through the format-sniffing reader.
        if f["reader"] != "raw" {
            assert_eq!(read_volume(&path, DEFAULT_MEMORY_CAP).unwrap(), v, "{name}");
        }
        formats.insert((
            f["reader"].as_str().unwrap().to_string(),
            f["type"].as_str().unwrap().to_string(),
        ));
        loaded += 1;
    }
    assert!(
        loaded >= 28 && refused >= 2,
        "{loaded} loaded, {refused} refused"
    );
    // Every type is in the fixtures of NIfTI and NRRD.
    for reader in ["nifti", "nrrd"] {
        for ty in ["u8", "i8", "u16", "i16", "u32", "i32", "f32", "f64"] {
            assert!(
                formats.contains(&(reader.to_string(), ty.to_string())),
                "no {reader} {ty} fixture"
            );
        }
    }
}

#[test]
fn native_types_stay_native() {
    let v = read_nifti(&dir().join("nifti1_u8.nii"), DEFAULT_MEMORY_CAP).unwrap();
    assert!(matches!(v.data, Scalars::U8(_)));
    assert_eq!(v.data.byte_len(), 5 * 4 * 3, "one byte per u8 voxel");
    let v = read_nrrd(&dir().join("nrrd_i16_gzip.nrrd"), DEFAULT_MEMORY_CAP).unwrap();
    assert!(matches!(v.data, Scalars::I16(_)));
    assert_eq!(v.data.range(), Some((-1024.0, 59.0 * 37.0 - 1024.0)));
    assert_eq!(v.data.to_f32()[1], -987.0);
    // A world position: voxel (1, 0, 0) is one step along the first space direction.
    let p0 = v.space.index_to_world([0.0; 3]);
    let p1 = v.space.index_to_world([1.0, 0.0, 0.0]);
    assert!(p0.iter().zip(&p1).any(|(a, b)| a != b));
    assert!(((0..3).map(|k| (p1[k] - p0[k]).powi(2)).sum::<f64>().sqrt() - 0.8).abs() < 1e-9);
}

/// Every fixture cut short at every length, and with every byte flipped: never a panic, an
/// error names the file, and a cut file loads only if it gives what the whole file gives
/// (an ASCII NRRD without its last newline), or inside an ASCII file's last value.
#[test]
fn truncated_and_corrupted_fixtures() {
    for f in fixtures() {
        let name = f["file"].as_str().unwrap();
        let bytes = std::fs::read(dir().join(name)).unwrap();
        let whole = load(&f, &dir().join(name), DEFAULT_MEMORY_CAP).ok();
        let copy = format!("cut-{name}");
        for len in 0..bytes.len() {
            let p = tmp(&copy, &bytes[..len]);
            match load(&f, &p, DEFAULT_MEMORY_CAP) {
                Err(e) => assert!(e.to_string().contains(&copy), "{name}[..{len}]: {e}"),
                // ASCII data cut inside the last value ("58" to "5") are still whole data.
                Ok(_) if name.contains("ascii") && len + 3 >= bytes.len() => {}
                Ok(v) => assert_eq!(Some(v), whole, "{name} cut to {len} bytes loaded"),
            }
        }
        let copy = format!("flip-{name}");
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0xA5;
            let p = tmp(&copy, &b);
            if let Err(e) = load(&f, &p, DEFAULT_MEMORY_CAP) {
                assert!(e.to_string().contains(&copy), "{name} byte {i}: {e}");
            }
        }
    }
}

#[test]
fn memory_cap_is_checked_first() {
    for f in fixtures() {
        if f.get("error").is_some() {
            continue;
        }
        let name = f["file"].as_str().unwrap();
        let e = load(&f, &dir().join(name), 50).unwrap_err().to_string();
        assert!(
            e.contains(name) && e.contains("over the memory cap of 50 bytes"),
            "{name}: {e}"
        );
    }
    // A header claiming 8 GiB + 1 byte is refused at the default cap, whatever the file holds.
    let h = b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2048 2048 2049\nencoding: gzip\n\n";
    let e = read_nrrd(&tmp("huge.nrrd", h), DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("huge.nrrd") && e.contains("memory cap"), "{e}");
    // Dimensions whose product overflows.
    let h = format!(
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: {} {} 2\nencoding: raw\n\n",
        usize::MAX,
        usize::MAX
    );
    let e = read_nrrd(&tmp("overflow.nrrd", h.as_bytes()), u64::MAX)
        .unwrap_err()
        .to_string();
    assert!(e.contains("overflow"), "{e}");
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

fn nrrd_with(header: &str, data: &[u8]) -> Vec<u8> {
    let mut f = format!("NRRD0004\n{header}\n").into_bytes();
    f.extend_from_slice(data);
    f
}

#[test]
fn claims_beyond_the_file_and_bad_streams() {
    let u8_3 = "type: uint8\ndimension: 3\nsizes: 3 1 1\n";
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        // A raw header claiming 2 GiB over 3 bytes: refused from the file size.
        (
            "claims.nrrd",
            nrrd_with(
                "type: uint16\ndimension: 3\nsizes: 1024 1024 1024\nencoding: raw\n",
                &[1, 2, 3],
            ),
            "holds 3 data bytes, but 1073741824 U16 values need 2147483648",
        ),
        (
            "claims-gz.nrrd",
            nrrd_with(
                "type: uint16\ndimension: 3\nsizes: 1024 1024 1024\nencoding: gzip\n",
                &gzip(&[1, 2, 3]),
            ),
            "gzip data holds 3 data bytes",
        ),
        // A decompression bomb: 16 MiB of zeros where the header claims 3 bytes.
        (
            "bomb.nrrd",
            nrrd_with(
                &format!("{u8_3}encoding: gzip\n"),
                &gzip(&vec![0; 16 << 20]),
            ),
            "holds more than 3 data bytes",
        ),
        (
            "badgz.nrrd",
            nrrd_with(&format!("{u8_3}encoding: gzip\n"), b"not gzip at all"),
            "bad gzip stream",
        ),
        (
            "badbz2.nrrd",
            nrrd_with(&format!("{u8_3}encoding: bzip2\n"), b"BZh9 not bzip2"),
            "bad bzip2 stream",
        ),
        (
            "int64.nrrd",
            nrrd_with(
                "type: int64\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n",
                &[0; 8],
            ),
            "unsupported type 'int64'",
        ),
        (
            "block.nrrd",
            nrrd_with("type: block\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n", &[0]),
            "unsupported type 'block'",
        ),
        (
            "zrl.nrrd",
            nrrd_with(&format!("{u8_3}encoding: zrl\n"), &[0]),
            "unsupported encoding 'zrl'",
        ),
        (
            "ascii-short.nrrd",
            nrrd_with(&format!("{u8_3}encoding: ascii\n"), b"1 2"),
            "ASCII data hold 2 values, but sizes need 3",
        ),
        (
            "ascii-range.nrrd",
            nrrd_with(&format!("{u8_3}encoding: ascii\n"), b"1 2 256"),
            "ASCII value 2 '256' is not a u8",
        ),
        (
            "ascii-long.nrrd",
            nrrd_with(&format!("{u8_3}encoding: ascii\n"), b"1 2 3 4"),
            "more than the 3 values",
        ),
        (
            "hex-bad.nrrd",
            nrrd_with(&format!("{u8_3}encoding: hex\n"), b"0102zz"),
            "'z' is not hex",
        ),
        (
            "skip-gz.nrrd",
            nrrd_with(&format!("{u8_3}encoding: gzip\nbyte skip: -1\n"), &[0]),
            "byte skip -1 needs raw encoding",
        ),
        (
            "list.nhdr",
            format!("NRRD0004\n{u8_3}encoding: raw\ndata file: LIST\na.raw\n").into_bytes(),
            "multi-file data",
        ),
        (
            "missing.nhdr",
            format!("NRRD0004\n{u8_3}encoding: raw\ndata file: nowhere.raw\n").into_bytes(),
            "data file",
        ),
        (
            "space.nrrd",
            nrrd_with(
                &format!(
                    "{u8_3}encoding: raw\nspace: sideways\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
                ),
                &[1, 2, 3],
            ),
            "unknown space 'sideways'",
        ),
        (
            "5d.nrrd",
            nrrd_with(
                "type: uint8\ndimension: 4\nsizes: 2 3 1 2\nencoding: raw\n",
                &[0; 12],
            ),
            "need a 3D volume",
        ),
        ("endless.nrrd", [b"NRRD0004\n".as_slice(), &[b'#'; 2 << 20]].concat(), "1 MiB"),
    ];
    for (name, bytes, want) in cases {
        let e = read_nrrd(&tmp(name, &bytes), DEFAULT_MEMORY_CAP)
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }

    // NIfTI: the u8 fixture relabelled as RGB24, cut inside its data, claiming more.
    let nii = std::fs::read(dir().join("nifti1_u8.nii")).unwrap();
    let mut rgb = nii.clone();
    rgb[70..72].copy_from_slice(&128i16.to_le_bytes());
    rgb[72..74].copy_from_slice(&24i16.to_le_bytes());
    let mut big = nii.clone();
    big[46..48].copy_from_slice(&1000i16.to_le_bytes()); // dim[3] = 1000
    let mut gz = gzip(&nii);
    let n = gz.len();
    gz[n - 8..].copy_from_slice(&[0; 8]); // a wrong CRC
    for (name, bytes, want) in [
        ("rgb.nii", rgb, "unsupported datatype RGB24"),
        (
            "claims.nii",
            big,
            "holds 60 data bytes, but 20000 U8 values need 20000",
        ),
        (
            "claims.nii.gz",
            gzip(&{
                let mut b = nii.clone();
                b[46..48].copy_from_slice(&1000i16.to_le_bytes());
                b
            }),
            "holds 60 data bytes",
        ),
        ("crc.nii.gz", gz, "bad gzip stream"),
    ] {
        let e = read_nifti(&tmp(name, &bytes), DEFAULT_MEMORY_CAP)
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }

    let e = read_volume(&tmp("what.bin", b"hello"), DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("what.bin") && e.contains("not a NRRD, NIfTI or TIFF"),
        "{e}"
    );
    // The u8 stack's first page claiming 60000 rows: more than the file holds.
    let mut tif = std::fs::read(dir().join("tiff_u8.tif")).unwrap();
    let ifd = u32::from_le_bytes(tif[4..8].try_into().unwrap()) as usize;
    let entries = u16::from_le_bytes(tif[ifd..ifd + 2].try_into().unwrap()) as usize;
    let mut patched = false;
    for k in 0..entries {
        let e = ifd + 2 + 12 * k;
        if u16::from_le_bytes([tif[e], tif[e + 1]]) == 257 {
            // ImageLength, SHORT or LONG: the value sits in the entry's first bytes.
            tif[e + 8..e + 10].copy_from_slice(&60000u16.to_le_bytes());
            patched = true;
        }
    }
    assert!(patched);
    let e = read_tiff(&tmp("tall.tif", &tif), DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    // (The tiff crate itself finds the strips inconsistent with the size before this loader's
    // own check, page size against file size, would.)
    assert!(
        e.contains("tall.tif")
            && (e.contains("inconsistent sizes") || e.contains("page 1 claims 5×60000")),
        "{e}"
    );
    let e = read_tiff(&tmp("not.tif", b"II*\0garbage"), DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not.tif"), "{e}");
}

/// `line skip`, `byte skip` (also -1) and hex data, on the f32 fixture's raw data.
#[test]
fn nrrd_skips_and_hex() {
    let json = fixtures()
        .into_iter()
        .find(|f| f["file"] == "nrrd_f32_detached.nhdr")
        .unwrap();
    let raw = std::fs::read(dir().join("nrrd_f32_detached.raw")).unwrap();
    let head = "type: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nspacings: 0.25 0.5 4\n";
    let mut skipped = b"first line\nsecond line\nABC".to_vec();
    skipped.extend_from_slice(&raw);
    tmp("skipped.raw", &skipped);
    let mut tail = vec![7u8; 13];
    tail.extend_from_slice(&raw);
    tmp("tail.raw", &tail);
    let hex: String = raw
        .iter()
        .enumerate()
        .map(|(i, b)| format!("{b:02x}{}", if i % 16 == 15 { "\n" } else { " " }))
        .collect();
    for (name, text) in [
        (
            "skips.nhdr",
            format!(
                "NRRD0004\n{head}encoding: raw\ndata file: skipped.raw\nline skip: 2\nbyte skip: 3\n"
            ),
        ),
        (
            "tail.nhdr",
            format!("NRRD0004\n{head}encoding: raw\ndata file: tail.raw\nbyte skip: -1\n"),
        ),
        (
            "hex.nrrd",
            format!("NRRD0004\n{head}encoding: hex\n\n{hex}"),
        ),
    ] {
        let v = read_nrrd(&tmp(name, text.as_bytes()), DEFAULT_MEMORY_CAP)
            .unwrap_or_else(|e| panic!("{e}"));
        check(&json, &v);
    }
    // Raw with a trailing byte is refused (the header must account for every byte).
    let e = read_nrrd(
        &tmp(
            "extra.nrrd",
            &nrrd_with(
                &format!("{head}encoding: raw\n"),
                &[raw.as_slice(), &[0]].concat(),
            ),
        ),
        DEFAULT_MEMORY_CAP,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("holds 241 data bytes"), "{e}");
}

#[test]
fn scalar_type_names() {
    for (names, ty) in [
        (
            &["u8", "uchar", "unsigned char", "uint8_t", "UINT8"][..],
            ScalarType::U8,
        ),
        (&["i8", "int8", "signed char"], ScalarType::I8),
        (
            &["short", "short int", "signed  short int", "int16_t", "i16"],
            ScalarType::I16,
        ),
        (&["ushort", "unsigned short int", "uint16"], ScalarType::U16),
        (&["int", "signed int", "int32"], ScalarType::I32),
        (&["uint", "unsigned int", "uint32_t"], ScalarType::U32),
        (&["float", "f32"], ScalarType::F32),
        (&["double", "float64", "f64"], ScalarType::F64),
    ] {
        for n in names {
            assert_eq!(ScalarType::parse(n), Some(ty), "{n}");
        }
    }
    for n in ["int64", "long long", "block", "u64", ""] {
        assert_eq!(ScalarType::parse(n), None, "{n}");
    }
}

#[test]
fn windows() {
    assert_eq!(window(40.0, 400.0), Ok((-160.0, 240.0)));
    assert_eq!(window(-600.0, 1500.0), Ok((-1350.0, 150.0)));
    for (c, w) in [
        (0.0, 0.0),
        (0.0, -1.0),
        (f64::NAN, 1.0),
        (0.0, f64::INFINITY),
    ] {
        assert!(window(c, w).is_err(), "{c}, {w}");
    }
}

/// The CLI renders a TIFF stack, an int16 gzip NRRD with a CT window and a big-endian raw
/// file; it refuses a bad window and two volume files.
#[test]
fn cli_formats_and_window() {
    let bin = env!("CARGO_BIN_EXE_volsample");
    let out = tmp("cli.png", b"");
    let render = |args: &[&str]| {
        Command::new(bin)
            .args([
                "render",
                "--size",
                "8",
                "--modes",
                "opacity-weighted",
                "--out",
            ])
            .arg(&out)
            .args(args)
            .output()
            .unwrap()
    };
    let d = |n: &str| dir().join(n).display().to_string();
    for args in [
        vec!["--tiff".to_string(), d("tiff_u16_deflate.tif")],
        vec![
            "--nrrd".into(),
            d("nrrd_i16_gzip.nrrd"),
            "--window".into(),
            "-500,1000".into(),
        ],
        vec![
            "--raw".into(),
            d("raw_i16_be.raw"),
            "--dims".into(),
            "5,4,3".into(),
            "--type".into(),
            "i16".into(),
            "--endian".into(),
            "big".into(),
        ],
        vec!["--nifti".into(), d("nifti2_f64.nii.gz")],
    ] {
        std::fs::write(&out, b"").unwrap();
        let o = render(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            std::fs::read(&out).unwrap().starts_with(b"\x89PNG"),
            "{args:?}"
        );
    }
    let tif = d("tiff_u8.tif");
    let nrrd = d("nrrd_u8_raw.nrrd");
    for (args, want) in [
        (
            vec!["--tiff", &tif, "--window", "40,0"],
            "--window: window center 40, width 0",
        ),
        (
            vec!["--tiff", &tif, "--window", "40"],
            "--window '40': need CENTER,WIDTH",
        ),
        (
            vec!["--tiff", &tif, "--window", "40,400", "--tf", &tif],
            "give --window or --tf, not both",
        ),
        (
            vec!["--tiff", &tif, "--nrrd", &nrrd],
            "--raw, --nrrd, --nifti, --tiff or --dicom, not several",
        ),
        (
            vec!["--tiff", &nrrd],
            "nrrd_u8_raw.nrrd: not a readable TIFF",
        ),
        (
            vec!["--raw", &tif, "--dims", "1,1,1", "--endian", "middle"],
            "unknown --endian 'middle'",
        ),
    ] {
        let o = render(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}
