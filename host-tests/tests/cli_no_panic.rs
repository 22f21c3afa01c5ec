//! Bad input to the `volsample` CLI ends in a clear error, never a panic (exit 101) or a
//! signal: closed stdout in a real shell pipeline, huge and zero sizes, overflowing products,
//! unwritable outputs and malformed or missing files for every loader. Driven through
//! `assert_cmd`, each with a time limit.

use std::path::PathBuf;
use std::time::Duration;

use assert_cmd::Command;

const BIN: &str = env!("CARGO_BIN_EXE_volsample");

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("volsample-no-panic-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn file(name: &str, bytes: &[u8]) -> String {
    let p = dir().join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_owned()
}

/// Runs the CLI; it must fail with exit 1 (our errors) or 2 (clap's), a message that
/// contains `want`, and no panic.
fn fails_cleanly(args: &[&str], want: &str) {
    let a = Command::new(BIN)
        .args(args)
        .timeout(Duration::from_secs(120))
        .assert()
        .failure();
    let o = a.get_output();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "{args:?}: status {:?}: {e}",
        o.status
    );
    assert!(!e.contains("panicked"), "{args:?}: {e}");
    assert!(e.contains(want), "{args:?}: want '{want}' in: {e}");
}

/// Runs `volsample ARGS | head -1` in bash with `pipefail` (so the status is the CLI's unless
/// it is 0): the CLI ends with status 0, prints no panic, and `head` got the first line.
fn piped_to_head(args: &str) {
    let script = format!("set -o pipefail; \"$0\" {args} | head -1");
    let a = Command::new("bash")
        .args(["-c", &script, BIN])
        .timeout(Duration::from_secs(600))
        .assert()
        .success();
    let o = a.get_output();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!e.contains("panicked"), "{args}: {e}");
    assert_eq!(
        String::from_utf8_lossy(&o.stdout).lines().count(),
        1,
        "{args}: head printed {:?}",
        String::from_utf8_lossy(&o.stdout)
    );
}

#[test]
fn closed_stdout_in_a_shell_pipeline() {
    let rep = dir().join("report");
    piped_to_head(&format!("report --preset tiny --out '{}'", rep.display()));
    piped_to_head("scenes");
    piped_to_head("demo");
    piped_to_head("filters --levels 3");
    let png = dir().join("head.png");
    piped_to_head(&format!("render --size 8 --out '{}'", png.display()));
}

#[test]
fn huge_and_zero_sizes() {
    let out = dir().join("s.png");
    let out = out.to_str().unwrap();
    for size in ["0", "100000", "4294967296", "18446744073709551615"] {
        fails_cleanly(&["render", "--size", size, "--out", out], "pixels");
    }
    fails_cleanly(
        &["render", "--size", "99999999999999999999999", "--out", out],
        "--size",
    );
    fails_cleanly(&["render", "--width", "0", "--out", out], "pixels");
    let nrrd = dir().join("p.nrrd");
    let nrrd = nrrd.to_str().unwrap();
    for size in ["0", "7", "1025", "18446744073709551615"] {
        fails_cleanly(&["phantom", "--size", size, "--out", nrrd], "--size");
    }
    let v = dir().join("v");
    let v = v.to_str().unwrap();
    fails_cleanly(
        &[
            "vectors",
            "--kernel",
            "composite-front-to-back",
            "--count",
            "18446744073709551615",
            "--out",
            v,
        ],
        "--count 18446744073709551615 is over the limit",
    );
    fails_cleanly(
        &[
            "vectors",
            "--kernel",
            "opacity-weighted-trilinear",
            "--frac-bits",
            "99",
            "--out",
            v,
        ],
        "frac",
    );
    fails_cleanly(
        &[
            "vectors",
            "--kernel",
            "extinction-weighted-nearest",
            "--table-size",
            "3",
            "--out",
            v,
        ],
        "table",
    );
}

#[test]
fn overflowing_products() {
    let raw = file("o.raw", &[0; 8]);
    let out = dir().join("o.png");
    let out = out.to_str().unwrap();
    for dims in [
        "4294967296,4294967296,2",
        "18446744073709551615,2,1",
        "2097152,2097152,2097152",
    ] {
        fails_cleanly(
            &[
                "render", "--raw", &raw, "--dims", dims, "--type", "u16", "--out", out,
            ],
            "o.raw",
        );
    }
    fails_cleanly(
        &[
            "render", "--raw", &raw, "--dims", "0,2,4", "--type", "u8", "--out", out,
        ],
        "zero",
    );
    // A NRRD header whose sizes multiply past every cap.
    let nrrd = file(
        "o.nrrd",
        b"NRRD0004\ntype: double\ndimension: 3\nsizes: 4294967296 4294967296 4294967296\nencoding: raw\n\n",
    );
    fails_cleanly(&["render", "--nrrd", &nrrd, "--out", out], "overflow");
}

#[test]
fn unwritable_outputs() {
    fails_cleanly(
        &["render", "--size", "8", "--out", "/nonexistent/x.png"],
        "/nonexistent/x.png",
    );
    fails_cleanly(
        &["phantom", "--size", "8", "--out", "/nonexistent/x.nrrd"],
        "/nonexistent/x.nrrd",
    );
    fails_cleanly(
        &[
            "vectors",
            "--kernel",
            "composite-front-to-back",
            "--count",
            "4",
            "--out",
            "/proc/v",
        ],
        "/proc/v",
    );
    // A regular file where the output folder should be.
    let f = file("not-a-dir", b"x");
    fails_cleanly(
        &[
            "vectors",
            "--kernel",
            "composite-front-to-back",
            "--count",
            "4",
            "--out",
            &f,
        ],
        "not-a-dir",
    );
}

#[test]
fn malformed_and_missing_files() {
    let out = dir().join("m.png");
    let out = out.to_str().unwrap();
    let junk = file("junk.bin", b"\x00\x01garbage\xff\xfe not any format\n");
    let empty = file("empty.bin", b"");
    let bad_nrrd = file(
        "bad.nrrd",
        b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n\nnot gzip",
    );
    let short_nrrd = file(
        "short.nrrd",
        b"NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n\x01\x02",
    );
    let gz_junk = file("junk.nii.gz", b"\x1f\x8b\x08\x00 broken gzip");
    let tiff_junk = file("junk.tif", b"II*\x00\xff\xff\xff\xff");
    let tf_junk = file("junk.tf", b"0 0 0 0\n1 2 3 4 5 6\n");
    let tf_json = file("junk.json", b"{\"points\": [[0, 0, 0, 0, \"a\"]]}");
    let dicom_empty = dir().join("empty-dicom");
    std::fs::create_dir_all(&dicom_empty).unwrap();
    let dicom_empty = dicom_empty.to_str().unwrap();
    for (flag, path) in [
        ("--nrrd", junk.as_str()),
        ("--nrrd", empty.as_str()),
        ("--nrrd", bad_nrrd.as_str()),
        ("--nrrd", short_nrrd.as_str()),
        ("--nrrd", "/nonexistent/v.nrrd"),
        ("--nifti", junk.as_str()),
        ("--nifti", empty.as_str()),
        ("--nifti", gz_junk.as_str()),
        ("--tiff", junk.as_str()),
        ("--tiff", tiff_junk.as_str()),
        ("--dicom", junk.as_str()),
        ("--dicom", dicom_empty),
        ("--dicom", "/nonexistent"),
    ] {
        let name = std::path::Path::new(path)
            .file_name()
            .unwrap()
            .to_str()
            .unwrap();
        fails_cleanly(&["render", flag, path, "--out", out], name);
    }
    // A transfer function applies to scalar volumes: a valid 2×2×2 raw one.
    let raw = file("ok.raw", &[0, 50, 100, 150, 200, 250, 30, 90]);
    for tf in [
        tf_junk.as_str(),
        tf_json.as_str(),
        empty.as_str(),
        "/nonexistent/t.tf",
    ] {
        let name = std::path::Path::new(tf)
            .file_name()
            .unwrap()
            .to_str()
            .unwrap();
        fails_cleanly(
            &[
                "render", "--raw", &raw, "--dims", "2,2,2", "--type", "u8", "--tf", tf, "--size",
                "8", "--out", out,
            ],
            name,
        );
    }
    // A raw file of the wrong size, and a folder given as a raw file.
    fails_cleanly(
        &[
            "render", "--raw", &junk, "--dims", "2,2,2", "--type", "u8", "--out", out,
        ],
        "junk.bin",
    );
    fails_cleanly(
        &[
            "render",
            "--raw",
            dicom_empty,
            "--dims",
            "2,2,2",
            "--type",
            "u8",
            "--out",
            out,
        ],
        "empty-dicom",
    );
}
