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
    fails_with(
        &["render", "--threads", "100000", "--out", out],
        "at most 1024",
    );
}

/// Writes an attached raw NRRD of bytes with the given space and direction lines.
fn nrrd(
    name: &str,
    dims: [usize; 3],
    space: &str,
    dirs: &str,
    origin: &str,
    data: &[u8],
) -> PathBuf {
    let p = dir().join(name);
    let mut bytes = format!(
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: {} {} {}\nencoding: raw\nspace: {space}\nspace directions: {dirs}\nspace origin: {origin}\n\n",
        dims[0], dims[1], dims[2]
    )
    .into_bytes();
    bytes.extend_from_slice(data);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// The byte of an asymmetric object at a RAS point (mm): bright blobs at the patient's
/// right (+x), anterior (+y) and superior (+z), of different values.
fn asymmetric(p: [f64; 3]) -> u8 {
    let blob = |c: [f64; 3], r: f64| (0..3).map(|k| (p[k] - c[k]).powi(2)).sum::<f64>() < r * r;
    if blob([6.0, 0.0, 0.0], 3.0) {
        250
    } else if blob([0.0, 6.0, 0.0], 2.5) {
        170
    } else if blob([0.0, 0.0, 6.0], 2.0) {
        90
    } else {
        0
    }
}

/// One asymmetric object saved as RAS, as LPS (x and y flipped) and with permuted axes
/// renders to the same image (within 2 levels: only the rounding of positions differs), and
/// its right side is on the image's left in the default anterior view.
#[test]
fn orientation_is_honoured() {
    let n = 17;
    let o = -8.0;
    let sample = |f: &dyn Fn(usize, usize, usize) -> [f64; 3]| {
        let mut v = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    v.push(asymmetric(f(i, j, k)));
                }
            }
        }
        v
    };
    let (i, j, k) = (
        |x: usize| x as f64,
        |x: usize| x as f64,
        |x: usize| x as f64,
    );
    let ras = nrrd(
        "ras.nrrd",
        [n; 3],
        "right-anterior-superior",
        "(1,0,0) (0,1,0) (0,0,1)",
        "(-8,-8,-8)",
        &sample(&|a, b, c| [o + i(a), o + j(b), o + k(c)]),
    );
    // LPS: index i runs towards the left (x_RAS = 8 − i), j towards posterior.
    let lps = nrrd(
        "lps.nrrd",
        [n; 3],
        "left-posterior-superior",
        "(1,0,0) (0,1,0) (0,0,1)",
        "(-8,-8,-8)",
        &sample(&|a, b, c| [-o - i(a), -o - j(b), o + k(c)]),
    );
    // RAS with permuted axes: index i along z, j along x, k along y.
    let permuted = nrrd(
        "permuted.nrrd",
        [n; 3],
        "right-anterior-superior",
        "(0,0,1) (1,0,0) (0,1,0)",
        "(-8,-8,-8)",
        &sample(&|a, b, c| [o + j(b), o + k(c), o + i(a)]),
    );
    let tf = dir().join("orient.tf.txt");
    std::fs::write(
        &tf,
        "0 0 0 0 0\n80 0 0 1 1\n160 0 1 0 1\n240 1 0 0 1\n255 1 0 0 1\n",
    )
    .unwrap();
    let mut images = Vec::new();
    for (name, file) in [("ras", &ras), ("lps", &lps), ("perm", &permuted)] {
        for azimuth in ["0", "40"] {
            let out = dir().join(format!("orient-{name}-{azimuth}.png"));
            let o = run(&[
                "render",
                "--quiet",
                "--nrrd",
                file.to_str().unwrap(),
                "--tf",
                tf.to_str().unwrap(),
                "--modes",
                "opacity-weighted",
                "--size",
                "48",
                "--azimuth",
                azimuth,
                "--a-stop",
                "1",
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{name}: {}", stderr(&o));
            images.push((name, azimuth, png(&out).2));
        }
    }
    let bar = volsample_host::images::LABEL_BAR;
    for (name, azimuth, img) in &images[2..] {
        let base = &images[usize::from(*azimuth == "40")].2;
        let worst = img
            .iter()
            .zip(base)
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap();
        assert!(worst <= 2, "{name} at azimuth {azimuth}: {worst} levels");
    }
    // Anterior view: the red (right) blob in the image's left half, below the label bar.
    let front = &images[0].2;
    let red = |left: bool| {
        (bar..bar + 48)
            .flat_map(|y| (0..48).map(move |x| (x, y)))
            .filter(|&(x, _)| (x < 24) == left)
            .map(|(x, y)| u32::from(front[3 * (y * 48 + x)]))
            .sum::<u32>()
    };
    assert!(
        red(true) > 10 * red(false).max(1),
        "{} vs {}",
        red(true),
        red(false)
    );
}
