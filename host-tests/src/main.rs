//! The `volsample` command-line tool.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use volsample_host::float_checks::FilterKind;
use volsample_host::pipeline::{self, ModeChoice, Precision};
use volsample_host::report;
use volsample_host::scene::{generate, load, phantom, Scene};
use volsample_host::view;

/// Volumes and images of 4 MiB and more in 2 MiB pages where Linux offers them
/// (`volsample_host::memory`).
#[global_allocator]
static ALLOCATOR: volsample_host::memory::HugePages = volsample_host::memory::HugePages;

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
enum Command {
    /// Render every paper scene with every mode × precision × filter, compare against two
    /// truths, time each method on large frames, and print tables and verdicts (the default
    /// command; `index.html` in the output folder).
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
        /// Timed frames per method on the large timing scene (the median is reported).
        #[arg(long, default_value_t = 3)]
        runs: usize,
    },
    /// Render one scene (or your own volume) with chosen modes side by side into a PNG,
    /// each panel labelled with its mode, filter and precision.
    Render(Box<RenderArgs>),
    /// Write a CT-like head phantom (8-bit NRRD: a skull-like shell around soft tissue) and a
    /// transfer function for it (text), to try `render` on a scan-like volume.
    Phantom {
        /// Voxels per axis (8..=1024).
        #[arg(long, default_value_t = 256)]
        size: usize,
        /// Output NRRD file; the transfer function goes beside it with `.tf.txt`.
        #[arg(long, default_value = "ct-head.nrrd")]
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

/// The `render` command's arguments.
#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// A scene name from `volsample scenes` (ignored with --raw/--nrrd/--nifti/--tiff/--dicom).
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
    /// A folder holding a DICOM series, one uncompressed grayscale slice per file (other files
    /// in it are skipped).
    #[arg(long, value_name = "DIR")]
    dicom: Option<PathBuf>,
    /// With --dicom: the SeriesInstanceUID to read when the folder holds several series.
    #[arg(long, value_name = "UID")]
    dicom_series: Option<String>,
    /// Dimensions of a raw file: `X,Y,Z` or `X Y Z`.
    #[arg(long, num_args = 1..=3, value_delimiter = ',', value_name = "X,Y,Z")]
    dims: Option<Vec<usize>>,
    /// Sample type of a raw file: u8, i8, u16, i16, u32, i32, f32, f64.
    #[arg(long = "type", default_value = "u8")]
    ty: String,
    /// Byte order of a raw file: little or big.
    #[arg(long, default_value = "little")]
    endian: String,
    /// Voxel spacing of a raw file in mm, `X,Y,Z` (default 1,1,1).
    #[arg(long, value_delimiter = ',', value_name = "X,Y,Z")]
    spacing: Option<Vec<f64>>,
    /// Without --tf: the default ramp over CENTER±WIDTH/2 in data units (e.g. 40,400 for CT
    /// soft tissue in Hounsfield units) instead of the data's range.
    #[arg(long, value_name = "CENTER,WIDTH", allow_hyphen_values = true)]
    window: Option<String>,
    /// Transfer function for a user volume: JSON or text, `s r g b a` per point (default: a
    /// white ramp from transparent at the data's minimum to opacity 0.6 at its maximum).
    #[arg(long)]
    tf: Option<PathBuf>,
    /// Modes, separated by commas or spaces: separate, opacity-weighted, preweighted,
    /// preweighted-u8, extinction, post-classified.
    #[arg(long, default_value = "separate,opacity-weighted")]
    modes: String,
    /// Reconstruction filter: trilinear, trilinear-tree, nearest, bspline.
    #[arg(long, default_value = "trilinear")]
    filter: String,
    /// Kernel arithmetic: f32, or int (8-bit storage, 8 fractional position bits; separate,
    /// opacity-weighted and preweighted-u8 with nearest or trilinear).
    #[arg(long, default_value = "f32")]
    precision: String,
    /// Step between samples in world units (mm for files with a spacing; default: half the
    /// smallest voxel spacing, or the scene's step).
    #[arg(long)]
    step: Option<f64>,
    /// The distance the voxels' opacities hold for, in world units (default: the smallest
    /// voxel spacing, or the scene's reference distance). Resampling a volume then keeps its
    /// look.
    #[arg(long)]
    unit_distance: Option<f64>,
    /// Early ray termination once a ray's opacity reaches this, in (0, 1] (default 0.99 for
    /// your volumes, the scene's own for scenes).
    #[arg(long)]
    a_stop: Option<f32>,
    /// Turn empty-space skipping off (the image is the same; only the time differs).
    #[arg(long)]
    no_skip: bool,
    /// Worker threads (default: one per core). The image is the same for any number.
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Image width and height in pixels (square); --width and --height override it.
    #[arg(long, default_value_t = 256)]
    size: usize,
    /// Image width in pixels.
    #[arg(long)]
    width: Option<usize>,
    /// Image height in pixels.
    #[arg(long)]
    height: Option<usize>,
    /// Camera: degrees about the up axis from the anterior view (90: from the patient's
    /// right, 180: from behind). Any camera option replaces a scene's own camera.
    #[arg(long, allow_hyphen_values = true)]
    azimuth: Option<f64>,
    /// Camera: degrees above the horizontal (90: from above).
    #[arg(long, allow_hyphen_values = true)]
    elevation: Option<f64>,
    /// Camera: the view direction as a world vector `X,Y,Z` (replaces azimuth/elevation).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z"
    )]
    view_dir: Option<Vec<f64>>,
    /// Camera: the world vector pointing up in the image, `X,Y,Z` (default superior, 0,0,1).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_name = "X,Y,Z"
    )]
    up: Option<Vec<f64>>,
    /// Camera: magnification (1 frames the whole volume).
    #[arg(long)]
    zoom: Option<f64>,
    /// Camera: perspective projection with this vertical field of view in degrees (default:
    /// orthographic).
    #[arg(long)]
    perspective: Option<f64>,
    /// Background color `R,G,B` in [0, 1] (default black).
    #[arg(long, value_delimiter = ',', value_name = "R,G,B")]
    background: Option<Vec<f32>>,
    /// Output PNG.
    #[arg(long, default_value = "render.png")]
    out: PathBuf,
}

/// Three values of a `X,Y,Z` or `X Y Z` option.
fn three<T: Copy>(name: &str, v: &[T]) -> Result<[T; 3], String> {
    let forms = if name == "dims" {
        "X,Y,Z or X Y Z"
    } else {
        "X,Y,Z"
    };
    <[T; 3]>::try_from(v).map_err(|_| format!("--{name} needs three values, {forms}"))
}

fn find_scene(name: &str) -> Result<Scene, String> {
    let mut all = generate::paper_scenes(true);
    all.extend(generate::tiny_scenes());
    all.into_iter()
        .find(|s| s.name == name)
        .ok_or_else(|| format!("unknown scene '{name}' (see `volsample scenes`)"))
}

/// A user's volume: its samples in their own type, where they lie in the world, and the
/// transfer function.
struct UserVolume {
    name: String,
    volume: load::LoadedVolume,
    affine: view::Affine,
    points: Vec<volsample::ControlPoint>,
}

/// The progress bar of a volume load ([`load::show_progress`]), taken down on drop.
struct LoadBar(indicatif::ProgressBar);

impl LoadBar {
    fn new() -> Self {
        let bar = indicatif::ProgressBar::new(0);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{msg} [{bar:40}] {bytes}/{total_bytes}, {elapsed}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message("loading");
        load::show_progress(Some(bar.clone()));
        Self(bar)
    }
}

impl Drop for LoadBar {
    fn drop(&mut self) {
        load::show_progress(None);
        self.0.finish_and_clear();
    }
}

fn user_volume(a: &RenderArgs) -> Result<Option<UserVolume>, String> {
    if a.tf.is_some() && a.window.is_some() {
        return Err("--window sets the default ramp; give --window or --tf, not both".into());
    }
    if a.dicom_series.is_some() && a.dicom.is_none() {
        return Err("--dicom-series chooses a series of a --dicom folder".into());
    }
    let cap = load::DEFAULT_MEMORY_CAP;
    // A bar over the bytes read (drawn only on a terminal), cleared when this returns.
    let _loading = (!a.quiet).then(LoadBar::new);
    let (path, vol) = match (&a.raw, &a.nrrd, &a.nifti, &a.tiff, &a.dicom) {
        (None, None, None, None, None) => return Ok(None),
        (Some(path), None, None, None, None) => {
            let dims = three("dims", a.dims.as_deref().ok_or("--raw needs --dims X,Y,Z")?)?;
            let ty = load::ScalarType::parse(&a.ty).ok_or_else(|| {
                format!(
                    "unknown --type '{}' (u8, i8, u16, i16, u32, i32, f32, f64)",
                    a.ty
                )
            })?;
            let big = match a.endian.as_str() {
                "little" => false,
                "big" => true,
                e => return Err(format!("unknown --endian '{e}' (little, big)")),
            };
            let spacing = match &a.spacing {
                Some(s) => {
                    let s = three("spacing", s)?;
                    if !s.iter().all(|x| x.is_finite() && *x > 0.0) {
                        return Err(format!("--spacing {s:?}: each value must be positive"));
                    }
                    Some(s)
                }
                None => None,
            };
            (path, load::read_raw(path, dims, ty, big, spacing, cap))
        }
        (None, Some(path), None, None, None) => (path, load::read_nrrd(path, cap)),
        (None, None, Some(path), None, None) => (path, load::read_nifti(path, cap)),
        (None, None, None, Some(path), None) => (path, load::read_tiff(path, cap)),
        (None, None, None, None, Some(path)) => (
            path,
            load::read_dicom_series(path, a.dicom_series.as_deref(), cap),
        ),
        _ => {
            return Err(
                "give one volume: --raw, --nrrd, --nifti, --tiff or --dicom, not several".into(),
            )
        }
    };
    let vol = vol.map_err(|e| e.to_string())?;
    if a.spacing.is_some() && a.raw.is_none() {
        return Err("--spacing is for --raw files (the others carry their own)".into());
    }
    let points = match &a.tf {
        Some(p) => load::load_transfer_function(p).map_err(|e| e.to_string())?,
        None => {
            // A default white ramp over the window or the data's range.
            let (lo, hi) = match &a.window {
                Some(text) => {
                    let cw = text
                        .split_once(',')
                        .and_then(|(c, w)| Some((c.trim().parse().ok()?, w.trim().parse().ok()?)));
                    let (c, w) = cw.ok_or_else(|| {
                        format!("--window '{text}': need CENTER,WIDTH, e.g. 40,400")
                    })?;
                    load::window(c, w).map_err(|e| format!("--window: {e}"))?
                }
                None => vol.data.range().unwrap_or((0.0, 1.0)),
            };
            let (lo, hi) = (lo as f32, hi as f32);
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
    let m = vol.space.affine;
    let affine = view::Affine {
        rows: [m[0], m[1], m[2]],
    };
    Ok(Some(UserVolume {
        name: path
            .file_name()
            .map_or_else(|| "volume".into(), |n| n.to_string_lossy().into_owned()),
        volume: vol,
        affine,
        points,
    }))
}

/// Classifies a loaded volume's samples to straight RGBA8, in their own type (8- and 16-bit
/// samples through a table of every value).
fn classify_loaded(
    data: &load::Scalars,
    points: &[volsample::ControlPoint],
) -> Result<Vec<volsample::StraightU8>, String> {
    use view::render::{classify, classify_table, classify_u8};
    match data {
        load::Scalars::U8(v) => classify_u8(v, points),
        load::Scalars::I8(v) => classify_table(v, points, |x| (i32::from(x) + 128) as usize, -128),
        load::Scalars::U16(v) => classify_table(v, points, usize::from, 0),
        load::Scalars::I16(v) => {
            classify_table(v, points, |x| (i32::from(x) + 32768) as usize, -32768)
        }
        load::Scalars::U32(v) => classify(v, points, |x| x as f32),
        load::Scalars::I32(v) => classify(v, points, |x| x as f32),
        load::Scalars::F32(v) => classify(v, points, |x| x),
        load::Scalars::F64(v) => classify(v, points, |x| x as f32),
    }
}

/// The modes of `--modes`, separated by commas and/or spaces.
fn parse_modes(text: &str) -> Result<Vec<ModeChoice>, String> {
    let names: Vec<&str> = text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .collect();
    if names.is_empty() {
        return Err("--modes names no mode".into());
    }
    names
        .into_iter()
        .map(|m| {
            ModeChoice::parse(m).ok_or_else(|| {
                let valid: Vec<&str> = ModeChoice::ALL.iter().map(|m| m.label()).collect();
                format!("unknown mode '{m}' (valid: {})", valid.join(", "))
            })
        })
        .collect()
}

fn parse_filter(name: &str) -> Result<FilterKind, String> {
    match name.trim() {
        "trilinear" => Ok(FilterKind::TrilinearSum),
        "trilinear-tree" => Ok(FilterKind::TrilinearTree),
        "nearest" => Ok(FilterKind::Nearest),
        "bspline" => Ok(FilterKind::BSpline),
        f => Err(format!(
            "unknown filter '{f}' (valid: trilinear, trilinear-tree, nearest, bspline)"
        )),
    }
}

fn parse_precision(name: &str) -> Result<Precision, String> {
    match name.trim() {
        "f32" => Ok(Precision::F32),
        "int" | "int8" => Ok(Precision::Int8),
        p => Err(format!("unknown precision '{p}' (valid: f32, int)")),
    }
}

/// The camera of `args`, if any camera option is given.
fn view_of(a: &RenderArgs) -> Result<Option<view::View>, String> {
    if a.azimuth.is_none()
        && a.elevation.is_none()
        && a.view_dir.is_none()
        && a.up.is_none()
        && a.zoom.is_none()
        && a.perspective.is_none()
    {
        return Ok(None);
    }
    let mut v = view::View {
        azimuth_deg: a.azimuth.unwrap_or(0.0),
        elevation_deg: a.elevation.unwrap_or(0.0),
        zoom: a.zoom.unwrap_or(1.0),
        ..view::View::default()
    };
    if let Some(d) = &a.view_dir {
        v.direction = Some(three("view-dir", d)?);
    }
    if let Some(u) = &a.up {
        v.up = three("up", u)?;
    }
    if let Some(fov) = a.perspective {
        v.projection = view::Projection::Perspective { fov_y_deg: fov };
    }
    Ok(Some(v))
}

fn render_cmd(a: &RenderArgs) -> Result<(), String> {
    match a.out.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("png") => {}
        _ => {
            return Err(format!(
                "--out {}: only PNG is written; give a file name ending in .png",
                a.out.display()
            ))
        }
    }
    let modes = parse_modes(&a.modes)?;
    let filter = parse_filter(&a.filter)?;
    let precision = parse_precision(&a.precision)?;
    let size = [a.width.unwrap_or(a.size), a.height.unwrap_or(a.size)];
    let [w, h] = size;
    match w.checked_mul(h).and_then(|n| n.checked_mul(modes.len())) {
        Some(n) if n > 0 && n <= view::render::MAX_PIXELS => {}
        _ => {
            return Err(format!(
                "image {w} x {h} times {} panels must have between 1 and {} pixels",
                modes.len(),
                view::render::MAX_PIXELS
            ))
        }
    }
    let background = match &a.background {
        Some(b) => {
            let c = three("background", b)?;
            if !c.iter().all(|x| (0.0..=1.0).contains(x)) {
                return Err(format!(
                    "--background {c:?}: each channel must lie in [0, 1]"
                ));
            }
            volsample::Sample { c, a: 1.0 }
        }
        None => generate::BLACK_BG,
    };
    let wants_post = modes.contains(&ModeChoice::PostClassified);
    let camera = view_of(a)?;
    // The volume, its placement, the default step, unit distance and termination, and the
    // camera.
    let (name, description, voxels, framed, step, unit, a_stop) = match user_volume(a)? {
        Some(u) => {
            let straight = classify_loaded(&u.volume.data, &u.points)?;
            let dims = u.volume.dims;
            let finest = u.affine.spacing().into_iter().fold(f64::INFINITY, f64::min);
            let framed = camera
                .unwrap_or_default()
                .frame_image(&u.affine, dims, size)?;
            // The scalars as f32 only where the post-classified mode needs them.
            let post = wants_post.then(|| (u.volume.data.to_f32(), u.points));
            let description = format!(
                "your volume, {} {}, {:?} from {:?}",
                dims.map(|n| n.to_string()).join("x"),
                u.volume.data.scalar_type().name(),
                u.volume.space.spacing,
                u.volume.space.source
            );
            drop(u.volume);
            (
                u.name,
                description,
                view::render::Voxels {
                    dims,
                    straight,
                    post,
                },
                framed,
                0.5 * finest,
                finest,
                0.99,
            )
        }
        None => {
            let s = find_scene(&a.scene)?;
            let prepared = s.prepare().map_err(|e| e.to_string())?;
            let affine = view::Affine::default();
            let framed = match camera {
                Some(v) => v.frame_image(&affine, s.dims, size)?,
                None => view::Framed::from_index_camera(&s.camera)?,
            };
            (
                s.name.clone(),
                s.description.clone(),
                view::render::Voxels {
                    dims: s.dims,
                    straight: pipeline::straight_u8(&prepared.rgba),
                    post: prepared.post,
                },
                framed,
                f64::from(s.step),
                f64::from(s.d_ref),
                s.a_stop,
            )
        }
    };
    if framed.spread > 0.01 {
        eprintln!(
            "volsample: warning: perspective view of an anisotropic volume: step lengths differ \
             by up to {:.1} % across the image (use an orthographic view for exact opacities)",
            100.0 * framed.spread
        );
    }
    let settings = view::render::Settings {
        size,
        step_mm: a.step.unwrap_or(step),
        unit_mm: a.unit_distance.unwrap_or(unit),
        a_stop: a.a_stop.unwrap_or(a_stop),
        skip: !a.no_skip,
        threads: a.threads,
        background,
        progress: !a.quiet,
    };
    if !(settings.a_stop > 0.0 && settings.a_stop <= 1.0) {
        return Err(format!("--a-stop {} must lie in (0, 1]", settings.a_stop));
    }
    let mut panels = Vec::new();
    let mut times = Vec::new();
    let mut isa = None;
    for mode in modes {
        let method = pipeline::Method {
            mode,
            precision,
            filter,
        };
        let img = view::render::render(&voxels, &framed, method, &settings)
            .map_err(|e| format!("{}: {e}", method.label()))?;
        isa = Some(img.isa);
        times.push(format!("{:.0} ms", img.seconds * 1e3));
        panels.push((method.label(), report::displayed(&img.pixels)));
    }
    if let Some(warning) = volsample_host::images::write_panels(&a.out, w, h, &panels)? {
        eprintln!("volsample: warning: {warning}");
    }
    let labels: Vec<&str> = panels.iter().map(|p| p.0.as_str()).collect();
    volsample_host::say!(
        "{name}: {} ({description}; {}; {}) -> {}",
        labels.join(" | "),
        times.join(", "),
        isa.map_or_else(String::new, |i| format!("{i:?}")),
        a.out.display()
    );
    Ok(())
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
            // Accuracy on small frames (the f64 truths are costly); time on large ones.
            let (scenes, runs, truth_step, timing) = match (full, preset) {
                (true, _) => (
                    generate::paper_scenes(true),
                    runs,
                    1.0 / 32.0,
                    report::timing_scenes(128, 128),
                ),
                (false, Preset::Default) => (
                    generate::paper_scenes(false),
                    runs,
                    1.0 / 16.0,
                    report::timing_scenes(128, 128),
                ),
                (false, Preset::Tiny) => (
                    generate::tiny_scenes(),
                    1,
                    1.0 / 8.0,
                    report::timing_scenes(24, 32),
                ),
            };
            volsample_host::say!(
                "volsample report: {} scenes, every mode x precision x filter against two truths; each method timed on {} frame(s) of a large scene",
                scenes.len(),
                runs
            );
            let result = report::run(&report::Options {
                scenes,
                timing,
                full,
                runs,
                truth_step,
                out: Some(out.clone()),
                progress: true,
            })?;
            volsample_host::out::emit(&report::format_report(&result));
            volsample_host::say!(
                "per-scene rows, images and the error-vs-time plot: {}/",
                out.display()
            );
            Ok(())
        }
        Command::Render(args) => render_cmd(&args),
        Command::Phantom { size, out } => write_phantom(size, &out),
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
            volsample_host::out::emit(&text);
            Ok(())
        }
        Command::Demo => {
            volsample_host::out::emit(&volsample_host::demo::run().map_err(|e| e.to_string())?);
            Ok(())
        }
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
                .map(|s| volsample_host::say!("{s}"))
                .map_err(|e| e.to_string())
        }
    }
}

/// Writes [`phantom::ct_head`] as an attached raw NRRD and its transfer function as text.
fn write_phantom(n: usize, out: &std::path::Path) -> Result<(), String> {
    use std::io::Write as _;
    if !(8..=1024).contains(&n) {
        return Err(format!("--size {n} must lie in 8..=1024"));
    }
    let data = phantom::ct_head(n);
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    let mut f = std::io::BufWriter::new(std::fs::File::create(out).map_err(io)?);
    write!(
        f,
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: {n} {n} {n}\nencoding: raw\n\n"
    )
    .and_then(|()| f.write_all(&data))
    .and_then(|()| f.flush())
    .map_err(io)?;
    let tf_path = out.with_extension("tf.txt");
    let mut text = String::from("# s r g b a (straight color, opacity per voxel length)\n");
    for p in phantom::ct_transfer_function() {
        text.push_str(&format!(
            "{} {} {} {} {}\n",
            p.s, p.c[0], p.c[1], p.c[2], p.a
        ));
    }
    std::fs::write(&tf_path, text).map_err(|e| format!("{}: {e}", tf_path.display()))?;
    volsample_host::say!(
        "{n}^3 CT-like head -> {} (transfer function: {})",
        out.display(),
        tf_path.display()
    );
    Ok(())
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
