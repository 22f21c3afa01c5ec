//! Loading user volumes and transfer functions: good files load, bad files give an error
//! that names the file and the problem, never a panic.

use std::io::Write;
use std::path::PathBuf;
use std::process::Command;

use volsample_host::scene::load::{
    load_nifti, load_nrrd, load_raw, load_transfer_function, ScalarType,
};

fn tmp(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("volsample-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

#[test]
fn raw_volumes() {
    let p = tmp("v.raw", &[0, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(
        load_raw(&p, [2, 2, 2], ScalarType::U8).unwrap(),
        (0..8).map(|v| v as f32).collect::<Vec<_>>()
    );
    assert_eq!(
        load_raw(&p, [2, 2, 1], ScalarType::U16).unwrap(),
        vec![256.0, 770.0, 1284.0, 1798.0]
    );
    let e = load_raw(&p, [3, 2, 2], ScalarType::U8)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("v.raw") && e.contains("8 data bytes") && e.contains("need 12"),
        "{e}"
    );
    let e = load_raw(&p, [0, 2, 2], ScalarType::U8)
        .unwrap_err()
        .to_string();
    assert!(e.contains("zero"), "{e}");
    let nan = tmp("nan.raw", &f32::NAN.to_le_bytes());
    let e = load_raw(&nan, [1, 1, 1], ScalarType::F32)
        .unwrap_err()
        .to_string();
    assert!(e.contains("NaN"), "{e}");
    let e = load_raw(
        &PathBuf::from("/nonexistent/x.raw"),
        [1, 1, 1],
        ScalarType::U8,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("/nonexistent/x.raw"), "{e}");
}

#[test]
fn nrrd_volumes() {
    let mut f =
        b"NRRD0004\n# comment\ntype: uint8\ndimension: 3\nsizes: 2 1 2\nencoding: raw\n\n".to_vec();
    f.extend([9, 8, 7, 6]);
    let (dims, v) = load_nrrd(&tmp("ok.nrrd", &f)).unwrap();
    assert_eq!((dims, v), ([2, 1, 2], vec![9.0, 8.0, 7.0, 6.0]));

    let mut be =
        b"NRRD0004\ntype: ushort\ndimension: 3\nsizes: 1 1 1\nendian: big\nencoding: raw\n\n"
            .to_vec();
    be.extend([1, 2]);
    assert_eq!(load_nrrd(&tmp("be.nrrd", &be)).unwrap().1, vec![258.0]);

    for (name, text, want) in [
        ("magic.nrrd", &b"P6\n"[..], "not a NRRD"),
        (
            "type.nrrd",
            b"NRRD0004\ntype: int64\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n",
            "unsupported type",
        ),
        (
            "dim.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 1 1\nencoding: raw\n\n",
            "3D",
        ),
        (
            "gz.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1 1 1\nencoding: zrl\n\n",
            "unsupported encoding",
        ),
        (
            "short.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n\x01",
            "1 data bytes",
        ),
        (
            "nosizes.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nencoding: raw\n\n",
            "sizes",
        ),
    ] {
        let e = load_nrrd(&tmp(name, text)).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
}

#[test]
fn transfer_functions() {
    let j = tmp(
        "tf.json",
        br#"{"points": [[0, 0, 0, 0, 0], [255, 1, 0.5, 0.25, 0.8]]}"#,
    );
    let pts = load_transfer_function(&j).unwrap();
    assert_eq!(pts.len(), 2);
    assert_eq!(pts[1].c, [1.0, 0.5, 0.25]);
    let t = tmp("tf.txt", b"# s r g b a\n0 0 0 0 0\n\n100 1 1 1 0.5\n");
    assert_eq!(load_transfer_function(&t).unwrap()[1].a, 0.5);
    for (name, text, want) in [
        ("bad.json", &b"{\"points\": [[0, 1]]}"[..], "need 5"),
        ("syntax.json", b"{\"points\": [", "bad JSON"),
        (
            "unsorted.txt",
            b"5 0 0 0 0\n1 0 0 0 0\n",
            "point 2 (s = 1) does not follow point 1 (s = 5)",
        ),
        ("range.txt", b"0 2 0 0 0\n", "outside [0, 1]"),
        ("words.txt", b"zero one two three four\n", "line 1"),
        ("empty.txt", b"", "no points"),
    ] {
        let e = load_transfer_function(&tmp(name, text))
            .unwrap_err()
            .to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
}

// NIfTI-1 files are written here byte by byte from the NIfTI-1 specification (nifti1.h), not
// with the loader's own header parser: a 348-byte header, 4 extension bytes, then the data.

/// Field offsets in the NIfTI-1 header (nifti1.h, `struct nifti_1_header`).
const SIZEOF_HDR: usize = 0;
const DIM: usize = 40; // short dim[8]
const DATATYPE: usize = 70;
const BITPIX: usize = 72;
const PIXDIM: usize = 76; // float pixdim[8]
const VOX_OFFSET: usize = 108;
const SCL_SLOPE: usize = 112;
const SCL_INTER: usize = 116;
const MAGIC: usize = 344;

/// NIfTI-1 datatype codes (nifti1.h `DT_*`).
const DT_UINT8: i16 = 2;
const DT_INT16: i16 = 4;
const DT_FLOAT32: i16 = 16;
const DT_RGB24: i16 = 128;
const DT_UINT16: i16 = 512;

/// A header being written in one byte order.
struct Nii {
    bytes: Vec<u8>,
    big: bool,
}

impl Nii {
    /// `dim[0] = dims.len()`, `dim[1..]` = `dims`, `vox_offset` 352, no scaling, magic
    /// `n+1\0`, extension bytes all zero (no extensions).
    fn new(dims: &[i16], datatype: i16, bitpix: i16, big: bool) -> Self {
        let mut h = Nii {
            bytes: vec![0; 352],
            big,
        };
        h.i32(SIZEOF_HDR, 348);
        let mut dim = [1i16; 8];
        dim[0] = dims.len() as i16;
        dim[1..=dims.len()].copy_from_slice(dims);
        for (k, d) in dim.iter().enumerate() {
            h.i16(DIM + 2 * k, *d);
        }
        h.i16(DATATYPE, datatype);
        h.i16(BITPIX, bitpix);
        for k in 0..8 {
            h.f32(PIXDIM + 4 * k, 1.0);
        }
        h.f32(VOX_OFFSET, 352.0);
        h.bytes[MAGIC..MAGIC + 4].copy_from_slice(b"n+1\0");
        h
    }

    fn put(&mut self, at: usize, le: &[u8]) {
        let field = &mut self.bytes[at..at + le.len()];
        field.copy_from_slice(le);
        if self.big {
            field.reverse();
        }
    }
    fn i16(&mut self, at: usize, v: i16) -> &mut Self {
        self.put(at, &v.to_le_bytes());
        self
    }
    fn i32(&mut self, at: usize, v: i32) -> &mut Self {
        self.put(at, &v.to_le_bytes());
        self
    }
    fn f32(&mut self, at: usize, v: f32) -> &mut Self {
        self.put(at, &v.to_le_bytes());
        self
    }

    /// The whole file: header, extension bytes, then `data`.
    fn file(&self, data: &[u8]) -> Vec<u8> {
        let mut f = self.bytes.clone();
        f.extend_from_slice(data);
        f
    }
}

fn u8_nii(dims: &[i16], data: &[u8]) -> Vec<u8> {
    Nii::new(dims, DT_UINT8, 8, false).file(data)
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

#[test]
fn nifti_dims_and_order() {
    // Value x + 10y + 50z at (x, y, z) of a 3×2×4 volume, written x fastest as NIfTI does.
    let mut data = Vec::new();
    for z in 0..4u8 {
        for y in 0..2u8 {
            for x in 0..3u8 {
                data.push(x + 10 * y + 50 * z);
            }
        }
    }
    let (dims, v) = load_nifti(&tmp("order.nii", &u8_nii(&[3, 2, 4], &data))).unwrap();
    assert_eq!(dims, [3, 2, 4]);
    for z in 0..4 {
        for y in 0..2 {
            for x in 0..3 {
                assert_eq!(v[x + 3 * (y + 2 * z)], (x + 10 * y + 50 * z) as f32);
            }
        }
    }
    // A 4-D file holding one volume (dim[4] = 1) is that volume.
    let (dims, v4) = load_nifti(&tmp("one.nii", &u8_nii(&[3, 2, 4, 1], &data))).unwrap();
    assert_eq!((dims, &v4), ([3, 2, 4], &v));
    // The data start at vox_offset: a 16-byte gap after the extension bytes is skipped.
    let mut h = Nii::new(&[2, 1, 1], DT_UINT8, 8, false);
    h.f32(VOX_OFFSET, 368.0);
    let mut data = vec![0xEE; 16];
    data.extend([7, 9]);
    let (_, v) = load_nifti(&tmp("offset.nii", &h.file(&data))).unwrap();
    assert_eq!(v, vec![7.0, 9.0]);
}

#[test]
fn nifti_types_and_byte_order() {
    let le: Vec<u8> = [-2i16, 300].iter().flat_map(|v| v.to_le_bytes()).collect();
    let f = Nii::new(&[2, 1, 1], DT_INT16, 16, false).file(&le);
    assert_eq!(
        load_nifti(&tmp("i16.nii", &f)).unwrap().1,
        vec![-2.0, 300.0]
    );

    let le: Vec<u8> = [1u16, 65535].iter().flat_map(|v| v.to_le_bytes()).collect();
    let f = Nii::new(&[1, 2, 1], DT_UINT16, 16, false).file(&le);
    let (dims, v) = load_nifti(&tmp("u16.nii", &f)).unwrap();
    assert_eq!((dims, v), ([1, 2, 1], vec![1.0, 65535.0]));

    let le: Vec<u8> = [0.25f32, -1.5]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let f = Nii::new(&[1, 1, 2], DT_FLOAT32, 32, false).file(&le);
    assert_eq!(load_nifti(&tmp("f32.nii", &f)).unwrap().1, vec![0.25, -1.5]);

    // Big-endian header and data (the byte order is found from dim[0]).
    let be: Vec<u8> = [258u16, 1].iter().flat_map(|v| v.to_be_bytes()).collect();
    let f = Nii::new(&[2, 1, 1], DT_UINT16, 16, true).file(&be);
    assert_eq!(load_nifti(&tmp("be.nii", &f)).unwrap().1, vec![258.0, 1.0]);
    let be: Vec<u8> = [0.5f32, 3.0].iter().flat_map(|v| v.to_be_bytes()).collect();
    let mut h = Nii::new(&[1, 2, 1], DT_FLOAT32, 32, true);
    h.f32(SCL_SLOPE, 2.0).f32(SCL_INTER, 1.0);
    assert_eq!(
        load_nifti(&tmp("bef32.nii", &h.file(&be))).unwrap().1,
        vec![2.0, 7.0]
    );
}

#[test]
fn nifti_scaling() {
    let data = [0u8, 1, 10, 255];
    let mut h = Nii::new(&[2, 2, 1], DT_UINT8, 8, false);
    h.f32(SCL_SLOPE, 0.5).f32(SCL_INTER, -2.0);
    assert_eq!(
        load_nifti(&tmp("scaled.nii", &h.file(&data))).unwrap().1,
        vec![-2.0, -1.5, 3.0, 125.5]
    );
    // A slope of 0 or NaN (nibabel writes NaN for unscaled data) means no scaling at all,
    // whatever the intercept.
    for (name, slope, inter) in [
        ("slope0.nii", 0.0, 5.0),
        ("slopenan.nii", f32::NAN, f32::NAN),
        ("slopeinf.nii", f32::INFINITY, 3.0),
    ] {
        let mut h = Nii::new(&[2, 2, 1], DT_UINT8, 8, false);
        h.f32(SCL_SLOPE, slope).f32(SCL_INTER, inter);
        assert_eq!(
            load_nifti(&tmp(name, &h.file(&data))).unwrap().1,
            vec![0.0, 1.0, 10.0, 255.0],
            "{name}"
        );
    }
    // int16 with a slope, as CT data often is.
    let le: Vec<u8> = [-1000i16, 24]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let mut h = Nii::new(&[2, 1, 1], DT_INT16, 16, false);
    h.f32(SCL_SLOPE, 1.0).f32(SCL_INTER, -1024.0);
    assert_eq!(
        load_nifti(&tmp("ct.nii", &h.file(&le))).unwrap().1,
        vec![-2024.0, -1000.0]
    );
}

#[test]
fn nifti_gzip() {
    let data: Vec<u8> = (0..24).collect();
    let plain = u8_nii(&[2, 3, 4], &data);
    let (dims, v) = load_nifti(&tmp("v.nii.gz", &gzip(&plain))).unwrap();
    assert_eq!(dims, [2, 3, 4]);
    assert_eq!(v, data.iter().map(|&b| f32::from(b)).collect::<Vec<_>>());
    // Recognised by content: a gzip stream under a plain name loads too.
    assert_eq!(
        load_nifti(&tmp("gz-named-plain.nii", &gzip(&plain)))
            .unwrap()
            .1,
        v
    );
    // A cut gzip stream, and a gzip stream of a file with too little data.
    let z = gzip(&plain);
    let e = load_nifti(&tmp("cut.nii.gz", &z[..z.len() / 2]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("cut.nii.gz") && e.contains("gzip"), "{e}");
    let e = load_nifti(&tmp("short.nii.gz", &gzip(&plain[..plain.len() - 1])))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("short.nii.gz") && e.contains("holds 23 data bytes"),
        "{e}"
    );
}

#[test]
fn nifti_errors() {
    let ok = |h: &Nii| h.file(&[0; 8]);
    let with = |f: &dyn Fn(&mut Nii)| {
        let mut h = Nii::new(&[2, 2, 2], DT_UINT8, 8, false);
        f(&mut h);
        ok(&h)
    };
    let f32_file = |v: f32, slope: f32| {
        let mut h = Nii::new(&[1, 1, 1], DT_FLOAT32, 32, false);
        h.f32(SCL_SLOPE, slope);
        h.file(&v.to_le_bytes())
    };
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.resize(400, 0);
    let mut nifti2 = vec![0u8; 600];
    nifti2[..4].copy_from_slice(&540i32.to_le_bytes());
    nifti2[4..12].copy_from_slice(b"n+2\0\r\n\x1a\n");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("magic.nii", png, "not a NIfTI-1 or NIfTI-2 file"),
        ("empty.nii", Vec::new(), "too short"),
        (
            "header-cut.nii",
            ok(&Nii::new(&[2, 2, 2], DT_UINT8, 8, false))[..200].to_vec(),
            "200 bytes is too short",
        ),
        // A NIfTI-2 header of zeros: read as NIfTI-2, refused for its datatype 0.
        ("nifti2.nii", nifti2, "unknown datatype code 0"),
        (
            "hdr.nii",
            with(&|h| h.bytes[MAGIC..MAGIC + 4].copy_from_slice(b"ni1\0")),
            "header-only",
        ),
        (
            "sizeof.nii",
            with(&|h| {
                h.i32(SIZEOF_HDR, 352);
            }),
            "sizeof_hdr is 352",
        ),
        (
            "rgb.nii",
            ok(&Nii::new(&[2, 2, 2], DT_RGB24, 24, false)),
            "unsupported datatype RGB24 (colour, not scalar samples) (code 128)",
        ),
        (
            "code.nii",
            ok(&Nii::new(&[2, 2, 2], 3, 8, false)),
            "unknown datatype code 3",
        ),
        (
            "bitpix.nii",
            ok(&Nii::new(&[2, 2, 2], DT_UINT16, 8, false)),
            "bitpix is 8",
        ),
        (
            "2d.nii",
            ok(&Nii::new(&[4, 2], DT_UINT8, 8, false)),
            "dim[0] (the number of dimensions) is 2",
        ),
        (
            "4d.nii",
            ok(&Nii::new(&[2, 2, 1, 2], DT_UINT8, 8, false)),
            "4-D with dim[4..=4] = [2]",
        ),
        (
            "dim0.nii",
            with(&|h| {
                h.i16(DIM, 0);
            }),
            "dim[0] (the number of dimensions) is 0",
        ),
        (
            "dim8.nii",
            with(&|h| {
                h.i16(DIM, 9);
            }),
            "dim[0] (the number of dimensions) is 9",
        ),
        (
            "zero.nii",
            ok(&Nii::new(&[2, 0, 2], DT_UINT8, 8, false)),
            "dim[2] is 0",
        ),
        (
            "negative.nii",
            ok(&Nii::new(&[2, 2, -4], DT_UINT8, 8, false)),
            "dim[3] is -4",
        ),
        (
            "voxoff.nii",
            with(&|h| {
                h.f32(VOX_OFFSET, 300.0);
            }),
            "vox_offset is 300",
        ),
        (
            "voxfrac.nii",
            with(&|h| {
                h.f32(VOX_OFFSET, 352.5);
            }),
            "vox_offset is 352.5",
        ),
        (
            "voxend.nii",
            with(&|h| {
                h.f32(VOX_OFFSET, 4096.0);
            }),
            "truncated: vox_offset is 4096",
        ),
        (
            "truncated.nii",
            u8_nii(&[2, 2, 2], &[1, 2, 3]),
            "holds 3 data bytes, but 8 U8 values need 8",
        ),
        (
            "long.nii",
            u8_nii(&[2, 2, 2], &[0; 9]),
            "holds 9 data bytes",
        ),
        (
            "nan.nii",
            f32_file(f32::NAN, 0.0),
            "value 0 is NaN or infinite",
        ),
        (
            "inf.nii",
            f32_file(f32::NEG_INFINITY, 0.0),
            "value 0 is NaN or infinite",
        ),
        (
            "overflow.nii",
            f32_file(f32::MAX, 4.0),
            "infinite after scaling",
        ),
        (
            "inter.nii",
            with(&|h| {
                h.f32(SCL_SLOPE, 2.0).f32(SCL_INTER, f32::NAN);
            }),
            "scl_inter is NaN",
        ),
    ];
    for (name, bytes, want) in cases {
        let e = load_nifti(&tmp(name, &bytes)).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(want), "{name}: {e}");
    }
    let e = load_nifti(&PathBuf::from("/nonexistent/x.nii"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/x.nii"), "{e}");
}

#[test]
fn nifti_cli() {
    let bin = env!("CARGO_BIN_EXE_volsample");
    let data: Vec<u8> = (0..64).map(|i| (i * 4) as u8).collect();
    let nii = tmp("cli.nii.gz", &gzip(&u8_nii(&[4, 4, 4], &data)));
    let png = nii.with_file_name("cli.png");
    let _ = std::fs::remove_file(&png);
    let o = Command::new(bin)
        .args([
            "render",
            "--size",
            "8",
            "--modes",
            "opacity-weighted",
            "--nifti",
        ])
        .arg(&nii)
        .arg("--out")
        .arg(&png)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::metadata(&png).unwrap().len() > 0);

    let nrrd = tmp("cli.nrrd", b"NRRD0004\n");
    let bad = tmp("cli-bad.nii", &u8_nii(&[4, 4], &[0; 16]));
    for (args, want) in [
        (
            vec!["--nifti".into(), nii.clone(), "--nrrd".into(), nrrd],
            "--raw, --nrrd, --nifti, --tiff or --dicom, not several",
        ),
        (vec!["--nifti".into(), bad], "cli-bad.nii: need a 3D volume"),
    ] {
        let o = Command::new(bin)
            .args(["render", "--size", "8", "--out"])
            .arg(&png)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}

/// The load progress bar (`show_progress`) follows the bytes the loaders read: its length is
/// the file's size and it ends at the end of the file, for a raw file and a gzip NRRD; once
/// cleared, loads leave the bar alone.
#[test]
fn load_progress_follows_the_bytes_read() {
    use volsample_host::scene::load::{read_nrrd, read_raw, show_progress, DEFAULT_MEMORY_CAP};
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/formats");
    let raw = tmp(
        "progress.raw",
        &(0..=255u8).cycle().take(4096).collect::<Vec<_>>(),
    );
    let gz = data.join("nrrd_i16_gzip.nrrd");
    let cases: [(&PathBuf, &dyn Fn() -> bool); 2] = [
        (&raw, &|| {
            read_raw(
                &raw,
                [16, 16, 16],
                ScalarType::U8,
                false,
                None,
                DEFAULT_MEMORY_CAP,
            )
            .is_ok()
        }),
        (&gz, &|| read_nrrd(&gz, DEFAULT_MEMORY_CAP).is_ok()),
    ];
    for (path, load) in cases {
        let len = std::fs::metadata(path).unwrap().len();
        check_progress(len, path, load);
    }
    // A DICOM series: the bar runs over the pixel bytes of its slices (5 slices of 6 × 4
    // int16 samples).
    let dicom = data.join("dicom/ct_i16_oblique");
    let load =
        || volsample_host::scene::load::read_dicom_series(&dicom, None, DEFAULT_MEMORY_CAP).is_ok();
    check_progress(5 * 6 * 4 * 2, &dicom, &load);

    fn check_progress(len: u64, path: &std::path::Path, load: &dyn Fn() -> bool) {
        let bar = indicatif::ProgressBar::hidden();
        show_progress(Some(bar.clone()));
        assert!(load(), "{}", path.display());
        show_progress(None);
        assert_eq!(bar.length(), Some(len), "{}", path.display());
        assert_eq!(bar.position(), len, "{}", path.display());
        // Cleared: another load moves it no more.
        bar.set_position(0);
        assert!(load());
        assert_eq!(bar.position(), 0);
    }
}

/// A column of tiny or huge finite lengths keeps its length: the squares of 2.16e-243 underflow
/// to zero and those of 1e200 overflow, which gave a zero and an infinite spacing (found by
/// the `load_raw` fuzz target); ordinary columns keep `√(Σ a²)` exactly.
#[test]
fn space_spacing_survives_underflow_and_overflow() {
    use volsample_host::scene::load::{Space, SpaceSource};
    let s = Space::diagonal([2.16e-243, 1e200, 0.5], SpaceSource::Given);
    assert_eq!(s.spacing, [2.16e-243, 1e200, 0.5]);
    let mut a = [[0.0; 4]; 4];
    a[0][0] = 3e-200;
    a[1][0] = 4e-200;
    a[0][1] = 3.0;
    a[1][1] = 4.0;
    a[2][2] = 1.0;
    let s = Space::from_affine(a, SpaceSource::Given);
    // 5e-200 within an ulp or two; the normal column exactly 5.
    assert!(
        (s.spacing[0] / 5e-200 - 1.0).abs() < 1e-15,
        "{:?}",
        s.spacing
    );
    assert_eq!(s.spacing[1], 5.0);
    assert_eq!(s.spacing[2], 1.0);
}
