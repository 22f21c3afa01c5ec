//! Kraus & Bürger 2008, §3.5–3.6: the ray-integration experiment of figs. 1 and 4, and the
//! wall and scattered-voxel renderings, as measurements.
//!
//! # Figs. 1 and 4
//!
//! A ray crosses a 2D grid (vertex spacing 1) perpendicular to one column of vertices with
//! color 1 and extinction `τ_max`; every other vertex is empty. Sampling is bilinear, so along
//! the ray (any height between two rows: the column's vertices are all equal) the fields are
//! the hat `h(x) = max(0, 1 − |x|)` around the column. Samples lie at `x_k = (k + r)·d` for
//! every integer `k`: `r ∈ [0, 1)` is the phase of the samples relative to the column in units
//! of `d` (every placement of the samples is one such `r`).
//!
//! * opacity-based, `d′ = d` (no correction): vertex opacity `α_v = 1 − e^(−τ_max·d)`,
//!   `α = 1 − Π_k (1 − α_v·h(x_k))`;
//! * extinction-based: `α = 1 − Π_k e^(−τ_max·h(x_k)·d) = 1 − e^(−τ_max·d·Σ_k h(x_k))`;
//! * exact: `1 − e^(−τ_max·∫h) = 1 − e^(−τ_max)`.
//!
//! Extinction-based sampling is exact whenever `d = 1/m`: `S(r) = d·Σ_k h((k + r)·d)` is
//! continuous, periodic in `r` and piecewise linear, with kinks only where a sample crosses a
//! knot of `h` (−1, 0, 1); for `d = 1/m` all three knots are crossed at the same `r`, where the
//! slope changes by `d·(1 − 2 + 1) = 0`, so `S` is constant, equal to its mean `∫h = 1`.
//!
//! [`fig4_model`] is the f64 model; [`fig4_core`] runs the same ray through the core's
//! `RayMarcher` (a `9 × 2 × 1` volume) so the model is tied to the library.
//!
//! # §3.6: wall and scattered voxels
//!
//! [`scene36`] renders an opaque (`α = 1`), white, one-voxel-wide wall (or scattered opaque
//! voxels) in a transparent `24³` volume with an oblique orthographic camera, trilinear,
//! opacity-based (`OpacityWeighted`, opacities for `d′`) or extinction-based
//! (`ExtinctionWeighted` of the same voxels converted for `d′`), swept over `d = d′`.
//!
//! The artifact criterion ([`artifact_rms`]): the RMS over the image of the opacity difference
//! between the rendering at step `d` and the converged rendering of the *same* data (`d′ = d`)
//! at step `d/`[`REFINE`] (opacity-corrected, or integrated, for the smaller step); a method
//! fails at `d` when the RMS exceeds one 8-bit step, `1/255` ([`ARTIFACT_RMS`]).
//! [`first_failure`] sweeps `d`. (Comparing against a fixed small `d` instead would measure
//! how the data change with `d′`: the opaque voxels' capped `τ = 64/d′` grows without bound as
//! `d′ → 0`, which thickens every silhouette.)

use volsample::{
    ExtinctionF32, ExtinctionWeighted, OpacityWeighted, Orthographic, Ray, RayMarcher, Sample,
    Step, StraightF32, Trilinear, Volume,
};

/// The `τ_max` values of fig. 4.
pub const TAU_MAX: [f64; 4] = [1.0, 2.0, 4.0, 8.0];

/// The sampling method of an experiment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Opacity-based sampling, `d′ = d`.
    OpacityBased,
    /// Extinction-based sampling.
    ExtinctionBased,
}

impl Method {
    /// Both methods.
    pub const ALL: [Method; 2] = [Method::OpacityBased, Method::ExtinctionBased];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Method::OpacityBased => "opacity-based",
            Method::ExtinctionBased => "extinction-based",
        }
    }
}

fn hat(x: f64) -> f64 {
    (1.0 - x.abs()).max(0.0)
}

/// The exact opacity of the fig. 1 ray: `1 − e^(−τ_max)`.
pub fn fig4_exact(tau_max: f64) -> f64 {
    -(-tau_max).exp_m1()
}

/// The integrated opacity of the fig. 1 ray with `method`, step `d > 0`, phase `r ∈ [0, 1)`
/// (f64 model, see the module docs).
pub fn fig4_model(method: Method, tau_max: f64, d: f64, r: f64) -> f64 {
    // Samples with |x_k| < 1: k from ⌈−1/d − r⌉ to ⌊1/d − r⌋.
    let k0 = (-1.0 / d - r).ceil() as i64;
    let k1 = (1.0 / d - r).floor() as i64;
    let hs = (k0..=k1).map(|k| hat((k as f64 + r) * d));
    match method {
        Method::ExtinctionBased => {
            let s: f64 = hs.sum();
            -(-tau_max * d * s).exp_m1()
        }
        Method::OpacityBased => {
            let a_v = -(-tau_max * d).exp_m1();
            1.0 - hs.map(|h| 1.0 - a_v * h).product::<f64>()
        }
    }
}

/// The fig. 1 ray through the core: a `9 × 2 × 1` volume whose column `x = 4` holds the
/// `τ_max` vertices (white), sampled by a `RayMarcher` with `Trilinear` (bilinear in the
/// plane) along `+x` at height `y = ½`, samples at `x = 4 + (k + r)·d`.
///
/// # Errors
/// From the core, for a `d` or `r` it rejects.
pub fn fig4_core(method: Method, tau_max: f32, d: f32, r: f32) -> Result<f32, volsample::Error> {
    let dims = [9, 2, 1];
    // An integer number of steps before the column, outside the volume box.
    let steps_before = (6.0 / d).ceil();
    let ray = Ray::new([4.0 - steps_before * d, 0.5, 0.0], [1.0, 0.0, 0.0])?;
    let step = Step::new(d)?.with_phase(r)?;
    let px = match method {
        Method::OpacityBased => {
            let a_v = -(-tau_max * d).exp_m1();
            let vox: Vec<StraightF32> = (0..18)
                .map(|i| StraightF32 {
                    c: [1.0; 3],
                    a: if i % 9 == 4 { a_v } else { 0.0 },
                })
                .collect();
            let vol = Volume::new(&vox, dims)?.with_reference_distance(d)?;
            RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .cast(&ray)
        }
        Method::ExtinctionBased => {
            let vox: Vec<ExtinctionF32> = (0..18)
                .map(|i| white_extinction(if i % 9 == 4 { tau_max } else { 0.0 }))
                .collect();
            let vol = Volume::new(&vox, dims)?;
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .cast(&ray)
        }
    };
    Ok(px.a)
}

/// One row of the fig. 4 sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fig4Row {
    /// `τ_max`.
    pub tau_max: f64,
    /// Step `d`.
    pub d: f64,
    /// Phase `r`.
    pub r: f64,
    /// Opacity-based result.
    pub opacity: f64,
    /// Extinction-based result.
    pub extinction: f64,
    /// `1 − e^(−τ_max)`.
    pub exact: f64,
}

/// The fig. 4 sweep: `d = i/nd·2` for `i = 1 ..= nd`, `r = j/nr` for `j = 0 .. nr`, every
/// `τ_max` of [`TAU_MAX`].
pub fn fig4_sweep(nd: usize, nr: usize) -> Vec<Fig4Row> {
    let mut rows = Vec::with_capacity(TAU_MAX.len() * nd * nr);
    for &tau_max in &TAU_MAX {
        for i in 1..=nd {
            let d = 2.0 * i as f64 / nd as f64;
            for j in 0..nr {
                let r = j as f64 / nr as f64;
                rows.push(Fig4Row {
                    tau_max,
                    d,
                    r,
                    opacity: fig4_model(Method::OpacityBased, tau_max, d, r),
                    extinction: fig4_model(Method::ExtinctionBased, tau_max, d, r),
                    exact: fig4_exact(tau_max),
                });
            }
        }
    }
    rows
}

/// The largest `|α − exact|` of each method over the rows with `lo < d < hi`, per `τ_max`:
/// `(τ_max, opacity-based, extinction-based)`.
pub fn fig4_max_errors(rows: &[Fig4Row], lo: f64, hi: f64) -> Vec<(f64, f64, f64)> {
    TAU_MAX
        .iter()
        .map(|&t| {
            let sel = rows
                .iter()
                .filter(|r| r.tau_max == t && r.d > lo && r.d < hi);
            let (o, e) = sel.fold((0.0f64, 0.0f64), |(o, e), r| {
                (
                    o.max((r.opacity - r.exact).abs()),
                    e.max((r.extinction - r.exact).abs()),
                )
            });
            (t, o, e)
        })
        .collect()
}

/// The sweep as CSV: `tau_max,d,r,alpha_opacity,alpha_extinction,alpha_exact`.
pub fn fig4_csv(rows: &[Fig4Row]) -> String {
    let mut s = String::from("tau_max,d,r,alpha_opacity,alpha_extinction,alpha_exact\n");
    for r in rows {
        s.push_str(&format!(
            "{},{:.6},{:.6},{:.9},{:.9},{:.9}\n",
            r.tau_max, r.d, r.r, r.opacity, r.extinction, r.exact
        ));
    }
    s
}

/// The two surfaces as an RGB image: a row of four panels (`τ_max` = 1, 2, 4, 8) per method
/// (opacity-based on top), each `nd × nr` pixels scaled by `zoom`, `d` growing to the right
/// and `r` downwards; the color shows `α − exact` on a diverging scale clipped at `±0.25`
/// (blue below, white at 0, red above). Returns `(width, height, rgb)`.
pub fn fig4_image(rows: &[Fig4Row], nd: usize, nr: usize, zoom: usize) -> (u32, u32, Vec<u8>) {
    let gap = 4;
    let pw = nd * zoom;
    let ph = nr * zoom;
    let w = 4 * pw + 5 * gap;
    let h = 2 * ph + 3 * gap;
    let mut img = vec![64u8; w * h * 3];
    for (pi, &tau_max) in TAU_MAX.iter().enumerate() {
        let panel: Vec<&Fig4Row> = rows.iter().filter(|r| r.tau_max == tau_max).collect();
        for (mi, method) in Method::ALL.iter().enumerate() {
            for (idx, row) in panel.iter().enumerate() {
                let (i, j) = (idx / nr, idx % nr);
                if i >= nd {
                    continue;
                }
                let v = match method {
                    Method::OpacityBased => row.opacity,
                    Method::ExtinctionBased => row.extinction,
                } - row.exact;
                let t = (v / 0.25).clamp(-1.0, 1.0);
                let c = if t >= 0.0 {
                    [255.0, 255.0 * (1.0 - t), 255.0 * (1.0 - t)]
                } else {
                    [255.0 * (1.0 + t), 255.0 * (1.0 + t), 255.0]
                };
                for dy in 0..zoom {
                    for dx in 0..zoom {
                        let x = gap + pi * (pw + gap) + i * zoom + dx;
                        let y = gap + mi * (ph + gap) + j * zoom + dy;
                        let o = (y * w + x) * 3;
                        for k in 0..3 {
                            img[o + k] = c[k].round() as u8;
                        }
                    }
                }
            }
        }
    }
    (w as u32, h as u32, img)
}

/// Encodes an RGB8 image as PNG.
///
/// # Errors
/// From the encoder.
pub fn encode_png(w: u32, h: u32, rgb: &[u8]) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// §3.6

/// The two §3.6 scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scene36 {
    /// An axis-aligned, one-voxel-wide wall of opaque voxels (`x = 11`, all `y`, `z`).
    Wall,
    /// Scattered opaque voxels (about 2 % of the interior, fixed seed).
    Scattered,
}

impl Scene36 {
    /// Both scenes.
    pub const ALL: [Scene36; 2] = [Scene36::Wall, Scene36::Scattered];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Scene36::Wall => "wall",
            Scene36::Scattered => "scattered voxels",
        }
    }

    /// The straight voxels of the `24³` volume: opaque white where occupied, else transparent.
    pub fn voxels(self) -> Vec<StraightF32> {
        let n = 24usize;
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n * n * n)
            .map(|i| {
                let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
                let inside = |c: usize| (3..n - 3).contains(&c);
                let occupied = match self {
                    Scene36::Wall => x == 11,
                    Scene36::Scattered => inside(x) && inside(y) && inside(z) && next() < 0.02,
                };
                StraightF32 {
                    c: [1.0; 3],
                    a: if occupied { 1.0 } else { 0.0 },
                }
            })
            .collect()
    }
}

/// Image size of the §3.6 renderings.
pub const IMAGE: usize = 48;

/// The artifact threshold: one 8-bit step.
pub const ARTIFACT_RMS: f64 = 1.0 / 255.0;

/// The converged rendering the artifact criterion compares against uses the step `d/REFINE`.
pub const REFINE: f32 = 8.0;

/// Renders `scene` with `method`, voxel opacities for `d_ref`, step `d`: an `IMAGE × IMAGE`
/// opacity image, orthographic, looking at the volume's centre along `(1, 0.37, 0.23)`
/// (oblique, so the pixels see the structures at every phase), 12 voxels wide.
///
/// # Errors
/// From the core.
pub fn scene36(
    scene: Scene36,
    method: Method,
    d: f32,
    d_ref: f32,
) -> Result<Vec<f32>, volsample::Error> {
    let dims = [24, 24, 24];
    let vox = scene.voxels();
    let dir = [1.0f32, 0.37, 0.23];
    let centre = [11.5f32; 3];
    let eye = [
        centre[0] - 30.0 * dir[0],
        centre[1] - 30.0 * dir[1],
        centre[2] - 30.0 * dir[2],
    ];
    let cam = Orthographic::new(eye, dir, [0.0, 0.0, 1.0], 12.0)?;
    let step = Step::new(d)?;
    let mut img = vec![Sample::TRANSPARENT; IMAGE * IMAGE];
    match method {
        Method::OpacityBased => {
            let vol = Volume::new(&vox, dims)?.with_reference_distance(d_ref)?;
            RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .render_into(&cam, IMAGE, IMAGE, &mut img)?;
        }
        Method::ExtinctionBased => {
            let ext: Vec<ExtinctionF32> = vox
                .iter()
                .map(|&v| ExtinctionF32::from_straight(v, d_ref))
                .collect();
            let vol = Volume::new(&ext, dims)?;
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .render_into(&cam, IMAGE, IMAGE, &mut img)?;
        }
    }
    Ok(img.iter().map(|s| s.a).collect())
}

/// RMS of `image − limit` over all pixels.
pub fn artifact_rms(image: &[f32], limit: &[f32]) -> f64 {
    let s: f64 = image
        .iter()
        .zip(limit)
        .map(|(a, b)| (f64::from(*a) - f64::from(*b)).powi(2))
        .sum();
    (s / image.len() as f64).sqrt()
}

/// The §3.6 sweep of one scene and method: `(d, RMS)` for `d = d′ = 0.05, 0.10, …, d_max`,
/// each against the same data rendered at step `d/REFINE`.
///
/// # Errors
/// From the core.
pub fn sweep36(
    scene: Scene36,
    method: Method,
    d_max: f32,
) -> Result<Vec<(f32, f64)>, volsample::Error> {
    let mut out = Vec::new();
    let mut i = 1;
    loop {
        let d = 0.05 * i as f32;
        if d > d_max + 1e-6 {
            break;
        }
        let limit = scene36(scene, method, d / REFINE, d)?;
        out.push((d, artifact_rms(&scene36(scene, method, d, d)?, &limit)));
        i += 1;
    }
    Ok(out)
}

/// The smallest `d` of a sweep whose RMS exceeds [`ARTIFACT_RMS`], if any.
pub fn first_failure(sweep: &[(f32, f64)]) -> Option<f32> {
    sweep
        .iter()
        .find(|(_, rms)| *rms > ARTIFACT_RMS)
        .map(|(d, _)| *d)
}

/// Sweep resolution of `volsample kraus`: `d` in steps of `2/ND`, `r` in steps of `1/NR`.
pub const ND: usize = 200;
/// See [`ND`].
pub const NR: usize = 100;

/// `volsample kraus`: writes `fig4.csv` and `fig4.png` into `out`, prints the maximum errors
/// over `0.5 < d < 1` per `τ_max`, and the §3.6 sweeps' first failing `d`.
///
/// # Errors
/// I/O or core errors, as text.
pub fn run(out: &std::path::Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| e.to_string())?;
    let rows = fig4_sweep(ND, NR);
    std::fs::write(out.join("fig4.csv"), fig4_csv(&rows)).map_err(|e| e.to_string())?;
    let (w, h, rgb) = fig4_image(&rows, ND, NR, 1);
    let png = encode_png(w, h, &rgb).map_err(|e| e.to_string())?;
    std::fs::write(out.join("fig4.png"), png).map_err(|e| e.to_string())?;
    crate::say!("Kraus fig. 1/4: max |alpha - (1 - e^-tau_max)| over 0.5 < d < 1 (d step 0.01, r step 0.01)");
    crate::say!(
        "{:>8} {:>15} {:>18}",
        "tau_max",
        "opacity-based",
        "extinction-based"
    );
    for (t, o, e) in fig4_max_errors(&rows, 0.5, 1.0) {
        crate::say!("{t:>8} {o:>15.6} {e:>18.6}");
    }
    crate::say!(
        "wrote {} and {} (rows: opacity-based, extinction-based; columns: tau_max 1, 2, 4, 8;",
        out.join("fig4.csv").display(),
        out.join("fig4.png").display()
    );
    crate::say!("  d grows to the right, r downwards; red = too opaque, blue = too transparent, full at 0.25)");
    crate::say!(
        "\nKraus §3.6, d = d', trilinear, {IMAGE}x{IMAGE} px: first d (step 0.05) whose opacity RMS against step d/{REFINE} exceeds 1/255"
    );
    for scene in Scene36::ALL {
        for method in Method::ALL {
            let sweep = sweep36(scene, method, 2.5).map_err(|e| e.to_string())?;
            let first = first_failure(&sweep)
                .map_or_else(|| "none up to 2.5".to_string(), |d| format!("{d:.2}"));
            crate::say!("{:<18} {:<18} {first}", scene.name(), method.name());
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// §3.5 with a fixed d′, and fig. 7 as the paper set it up.

/// The fig. 1 ray with opacity-based sampling whose vertex opacities hold for a fixed
/// reference distance `d_ref` (`α_v = 1 − e^(−τ_max·d′)`), opacity-corrected to the step `d`
/// (Kraus §3.5, "a larger distance `d′ > d`"):
/// `α = 1 − Π_k (1 − α_v·h(x_k))^(d/d′)` over the samples `x_k = (k + r)·d`.
///
/// With `d_ref = d` this is [`fig4_model`]`(OpacityBased, …)`.
pub fn fig4_model_fixed_dref(tau_max: f64, d: f64, d_ref: f64, r: f64) -> f64 {
    let k0 = (-1.0 / d - r).ceil() as i64;
    let k1 = (1.0 / d - r).floor() as i64;
    let a_v = -(-tau_max * d_ref).exp_m1();
    // Σ ln(1 − α_v·h), then the corrected transmittance e^((d/d′)·Σ).
    let log_t: f64 = (k0..=k1)
        .map(|k| (-a_v * hat((k as f64 + r) * d)).ln_1p())
        .sum();
    -((d / d_ref) * log_t).exp_m1()
}

/// The same ray through the core: [`fig4_core`]'s `9 × 2 × 1` volume with opacities for
/// `d_ref`, marched with `OpacityWeighted` at step `d` (the marcher corrects the opacity,
/// as `d ≠ d′`).
///
/// # Errors
/// From the core.
pub fn fig4_core_fixed_dref(
    tau_max: f32,
    d: f32,
    d_ref: f32,
    r: f32,
) -> Result<f32, volsample::Error> {
    let dims = [9, 2, 1];
    let steps_before = (6.0 / d).ceil();
    let ray = Ray::new([4.0 - steps_before * d, 0.5, 0.0], [1.0, 0.0, 0.0])?;
    let step = Step::new(d)?.with_phase(r)?;
    let a_v = -(-tau_max * d_ref).exp_m1();
    let vox: Vec<StraightF32> = (0..18)
        .map(|i| StraightF32 {
            c: [1.0; 3],
            a: if i % 9 == 4 { a_v } else { 0.0 },
        })
        .collect();
    let vol = Volume::new(&vox, dims)?.with_reference_distance(d_ref)?;
    let m = RayMarcher::new(
        vol,
        OpacityWeighted,
        Trilinear::new(),
        crate::pipeline::front_to_back()?,
        step,
    )?;
    Ok(m.cast(&ray).a)
}

/// The orthographic camera of the §3.6 renderings ([`scene36`]).
///
/// # Errors
/// From the core (never for these constants).
pub fn scene36_camera() -> Result<Orthographic, volsample::Error> {
    let dir = [1.0f32, 0.37, 0.23];
    let centre = [11.5f32; 3];
    let eye = [
        centre[0] - 30.0 * dir[0],
        centre[1] - 30.0 * dir[1],
        centre[2] - 30.0 * dir[2],
    ];
    Orthographic::new(eye, dir, [0.0, 0.0, 1.0], 12.0)
}

/// The occupancy of the §3.6 scenes' `24³` volume (1 where [`Scene36::voxels`] is opaque).
pub fn scene36_occupancy(scene: Scene36) -> Vec<f64> {
    scene
        .voxels()
        .iter()
        .map(|v| if v.a > 0.0 { 1.0 } else { 0.0 })
        .collect()
}

/// Kraus fig. 7 as the paper sets its experiments up (§3.5): the occupied voxels of `scene`
/// have a fixed extinction `τ` per unit length (independent of the step), white; the
/// opacity-based rendering stores the opacity for `d′ = d`, `α_v = 1 − e^(−τd)`; the
/// extinction-based one stores `τ`. Step `d`, sample phase `r` (a viewing parameter: where
/// the samples fall along the rays). The camera and image are those of [`scene36`].
///
/// # Errors
/// From the core.
pub fn scene36_tau(
    scene: Scene36,
    method: Method,
    tau: f32,
    d: f32,
    r: f32,
) -> Result<Vec<f32>, volsample::Error> {
    let dims = [24, 24, 24];
    let occ = scene36_occupancy(scene);
    let cam = scene36_camera()?;
    let step = Step::new(d)?.with_phase(r)?;
    let mut img = vec![Sample::TRANSPARENT; IMAGE * IMAGE];
    match method {
        Method::OpacityBased => {
            let a_v = -(-tau * d).exp_m1();
            let vox: Vec<StraightF32> = occ
                .iter()
                .map(|&o| StraightF32 {
                    c: [1.0; 3],
                    a: if o > 0.0 { a_v } else { 0.0 },
                })
                .collect();
            let vol = Volume::new(&vox, dims)?.with_reference_distance(d)?;
            RayMarcher::new(
                vol,
                OpacityWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .render_into(&cam, IMAGE, IMAGE, &mut img)?;
        }
        Method::ExtinctionBased => {
            let vox: Vec<ExtinctionF32> = occ
                .iter()
                .map(|&o| white_extinction(if o > 0.0 { tau } else { 0.0 }))
                .collect();
            let vol = Volume::new(&vox, dims)?;
            RayMarcher::new(
                vol,
                ExtinctionWeighted,
                Trilinear::new(),
                crate::pipeline::front_to_back()?,
                step,
            )?
            .render_into(&cam, IMAGE, IMAGE, &mut img)?;
        }
    }
    Ok(img.iter().map(|s| s.a).collect())
}

/// The trilinear interpolation of the scalar field `f` (`24³`, `x` fastest) at `p`, in f64,
/// clamped to the edge as the core's filters are (a position outside `[0, 23]` reads the
/// nearest edge plane).
fn trilinear_f64(f: &[f64], p: [f64; 3]) -> f64 {
    let n = 24usize;
    let p = p.map(|c| c.clamp(0.0, (n - 1) as f64));
    let i = p.map(|c| (c.floor() as usize).min(n - 2));
    let t = [0, 1, 2].map(|k| p[k] - i[k] as f64);
    let mut s = 0.0;
    for corner in 0..8usize {
        let o = [corner & 1, (corner >> 1) & 1, corner >> 2];
        let w: f64 = (0..3)
            .map(|k| if o[k] == 1 { t[k] } else { 1.0 - t[k] })
            .product();
        s += w * f[(i[0] + o[0]) + n * ((i[1] + o[1]) + n * (i[2] + o[2]))];
    }
    s
}

/// `∫ f(o + s·u) ds` of the trilinearly interpolated `24³` field `f` (clamped to the edge)
/// along a line, over the part inside the volume box `[−½, 23.5]³` (where the core's rays
/// sample), in f64. Between consecutive crossings of the planes `x, y, z ∈ {0, 1, …, 23}`
/// the integrand is a polynomial of degree at most 3 in `s`, which Simpson's rule integrates
/// exactly, so the result is exact up to rounding.
pub fn line_integral_trilinear(f: &[f64], o: [f64; 3], u: [f64; 3]) -> f64 {
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if u[k] == 0.0 {
            if !(-0.5..=23.5).contains(&o[k]) {
                return 0.0;
            }
        } else {
            let (a, b) = ((-0.5 - o[k]) / u[k], (23.5 - o[k]) / u[k]);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
        }
    }
    if hi <= lo {
        return 0.0;
    }
    let mut cuts = vec![lo, hi];
    for k in 0..3 {
        if u[k] != 0.0 {
            for plane in 0..=23 {
                let s = (f64::from(plane) - o[k]) / u[k];
                if s > lo && s < hi {
                    cuts.push(s);
                }
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let at = |s: f64| trilinear_f64(f, [0, 1, 2].map(|k| o[k] + s * u[k]));
    cuts.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            (b - a) / 6.0 * (at(a) + 4.0 * at(0.5 * (a + b)) + at(b))
        })
        .sum()
}

/// The exact opacity image of [`scene36_tau`]'s data: per pixel (the same rays),
/// `1 − e^(−τ·∫ occupancy)` with the trilinearly interpolated occupancy integrated exactly
/// ([`line_integral_trilinear`]): the limit both methods approach as `d → 0` (Kraus eq. 1
/// for the interpolated extinction field).
///
/// # Errors
/// From the core's camera.
pub fn scene36_exact(scene: Scene36, tau: f64) -> Result<Vec<f64>, volsample::Error> {
    use volsample::Camera;
    let occ = scene36_occupancy(scene);
    let cam = scene36_camera()?;
    let mut out = Vec::with_capacity(IMAGE * IMAGE);
    for j in 0..IMAGE {
        for i in 0..IMAGE {
            let ray = cam.ray(i, j, IMAGE, IMAGE);
            let o = ray.origin().map(f64::from);
            let u = ray.dir().map(f64::from);
            let len = u.iter().map(|c| c * c).sum::<f64>().sqrt();
            let u = u.map(|c| c / len);
            out.push(-(-tau * line_integral_trilinear(&occ, o, u)).exp_m1());
        }
    }
    Ok(out)
}

/// The fig. 7 measures of one method at one `τ` and step `d`, over the sample phases
/// `r = j/phases`: `(RMS of α − exact over all pixels and phases, RMS over pixels of the
/// standard deviation of α across the phases)`. The first is the error; the second is the
/// paper's "variation of the projected intensity depending on the viewing parameters"
/// (the exact image does not depend on the phase).
///
/// # Errors
/// From the core.
pub fn fig7_measures(
    scene: Scene36,
    method: Method,
    tau: f32,
    d: f32,
    phases: usize,
    exact: &[f64],
) -> Result<(f64, f64), volsample::Error> {
    let imgs: Vec<Vec<f32>> = (0..phases)
        .map(|j| scene36_tau(scene, method, tau, d, j as f32 / phases as f32))
        .collect::<Result<_, _>>()?;
    let n = exact.len() as f64;
    let mut err2 = 0.0;
    let mut var = 0.0;
    for (p, &e) in exact.iter().enumerate() {
        let vals: Vec<f64> = imgs.iter().map(|im| f64::from(im[p])).collect();
        let mean = vals.iter().sum::<f64>() / phases as f64;
        err2 += vals.iter().map(|v| (v - e).powi(2)).sum::<f64>() / phases as f64;
        var += vals.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / phases as f64;
    }
    Ok(((err2 / n).sqrt(), (var / n).sqrt()))
}

/// A white voxel of extinction `t`: `τ = t`, `C^τ = t·(1, 1, 1)`.
fn white_extinction(t: f32) -> ExtinctionF32 {
    ExtinctionF32 {
        c_tau: [t; 3],
        tau: t,
    }
}
