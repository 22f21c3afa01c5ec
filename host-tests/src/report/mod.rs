//! The accuracy-against-time report: every paper scene, every method, against two truths (the
//! continuous scene and the interpolated extinction field), each method timed on large
//! frames; tables and verdicts on stdout, and on disk CSV, JSON, images, error-against-time
//! plots and `index.html`.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};

pub mod html;
mod text;
mod verdict;

pub use text::format_report;
pub use verdict::{as_good, group_verdict, leaks, precision_lines, scene_verdict};
use volsample::Sample;

use crate::float_checks::FilterKind;
use crate::images;
use crate::pipeline::{self, Method, ModeChoice, Precision};
use crate::reference::{self, RefAssoc, RefCamera, RefFilter, RefSource};
use crate::scene::{Prepared, Scene};

/// Report options.
#[derive(Debug, Clone)]
pub struct Options {
    /// The scenes.
    pub scenes: Vec<Scene>,
    /// The scenes each group's methods are timed on (large frames: see [`timing_scenes`]).
    pub timing: Vec<Scene>,
    /// Run the tree trilinear order too.
    pub full: bool,
    /// Timed frames per method (the median is reported).
    pub runs: usize,
    /// Ground-truth substep, voxels.
    pub truth_step: f64,
    /// Output directory (`None`: no files).
    pub out: Option<PathBuf>,
    /// Show a progress bar.
    pub progress: bool,
}

/// Scenes whose numbers may be summarised together: they offer the same methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Group {
    /// RGBA voxels (generated, or classified before sampling): every mode but
    /// `PostClassified`.
    Rgba,
    /// Scalars with a transfer function: `PostClassified` too.
    Transfer,
}

impl Group {
    /// The group of a prepared scene.
    pub fn of(prepared: &Prepared) -> Self {
        if prepared.post.is_some() {
            Group::Transfer
        } else {
            Group::Rgba
        }
    }

    /// A short label.
    pub fn label(self) -> &'static str {
        match self {
            Group::Rgba => "RGBA scenes",
            Group::Transfer => "transfer-function scenes",
        }
    }
}

/// What a method's image is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Truth {
    /// The scene's continuous definition, integrated exactly
    /// ([`crate::scene::continuous::continuous_truth`]).
    Continuous,
    /// The trilinearly interpolated extinction field of the voxels ([`ground_truth`]).
    Field,
}

impl Truth {
    /// A short label.
    pub fn label(self) -> &'static str {
        match self {
            Truth::Continuous => "continuous scene",
            Truth::Field => "extinction field",
        }
    }

    /// What the truth is, and which method it favours.
    pub fn describes(self) -> &'static str {
        match self {
            Truth::Continuous => {
                "the scene's shapes and fields before voxelization, integrated exactly \
                 (favours no method; every error includes what voxelizing lost)"
            }
            Truth::Field => {
                "the trilinear extinction field of the voxels, integrated exactly (Kraus's \
                 model: favours extinction, which converges to it by construction)"
            }
        }
    }
}

/// Image errors in 8-bit levels, per pixel the largest of the three channels' errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// RMS over pixels and RGB channels.
    pub rms: f64,
    /// The 99th percentile of the pixels' errors (nearest rank).
    pub p99: f64,
    /// The share of pixels off by more than [`VISIBLE_LEVELS`], in `[0, 1]`.
    pub over: f64,
}

/// An error that shows: more than 8 of 255 levels in a channel.
pub const VISIBLE_LEVELS: f64 = 8.0;

/// One row of the report: a method on a scene, against each truth.
#[derive(Debug, Clone)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// The scene's group.
    pub group: Group,
    /// The method.
    pub method: Method,
    /// Errors against the continuous scene (`None` for a scene without a definition).
    pub continuous: Option<Errors>,
    /// Errors against the interpolated extinction field.
    pub field: Errors,
    /// For a method of another precision than `f32`: its errors against the `f32` method of
    /// the same mode and filter on the same scene (what the precision alone costs).
    pub from_f32: Option<Errors>,
    /// Samples per image of the accuracy frame.
    pub samples: u64,
}

impl Row {
    /// The errors against `truth`, where the row has them.
    pub fn against(&self, truth: Truth) -> Option<Errors> {
        match truth {
            Truth::Continuous => self.continuous,
            Truth::Field => Some(self.field),
        }
    }
}

/// A method's time on its group's timing scene.
#[derive(Debug, Clone)]
pub struct Timing {
    /// The group timed.
    pub group: Group,
    /// The scene timed on.
    pub scene: String,
    /// Its volume and image sizes.
    pub sizes: ([usize; 3], [usize; 2]),
    /// The method.
    pub method: Method,
    /// Median ns per sample over the timed frames.
    pub ns_per_sample: f64,
    /// Samples per frame.
    pub samples: u64,
}

/// Where the times were taken: the instruction set, threads and CPU.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The marchers' instruction set.
    pub isa: volsample::Isa,
    /// Threads per frame.
    pub threads: usize,
    /// The CPU's model name (`/proc/cpuinfo`), or "unknown CPU".
    pub cpu: String,
}

impl Machine {
    /// This machine, as the report's marchers run on it.
    pub fn here() -> Self {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|t| {
                t.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_string())
            })
            .unwrap_or_else(|| "unknown CPU".into());
        Machine {
            isa: crate::isa::chosen(),
            threads: 1,
            cpu,
        }
    }

    /// One line naming it.
    pub fn line(&self) -> String {
        format!(
            "{} instance, {} thread{}, {}",
            self.isa.name(),
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            self.cpu
        )
    }
}

/// Everything a report run measured.
#[derive(Debug, Clone)]
pub struct Report {
    /// Accuracy rows, per scene and method.
    pub rows: Vec<Row>,
    /// Times, per group and method.
    pub timings: Vec<Timing>,
    /// Where the times were taken.
    pub machine: Machine,
}

/// The scenes the report times each group's methods on: frames large enough to be stable
/// (`n³` volumes, `size²` rays): the red-air ball for the RGBA group, the transfer-function
/// shells for the other.
pub fn timing_scenes(n: usize, size: usize) -> Vec<Scene> {
    let mut v = vec![
        crate::scene::generate::ball_in_air(n, crate::scene::generate::RED_AIR, "red"),
        crate::scene::generate::tf_ramp(n),
    ];
    for s in &mut v {
        s.image = [size, size];
    }
    v
}

/// The camera of a scene for the f64 reference.
pub fn ref_camera(scene: &Scene) -> RefCamera {
    let v3 = |v: [f32; 3]| v.map(f64::from);
    match scene.camera {
        crate::float_checks::CameraSpec::Orthographic(e, d, u, x) => {
            let l = d.iter().map(|a| a * a).sum::<f32>().sqrt();
            RefCamera::Orthographic {
                eye: v3(e),
                dir: v3(d.map(|a| a / l)),
                up: v3(u),
                extent: f64::from(x),
            }
        }
        crate::float_checks::CameraSpec::Perspective(e, t, u, f) => RefCamera::Perspective {
            eye: v3(e),
            target: v3(t),
            up: v3(u),
            fov_y: f64::from(f),
        },
    }
}

/// `pixel(i, j)` for every pixel of a `w × h` image, row-major, rows on all cores.
pub fn per_pixel(
    w: usize,
    h: usize,
    pixel: impl Fn(usize, usize) -> [f32; 3] + Sync,
) -> Vec<[f32; 3]> {
    let threads = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .min(h.max(1));
    let mut out = vec![[0.0f32; 3]; w * h];
    let rows_per = h.div_ceil(threads).max(1);
    std::thread::scope(|sc| {
        for (t, chunk) in out.chunks_mut(rows_per * w.max(1)).enumerate() {
            let pixel = &pixel;
            sc.spawn(move || {
                for (k, px) in chunk.iter_mut().enumerate() {
                    let idx = t * rows_per * w + k;
                    *px = pixel(idx % w, idx / w);
                }
            });
        }
    });
    out
}

/// The extinction-field truth: the emission–absorption integral along each pixel's ray, with
/// fine substeps `h`, of the trilinear extinction field of the prepared RGBA voxels — or, for
/// transfer-function scenes, of the transfer function applied to the trilinearly interpolated
/// scalar at every substep. Over the scene's background. Rows run on all cores.
pub fn ground_truth(scene: &Scene, prepared: &Prepared, h: f64) -> Vec<[f32; 3]> {
    let d_ref = f64::from(scene.d_ref);
    let straight = reference::RefVolume::new(
        scene.dims,
        prepared
            .rgba
            .iter()
            .map(|v| reference::RefVoxel::new(v.c.map(f64::from), f64::from(v.a)))
            .collect(),
        d_ref,
    );
    let post = prepared.post.as_ref().map(|(s, pts)| {
        (
            reference::RefScalarVolume::new(
                scene.dims,
                s.iter().map(|&x| f64::from(x)).collect(),
                d_ref,
            ),
            reference::RefTransferFunction::new(
                pts.iter()
                    .map(|p| {
                        reference::RefControlPoint::new(
                            f64::from(p.s),
                            p.c.map(f64::from),
                            f64::from(p.a),
                        )
                    })
                    .collect(),
            ),
        )
    });
    let source = match &post {
        Some((s, tf)) => RefSource::Scalar(s, tf),
        None => RefSource::Straight(&straight),
    };
    let cam = ref_camera(scene);
    let [w, hgt] = scene.image;
    let bg = RefAssoc::new(
        scene.background.c.map(f64::from),
        f64::from(scene.background.a),
    );
    per_pixel(w, hgt, |i, j| {
        let ray = reference::camera_ray(&cam, w, hgt, i, j);
        let acc = reference::integrate_source_exact(source, RefFilter::Trilinear, &ray, h);
        reference::over_background(acc, bg).color.map(|c| c as f32)
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The errors of a displayed image against a truth, in 8-bit levels.
pub fn errors(img: &[[f32; 3]], truth: &[[f32; 3]]) -> Errors {
    let (mut sum, mut n) = (0.0f64, 0usize);
    let mut per_pixel = Vec::with_capacity(img.len());
    for (a, b) in img.iter().zip(truth) {
        let mut worst = 0.0f64;
        for k in 0..3 {
            let e = 255.0 * f64::from(a[k] - b[k]).abs();
            sum += e * e;
            worst = worst.max(e);
            n += 1;
        }
        per_pixel.push(worst);
    }
    per_pixel.sort_by(f64::total_cmp);
    let p99 = match per_pixel.len() {
        0 => 0.0,
        // Nearest rank: the smallest error at least 99 % of the pixels do not exceed.
        m => per_pixel[((0.99 * m as f64).ceil() as usize).clamp(1, m) - 1],
    };
    let over = per_pixel.iter().filter(|&&e| e > VISIBLE_LEVELS).count() as f64
        / per_pixel.len().max(1) as f64;
    Errors {
        rms: (sum / n.max(1) as f64).sqrt(),
        p99,
        over,
    }
}

/// The smallest width, in pixels, of the report's images on disk (small frames are enlarged).
pub const SHOWN: usize = 256;

fn file_label(m: &Method) -> String {
    m.label().replace('/', "_")
}

fn progress(opts: &Options, total: u64) -> Result<ProgressBar, String> {
    if !opts.progress {
        return Ok(ProgressBar::hidden());
    }
    let b = ProgressBar::new(total);
    b.set_style(
        ProgressStyle::with_template("{elapsed:>4} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| e.to_string())?
            .progress_chars("=> "),
    );
    Ok(b)
}

/// Runs the report: each scene's methods against both truths, then each group's methods
/// timed on the group's timing scene.
///
/// # Errors
/// A scene the core rejects, or an output file that cannot be written.
pub fn run(opts: &Options) -> Result<Report, String> {
    let prepare = |scene: &Scene| {
        scene
            .prepare()
            .map_err(|e| format!("scene {}: {e}", scene.name))
    };
    let mut plan = Vec::new();
    for scene in &opts.scenes {
        let prepared = prepare(scene)?;
        let methods = Method::all(prepared.post.is_some(), opts.full);
        plan.push((scene, prepared, methods));
    }
    let mut timing_plan = Vec::new();
    for scene in &opts.timing {
        let prepared = prepare(scene)?;
        let group = Group::of(&prepared);
        if plan.iter().any(|(_, p, _)| Group::of(p) == group) {
            let methods: Vec<Method> = Method::all(prepared.post.is_some(), opts.full)
                .into_iter()
                .filter(Method::timed)
                .collect();
            timing_plan.push((scene, prepared, methods));
        }
    }
    let total: u64 = plan.iter().map(|(_, _, m)| 2 + m.len() as u64).sum::<u64>()
        + timing_plan
            .iter()
            .map(|(_, _, m)| m.len() as u64)
            .sum::<u64>();
    let bar = progress(opts, total)?;
    let mut rows = Vec::new();
    for (scene, prepared, methods) in &plan {
        bar.set_message(format!("{}: truths", scene.name));
        let field = ground_truth(scene, prepared, opts.truth_step);
        bar.inc(1);
        let continuous = crate::scene::continuous::continuous_truth(scene, opts.truth_step);
        bar.inc(1);
        let dir = opts
            .out
            .as_ref()
            .map(|o| o.join("images").join(&scene.name));
        let [w, h] = scene.image;
        // Images enlarged to at least `SHOWN` pixels across.
        let k = SHOWN.div_ceil(w.max(1));
        if let Some(d) = &dir {
            std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
            images::write_rgb_scaled(&d.join("truth.png"), w, h, &field, k)?;
            if let Some(c) = &continuous {
                images::write_rgb_scaled(&d.join("truth-continuous.png"), w, h, c, k)?;
            }
        }
        // The f32 images per (mode, filter), for the other precisions' `from_f32`
        // (`Method::all` lists the f32 methods first).
        let mut f32_images: Vec<(ModeChoice, FilterKind, Vec<[f32; 3]>)> = Vec::new();
        for m in methods {
            bar.set_message(format!("{}: {}", scene.name, m.label()));
            let r = pipeline::render(scene, prepared, *m)
                .map_err(|e| format!("{} {}: {e}", scene.name, m.label()))?;
            let img: Vec<[f32; 3]> = r.pixels.iter().map(images::display).collect();
            if let Some(d) = &dir {
                let truth = continuous.as_ref().unwrap_or(&field);
                let err = images::error_map(&img, truth);
                let base = file_label(m);
                images::write_rgb_scaled(&d.join(format!("{base}.png")), w, h, &img, k)?;
                images::write_rgb_scaled(
                    &d.join(format!("{base}-diff.png")),
                    w,
                    h,
                    &images::error_image(&err, 8.0),
                    k,
                )?;
            }
            let from_f32 = if m.precision == Precision::F32 {
                f32_images.push((m.mode, m.filter, img.clone()));
                None
            } else {
                f32_images
                    .iter()
                    .find(|(mode, filter, _)| *mode == m.mode && *filter == m.filter)
                    .map(|(_, _, f)| errors(&img, f))
            };
            rows.push(Row {
                scene: scene.name.clone(),
                group: Group::of(prepared),
                method: *m,
                continuous: continuous.as_ref().map(|c| errors(&img, c)),
                field: errors(&img, &field),
                from_f32,
                samples: r.samples,
            });
            bar.inc(1);
        }
    }
    let mut timings = Vec::new();
    for (scene, prepared, methods) in &timing_plan {
        for m in methods {
            bar.set_message(format!("timing {}: {}", scene.name, m.label()));
            // One pipeline, `runs` frames (the first also warms the caches), one count.
            let (seconds, samples) = pipeline::time_frames(scene, prepared, *m, opts.runs.max(1))
                .map_err(|e| format!("{} {}: {e}", scene.name, m.label()))?;
            let times: Vec<f64> = seconds
                .iter()
                .map(|s| s * 1e9 / samples.max(1) as f64)
                .collect();
            timings.push(Timing {
                group: Group::of(prepared),
                scene: scene.name.clone(),
                sizes: (scene.dims, scene.image),
                method: *m,
                ns_per_sample: median(times),
                samples,
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let report = Report {
        rows,
        timings,
        machine: Machine::here(),
    };
    if let Some(out) = &opts.out {
        text::write_outputs(out, &report)?;
    }
    Ok(report)
}

impl Report {
    /// The groups present, in order.
    pub fn groups(&self) -> Vec<Group> {
        let mut g: Vec<Group> = self.rows.iter().map(|r| r.group).collect();
        g.sort();
        g.dedup();
        g
    }

    /// The scenes present, in order of appearance.
    pub fn scenes(&self) -> Vec<&str> {
        let mut v: Vec<&str> = Vec::new();
        for r in &self.rows {
            if !v.contains(&r.scene.as_str()) {
                v.push(&r.scene);
            }
        }
        v
    }

    /// The time of `method` on its group's timing scene (`NaN` where it was not timed).
    pub fn ns(&self, group: Group, method: &Method) -> f64 {
        self.timings
            .iter()
            .find(|t| t.group == group && t.method == *method)
            .map_or(f64::NAN, |t| t.ns_per_sample)
    }

    /// The truth a group's verdict uses: the continuous scene where every scene of the group
    /// has one, else the extinction field.
    pub fn truth_of(&self, group: Group) -> Truth {
        let all = self
            .rows
            .iter()
            .filter(|r| r.group == group)
            .all(|r| r.continuous.is_some());
        if all {
            Truth::Continuous
        } else {
            Truth::Field
        }
    }

    /// Per method of `group`: the mean of each error over the group's scenes against
    /// `truth`, the time, and the number of scenes. Sorted by mean RMS.
    pub fn summary(&self, group: Group, truth: Truth) -> Vec<Summary> {
        let mut methods: Vec<Method> = Vec::new();
        for r in self.rows.iter().filter(|r| r.group == group) {
            if !methods.contains(&r.method) {
                methods.push(r.method);
            }
        }
        let mut out: Vec<Summary> = methods
            .into_iter()
            .filter_map(|m| {
                let e: Vec<Errors> = self
                    .rows
                    .iter()
                    .filter(|r| r.group == group && r.method == m)
                    .map(|r| r.against(truth))
                    .collect::<Option<_>>()?;
                let n = e.len() as f64;
                let mean = |f: fn(&Errors) -> f64| e.iter().map(f).sum::<f64>() / n;
                let from_f32: Option<Vec<f64>> = self
                    .rows
                    .iter()
                    .filter(|r| r.group == group && r.method == m)
                    .map(|r| r.from_f32.map(|e| e.rms))
                    .collect();
                Some(Summary {
                    from_f32: from_f32.map(|v| v.iter().sum::<f64>() / n),
                    method: m,
                    errors: Errors {
                        rms: mean(|e| e.rms),
                        p99: mean(|e| e.p99),
                        over: mean(|e| e.over),
                    },
                    ns: self.ns(group, &m),
                    scenes: e.len(),
                })
            })
            .collect();
        out.sort_by(|a, b| a.errors.rms.total_cmp(&b.errors.rms));
        out
    }
}

/// A method's numbers over a group of scenes.
#[derive(Debug, Clone)]
pub struct Summary {
    /// The method.
    pub method: Method,
    /// Mean errors over the scenes.
    pub errors: Errors,
    /// ns/sample on the group's timing scene.
    pub ns: f64,
    /// The mean RMS against the `f32` method of the same mode and filter, where every scene
    /// has it ([`Row::from_f32`]).
    pub from_f32: Option<f64>,
    /// Scenes averaged.
    pub scenes: usize,
}

/// The time and cost cells of a table row: ns/sample with one decimal and the ratio to the
/// cheapest, or "-" for a method not timed (the emulated GPU texture unit).
pub fn time_cells(ns: f64, cheapest: f64) -> (String, String) {
    if ns.is_finite() {
        (format!("{ns:.1}"), format!("{:.2}x", ns / cheapest))
    } else {
        ("-".into(), "-".into())
    }
}

/// Whether a method is the paper's recommendation (for the plot's highlighting).
pub fn highlighted(m: &Method) -> bool {
    m.mode == ModeChoice::OpacityWeighted
        && m.precision == Precision::F32
        && m.filter == FilterKind::TrilinearSum
}

/// Composited pixels to displayed colors.
pub fn displayed(p: &[Sample]) -> Vec<[f32; 3]> {
    p.iter().map(images::display).collect()
}
