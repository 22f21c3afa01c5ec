//! `volsample vectors` (issue 7): the files round-trip through the reader back to the same
//! kernel results, the expected outputs agree bit for bit with the `f64` models in
//! `int_model`, the generator is deterministic, and bad arguments give clear errors.

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::Command;

use volsample::fixed_point::{ExtinctionFx, IntPos, IntRatio, IntStop, ONE};
use volsample::render::IntRayMarcher;
use volsample::{Camera, OpacityWeighted, Perspective, Step, StraightU8, Trilinear, Volume};
use volsample_host::int_model::extinction as ext_model;
use volsample_host::int_model::{self, composite, correction, downsample, round_half_up, sample};
use volsample_host::vectors::{
    self, build, corner_cases, corner_count, expected, expected_counted, extinction_tables,
    generate, input_layout, output_layout, ray_positions, read, read_hex, write, Case, Kernel, Raw,
    SampleFilter, SampleMode, Spec, SplitMix64, VectorError, GENERATOR_VERSION, RAY_MAX_SAMPLES,
    TABLE_SIZES,
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

/// The kernels whose inputs hold `F`-bit positions.
fn positional(kernel: Kernel) -> bool {
    matches!(
        kernel,
        Kernel::Sample(..) | Kernel::Extinction(_) | Kernel::RayMarch(_)
    )
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
            if f != 8 && !positional(kernel) {
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
            assert_eq!(back.samples_taken, set.samples_taken, "{}", kernel.name());
            let counted = matches!(kernel, Kernel::RayMarch(_));
            assert_eq!(back.samples_taken.len(), if counted { 700 } else { 0 });
            for (i, (case, &e)) in back.cases.iter().zip(&back.expected).enumerate() {
                assert_eq!(
                    expected(&s, case).unwrap(),
                    e,
                    "{}: {case:?}",
                    kernel.name()
                );
                let n = expected_counted(&s, case).unwrap().1;
                assert_eq!(n, back.samples_taken.get(i).copied(), "{}", kernel.name());
            }
            // The ratio_raw field is the core's IntRatio of the f32 ratio.
            let l = input_layout(&s);
            if let Some(at) = l.fields.iter().position(|f| f.name == "ratio_raw") {
                let words = read_hex(&dir.0.join(vectors::INPUTS_FILE), &l).unwrap();
                for (w, c) in words.iter().zip(&back.cases) {
                    let ratio = match c {
                        Case::Correction { ratio, .. }
                        | Case::Extinction { ratio, .. }
                        | Case::RayMarch { ratio, .. } => *ratio,
                        _ => panic!("{}: a ratio field but no ratio", kernel.name()),
                    };
                    assert_eq!(l.unpack(w)[at], IntRatio::new(ratio).unwrap().raw());
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
        // The kernels that read tables ship them, one entry per line of the stated width.
        let has_tables = matches!(
            kernel,
            Kernel::Correction | Kernel::Extinction(_) | Kernel::RayMarch(_)
        );
        assert_eq!(m.get("tables").is_some(), has_tables, "{}", kernel.name());
        for t in m["tables"].as_array().into_iter().flatten() {
            let body = std::fs::read_to_string(dir.0.join(t["file"].as_str().unwrap())).unwrap();
            assert_eq!(body.lines().count() as u64, t["entries"].as_u64().unwrap());
            let digits = t["hex_digits"].as_u64().unwrap() as usize;
            assert!(body.lines().all(|l| l.len() == digits));
            assert!(t["meaning"].as_str().unwrap().contains("½⌋"));
        }
        if kernel.has_table_size() {
            assert_eq!(m["table_size"], 257);
            assert_eq!(m["tables"][0]["entries"], 257);
        } else {
            assert!(m.get("table_size").is_none());
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

/// The `u128` model of the extinction kernel (`int_model::extinction`) on one case.
fn model_extinction(filter: SampleFilter, f: u32, c: &Case, t: &ext_model::Tables) -> Raw {
    let Case::Extinction {
        voxels,
        frac,
        ratio,
    } = c
    else {
        panic!("not an extinction case")
    };
    let taps: Vec<(u32, [u32; 3])> = voxels.iter().map(|v| (v.tau, v.c_tau)).collect();
    let r = ext_model::ratio_raw(*ratio);
    let (c, a) = match filter {
        SampleFilter::Trilinear => {
            ext_model::kernel(&taps, &ext_model::int_weights(f, *frac), 3 * f, r, t)
        }
        SampleFilter::Nearest => {
            let h = 1 << (f - 1);
            let sel = usize::from(frac[0] >= h)
                | usize::from(frac[1] >= h) << 1
                | usize::from(frac[2] >= h) << 2;
            ext_model::kernel(&taps[sel..=sel], &[1], 0, r, t)
        }
    };
    [c[0], c[1], c[2], a]
}

/// The model of one ray: the positions `p + k·Δ`, the `f64` sample model at each (taps
/// clamped to the 4×4×4 volume), the model correction when the ratio is not 1, the model
/// compositor with its stop, then one model step over the background.
fn model_ray(
    filter: SampleFilter,
    f: u32,
    c: &Case,
    corr: &mut HashMap<u32, correction::CorrTables>,
) -> (Raw, u32) {
    let Case::RayMarch {
        voxels,
        start,
        step,
        samples,
        ratio,
        a_stop,
        background,
    } = c
    else {
        panic!("not a ray-march case")
    };
    let at = |x: u32, y: u32, z: u32| voxels[(x.min(3) + 4 * y.min(3) + 16 * z.min(3)) as usize];
    let mut out = Vec::new();
    for k in 0..i64::from(*samples) {
        let p: [u32; 3] =
            std::array::from_fn(|a| (i64::from(start[a]) + k * i64::from(step[a])) as u32);
        let (taps, w): (Vec<[u8; 4]>, Vec<f64>) = match filter {
            SampleFilter::Trilinear => {
                let i = p.map(|x| x >> f);
                let fr = p.map(|x| x & ((1 << f) - 1));
                let taps = (0..8)
                    .map(|t| at(i[0] + (t & 1), i[1] + ((t >> 1) & 1), i[2] + (t >> 2)))
                    .collect();
                (taps, int_model::trilinear_weights(f, fr).to_vec())
            }
            SampleFilter::Nearest => {
                let i = p.map(|x| (x + (1 << (f - 1))) >> f);
                (vec![at(i[0], i[1], i[2])], vec![1.0])
            }
        };
        let m = sample::opacity_weighted(&taps, &w);
        let mut s = [m.c[0], m.c[1], m.c[2], m.a];
        if *ratio != 1.0 {
            let t = corr
                .entry(ratio.to_bits())
                .or_insert_with(|| correction::tables(*ratio));
            let (c, a) = t.apply([s[0], s[1], s[2]], s[3]);
            s = [c[0], c[1], c[2], a];
        }
        out.push(s);
    }
    let (acc, used) = composite::front_to_back(&out, *a_stop);
    (model_step(acc, *background), used as u32)
}

#[test]
fn expected_outputs_match_the_f64_models() {
    let mut corr_tables: HashMap<u32, correction::CorrTables> = HashMap::new();
    let ext_tables = ext_model::tables(257);
    for kernel in Kernel::ALL {
        for f in [4, 8, 12] {
            if f != 8 && !positional(kernel) {
                continue;
            }
            let n = match kernel {
                Kernel::Correction => 1500,
                Kernel::RayMarch(_) => 1200,
                _ => 4000,
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
                    (Kernel::Extinction(filter), _) => model_extinction(filter, f, c, &ext_tables),
                    (Kernel::RayMarch(filter), _) => {
                        let (m, used) = model_ray(filter, f, c, &mut corr_tables);
                        let taken = expected_counted(&s, c).unwrap().1;
                        assert_eq!(taken, Some(used), "{} F={f}: {c:?}", kernel.name());
                        m
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
    // Table sizes: only the supported ones, only for the extinction kernels.
    let ext = spec(Kernel::Extinction(SampleFilter::Trilinear), 10, 1, 8);
    for n in [0, 3, 256, 258, 65537] {
        let e = ext.with_table_size(n).unwrap_err();
        assert!(matches!(e, VectorError::TableSize(m) if m == n), "{e}");
        assert!(e.to_string().contains("--table-size") && e.to_string().contains("4097"));
    }
    for n in TABLE_SIZES {
        assert_eq!(ext.with_table_size(n).unwrap().table_size(), n);
    }
    let e = spec(Kernel::Composite, 10, 1, 8)
        .with_table_size(257)
        .unwrap_err();
    assert!(matches!(e, VectorError::TableSizeNotApplicable(_)));
    assert!(e.to_string().contains("composite-front-to-back"), "{e}");
    // A case the kernel cannot take is an error, not a panic.
    let ray = |start: [u32; 3], step: [i32; 3], samples: u32, a_stop: u16| Case::RayMarch {
        voxels: [[9, 9, 9, 9]; 64],
        start,
        step,
        samples,
        ratio: 1.0,
        a_stop,
        background: [0; 4],
    };
    let rs = spec(Kernel::RayMarch(SampleFilter::Trilinear), 1, 1, 8);
    let bad = [
        ray([10, 0, 0], [-4, 0, 0], 4, ONE), // p_3 = −2
        ray([0; 3], [0; 3], RAY_MAX_SAMPLES + 1, ONE),
    ];
    for c in bad {
        let e = expected(&rs, &c).unwrap_err();
        assert!(matches!(e, VectorError::InvalidCase(_)), "{e}");
    }
    assert!(matches!(
        expected(&rs, &ray([0; 3], [0; 3], 1, 0)),
        Err(VectorError::Core(volsample::Error::InvalidThreshold))
    ));
    let fx = ExtinctionFx {
        tau: 5,
        c_tau: [6, 0, 0],
    };
    let c = Case::Extinction {
        voxels: [fx; 8],
        frac: [0; 3],
        ratio: 1.0,
    };
    assert!(matches!(expected(&ext, &c), Err(VectorError::Core(_))));
    let e = expected(&ext, &ray([0; 3], [0; 3], 1, ONE)).unwrap_err();
    assert!(
        e.to_string().contains("extinction-weighted-trilinear"),
        "{e}"
    );
}

/// The extinction corner cases hold the extremes, and their outputs are the known values.
#[test]
fn extinction_corner_cases_cover_the_extremes() {
    for filter in [SampleFilter::Nearest, SampleFilter::Trilinear] {
        let s = spec(Kernel::Extinction(filter), 1000, 3, 8);
        let set = build(&s).unwrap();
        let n = corner_count(&s);
        assert_eq!(set.cases[..n], corner_cases(&s)[..]);
        let corners: Vec<_> = set.cases[..n].iter().zip(&set.expected[..n]).collect();
        let find = |p: &dyn Fn(&[ExtinctionFx; 8], f32) -> bool| {
            corners
                .iter()
                .filter(|(c, _)| match c {
                    Case::Extinction { voxels, ratio, .. } => p(voxels, *ratio),
                    _ => false,
                })
                .map(|(_, e)| **e)
                .collect::<Vec<Raw>>()
        };
        let equal = |v: &[ExtinctionFx; 8]| v.iter().all(|x| *x == v[0]);
        let max = volsample::fixed_point::extinction::MAX_DEPTH_RAW;
        // α = 0 everywhere: nothing, at every ratio.
        let zero = find(&|v, _| equal(v) && v[0].tau == 0);
        assert!(!zero.is_empty() && zero.iter().all(|e| *e == [0; 4]));
        // α = 255 everywhere (depth capped at 64), white: opaque white at r = 1.
        let opaque = find(&|v, r| {
            equal(v) && v[0] == ExtinctionFx::from_straight_u8(StraightU8([255; 4])) && r == 1.0
        });
        assert!(!opaque.is_empty() && opaque.iter().all(|e| *e == [ONE; 4]));
        assert_eq!(
            ExtinctionFx::from_straight_u8(StraightU8([255; 4])).tau,
            max
        );
        // α_F = 1, all equal: the exact 1/255 at r = 1 (D·φ(D)·... = α).
        let faint = find(&|v, r| {
            equal(v)
                && v[0] == ExtinctionFx::from_straight_u8(StraightU8([255, 128, 0, 1]))
                && r == 1.0
        });
        assert!(!faint.is_empty() && faint.iter().all(|e| e[3] == 256 && e[0] == 256));
        // The φ/e^(−x) split at x = 1 and the saturation at x = 16 are both hit exactly.
        assert!(
            !find(&|v, r| equal(v) && u64::from(v[0].tau) * (r as u64) == 1 << 20 && r == 1.0)
                .is_empty()
        );
        assert!(!find(&|v, r| equal(v) && v[0].tau == (1 << 20) - 1 && r == 1.0).is_empty());
        assert!(!find(&|v, r| equal(v) && v[0].tau == 16 << 20 && r == 1.0).is_empty());
        assert!(!find(&|v, _| equal(v) && v[0].tau == max && v[0].c_tau[0] == max).is_empty());
        // Ratios other than 1, tiny and huge.
        for r in [1.0 / 1_073_741_824.0, 1.0 / 4096.0, 1024.0] {
            assert!(!find(&|_, x| x == r).is_empty(), "ratio {r}");
        }
        // Every output keeps C̃ ≤ α ≤ ONE.
        assert!(set
            .expected
            .iter()
            .all(|e| e[3] <= ONE && e[..3].iter().all(|&c| c <= e[3])));
    }
}

/// The ray-march corner cases hold the extremes the issue names, with their known outputs.
#[test]
fn ray_march_corner_cases_cover_the_extremes() {
    for filter in [SampleFilter::Nearest, SampleFilter::Trilinear] {
        for f in [4, 8, 12] {
            let s = spec(Kernel::RayMarch(filter), 500, 3, f);
            let set = build(&s).unwrap();
            let n = corner_count(&s);
            assert!(n >= 200, "{n} corners");
            let corners: Vec<_> = (0..n)
                .map(|i| (&set.cases[i], set.expected[i], set.samples_taken[i]))
                .collect();
            type Pred<'a> = &'a dyn Fn(&[[u8; 4]; 64], u32, u16, Raw) -> bool;
            let find = |p: Pred| {
                corners
                    .iter()
                    .filter_map(|(c, e, k)| match c {
                        Case::RayMarch {
                            voxels,
                            samples,
                            a_stop,
                            background,
                            ..
                        } => p(voxels, *samples, *a_stop, *background).then_some((
                            *e,
                            *k,
                            *samples,
                            *background,
                        )),
                        _ => None,
                    })
                    .collect::<Vec<_>>()
            };
            let equal = |v: &[[u8; 4]; 64]| v.iter().all(|x| *x == v[0]);
            // Background only: no sample, the output is the background.
            let bg_only = find(&|_, n, _, _| n == 0);
            assert!(!bg_only.is_empty());
            assert!(bg_only.iter().all(|&(e, k, _, bg)| k == 0 && e == bg));
            // α = 0 everywhere: every sample is taken and adds nothing.
            let clear = find(&|v, n, _, _| equal(v) && v[0][3] == 0 && n > 0);
            assert!(!clear.is_empty());
            assert!(clear.iter().all(|&(e, k, n, bg)| k == n && e == bg));
            // α = 255 everywhere: the first sample makes the ray opaque and stops it.
            let opaque = find(&|v, n, _, _| equal(v) && v[0] == [255; 4] && n > 0);
            assert!(!opaque.is_empty());
            assert!(opaque.iter().all(|&(e, k, _, _)| k == 1 && e[3] == ONE));
            // Early termination at the first sample (A_stop = 1 behind a non-zero sample).
            let early = find(&|v, n, a, _| equal(v) && v[0][3] > 0 && a == 1 && n > 1);
            assert!(!early.is_empty() && early.iter().all(|&(_, k, _, _)| k == 1));
            // All voxels equal, mid opacity, and the longest ray.
            assert!(!find(&|v, _, _, _| equal(v) && v[0][3] == 137).is_empty());
            assert!(!find(&|_, n, _, _| n == RAY_MAX_SAMPLES).is_empty());
            // Every corner ray stays inside the volume: 0 ≤ p_k ≤ 3·2^F.
            for (c, _, _) in &corners {
                let Case::RayMarch {
                    start,
                    step,
                    samples,
                    ..
                } = c
                else {
                    unreachable!()
                };
                for p in ray_positions(*start, *step, *samples).unwrap() {
                    assert!(p.iter().all(|&x| x <= 3 << f), "{p:?}");
                }
            }
        }
    }
}

/// The random rays stay inside the volume too, and exercise stops, corrections and every
/// sample count.
#[test]
fn ray_march_random_rays_stay_inside_and_vary() {
    let s = spec(Kernel::RayMarch(SampleFilter::Trilinear), 3000, 77, 6);
    let set = build(&s).unwrap();
    let mut counts = [false; RAY_MAX_SAMPLES as usize + 1];
    let (mut stopped, mut corrected) = (0, 0);
    for (c, &k) in set.cases.iter().zip(&set.samples_taken) {
        let Case::RayMarch {
            start,
            step,
            samples,
            ratio,
            ..
        } = c
        else {
            unreachable!()
        };
        for p in ray_positions(*start, *step, *samples).unwrap() {
            assert!(p.iter().all(|&x| x <= 3 << 6), "{c:?}");
        }
        counts[*samples as usize] = true;
        stopped += usize::from(k < *samples);
        corrected += usize::from(*ratio != 1.0);
    }
    assert!(counts.iter().all(|&c| c), "every n in 0..=31 drawn");
    assert!(
        stopped > 100 && corrected > 1000,
        "{stopped} stopped, {corrected} corrected"
    );
}

/// Every supported table size writes the core's tables (which equal the independent model's)
/// and reads back to the same kernel results; the size changes the outputs, not the inputs.
#[test]
fn extinction_table_sizes_round_trip_and_ship_the_core_tables() {
    let mut inputs = Vec::new();
    let mut outputs = Vec::new();
    for n in TABLE_SIZES {
        let s = spec(Kernel::Extinction(SampleFilter::Trilinear), 400, 8, 8)
            .with_table_size(n)
            .unwrap();
        let set = build(&s).unwrap();
        let dir = Scratch::new(&format!("tables-{n}"));
        write(&set, &dir.0).unwrap();
        let back = read(&dir.0).unwrap();
        assert_eq!(back.spec.table_size(), n);
        assert_eq!(back, set);
        let model = ext_model::tables(n);
        for (file, want) in [
            ("table_phi.hex", &model.phi),
            ("table_exp.hex", &model.exp),
            ("table_exp_int.hex", &model.exp_int),
        ] {
            let body = std::fs::read_to_string(dir.0.join(file)).unwrap();
            let got: Vec<u32> = body
                .lines()
                .map(|l| u32::from_str_radix(l, 16).unwrap())
                .collect();
            assert_eq!(&got, want, "{file}, N = {n}");
        }
        let files = extinction_tables(n).unwrap();
        assert_eq!(files[0].values.len(), n);
        for (c, &e) in set.cases.iter().zip(&set.expected) {
            assert_eq!(
                model_extinction(SampleFilter::Trilinear, 8, c, &model),
                e,
                "N = {n}: {c:?}"
            );
        }
        inputs.push(std::fs::read(dir.0.join(vectors::INPUTS_FILE)).unwrap());
        outputs.push(set.expected);
    }
    assert!(inputs.windows(2).all(|w| w[0] == w[1]));
    // The coarsest table (N = 5) is visibly less accurate than the default (N = 257).
    assert_ne!(outputs[0], outputs[3]);
    assert!(extinction_tables(256).is_err());
}

/// `march_positions`, which the ray-march vectors use, takes the marcher's own steps: fed the
/// positions `cast_counted` samples (from `sample_range` and `quantize`), it returns the
/// same composite and count for every ray, with and without correction and early stops.
#[test]
fn march_positions_agrees_with_cast_counted() {
    let voxels: Vec<StraightU8> = (0..64u32)
        .map(|i| {
            let (x, y, z) = (i & 3, (i >> 2) & 3, i >> 4);
            StraightU8([
                (60 * x) as u8,
                (80 * y) as u8,
                (50 * z) as u8,
                (9 * (x + y + z) + 5 * (i % 7)) as u8,
            ])
        })
        .collect();
    let vol = Volume::new(&voxels, [4, 4, 4]).unwrap();
    let cam = Perspective::new([1.5, 1.5, -6.0], [1.6, 1.4, 1.5], [0.0, 1.0, 0.0], 0.9).unwrap();
    let mut total = 0;
    for (d, a_stop) in [(1.0, ONE), (0.5, ONE / 2), (0.3, 9000)] {
        let m = IntRayMarcher::<_, _, _, 8>::new(
            vol,
            OpacityWeighted,
            Trilinear::new(),
            IntStop::new(a_stop).unwrap(),
            Step::new(d).unwrap(),
        )
        .unwrap()
        .with_background(volsample::fixed_point::IntSample::new([100, 0, 200], 300).unwrap());
        for j in 0..7 {
            for i in 0..7 {
                let ray = cam.ray(i, j, 7, 7);
                let (t0, n) = m.sample_range(&ray);
                let pos: Vec<IntPos<8>> = (0..n)
                    .map(|k| m.quantize(ray.at(t0 + k as f32 * d)).unwrap())
                    .collect();
                let got = m.march_positions(pos.iter().copied());
                assert_eq!(got, m.cast_counted(&ray), "ray ({i}, {j}), d = {d}");
                total += got.1;
            }
        }
    }
    assert!(total > 200, "{total} samples");
}

#[test]
fn cli_reports_bad_arguments_without_panicking() {
    let dir = Scratch::new("cli");
    std::fs::create_dir_all(&dir.0).unwrap();
    let file = dir.0.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let out = file.join("sub");
    let cases: [(&[&str], &str); 8] = [
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
        (
            &[
                "--kernel",
                "extinction-weighted-nearest",
                "--table-size",
                "256",
            ],
            "--table-size 256 is not supported",
        ),
        (
            &["--kernel", "separate-nearest", "--table-size", "257"],
            "applies only to the extinction-weighted-* kernels",
        ),
        (
            &["--kernel", "ray-march-opacity-weighted-cubic"],
            "ray-march-opacity-weighted-trilinear",
        ),
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
    // And with a table size, for an extinction kernel.
    let good = dir.0.join("good-ext");
    let o = Command::new(bin)
        .args([
            "vectors",
            "--kernel",
            "extinction-weighted-trilinear",
            "--table-size",
            "17",
            "--count",
            "30",
            "--out",
        ])
        .arg(&good)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("table size 17"));
    assert_eq!(read(&good).unwrap().spec.table_size(), 17);
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

/// A field of a `.hex` line, decoded from the manifest's offset, width and signedness alone
/// (as a test bench would), independently of the crate's `Layout`.
fn manifest_field(line: &str, field: &serde_json::Value) -> i64 {
    let (offset, width) = (
        field["offset"].as_u64().unwrap() as usize,
        field["width"].as_u64().unwrap() as usize,
    );
    let digits: Vec<u32> = line
        .chars()
        .rev()
        .map(|c| c.to_digit(16).unwrap())
        .collect();
    let bit = |b: usize| i64::from((digits[b / 4] >> (b % 4)) & 1);
    let v = (0..width).fold(0i64, |acc, b| acc | bit(offset + b) << b);
    if field["signed"].as_bool().unwrap() && bit(offset + width - 1) == 1 {
        v - (1i64 << width)
    } else {
        v
    }
}

/// The manifest documents the words of the new kernels: decoding each line by the
/// manifest's field table gives back the case and the core's outputs.
#[test]
fn manifest_fields_decode_the_new_kernels_words() {
    for kernel in [
        Kernel::Extinction(SampleFilter::Nearest),
        Kernel::Extinction(SampleFilter::Trilinear),
        Kernel::RayMarch(SampleFilter::Nearest),
        Kernel::RayMarch(SampleFilter::Trilinear),
    ] {
        for f in [4, 12] {
            let s = spec(kernel, 400, 21, f);
            let set = build(&s).unwrap();
            let dir = Scratch::new(&format!("decode-{}-{f}", kernel.name()));
            write(&set, &dir.0).unwrap();
            let m: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(dir.0.join(vectors::MANIFEST_FILE)).unwrap(),
            )
            .unwrap();
            let by_name = |key: &str| -> HashMap<String, serde_json::Value> {
                m[key]["fields"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|f| (f["name"].as_str().unwrap().to_string(), f.clone()))
                    .collect()
            };
            let (fi, fo) = (by_name("inputs"), by_name("expected"));
            let lines = |file: &str| {
                std::fs::read_to_string(dir.0.join(file))
                    .unwrap()
                    .lines()
                    .map(String::from)
                    .collect::<Vec<_>>()
            };
            let (ins, outs) = (lines(vectors::INPUTS_FILE), lines(vectors::EXPECTED_FILE));
            for (i, case) in set.cases.iter().enumerate() {
                let get = |name: &str| manifest_field(&ins[i], &fi[name]);
                let out = |name: &str| manifest_field(&outs[i], &fo[name]);
                let e = set.expected[i];
                assert_eq!(
                    ["r", "g", "b", "a"].map(out),
                    e.map(i64::from),
                    "{}: {case:?}",
                    kernel.name()
                );
                match case {
                    Case::Extinction {
                        voxels,
                        frac,
                        ratio,
                    } => {
                        for (v, x) in voxels.iter().enumerate() {
                            assert_eq!(get(&format!("v{v}_tau")), i64::from(x.tau));
                            for (k, ch) in ["r", "g", "b"].iter().enumerate() {
                                let c = get(&format!("v{v}_ctau_{ch}"));
                                assert_eq!(c, i64::from(x.c_tau[k]));
                            }
                        }
                        assert_eq!(["fx", "fy", "fz"].map(get), frac.map(i64::from));
                        assert_eq!(get("ratio_f32"), i64::from(ratio.to_bits()));
                    }
                    Case::RayMarch {
                        voxels,
                        start,
                        step,
                        samples,
                        ratio,
                        a_stop,
                        background,
                    } => {
                        for (v, x) in voxels.iter().enumerate() {
                            let got = ["r", "g", "b", "a"].map(|ch| get(&format!("v{v}_{ch}")));
                            assert_eq!(got, x.map(i64::from));
                        }
                        assert_eq!(["px", "py", "pz"].map(get), start.map(i64::from));
                        assert_eq!(["dx", "dy", "dz"].map(get), step.map(i64::from));
                        assert_eq!(get("n"), i64::from(*samples));
                        assert_eq!(get("ratio_f32"), i64::from(ratio.to_bits()));
                        assert_eq!(get("a_stop"), i64::from(*a_stop));
                        let bg = ["bg_r", "bg_g", "bg_b", "bg_a"].map(get);
                        assert_eq!(bg, background.map(i64::from));
                        assert_eq!(out("samples"), i64::from(set.samples_taken[i]));
                    }
                    _ => unreachable!(),
                }
            }
            // Negative steps occur, so the signed fields are really exercised.
            if matches!(kernel, Kernel::RayMarch(_)) {
                assert!(set.cases.iter().any(|c| matches!(c,
                    Case::RayMarch { step, .. } if step.iter().any(|&d| d < 0))));
            }
        }
    }
}

/// The manifests are self-contained (issue 32): the arithmetic is written out in each, not
/// deferred to the Rust docs; every rounding step names its rule; field names are unique
/// within a word, and the rules never use a field's name for anything else.
#[test]
fn manifests_are_self_contained_with_one_name_per_field() {
    for kernel in Kernel::ALL {
        let s = spec(kernel, 60, 3, 8);
        let m = vectors::manifest(&s);
        let rounding = m["rounding"].to_string();
        for deferral in ["docs", "volsample::", "fixed_point"] {
            assert!(
                !rounding.contains(deferral),
                "{}: the rounding rules defer to '{deferral}': {rounding}",
                kernel.name()
            );
        }
        let mut names = Vec::new();
        for key in ["inputs", "expected"] {
            let fields: Vec<String> = m[key]["fields"]
                .as_array()
                .unwrap()
                .iter()
                .map(|f| f["name"].as_str().unwrap().to_string())
                .collect();
            let mut unique = fields.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), fields.len(), "{}: {key}", kernel.name());
            names.extend(fields);
        }
        // Position and step fields are named only as fields (the weights' per-axis factors
        // were once also called px, py, pz).
        for name in names
            .iter()
            .filter(|n| n.len() == 2 && n.starts_with(['p', 'd']))
        {
            let pattern = |sep: char| format!("{name}{sep}");
            for sep in ['·', ' ', ','] {
                assert!(
                    !rounding.contains(&pattern(sep)),
                    "{}: the rules use the field name {name} for something else",
                    kernel.name()
                );
            }
        }
    }
    // The correction (also inside the ray-march manifests) spells out each step with its rule
    // and reads the tables by file name.
    for kernel in [
        Kernel::Correction,
        Kernel::RayMarch(SampleFilter::Nearest),
        Kernel::RayMarch(SampleFilter::Trilinear),
    ] {
        let m = vectors::manifest(&spec(kernel, 60, 3, 8));
        let text = m["rounding"].to_string();
        for t in m["tables"].as_array().unwrap() {
            let file = t["file"].as_str().unwrap();
            assert!(text.contains(file.trim_end_matches(".hex")), "{file}");
        }
        for needle in [
            "2^57) >> 58",
            "2^42) >> 43",
            "2^78) >> 79",
            "2^82) >> 83",
            "div (2·v)",
        ] {
            assert!(text.contains(needle), "{}: {needle}", kernel.name());
        }
        let steps = if kernel == Kernel::Correction {
            m["rounding"]["steps"].clone()
        } else {
            m["rounding"]["correction"]["rule"]["steps"].clone()
        };
        let steps = steps.as_array().unwrap();
        assert_eq!(steps.len(), 8);
        for st in steps {
            let rule = st["rule"].as_str().unwrap();
            assert!(
                ["round half up", "truncate", "saturate", "exact"]
                    .iter()
                    .any(|r| rule.contains(r)),
                "{rule}"
            );
        }
    }
}

/// `host-tests/rtl/read_vectors.py` (the stdlib-only reader run by the RTL stage) decodes the
/// files from their manifest alone and recomputes every expected word; a flipped expected
/// bit must be reported as exactly that one mismatch. Needs `python3` (as `rtl/run.sh`).
#[test]
fn python_manifest_reader_recomputes_the_expected_words() {
    let reader = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("rtl/read_vectors.py");
    let run = |dir: &std::path::Path, expected: Option<&std::path::Path>| {
        let mut cmd = Command::new("python3");
        cmd.arg(&reader).arg("--check").arg(dir);
        if let Some(e) = expected {
            cmd.arg("--expected").arg(e);
        }
        let out = cmd
            .output()
            .expect("python3 runs host-tests/rtl/read_vectors.py (install python3)");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
        )
    };
    for (kernel, f) in [
        (Kernel::Composite, 8),
        (
            Kernel::Sample(SampleMode::OpacityWeighted, SampleFilter::Trilinear),
            5,
        ),
        (
            Kernel::Sample(SampleMode::Separate, SampleFilter::Nearest),
            11,
        ),
    ] {
        let dir = Scratch::new(&format!("python-{}", kernel.name()));
        write(&build(&spec(kernel, 600, 9, f)).unwrap(), &dir.0).unwrap();
        let (ok, text) = run(&dir.0, None);
        assert!(ok, "{}: {text}", kernel.name());
        assert!(text.contains(": 600 vectors, 0 mismatches"), "{text}");
        // Bit 0 of expected word 500 flipped: the reader must report that word and no other.
        let words = std::fs::read_to_string(dir.0.join(vectors::EXPECTED_FILE)).unwrap();
        let mut lines: Vec<String> = words.lines().map(String::from).collect();
        let last = lines[500].pop().unwrap().to_digit(16).unwrap() ^ 1;
        lines[500].push(char::from_digit(last, 16).unwrap());
        let mutated = dir.0.join("mutated.hex");
        std::fs::write(&mutated, lines.join("\n") + "\n").unwrap();
        let (ok, text) = run(&dir.0, Some(&mutated));
        assert!(!ok, "{}: {text}", kernel.name());
        assert!(text.contains("MISMATCH vector 500:"), "{text}");
        assert!(text.contains(": 600 vectors, 1 mismatches"), "{text}");
    }
}
