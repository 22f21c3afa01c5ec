//! The accuracy-against-time report: every paper scene, every method, against the ground
//! truth; a table on stdout, CSV, JSON, PNG images and an error-against-time plot on disk.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressStyle};
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
    /// Run the tree trilinear order too.
    pub full: bool,
    /// Timed runs per method (the median is reported).
    pub runs: usize,
    /// Ground-truth substep, voxels.
    pub truth_step: f64,
    /// Output directory (`None`: no files).
    pub out: Option<PathBuf>,
    /// Show a progress bar.
    pub progress: bool,
}

/// One row of the report.
#[derive(Debug, Clone)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// The method.
    pub method: Method,
    /// RMS error over pixels and RGB channels, 8-bit units.
    pub rms: f64,
    /// Largest error, 8-bit units.
    pub max: f64,
    /// Median ns per sample over the timed runs.
    pub ns_per_sample: f64,
    /// Samples per image.
    pub samples: u64,
}

fn ref_camera(scene: &Scene) -> RefCamera {
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

/// The ground truth: the emission–absorption integral along each pixel's ray, with fine
/// substeps `h`, of the trilinear extinction field of the prepared RGBA voxels — or, for
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
    let threads = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .min(hgt.max(1));
    let mut out = vec![[0.0f32; 3]; w * hgt];
    let rows_per = hgt.div_ceil(threads);
    std::thread::scope(|sc| {
        for (t, chunk) in out.chunks_mut(rows_per * w).enumerate() {
            let cam = &cam;
            sc.spawn(move || {
                for (k, px) in chunk.iter_mut().enumerate() {
                    let idx = t * rows_per * w + k;
                    let ray = reference::camera_ray(cam, w, hgt, idx % w, idx / w);
                    let acc =
                        reference::integrate_source_exact(source, RefFilter::Trilinear, &ray, h);
                    let p = reference::over_background(acc, bg);
                    *px = p.color.map(|c| c as f32);
                }
            });
        }
    });
    out
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

/// RMS and max error in 8-bit units between two displayed images.
pub fn errors(img: &[[f32; 3]], truth: &[[f32; 3]]) -> (f64, f64) {
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0usize);
    for (a, b) in img.iter().zip(truth) {
        for k in 0..3 {
            let e = 255.0 * f64::from(a[k] - b[k]).abs();
            sum += e * e;
            max = max.max(e);
            n += 1;
        }
    }
    ((sum / n.max(1) as f64).sqrt(), max)
}

fn file_label(m: &Method) -> String {
    m.label().replace('/', "_")
}

/// Runs the report.
///
/// # Errors
/// A scene the core rejects, or an output file that cannot be written.
pub fn run(opts: &Options) -> Result<Vec<Row>, String> {
    let mut plan = Vec::new();
    for scene in &opts.scenes {
        let prepared = scene
            .prepare()
            .map_err(|e| format!("scene {}: {e}", scene.name))?;
        let methods = Method::all(prepared.post.is_some(), opts.full);
        plan.push((scene, prepared, methods));
    }
    let total: u64 = plan.iter().map(|(_, _, m)| 1 + m.len() as u64).sum();
    let bar = if opts.progress {
        let b = ProgressBar::new(total);
        b.set_style(
            ProgressStyle::with_template("{elapsed:>4} [{bar:40}] {pos}/{len} {msg}")
                .map_err(|e| e.to_string())?
                .progress_chars("=> "),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    let mut rows = Vec::new();
    for (scene, prepared, methods) in &plan {
        bar.set_message(format!("{}: ground truth", scene.name));
        let truth = ground_truth(scene, prepared, opts.truth_step);
        bar.inc(1);
        let dir = opts
            .out
            .as_ref()
            .map(|o| o.join("images").join(&scene.name));
        if let Some(d) = &dir {
            std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
            let [w, h] = scene.image;
            images::write_rgb(&d.join("truth.png"), w, h, &truth)?;
        }
        for m in methods {
            bar.set_message(format!("{}: {}", scene.name, m.label()));
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..opts.runs.max(1) {
                let r = pipeline::render(scene, prepared, *m)
                    .map_err(|e| format!("{} {}: {e}", scene.name, m.label()))?;
                times.push(r.seconds * 1e9 / r.samples.max(1) as f64);
                last = Some(r);
            }
            let r = last.ok_or("no run")?;
            let img: Vec<[f32; 3]> = r.pixels.iter().map(images::display).collect();
            let (rms, max) = errors(&img, &truth);
            if let Some(d) = &dir {
                let [w, h] = scene.image;
                let err = images::error_map(&img, &truth);
                let base = file_label(m);
                images::write_rgb(&d.join(format!("{base}.png")), w, h, &img)?;
                images::write_rgb(
                    &d.join(format!("{base}-diff.png")),
                    w,
                    h,
                    &images::error_image(&err, 8.0),
                )?;
                images::write_rgb(
                    &d.join(format!("{base}-diff-eq.png")),
                    w,
                    h,
                    &images::equalised_error_image(&err),
                )?;
            }
            rows.push(Row {
                scene: scene.name.clone(),
                method: *m,
                rms,
                max,
                ns_per_sample: median(times),
                samples: r.samples,
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    if let Some(out) = &opts.out {
        write_outputs(out, &rows)?;
    }
    Ok(rows)
}

/// Per-method summary over all scenes: mean RMS, worst max, median ns/sample.
pub fn summary(rows: &[Row]) -> Vec<(Method, f64, f64, f64, usize)> {
    let mut methods: Vec<Method> = Vec::new();
    for r in rows {
        if !methods.contains(&r.method) {
            methods.push(r.method);
        }
    }
    methods
        .into_iter()
        .map(|m| {
            let sel: Vec<&Row> = rows.iter().filter(|r| r.method == m).collect();
            let rms = sel.iter().map(|r| r.rms).sum::<f64>() / sel.len() as f64;
            let max = sel.iter().map(|r| r.max).fold(0.0, f64::max);
            let ns = median(sel.iter().map(|r| r.ns_per_sample).collect());
            (m, rms, max, ns, sel.len())
        })
        .collect()
}

/// The stdout table: one line per method, sorted by mean RMS error, cost relative to the
/// cheapest method.
pub fn format_table(rows: &[Row]) -> String {
    let mut s = summary(rows);
    s.sort_by(|a, b| a.1.total_cmp(&b.1));
    let cheapest = s.iter().map(|r| r.3).fold(f64::INFINITY, f64::min);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<44} {:>7} {:>8} {:>9} {:>6} {:>7}",
        "method (mode/precision/filter)", "RMS", "max", "ns/sample", "cost", "scenes"
    );
    let _ = writeln!(out, "{}", "-".repeat(86));
    for (m, rms, max, ns, n) in s {
        let _ = writeln!(
            out,
            "{:<44} {:>7.2} {:>8.1} {:>9.1} {:>5.2}x {:>7}",
            m.label(),
            rms,
            max,
            ns,
            ns / cheapest,
            n
        );
    }
    let _ = writeln!(
        out,
        "errors in 8-bit levels against the ground truth (f64, exact extinction integration);"
    );
    let _ = writeln!(
        out,
        "RMS is the mean over scenes, max the worst pixel; ns/sample is the median over scenes"
    );
    out
}

fn write_outputs(out: &Path, rows: &[Row]) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut csv =
        String::from("scene,mode,precision,filter,rms_8bit,max_8bit,ns_per_sample,samples\n");
    let mut json = Vec::new();
    for r in rows {
        let l = r.method.label();
        let parts: Vec<&str> = l.split('/').collect();
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.4},{:.3},{:.3},{}",
            r.scene, parts[0], parts[1], parts[2], r.rms, r.max, r.ns_per_sample, r.samples
        );
        json.push(serde_json::json!({
            "scene": r.scene, "mode": parts[0], "precision": parts[1], "filter": parts[2],
            "rms_8bit": r.rms, "max_8bit": r.max, "ns_per_sample": r.ns_per_sample, "samples": r.samples,
        }));
    }
    let w = |name: &str, text: String| {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    w("report.csv", csv)?;
    w(
        "report.json",
        serde_json::to_string_pretty(&serde_json::json!({ "rows": json }))
            .map_err(|e| e.to_string())?,
    )?;
    w("report.txt", format_table(rows))?;
    crate::plot::error_vs_time(&out.join("error_vs_time.png"), &summary(rows))
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
