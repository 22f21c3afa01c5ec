//! The `volsample` command-line tool.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{self, Method, ModeChoice, Precision};
use volsample_host::report;
use volsample_host::scene::{self, generate, load, Scene};

/// Sample and composite RGBA volumes, and show what each sampling choice costs in accuracy
/// and in time.
#[derive(Parser, Debug)]
#[command(
    name = "volsample",
    version,
    about,
    after_help = "Environment: VOLSAMPLE_ISA=baseline|avx2 forces the kernels' instruction set \
                  (default: the best this CPU has; every instance gives the same images)."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Preset {
    /// Three 12³ scenes at 16×16 pixels, one timed run (CI smoke test).
    Tiny,
    /// The papers' scenes at 32³, 64×64 pixels (under two minutes on 2 cores).
    Default,
}

#[derive(Subcommand, Debug)]
#[allow(clippy::large_enum_variant)] // parsed once; `Render` has many flags
enum Command {
    /// Render every paper scene with every mode × precision × filter, compare against the
    /// ground truth, and print error and time side by side (the default command).
    Report {
        /// Everything: 32³ and 128³ scenes at 128×128, both trilinear orders.
        #[arg(long)]
        full: bool,
        /// A smaller preset.
        #[arg(long, value_enum, default_value = "default")]
        preset: Preset,
        /// Output directory for CSV, JSON, PNG images and the plot.
        #[arg(long, default_value = "report-out")]
        out: PathBuf,
        /// Timed runs per method (the median is reported).
        #[arg(long, default_value_t = 3)]
        runs: usize,
    },
    /// Render one scene (or your own volume) with chosen modes side by side into a PNG.
    Render {
        /// A scene name from `volsample scenes` (ignored with --raw/--nrrd/--nifti/--tiff).
        #[arg(long, default_value = "red-32")]
        scene: String,
        /// A raw volume file (needs --dims and --type).
        #[arg(long)]
        raw: Option<PathBuf>,
        /// A NRRD volume file (.nrrd, or a detached .nhdr).
        #[arg(long)]
        nrrd: Option<PathBuf>,
        /// A NIfTI-1 or NIfTI-2 volume file (.nii or .nii.gz).
        #[arg(long)]
        nifti: Option<PathBuf>,
        /// A multi-page TIFF stack, one grayscale page per slice.
        #[arg(long)]
        tiff: Option<PathBuf>,
        /// Dimensions of a raw file, e.g. 64,64,32.
        #[arg(long, value_delimiter = ',', num_args = 1..=3)]
        dims: Option<Vec<usize>>,
        /// Sample type of a raw file: u8, i8, u16, i16, u32, i32, f32, f64.
        #[arg(long = "type", default_value = "u8")]
        ty: String,
        /// Byte order of a raw file: little or big.
        #[arg(long, default_value = "little")]
        endian: String,
        /// Without --tf: the default ramp over CENTER±WIDTH/2 in data units (e.g. 40,400 for
        /// CT soft tissue in Hounsfield units) instead of the data's range.
        #[arg(long, value_name = "CENTER,WIDTH", allow_hyphen_values = true)]
        window: Option<String>,
        /// Transfer function for a user volume: JSON or text, `s r g b a` per point.
        #[arg(long)]
        tf: Option<PathBuf>,
        /// Modes, comma separated (separate, opacity-weighted, preweighted, preweighted-u8,
        /// extinction, post-classified).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "separate,opacity-weighted"
        )]
        modes: Vec<String>,
        /// Step in voxels.
        #[arg(long)]
        step: Option<f32>,
        /// Image size in pixels (square).
        #[arg(long, default_value_t = 256)]
        size: usize,
        /// Output PNG.
        #[arg(long, default_value = "render.png")]
        out: PathBuf,
    },
    /// List the scenes and the effects (stages) each calls for.
    Scenes,
    /// The papers' three-sample ray and an ASCII rendering, Separate vs OpacityWeighted.
    Demo,
    /// Filter-design evaluator (Kraus §4.2): eps and eps_c of (a, b, b, a) downsampling.
    Filters {
        /// Pyramid levels n (10 is close to the limit).
        #[arg(long, default_value_t = 10)]
        levels: u32,
    },
    /// Kraus figs. 1/4 ray experiment (CSV, PNG) and the §3.6 artifact thresholds.
    Kraus {
        /// Output directory.
        #[arg(long, default_value = "kraus-out")]
        out: PathBuf,
    },
    /// Reference vectors of an integer kernel for HDL test benches: $readmemh-readable
    /// inputs.hex and expected.hex plus manifest.json (see `volsample_host::vectors`).
    Vectors {
        /// opacity-weighted-{nearest,trilinear}, separate-{nearest,trilinear},
        /// preweighted-{nearest,trilinear}, composite-front-to-back, opacity-correction,
        /// downsample-opacity-based, extinction-weighted-{nearest,trilinear},
        /// ray-march-opacity-weighted-{nearest,trilinear}.
        #[arg(long)]
        kernel: String,
        /// Number of vectors (corner cases first, then random).
        #[arg(long, default_value_t = 10_000)]
        count: usize,
        /// Seed of the SplitMix64 generator.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Fractional position bits F of the sampling kernels (4..=12).
        #[arg(long, default_value_t = 8)]
        frac_bits: u32,
        /// Entries of the phi/exp tables of the extinction-weighted-* kernels: 5, 17, 65,
        /// 257 (the default), 1025 or 4097.
        #[arg(long)]
        table_size: Option<usize>,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
}

fn find_scene(name: &str) -> Result<Scene, String> {
    let mut all = generate::paper_scenes(true);
    all.extend(generate::tiny_scenes());
    all.into_iter()
        .find(|s| s.name == name)
        .ok_or_else(|| format!("unknown scene '{name}' (see `volsample scenes`)"))
}

#[allow(clippy::too_many_arguments)]
fn user_scene(
    raw: Option<PathBuf>,
    nrrd: Option<PathBuf>,
    nifti: Option<PathBuf>,
    tiff: Option<PathBuf>,
    dims: Option<Vec<usize>>,
    (ty, endian): (&str, &str),
    window: Option<String>,
    tf: Option<PathBuf>,
) -> Result<Option<Scene>, String> {
    if tf.is_some() && window.is_some() {
        return Err("--window sets the default ramp; give --window or --tf, not both".into());
    }
    let cap = load::DEFAULT_MEMORY_CAP;
    let vol = match (raw, nrrd, nifti, tiff) {
        (None, None, None, None) => return Ok(None),
        (Some(path), None, None, None) => {
            let dims: [usize; 3] = dims
                .ok_or("--raw needs --dims X,Y,Z")?
                .try_into()
                .map_err(|_| "--dims needs three values")?;
            let ty = load::ScalarType::parse(ty).ok_or_else(|| {
                format!("unknown --type '{ty}' (u8, i8, u16, i16, u32, i32, f32, f64)")
            })?;
            let big = match endian {
                "little" => false,
                "big" => true,
                e => return Err(format!("unknown --endian '{e}' (little, big)")),
            };
            load::read_raw(&path, dims, ty, big, None, cap)
        }
        (None, Some(path), None, None) => load::read_nrrd(&path, cap),
        (None, None, Some(path), None) => load::read_nifti(&path, cap),
        (None, None, None, Some(path)) => load::read_tiff(&path, cap),
        _ => {
            return Err(
                "give one volume file: --raw, --nrrd, --nifti or --tiff, not several".into(),
            )
        }
    }
    .map_err(|e| e.to_string())?;
    let (dims, data) = (vol.dims, vol.data.to_f32());
    let points = match tf {
        Some(p) => load::load_transfer_function(&p).map_err(|e| e.to_string())?,
        None => {
            // A default ramp over the window or the data's range.
            let (lo, hi) = match window {
                Some(text) => {
                    let cw = text
                        .split_once(',')
                        .and_then(|(c, w)| Some((c.trim().parse().ok()?, w.trim().parse().ok()?)));
                    let (c, w) = cw.ok_or_else(|| {
                        format!("--window '{text}': need CENTER,WIDTH, e.g. 40,400")
                    })?;
                    let (lo, hi) = load::window(c, w).map_err(|e| format!("--window: {e}"))?;
                    (lo as f32, hi as f32)
                }
                None => data
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                        (a.min(v), b.max(v))
                    }),
            };
            let hi = if hi > lo { hi } else { lo + 1.0 };
            vec![
                volsample::ControlPoint {
                    s: lo,
                    c: [1.0; 3],
                    a: 0.0,
                },
                volsample::ControlPoint {
                    s: hi,
                    c: [1.0; 3],
                    a: 0.6,
                },
            ]
        }
    };
    let n = dims.iter().copied().max().unwrap_or(1);
    Ok(Some(Scene {
        name: "user".into(),
        description: "user volume".into(),
        dims,
        data: scene::VolumeData::Scalar(data),
        classification: scene::Classification::Transfer(points),
        light: None,
        step: 0.5,
        phase: 0.0,
        d_ref: 1.0,
        a_stop: 1.0,
        background: generate::BLACK_BG,
        camera: {
            let mut c = generate::camera_towards(n, [0.3, 0.2, 1.0]);
            if let volsample_host::float_checks::CameraSpec::Orthographic(ref mut eye, _, _, _) = c
            {
                let centre = dims.map(|d| (d as f32 - 1.0) * 0.5);
                let off = (n as f32 - 1.0) * 0.5;
                for k in 0..3 {
                    eye[k] += centre[k] - off;
                }
            }
            c
        },
        image: [256, 256],
    }))
}

fn run() -> Result<(), String> {
    let cli = Cli::parse();
    // A bad `VOLSAMPLE_ISA` stops here, before any work, with the choices.
    volsample_host::isa::from_env()?;
    match cli.command.unwrap_or(Command::Report {
        full: false,
        preset: Preset::Default,
        out: PathBuf::from("report-out"),
        runs: 3,
    }) {
        Command::Report {
            full,
            preset,
            out,
            runs,
        } => {
            let (scenes, runs, truth_step) = match (full, preset) {
                (true, _) => (generate::paper_scenes(true), runs, 1.0 / 32.0),
                (false, Preset::Default) => (generate::paper_scenes(false), runs, 1.0 / 16.0),
                (false, Preset::Tiny) => (generate::tiny_scenes(), 1, 1.0 / 8.0),
            };
            println!(
                "volsample report: {} scenes, every mode x precision x filter, {} timed run(s) each",
                scenes.len(),
                runs
            );
            let rows = report::run(&report::Options {
                scenes,
                full,
                runs,
                truth_step,
                out: Some(out.clone()),
                progress: true,
            })?;
            emit(&report::format_table(&rows))?;
            println!(
                "per-scene rows, images and the error-vs-time plot: {}/",
                out.display()
            );
            Ok(())
        }
        Command::Render {
            scene,
            raw,
            nrrd,
            nifti,
            tiff,
            dims,
            ty,
            endian,
            window,
            tf,
            modes,
            step,
            size,
            out,
        } => {
            let mut s = match user_scene(raw, nrrd, nifti, tiff, dims, (&ty, &endian), window, tf)?
            {
                Some(s) => s,
                None => find_scene(&scene)?,
            };
            if let Some(d) = step {
                s.step = d;
            }
            if size == 0 {
                return Err("--size must be positive".into());
            }
            s.image = [size, size];
            let prepared = s.prepare().map_err(|e| e.to_string())?;
            let mut strip = Vec::new();
            let mut labels = Vec::new();
            for m in &modes {
                let mode = ModeChoice::parse(m).ok_or_else(|| format!("unknown mode '{m}'"))?;
                let method = Method {
                    mode,
                    precision: Precision::F32,
                    filter: FilterKind::TrilinearSum,
                };
                let r = pipeline::render(&s, &prepared, method).map_err(|e| format!("{m}: {e}"))?;
                strip.push(report::displayed(&r.pixels));
                labels.push(m.clone());
            }
            // Side by side, left to right in the order given.
            let w = size * strip.len();
            let mut img = vec![[0.0f32; 3]; w * size];
            for (k, part) in strip.iter().enumerate() {
                for j in 0..size {
                    for i in 0..size {
                        img[j * w + k * size + i] = part[j * size + i];
                    }
                }
            }
            volsample_host::images::write_rgb(&out, w, size, &img)?;
            println!(
                "{}: {} ({}) -> {}",
                s.name,
                labels.join(" | "),
                s.description,
                out.display()
            );
            Ok(())
        }
        Command::Scenes => {
            let mut text = format!("{:<22} {:<44} effects\n", "scene", "description");
            let mut all = generate::paper_scenes(true);
            all.extend(generate::tiny_scenes());
            for s in all {
                text.push_str(&format!(
                    "{:<22} {:<44} {}\n",
                    s.name,
                    s.description,
                    s.effects()
                ));
            }
            emit(&text)
        }
        Command::Demo => emit(&volsample_host::demo::run().map_err(|e| e.to_string())?),
        Command::Filters { levels } => volsample_host::filters::run(levels),
        Command::Kraus { out } => volsample_host::kraus::run(&out),
        Command::Vectors {
            kernel,
            count,
            seed,
            frac_bits,
            table_size,
            out,
        } => {
            use volsample_host::vectors::{run_spec, Spec};
            Spec::new(&kernel, count, seed, frac_bits)
                .and_then(|s| match table_size {
                    Some(n) => s.with_table_size(n),
                    None => Ok(s),
                })
                .and_then(|s| run_spec(&s, &out))
                .map(|s| println!("{s}"))
                .map_err(|e| e.to_string())
        }
    }
}

/// Writes `text` to stdout; a closed pipe (`volsample scenes | head`) ends the output quietly
/// instead of panicking.
fn emit(text: &str) -> Result<(), String> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(format!("stdout: {e}")),
        _ => Ok(()),
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("volsample: {e}");
            ExitCode::FAILURE
        }
    }
}
