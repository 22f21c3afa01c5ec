//! The `volsample` CLI's defects, each as a regression test: `--dims` forms, closed pipes,
//! huge sizes, output extensions, mode lists with spaces, unknown names, transfer-function
//! errors, panel labels, camera options, thread-count invariance.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_volsample"))
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("volsample-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Fails unless the command failed cleanly (exit 1, a message containing `want`, no panic).
fn fails_with(args: &[&str], want: &str) {
    let o = run(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
    assert!(e.contains(want) && !e.contains("panicked"), "{args:?}: {e}");
}

/// Width and height of a PNG, and its RGB bytes.
fn png(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// A 6³ raw u8 volume with a bright core.
fn raw_file() -> PathBuf {
    let p = dir().join("v.raw");
    let data: Vec<u8> = (0..216)
        .map(|i| {
            let (x, y, z) = (i % 6, i / 6 % 6, i / 36);
            if (1..5).contains(&x) && (1..5).contains(&y) && (1..5).contains(&z) {
                200
            } else {
                10
            }
        })
        .collect();
    std::fs::write(&p, data).unwrap();
    p
}

#[test]
fn dims_take_commas_or_spaces() {
    let raw = raw_file();
    let raw = raw.to_str().unwrap();
    let out = dir().join("dims.png");
    let out = out.to_str().unwrap();
    for dims in [vec!["6,6,6"], vec!["6", "6", "6"]] {
        let mut args = vec![
            "render", "--quiet", "--size", "8", "--raw", raw, "--out", out, "--dims",
        ];
        args.extend(dims.iter());
        let o = run(&args);
        assert!(o.status.success(), "{dims:?}: {}", stderr(&o));
    }
    fails_with(
        &["render", "--raw", raw, "--dims", "6,6", "--out", out],
        "--dims needs three values",
    );
    fails_with(
        &["render", "--raw", raw, "--out", out],
        "--raw needs --dims X,Y,Z",
    );
}

/// A command whose stdout is a pipe already closed by its reader ends with status 0 and no
/// message, as after `| head -1`.
#[test]
fn closed_stdout_ends_quietly() {
    let out = dir().join("pipe.png");
    for args in [
        vec!["scenes"],
        vec!["demo"],
        vec![
            "report",
            "--preset",
            "tiny",
            "--out",
            dir().join("rep").to_str().unwrap(),
        ],
        vec![
            "render",
            "--quiet",
            "--size",
            "8",
            "--out",
            out.to_str().unwrap(),
        ],
    ] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = bin()
            .args(&args)
            .stdout(Stdio::from(writer))
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
    }
    // The render still wrote its image before saying so.
    assert!(png(&out).0 > 0);
}

#[test]
fn sizes_are_bounded() {
    let out = dir().join("big.png");
    let out = out.to_str().unwrap();
    for size in ["100000", "4294967296", "18446744073709551615"] {
        fails_with(&["render", "--size", size, "--out", out], "pixels");
    }
    fails_with(&["render", "--size", "0", "--out", out], "pixels");
    fails_with(&["render", "--width", "0", "--out", out], "pixels");
}

#[test]
fn output_must_be_png() {
    for name in ["x.jpg", "x", "x.png.tmp"] {
        let out = dir().join(name);
        fails_with(
            &["render", "--out", out.to_str().unwrap()],
            "only PNG is written",
        );
        assert!(!out.exists(), "{name} written");
    }
}

#[test]
fn names_are_checked_and_listed() {
    let out = dir().join("names.png");
    let out = out.to_str().unwrap();
    let o = run(&[
        "render",
        "--quiet",
        "--size",
        "8",
        "--modes",
        "separate, opacity-weighted  extinction",
        "--out",
        out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(png(Path::new(out)).0, 24, "three panels of 8");
    fails_with(
        &["render", "--modes", "separate,foo", "--out", out],
        "unknown mode 'foo' (valid: separate, opacity-weighted, preweighted, preweighted-u8, extinction, post-classified)",
    );
    fails_with(
        &["render", "--filter", "cubic", "--out", out],
        "unknown filter 'cubic' (valid:",
    );
    fails_with(
        &["render", "--precision", "f16", "--out", out],
        "unknown precision 'f16' (valid:",
    );
    fails_with(
        &["render", "--scene", "nope", "--out", out],
        "unknown scene 'nope'",
    );
    fails_with(
        &[
            "render",
            "--precision",
            "int",
            "--modes",
            "extinction",
            "--out",
            out,
        ],
        "no integer kernel for extinction",
    );
}

#[test]
fn transfer_function_errors_name_the_point() {
    let raw = raw_file();
    let out = dir().join("tf.png");
    for (name, text, want) in [
        (
            "unsorted.txt",
            "0 1 1 1 0\n100 1 1 1 1\n50 1 1 1 1\n",
            "point 3 (s = 50)",
        ),
        (
            "range.txt",
            "0 1 1 1 0\n100 1 1.5 1 1\n",
            "point 2 (s = 100): green 1.5",
        ),
        (
            "opacity.txt",
            "0 1 1 1 -0.5\n",
            "point 1 (s = 0): opacity -0.5",
        ),
    ] {
        let tf = dir().join(name);
        std::fs::write(&tf, text).unwrap();
        fails_with(
            &[
                "render",
                "--raw",
                raw.to_str().unwrap(),
                "--dims",
                "6,6,6",
                "--tf",
                tf.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            want,
        );
    }
}

/// Every panel sits under a label bar; with the font installed the bar holds the label's
/// light pixels, without it the CLI says the labels were left out.
#[test]
fn panels_are_labelled() {
    let out = dir().join("labels.png");
    let o = run(&[
        "render",
        "--quiet",
        "--size",
        "40",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (w, h, rgb) = png(&out);
    let bar = volsample_host::images::LABEL_BAR;
    assert_eq!((w, h), (80, 40 + bar as u32));
    // Bright pixels in each panel's bar.
    for panel in 0..2 {
        let lit = (0..bar)
            .flat_map(|j| (0..40).map(move |i| 3 * (j * 80 + panel * 40 + i)))
            .filter(|&o| rgb[o] > 128)
            .count();
        if Path::new(volsample_host::plot::FONT).exists() {
            assert!(lit > 20, "panel {panel}: {lit} label pixels");
        } else {
            assert!(
                stderr(&o).contains("panel labels left out"),
                "{}",
                stderr(&o)
            );
        }
    }
}

#[test]
fn camera_options_and_threads() {
    let raw = raw_file();
    let raw = raw.to_str().unwrap();
    let mut images = Vec::new();
    for threads in ["1", "2", "3"] {
        let out = dir().join(format!("cam{threads}.png"));
        let o = run(&[
            "render",
            "--quiet",
            "--raw",
            raw,
            "--dims",
            "6,6,6",
            "--azimuth",
            "-30",
            "--elevation",
            "20",
            "--perspective",
            "35",
            "--zoom",
            "1.5",
            "--up",
            "0,0,1",
            "--width",
            "30",
            "--height",
            "20",
            "--background",
            "0.2,0.3,0.4",
            "--threads",
            threads,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (w, h, rgb) = png(&out);
        assert_eq!((w, h), (60, 20 + volsample_host::images::LABEL_BAR as u32));
        images.push(rgb);
    }
    assert!(
        images.iter().all(|i| *i == images[0]),
        "thread counts differ"
    );
    let out = dir().join("cam.png");
    let out = out.to_str().unwrap();
    fails_with(
        &["render", "--zoom", "0", "--out", out],
        "zoom must be positive",
    );
    fails_with(
        &["render", "--perspective", "180", "--out", out],
        "field of view",
    );
    fails_with(
        &["render", "--view-dir", "0,0,0", "--out", out],
        "view direction",
    );
    fails_with(
        &["render", "--background", "2,0,0", "--out", out],
        "--background",
    );
    fails_with(&["render", "--a-stop", "0", "--out", out], "--a-stop");
}
