//! DICOM series against folders written by pydicom from numpy arrays
//! (`tests/data/formats/make_dicom_fixtures.py`). Each folder has a JSON file beside it with
//! the dimensions, sample type, values (x fastest) and RAS+ affine a correct loader must
//! return, the affine being the design the script derived the DICOM attributes from; or, for a
//! folder that must be refused, a piece of the error. Then refusals built here from those
//! files: lengths claiming more than the file holds, truncated files, the memory cap, an
//! empty folder, a single file given instead of its folder.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use volsample_host::scene::load::{
    read_dicom_series, read_volume, LoadedVolume, SpaceSource, DEFAULT_MEMORY_CAP,
};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/formats/dicom")
}

/// A fresh empty temporary folder.
fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir()
        .join(format!("volsample-dicom-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A copy of fixture folder `name` in a temporary folder; its files sorted by name.
fn copy_fixture(name: &str) -> (PathBuf, Vec<PathBuf>) {
    let d = tmp_dir(name);
    let mut files = Vec::new();
    for e in std::fs::read_dir(dir().join(name)).unwrap() {
        let p = e.unwrap().path();
        let to = d.join(p.file_name().unwrap());
        std::fs::copy(&p, &to).unwrap();
        if to.extension().is_some_and(|x| x == "dcm") {
            files.push(to);
        }
    }
    files.sort();
    (d, files)
}

/// Every fixture's JSON, sorted by name.
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

/// Checks a loaded volume against its fixture's JSON.
fn check(f: &Value, v: &LoadedVolume) {
    let name = f["dir"].as_str().unwrap();
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
    for (i, w) in want.iter().enumerate() {
        assert_eq!(
            v.data.get(i).unwrap(),
            w.as_f64().unwrap(),
            "{name}: value {i}"
        );
    }
    let affine: Vec<Vec<f64>> = f["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect();
    for (r, (row, want)) in v.space.affine.iter().zip(&affine).enumerate() {
        for (c, (got, w)) in row.iter().zip(want).enumerate() {
            // DS values carry 10 significant digits (the fixtures' `ds_str`).
            assert!(
                (got - w).abs() <= 1e-6,
                "{name}: affine[{r}][{c}] {got} vs {w}: {:?}",
                v.space.affine
            );
        }
    }
    for (c, s) in v.space.spacing.iter().enumerate() {
        let norm = (0..3)
            .map(|r| affine[r][c] * affine[r][c])
            .sum::<f64>()
            .sqrt();
        assert!((s - norm).abs() <= 1e-6, "{name}: spacing {c}");
    }
    assert_eq!(f["source"], "dicom-patient", "{name}");
    assert_eq!(v.space.source, SpaceSource::DicomPatient, "{name}");
}

#[test]
fn series_load_as_pydicom_wrote_them() {
    let mut loaded = Vec::new();
    let mut refused = 0;
    for f in fixtures() {
        let name = f["dir"].as_str().unwrap();
        let path = dir().join(name);
        let r = read_dicom_series(&path, None, DEFAULT_MEMORY_CAP);
        if let Some(want) = f.get("error") {
            let e = r.expect_err(name).to_string();
            assert!(
                e.contains(name) && e.contains(want.as_str().unwrap()) && !e.contains("panicked"),
                "{name}: {e}"
            );
            if let Some(file) = f.get("names") {
                assert!(e.contains(file.as_str().unwrap()), "{name}: {e}");
            }
            refused += 1;
            continue;
        }
        let v = r.unwrap_or_else(|e| panic!("{e}"));
        check(&f, &v);
        // The same through the format-sniffing reader, given the folder.
        assert_eq!(read_volume(&path, DEFAULT_MEMORY_CAP).unwrap(), v, "{name}");
        loaded.push(f["type"].as_str().unwrap().to_string());
    }
    loaded.sort();
    assert_eq!(
        loaded,
        ["f32", "i16", "i32", "u16", "u8"],
        "sample types loaded"
    );
    assert_eq!(refused, 7);
}

#[test]
fn non_dicom_files_and_dicomdir_are_skipped() {
    // The CT folder holds NOTES.txt and a DICOMDIR beside its five slices; loading it is
    // covered above. Without them, the same volume.
    let with = read_dicom_series(&dir().join("ct_i16_oblique"), None, DEFAULT_MEMORY_CAP).unwrap();
    let (d, _) = copy_fixture("ct_i16_oblique");
    std::fs::remove_file(d.join("NOTES.txt")).unwrap();
    std::fs::remove_file(d.join("DICOMDIR")).unwrap();
    assert_eq!(
        read_dicom_series(&d, None, DEFAULT_MEMORY_CAP).unwrap(),
        with
    );
    // A folder with only the text file has no image.
    let only = tmp_dir("only-text");
    std::fs::copy(
        dir().join("ct_i16_oblique/NOTES.txt"),
        only.join("NOTES.txt"),
    )
    .unwrap();
    let e = read_dicom_series(&only, None, DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no DICOM image files"), "{e}");
}

#[test]
fn slice_order_comes_from_positions_not_names() {
    // Renaming the files in reverse position order changes nothing.
    let want = read_dicom_series(&dir().join("ct_i16_oblique"), None, DEFAULT_MEMORY_CAP).unwrap();
    let (d, files) = copy_fixture("ct_i16_oblique");
    for (k, f) in files.iter().enumerate() {
        std::fs::rename(f, d.join(format!("{}.dcm", 9 - k))).unwrap();
    }
    assert_eq!(
        read_dicom_series(&d, None, DEFAULT_MEMORY_CAP).unwrap(),
        want
    );
}

#[test]
fn a_series_is_chosen_by_uid() {
    let path = dir().join("err_two_series");
    let e = read_dicom_series(&path, None, DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    // "…: 2 series in one folder: UID (N files), UID (M files); choose one …"
    let list = e
        .split_once("folder: ")
        .unwrap()
        .1
        .split_once(';')
        .unwrap()
        .0;
    let mut seen = Vec::new();
    for item in list.split(", ") {
        let (uid, count) = item.split_once(" (").unwrap();
        let n: usize = count.split_once(' ').unwrap().0.parse().unwrap();
        let v = read_dicom_series(&path, Some(uid), DEFAULT_MEMORY_CAP).unwrap();
        assert_eq!(v.dims, [3, 2, n], "{uid}");
        seen.push(n);
    }
    seen.sort();
    assert_eq!(seen, [1, 3]);
    let e = read_dicom_series(&path, Some("1.2.3"), DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no files of series 1.2.3; the folder holds"),
        "{e}"
    );
}

/// Byte offset of the first `pattern` in `bytes`.
fn find(bytes: &[u8], pattern: &[u8]) -> usize {
    bytes
        .windows(pattern.len())
        .position(|w| w == pattern)
        .unwrap()
}

#[test]
fn lengths_past_the_end_of_the_file_are_refused() {
    // (7FE0,0010) OW, reserved, then a 4-byte length (Explicit VR Little Endian).
    let pixel_data = [0xE0, 0x7F, 0x10, 0x00, b'O', b'W', 0, 0];
    // (0020,0032) DS ImagePositionPatient with a 2-byte length.
    let position = [0x20, 0x00, 0x32, 0x00, b'D', b'S'];
    for (what, want) in [
        ("pixel data", "element (7FE0,0010) at byte"),
        ("position", "element (0020,0032) at byte"),
        (
            "meta group length",
            "the file meta group claims to end at byte",
        ),
        ("truncated", "element (7FE0,0010) at byte"),
    ] {
        let (d, files) = copy_fixture("ct_i16_oblique");
        let victim = &files[2];
        let mut b = std::fs::read(victim).unwrap();
        match what {
            "pixel data" => {
                let at = find(&b, &pixel_data) + 8;
                b[at..at + 4].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
            }
            "position" => {
                let at = find(&b, &position) + 6;
                b[at..at + 2].copy_from_slice(&0xFFF0u16.to_le_bytes());
            }
            "meta group length" => {
                // (0002,0000) UL, 2-byte length 4, then the value.
                let at = find(&b, &[0x02, 0x00, 0x00, 0x00, b'U', b'L', 4, 0]) + 8;
                b[at..at + 4].copy_from_slice(&0x7FFF_FFF0u32.to_le_bytes());
            }
            _ => b.truncate(b.len() - 7),
        }
        std::fs::write(victim, &b).unwrap();
        let e = read_dicom_series(&d, None, DEFAULT_MEMORY_CAP)
            .unwrap_err()
            .to_string();
        let name = victim.file_name().unwrap().to_str().unwrap();
        assert!(e.contains(name) && e.contains(want), "{what}: {e}");
        if what != "meta group length" {
            assert!(e.contains("bytes, but the file has only"), "{what}: {e}");
        }
    }
}

#[test]
fn memory_cap_is_checked_before_reading() {
    // 6 × 4 × 5 i16 samples: 240 bytes.
    let path = dir().join("ct_i16_oblique");
    assert!(read_dicom_series(&path, None, 240).is_ok());
    let e = read_dicom_series(&path, None, 239).unwrap_err().to_string();
    assert!(
        e.contains("6×4×5") && e.contains("over the memory cap of 239 bytes"),
        "{e}"
    );
}

#[test]
fn a_single_file_or_a_missing_folder_is_refused() {
    let file = std::fs::read_dir(dir().join("cor_u8"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "dcm"))
        .unwrap();
    let e = read_volume(&file, DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("a DICOM file: give its folder"), "{e}");
    let e = read_dicom_series(&file, None, DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a folder"), "{e}");
    let e = read_dicom_series(&dir().join("absent"), None, DEFAULT_MEMORY_CAP)
        .unwrap_err()
        .to_string();
    assert!(e.contains("absent"), "{e}");
}

#[test]
fn render_a_dicom_folder() {
    let bin = env!("CARGO_BIN_EXE_volsample");
    let out = tmp_dir("render").join("ct.png");
    let path = dir().join("ct_i16_oblique");
    let o = Command::new(bin)
        .args([
            "render",
            "--quiet",
            "--size",
            "24",
            "--window",
            "-1000,1600",
            "--dicom",
        ])
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.width, 48, "two panels of 24 pixels");
    assert!(buf.iter().any(|&b| b > 0), "an all-black image");

    let two = dir().join("err_two_series");
    for (args, want) in [
        (
            vec!["--dicom", two.to_str().unwrap()],
            "2 series in one folder",
        ),
        (
            vec!["--dicom", two.to_str().unwrap(), "--dicom-series", "1.2.3"],
            "no files of series 1.2.3",
        ),
        (
            vec!["--dicom-series", "1.2.3"],
            "--dicom-series chooses a series of a --dicom folder",
        ),
        (
            vec!["--dicom", dir().join("err_jpeg").to_str().unwrap()],
            "JPEG Baseline (Process 1) (1.2.840.10008.1.2.4.50) is compressed",
        ),
    ] {
        let o = Command::new(bin)
            .args(["render", "--quiet", "--size", "8", "--out"])
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(want) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn corrupt_bytes_give_errors_not_panics() {
    // Every byte of one slice, in turn, inverted: the series loads or is refused, and each
    // refusal names a file or the folder.
    let (d, files) = copy_fixture("cor_u8");
    let victim = &files[1];
    let good = std::fs::read(victim).unwrap();
    let mut refused = 0;
    for at in 128..good.len() {
        let mut b = good.clone();
        b[at] ^= 0xFF;
        std::fs::write(victim, &b).unwrap();
        if let Err(e) = read_dicom_series(&d, None, DEFAULT_MEMORY_CAP) {
            assert!(e.to_string().contains("cor_u8"), "byte {at}: {e}");
            refused += 1;
        }
    }
    assert!(refused > 100, "{refused} refusals");
}
