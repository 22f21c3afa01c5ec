//! `volsample vectors` (issue 7): the files round-trip through the reader back to the same
//! kernel results, the expected outputs agree bit for bit with the `f64` models in
//! `int_model`, the generator is deterministic, and bad arguments give clear errors.

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

use volsample::fixed_point::IntRatio;
use volsample_host::int_model::{self, composite, correction, downsample, round_half_up, sample};
use volsample_host::vectors::{
    self, build, corner_count, expected, generate, input_layout, output_layout, read, read_hex,
    write, Case, Kernel, Raw, SampleFilter, SampleMode, Spec, SplitMix64, VectorError,
    GENERATOR_VERSION,
};

/// A fresh scratch directory for one test (removed by [`Scratch::drop`]).
struct Scratch(PathBuf);
impl Scratch {
    fn new(name: &str) -> Self {
        let p =
            std::env::temp_dir().join(format!("volsample-vectors-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        Scratch(p)
    }
}
impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn spec(kernel: Kernel, count: usize, seed: u64, f: u32) -> Spec {
    Spec::new(kernel.name(), count, seed, f).unwrap()
}

#[test]
fn splitmix64_known_answers() {
    // The published SplitMix64 sequence for seed 0, so a reimplementation can check itself.
    let mut r = SplitMix64::new(0);
    assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
    assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
}

#[test]
fn files_round_trip_to_the_same_kernel_results() {
    for kernel in Kernel::ALL {
        for f in [4, 8, 12] {
            if f != 8 && !matches!(kernel, Kernel::Sample(..)) {
                continue;
            }
            let s = spec(kernel, 700, 11, f);
            let set = build(&s).unwrap();
            let dir = Scratch::new(&format!("rt-{}-{f}", kernel.name()));
            write(&set, &dir.0).unwrap();
            let back = read(&dir.0).unwrap();
            assert_eq!(back.spec, s, "{}", kernel.name());
            assert_eq!(back.cases, generate(&s), "{}", kernel.name());
            assert_eq!(back.expected, set.expected, "{}", kernel.name());
            for (case, &e) in back.cases.iter().zip(&back.expected) {
                assert_eq!(
                    expected(&s, case).unwrap(),
                    e,
                    "{}: {case:?}",
                    kernel.name()
                );
            }
            // The correction's ratio_raw field is the core's IntRatio of the f32 ratio.
            if kernel == Kernel::Correction {
                let l = input_layout(&s);
                let words = read_hex(&dir.0.join(vectors::INPUTS_FILE), &l).unwrap();
                for (w, c) in words.iter().zip(&back.cases) {
                    let Case::Correction { ratio, .. } = c else {
                        panic!("not a correction case")
                    };
                    assert_eq!(l.unpack(w)[4], IntRatio::new(*ratio).unwrap().raw());
                }
            }
        }
    }
}

#[test]
fn manifest_describes_the_files() {
    for kernel in Kernel::ALL {
        let s = spec(kernel, 100, 5, 8);
        let dir = Scratch::new(&format!("manifest-{}", kernel.name()));
        write(&build(&s).unwrap(), &dir.0).unwrap();
        let text = std::fs::read_to_string(dir.0.join(vectors::MANIFEST_FILE)).unwrap();
        let m: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(m["kernel"], kernel.name());
        assert_eq!(m["count"], 100);
        assert_eq!(m["seed"], 5);
        assert_eq!(m["generator"]["version"], GENERATOR_VERSION);
        assert!(m["generator"]["prng"]
            .as_str()
            .unwrap()
            .starts_with("SplitMix64"));
        assert!(text.contains("round half up"));
        for (key, layout) in [
            ("inputs", input_layout(&s)),
            ("expected", output_layout(&s)),
        ] {
            let fields = m[key]["fields"].as_array().unwrap();
            assert_eq!(fields.len(), layout.fields.len());
            // Contiguous from bit 0, and the word width is the sum of the field widths.
            let mut next = 0;
            for (j, f) in fields.iter().zip(&layout.fields) {
                assert_eq!(j["offset"], next);
                assert_eq!(j["offset"], f.offset);
                assert_eq!(j["width"], f.width);
                assert_eq!(j["frac_bits"], f.frac_bits);
                next += f.width;
            }
            assert_eq!(m[key]["word_bits"], next);
            // Every line has exactly hex_digits digits.
            let digits = m[key]["hex_digits"].as_u64().unwrap() as usize;
            let file = dir.0.join(m[key]["file"].as_str().unwrap());
            let body = std::fs::read_to_string(file).unwrap();
            assert_eq!(body.lines().count(), 100);
            assert!(body
                .lines()
                .all(|l| l.len() == digits && l.chars().all(|c| c.is_ascii_hexdigit())));
        }
        if kernel == Kernel::Correction {
            for t in m["tables"].as_array().unwrap() {
                let body =
                    std::fs::read_to_string(dir.0.join(t["file"].as_str().unwrap())).unwrap();
                assert_eq!(body.lines().count() as u64, t["entries"].as_u64().unwrap());
            }
        }
    }
}

/// The corner cases the issue asks for are present, and come first.
#[test]
fn corner_cases_come_first_and_cover_the_extremes() {
    let s = spec(
        Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Trilinear),
        10_000,
        1,
        8,
    );
    let cases = generate(&s);
    let corners = &cases[..corner_count(&s)];
    type Pred<'a> = &'a dyn Fn(&[[u8; 4]; 8], [u32; 3]) -> bool;
    let has = |p: Pred| {
        corners.iter().any(|c| match c {
            Case::Sample { voxels, frac } => p(voxels, *frac),
            _ => false,
        })
    };
    let all_equal = |v: &[[u8; 4]; 8]| v.iter().all(|x| *x == v[0]);
    assert!(has(&|v, _| all_equal(v) && v[0][3] == 0));
    assert!(has(&|v, _| all_equal(v) && v[0][3] == 255));
    assert!(has(&|v, _| all_equal(v) && v[0][3] == 1));
    assert!(has(&|v, _| v.iter().flatten().all(|&b| b == 255))); // saturating
    assert!(has(&|_, f| f == [0, 0, 0])); // weight 2^3F at corner 0, 0 elsewhere
    assert!(has(&|_, f| f == [255, 255, 255])); // largest weight on corner 7
                                                // A count below the number of corners keeps the first corners.
    let few = spec(Kernel::Composite, 3, 9, 8);
    assert_eq!(
        generate(&few),
        generate(&spec(Kernel::Composite, 100, 1, 8))[..3]
    );
}

fn model_sample(mode: SampleMode, filter: SampleFilter, f: u32, c: &Case) -> Raw {
    let Case::Sample { voxels, frac } = c else {
        panic!("not a sample case")
    };
    let (taps, w): (Vec<[u8; 4]>, Vec<f64>) = match filter {
        SampleFilter::Trilinear => (
            voxels.to_vec(),
            int_model::trilinear_weights(f, *frac).to_vec(),
        ),
        SampleFilter::Nearest => {
            let h = 1 << (f - 1);
            let sel = usize::from(frac[0] >= h)
                | usize::from(frac[1] >= h) << 1
                | usize::from(frac[2] >= h) << 2;
            (vec![voxels[sel]], vec![1.0])
        }
    };
    let m = match mode {
        SampleMode::OpacityWeighted => sample::opacity_weighted(&taps, &w),
        SampleMode::Separate => sample::separate(&taps, &w),
        SampleMode::Preweighted => sample::preweighted(&taps, &w),
    };
    [m.c[0], m.c[1], m.c[2], m.a]
}

/// One step of the model compositor (`int_model::composite::front_to_back` from an arbitrary
/// accumulator): `x + ⌊T·x_s/ONE + ½⌋`, `T = ONE − A`.
fn model_step(acc: Raw, s: Raw) -> Raw {
    let t = int_model::ONE - f64::from(acc[3]);
    std::array::from_fn(|k| {
        int_model::to_u16(f64::from(acc[k]) + round_half_up(t * f64::from(s[k]) / int_model::ONE))
    })
}

#[test]
fn expected_outputs_match_the_f64_models() {
    let mut corr_tables: HashMap<u32, correction::CorrTables> = HashMap::new();
    for kernel in Kernel::ALL {
        for f in [4, 8, 12] {
            if f != 8 && !matches!(kernel, Kernel::Sample(..)) {
                continue;
            }
            let n = if kernel == Kernel::Correction {
                1500
            } else {
                4000
            };
            let s = spec(kernel, n, 0xC0FFEE + u64::from(f), f);
            let set = build(&s).unwrap();
            for (c, &e) in set.cases.iter().zip(&set.expected) {
                let model = match (kernel, c) {
                    (Kernel::Sample(mode, filter), _) => model_sample(mode, filter, f, c),
                    (Kernel::Composite, Case::Composite { acc, s }) => {
                        let m = model_step(*acc, *s);
                        if *acc == [0; 4] {
                            assert_eq!(composite::front_to_back(&[*s], u16::MAX).0, m);
                        }
                        m
                    }
                    (Kernel::Downsample, Case::Downsample { taps, a_raw }) => {
                        // The model's direct 64-tap sums over the same 6×6×6 embedding.
                        let mut vol = vec![[0u64; 4]; 216];
                        for (t, v) in taps.iter().enumerate() {
                            let (i, j, k) = (t % 4, (t / 4) % 4, t / 16);
                            vol[(1 + i) + 6 * ((1 + j) + 6 * (1 + k))] = v.map(u64::from);
                        }
                        let (_, out) = downsample::opacity_level([6, 6, 6], &vol, *a_raw, 255);
                        out[13].raw.map(|x| u16::try_from(x).unwrap())
                    }
                    (Kernel::Correction, Case::Correction { ratio, s }) => {
                        let t = corr_tables
                            .entry(ratio.to_bits())
                            .or_insert_with(|| correction::tables(*ratio));
                        let (c, a) = t.apply([s[0], s[1], s[2]], s[3]);
                        [c[0], c[1], c[2], a]
                    }
                    _ => unreachable!(),
                };
                assert_eq!(e, model, "{} F={f}: {c:?}", kernel.name());
                // Every output keeps C̃ ≤ α ≤ full scale.
                let full = if kernel == Kernel::Downsample {
                    255
                } else {
                    volsample::fixed_point::ONE
                };
                assert!(e[3] <= full && e[..3].iter().all(|&x| x <= e[3]));
            }
        }
    }
}

#[test]
fn same_seed_same_bytes_different_seed_different_bytes() {
    for kernel in Kernel::ALL {
        let files = |seed: u64, tag: &str| {
            let s = spec(kernel, 300, seed, 8);
            let dir = Scratch::new(&format!("det-{}-{tag}", kernel.name()));
            write(&build(&s).unwrap(), &dir.0).unwrap();
            let read = |f: &str| std::fs::read(dir.0.join(f)).unwrap();
            (
                read(vectors::INPUTS_FILE),
                read(vectors::EXPECTED_FILE),
                read(vectors::MANIFEST_FILE),
            )
        };
        let a = files(42, "a");
        let b = files(42, "b");
        let c = files(43, "c");
        assert_eq!(a, b, "{}: same seed, different bytes", kernel.name());
        assert_ne!(a.0, c.0, "{}: different seeds, same inputs", kernel.name());
        assert_ne!(a.2, c.2, "{}: the manifest records the seed", kernel.name());
        // The corner cases are the same for every seed.
        let n = corner_count(&spec(kernel, 300, 42, 8));
        let lines = |v: &[u8]| {
            String::from_utf8(v.to_vec())
                .unwrap()
                .lines()
                .take(n)
                .map(String::from)
                .collect::<Vec<_>>()
        };
        assert_eq!(lines(&a.0), lines(&c.0));
    }
}

#[test]
fn bad_arguments_are_clear_errors() {
    let e = Spec::new("opacity-weighted-cubic", 10, 1, 8).unwrap_err();
    assert!(matches!(e, VectorError::UnknownKernel(_)));
    let msg = e.to_string();
    assert!(
        msg.contains("opacity-weighted-cubic") && msg.contains("composite-front-to-back"),
        "{msg}"
    );
    let e = Spec::new("separate-nearest", 0, 1, 8).unwrap_err();
    assert!(matches!(e, VectorError::ZeroCount));
    assert!(e.to_string().contains("--count"));
    for f in [0, 3, 13, 64] {
        assert!(matches!(
            Spec::new("separate-nearest", 1, 1, f),
            Err(VectorError::FracBits(_))
        ));
    }
    // An output path below a regular file cannot be created, even as root.
    let dir = Scratch::new("unwritable");
    std::fs::create_dir_all(&dir.0).unwrap();
    let file = dir.0.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let set = build(&spec(Kernel::Composite, 5, 1, 8)).unwrap();
    let e = write(&set, &file.join("out")).unwrap_err();
    assert!(matches!(e, VectorError::Write { .. }));
    assert!(e.to_string().contains("a-file"), "{e}");
    // A malformed file is a parse error naming the line.
    let s = spec(Kernel::Composite, 5, 1, 8);
    write(&build(&s).unwrap(), &dir.0.join("ok")).unwrap();
    let p = dir.0.join("ok").join(vectors::EXPECTED_FILE);
    std::fs::write(&p, "0000000000000000\n123\n").unwrap();
    let e = read_hex(&p, &output_layout(&s)).unwrap_err();
    assert!(e.to_string().contains("line 2"), "{e}");
    // A short file disagrees with the manifest.
    std::fs::write(&p, "0000000000000000\n").unwrap();
    assert!(read(&dir.0.join("ok")).is_err());
}

#[test]
fn cli_reports_bad_arguments_without_panicking() {
    let dir = Scratch::new("cli");
    std::fs::create_dir_all(&dir.0).unwrap();
    let file = dir.0.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let out = file.join("sub");
    let cases: [(&[&str], &str); 5] = [
        (&["--kernel", "nope"], "unknown kernel 'nope'"),
        (
            &["--kernel", "separate-nearest", "--count", "0"],
            "--count must be at least 1",
        ),
        (
            &["--kernel", "separate-nearest", "--frac-bits", "13"],
            "outside 4..=12",
        ),
        (&["--kernel", "separate-nearest", "--count=-3"], "--count"),
        (&["--kernel", "separate-nearest", "--seed", "x"], "--seed"),
    ];
    let bin = env!("CARGO_BIN_EXE_volsample");
    for (args, want) in cases {
        let o = Command::new(bin)
            .arg("vectors")
            .args(args)
            .arg("--out")
            .arg(dir.0.join("never"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let o = Command::new(bin)
        .args([
            "vectors",
            "--kernel",
            "composite-front-to-back",
            "--count",
            "3",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("cannot write") && err.contains("a-file"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    // And a good request succeeds and writes the three files.
    let good = dir.0.join("good");
    let o = Command::new(bin)
        .args([
            "vectors",
            "--kernel",
            "opacity-weighted-trilinear",
            "--count",
            "60",
            "--seed",
            "2",
            "--out",
        ])
        .arg(&good)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&good).unwrap().cases.len(), 60);
}

/// The RTL divides by 255 as `(x·16843010) >> 32` (`host-tests/rtl/vs_div255.v`); its
/// callers keep `x < 2^24`. Exhaustive over that domain.
#[test]
fn rtl_div255_multiply_shift_is_exact_below_2_pow_24() {
    const MAGIC: u64 = 16_843_010; // ⌈2^32/255⌉
    assert_eq!(MAGIC, (1u64 << 32).div_ceil(255));
    for x in 0..1u64 << 24 {
        assert_eq!((x * MAGIC) >> 32, x / 255, "x = {x}");
    }
}
