//! The float ray marcher's fast paths against one ray at a time, for the fuzz target
//! `marcher_packets` and its corpus replay (`tests/int_corpus_replay.rs` runs every target of
//! [`crate::checks::TARGETS`], this one included).
//!
//! For a fuzzed volume (every voxel format and mode: `OpacityWeighted`, `Separate`,
//! `Preweighted` and `ExtinctionWeightedU8` over bytes; `OpacityWeighted`, `Separate`,
//! `ExtinctionWeighted` and `PostClassified` over `f32`), filter and order (trilinear with a
//! threshold and a background, the lerp tree, nearest, the B-spline front to back, trilinear
//! back to front), step, phase and rays, in every instruction set this CPU has
//! (`volsample::Isa::available`), bit for bit against the baseline instance's single rays:
//! - `cast_counted` (four samples of a ray in lanes) and its sample count;
//! - `cast4` packets and `cast_rays` of every length 0 to 9 (each packet tail);
//! - `render_into` with an orthographic camera against `cast` of each pixel's ray;
//! - front to back, `cast_counted` against the public per-sample kernel one sample at a time
//!   (`RayMarcher::sample`, `front_to_back`, `over`);
//! - for the `f32` storage modes, the image of the fuzzed camera, filter, order, step and
//!   phase against the f64 reference renderer within the tolerance table's pixel bound
//!   ([`FloatCase::compare_image`], as the property test `render_matches_reference` holds it).

use crate::float_checks::{CameraSpec, FilterKind, FloatCase, ModeKind, RenderSpec};
use arbitrary::Arbitrary;
use volsample::composite::{front_to_back, over, Order, Termination};
use volsample::mode::{ExtinctionWeightedU8, TauTable};
use volsample::skip::Skipping;
use volsample::voxel::Voxel;
use volsample::{
    AssociatedU8, BackToFront, Camera, ControlPoint, ExtinctionF32, ExtinctionWeighted, Filter,
    FrontToBack, Isa, Mode, Nearest, OpacityWeighted, Orthographic, PostClassified, Preweighted,
    Ray, RayMarcher, Sample, Separate, Step, StraightF32, StraightU8, Threshold, TransferFunction,
    Trilinear, TriquadraticBSpline, Volume,
};

/// One fuzz input of `marcher_packets`.
#[derive(Debug, Default, Arbitrary)]
pub struct MarcherInput {
    /// Dimensions, each `1 + d % 5`.
    pub dims: [u8; 3],
    /// Voxel format and mode (8 of them).
    pub mode: u8,
    /// Filter and order (5 of them).
    pub filter: u8,
    /// Reference distance `0.25 + d / 128`.
    pub d_ref: u8,
    /// Step `0.05 + s / 160`.
    pub step: u8,
    /// Step phase `p / 256`.
    pub phase: u8,
    /// Early-termination threshold `(1 + t) / 256`.
    pub stop: u8,
    /// Nine rays: origin offsets and direction, each byte mapped to `[-1, 1)`.
    pub rays: [[u8; 6]; 9],
    /// Camera: the eye's offset and direction.
    pub camera: [u8; 6],
    /// Voxel bytes, cycled to fill the volume.
    pub voxels: Vec<u8>,
}

fn unit(b: u8) -> f32 {
    f32::from(b) / 128.0 - 1.0
}

fn same(a: &Sample, b: &Sample) -> bool {
    a.a.to_bits() == b.a.to_bits()
        && a.c
            .iter()
            .zip(&b.c)
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The input's voxel bytes, cycled to fill a volume of `dims` (zeros if there are none).
fn straight_u8(inp: &MarcherInput, dims: [usize; 3]) -> Vec<StraightU8> {
    let n = dims[0] * dims[1] * dims[2];
    let bytes: Vec<u8> = if inp.voxels.is_empty() {
        vec![0; 4 * n]
    } else {
        inp.voxels.iter().copied().cycle().take(4 * n).collect()
    };
    bytes
        .chunks_exact(4)
        .map(|c| StraightU8([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// `v` in `f32`, each byte over 255.
fn to_f32(v: StraightU8) -> StraightF32 {
    let [r, g, b, a] = v.0.map(|n| f32::from(n) / 255.0);
    StraightF32 { c: [r, g, b], a }
}

/// A ray from `b` starting outside a box of `dims`, aimed near its centre (`None` for a
/// direction the core refuses).
fn ray(b: [u8; 6], dims: [usize; 3]) -> Option<Ray> {
    let c = dims.map(|n| n as f32 * 0.5 - 0.5);
    let dir = [b[3], b[4], b[5]].map(unit);
    let back = 2.0 * dims.iter().copied().max().unwrap_or(1) as f32;
    let origin = [0, 1, 2].map(|k| c[k] + unit(b[k]) * c[k].max(0.5) - dir[k] * back);
    Ray::new(origin, dir).ok()
}

/// Runs the check of [`MarcherInput`] (see the module documentation).
///
/// # Errors
/// The first difference found, naming the mode, filter, instruction set and ray.
pub fn marcher_packets(inp: &MarcherInput) -> Result<(), String> {
    let dims = inp.dims.map(|d| usize::from(d % 5) + 1);
    let u8s = straight_u8(inp, dims);
    let f32s: Vec<StraightF32> = u8s.iter().map(|v| to_f32(*v)).collect();
    let d_ref = 0.25 + f32::from(inp.d_ref) / 128.0;
    let step = Step::new(0.05 + f32::from(inp.step) / 160.0)
        .and_then(|s| s.with_phase(f32::from(inp.phase) / 256.0))
        .map_err(|e| format!("step: {e}"))?;
    let stop = FrontToBack(
        Threshold::new((1.0 + f32::from(inp.stop)) / 256.0).map_err(|e| format!("stop: {e}"))?,
    );
    let rays: Vec<Ray> = inp.rays.iter().filter_map(|&b| ray(b, dims)).collect();
    let cam = {
        let c = dims.map(|n| n as f32 * 0.5 - 0.5);
        let d = [inp.camera[3], inp.camera[4], inp.camera[5]].map(unit);
        let back = 2.0 * dims.iter().copied().max().unwrap_or(1) as f32;
        let eye = [0, 1, 2].map(|k| c[k] + unit(inp.camera[k]) - d[k] * back);
        let up = if d[0].abs() < 0.5 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        Orthographic::new(eye, d, up, back).ok()
    };
    against_reference(inp)?;
    let f = Family {
        filter: inp.filter % 5,
        stop,
        step,
        rays: &rays,
        cam,
    };
    match inp.mode % 8 {
        0 => f.run(vol(dims, d_ref, &u8s)?, OpacityWeighted, "OW u8"),
        1 => f.run(vol(dims, d_ref, &u8s)?, Separate, "Separate u8"),
        2 => {
            let assoc: Vec<AssociatedU8> = u8s
                .iter()
                .map(|v| {
                    let [r, g, b, a] = v.0;
                    let m = |c: u8| ((u16::from(c) * u16::from(a)) / 255) as u8;
                    AssociatedU8([m(r), m(g), m(b), a])
                })
                .collect();
            f.run(vol(dims, d_ref, &assoc)?, Preweighted, "Preweighted u8")
        }
        3 => {
            let taus = TauTable::new(d_ref).map_err(|e| format!("taus: {e}"))?;
            f.run(
                vol(dims, d_ref, &u8s)?,
                ExtinctionWeightedU8::new(&taus),
                "Extinction u8",
            )
        }
        4 => f.run(vol(dims, d_ref, &f32s)?, OpacityWeighted, "OW f32"),
        5 => f.run(vol(dims, d_ref, &f32s)?, Separate, "Separate f32"),
        6 => {
            let ext: Vec<ExtinctionF32> = f32s
                .iter()
                .map(|&v| ExtinctionF32::from_straight(v, d_ref))
                .collect();
            let v = Volume::new(&ext, dims).map_err(|e| format!("volume: {e}"))?;
            f.run(v, ExtinctionWeighted, "Extinction f32")
        }
        _ => {
            let scalars: Vec<f32> = u8s.iter().map(|v| f32::from(v.0[0]) / 255.0).collect();
            let tf =
                TransferFunction::<3>::new(&tf_points(&u8s)).map_err(|e| format!("tf: {e}"))?;
            f.run(
                vol(dims, d_ref, &scalars)?,
                PostClassified::new(&tf),
                "PostClassified",
            )
        }
    }
}

/// The transfer function of `PostClassified`: its first point's colour and opacity come from
/// the first voxel.
fn tf_points(u8s: &[StraightU8]) -> [ControlPoint; 3] {
    let [a, b, c, d] = u8s
        .first()
        .map_or([0; 4], |v| v.0)
        .map(|x| f32::from(x) / 255.0);
    [
        ControlPoint {
            s: 0.0,
            c: [a, b, c],
            a: d,
        },
        ControlPoint {
            s: 0.4,
            c: [1.0, 0.5, 0.2],
            a: 0.3,
        },
        ControlPoint {
            s: 1.0,
            c: [1.0; 3],
            a: 0.9,
        },
    ]
}

/// The `f32` storage modes (`inp.mode` 4 to 7) rendered with the fuzzed camera, filter, order,
/// step and phase, against the f64 reference renderer within
/// [`render_pixel_bound`](crate::tolerance::render_pixel_bound). As in the property test,
/// opacities are scaled by 0.9 when `d ≠ d′`, where the bound needs opacity correction well
/// conditioned. The core's image comes from the marcher types the bit-identity check builds
/// (the same filter, order, threshold and background), so the fuzz build gains no marcher
/// instances.
///
/// Returns how many pixels were compared (0 for the other modes and for a camera the core
/// refuses).
///
/// # Errors
/// The first pixel out of its bound.
pub fn against_reference(inp: &MarcherInput) -> Result<usize, String> {
    let mode = match inp.mode % 8 {
        4 => ModeKind::OpacityWeighted,
        5 => ModeKind::Separate,
        6 => ModeKind::ExtinctionWeighted,
        7 => ModeKind::PostClassified,
        _ => return Ok(0),
    };
    let dims = inp.dims.map(|d| usize::from(d % 5) + 1);
    let u8s = straight_u8(inp, dims);
    let mut case = FloatCase {
        dims,
        voxels: u8s.iter().map(|v| to_f32(*v)).collect(),
        scalars: u8s.iter().map(|v| f32::from(v.0[0]) / 255.0).collect(),
        tf: tf_points(&u8s).to_vec(),
        d_ref: 0.25 + f32::from(inp.d_ref) / 128.0,
    };
    let step = 0.05 + f32::from(inp.step) / 160.0;
    if step != case.d_ref {
        for v in &mut case.voxels {
            v.a *= 0.9;
        }
        for p in &mut case.tf {
            p.a *= 0.9;
        }
    }
    let c = case.dims.map(|n| n as f32 * 0.5 - 0.5);
    let d = [inp.camera[3], inp.camera[4], inp.camera[5]].map(unit);
    let len = d.iter().map(|x| x * x).sum::<f32>().sqrt();
    let back = 2.0 * case.dims.iter().copied().max().unwrap_or(1) as f32;
    let eye = [0, 1, 2].map(|k| c[k] + unit(inp.camera[k]) - d[k] * back);
    let up = if d[0].abs() < 0.5 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    // The reference camera takes a unit direction (the core normalises its own).
    let dir = d.map(|x| x / len);
    if len == 0.0 || Orthographic::new(eye, dir, up, back).is_err() {
        return Ok(0);
    }
    let threshold = (1.0 + f32::from(inp.stop)) / 256.0;
    let selector = inp.filter % 5;
    let (filter, a_stop, background, back_to_front) = match selector {
        0 => (FilterKind::TrilinearSum, threshold, BG, false),
        1 => (FilterKind::TrilinearTree, 1.0, Sample::TRANSPARENT, false),
        2 => (FilterKind::Nearest, threshold, Sample::TRANSPARENT, false),
        3 => (FilterKind::BSpline, 1.0, Sample::TRANSPARENT, false),
        _ => (FilterKind::TrilinearSum, 1.0, Sample::TRANSPARENT, true),
    };
    let spec = RenderSpec {
        camera: CameraSpec::Orthographic(eye, dir, up, back),
        width: 5,
        height: 3,
        step,
        phase: f32::from(inp.phase) / 256.0,
        background,
        a_stop,
        back_to_front,
    };
    let cam = Orthographic::new(eye, dir, up, back).map_err(|e| format!("camera: {e}"))?;
    let stop = FrontToBack(Threshold::new(threshold).map_err(|e| format!("stop: {e}"))?);
    let step = Step::new(step)
        .and_then(|s| s.with_phase(spec.phase))
        .map_err(|e| format!("step: {e}"))?;
    let look = Look {
        selector,
        stop,
        step,
        cam,
        spec,
    };
    // The core's image through the marcher types `Family::run` builds (no further
    // instances), on the conditioned case's voxels.
    let d_ref = case.d_ref;
    let image = match mode {
        ModeKind::OpacityWeighted => look.image(vol(dims, d_ref, &case.voxels)?, OpacityWeighted),
        ModeKind::Separate => look.image(vol(dims, d_ref, &case.voxels)?, Separate),
        ModeKind::ExtinctionWeighted => {
            look.image(vol(dims, d_ref, &case.extinction())?, ExtinctionWeighted)
        }
        _ => {
            let tf = TransferFunction::<3>::new(&case.tf).map_err(|e| format!("tf: {e}"))?;
            look.image(vol(dims, d_ref, &case.scalars)?, PostClassified::new(&tf))
        }
    }?;
    case.compare_image(mode, filter, &spec, &image)
        .map(|(compared, _)| compared)
        .map_err(|e| format!("against the reference: {e}"))
}

/// The camera, filter/order, threshold and step of [`against_reference`].
struct Look {
    selector: u8,
    stop: FrontToBack<Threshold>,
    step: Step,
    cam: Orthographic,
    spec: RenderSpec,
}

impl Look {
    /// The image of `mode` on `vol`, through the marcher [`Family::run`] builds for the same
    /// filter selector.
    fn image<V: Voxel, M: Mode<V> + Copy>(
        &self,
        vol: Volume<'_, V>,
        mode: M,
    ) -> Result<Vec<Sample>, String> {
        let (w, h) = (self.spec.width, self.spec.height);
        let mut img = vec![Sample::TRANSPARENT; w * h];
        let (stop, step, ftb) = (self.stop, self.step, FrontToBack::new());
        let err = |e: volsample::Error| format!("reference image: {e}");
        match self.selector {
            0 => RayMarcher::new(vol, mode, Trilinear::new(), stop, step)
                .and_then(|m| m.with_background(BG))
                .and_then(|m| m.render_into(&self.cam, w, h, &mut img)),
            1 => RayMarcher::new(vol, mode, Trilinear::tree(), ftb, step)
                .and_then(|m| m.render_into(&self.cam, w, h, &mut img)),
            2 => RayMarcher::new(vol, mode, Nearest, stop, step)
                .and_then(|m| m.render_into(&self.cam, w, h, &mut img)),
            3 => RayMarcher::new(vol, mode, TriquadraticBSpline, ftb, step)
                .and_then(|m| m.render_into(&self.cam, w, h, &mut img)),
            _ => RayMarcher::new(vol, mode, Trilinear::new(), BackToFront, step)
                .and_then(|m| m.render_into(&self.cam, w, h, &mut img)),
        }
        .map_err(err)?;
        Ok(img)
    }
}

/// `data` as a volume of `dims` with the reference distance `d_ref`.
fn vol<V: Voxel>(dims: [usize; 3], d_ref: f32, data: &[V]) -> Result<Volume<'_, V>, String> {
    Volume::new(data, dims)
        .and_then(|v| v.with_reference_distance(d_ref))
        .map_err(|e| format!("volume: {e}"))
}

/// What a case shares across voxel formats and modes.
struct Family<'r> {
    filter: u8,
    stop: FrontToBack<Threshold>,
    step: Step,
    rays: &'r [Ray],
    cam: Option<Orthographic>,
}

/// The background of the trilinear front-to-back marcher.
const BG: Sample = Sample {
    c: [0.1, 0.2, 0.3],
    a: 0.5,
};

impl Family<'_> {
    fn run<V: Voxel, M: Mode<V> + Copy>(
        &self,
        vol: Volume<'_, V>,
        mode: M,
        what: &str,
    ) -> Result<(), String> {
        let (stop, step, ftb) = (self.stop, self.step, FrontToBack::new());
        let t = Sample::TRANSPARENT;
        let done = |a| stop.0.done(a);
        let never = |_: f32| false;
        let err = |e: volsample::Error| format!("{what}: marcher: {e}");
        match self.filter {
            0 => {
                let m = RayMarcher::new(vol, mode, Trilinear::new(), stop, step)
                    .and_then(|m| m.with_background(BG))
                    .map_err(err)?;
                self.check(&m, &format!("{what} trilinear"))?;
                lanes(&m, self.rays, done, BG, &format!("{what} trilinear"))
            }
            1 => {
                let m = RayMarcher::new(vol, mode, Trilinear::tree(), ftb, step).map_err(err)?;
                self.check(&m, &format!("{what} tree"))?;
                lanes(&m, self.rays, never, t, &format!("{what} tree"))
            }
            2 => {
                let m = RayMarcher::new(vol, mode, Nearest, stop, step).map_err(err)?;
                self.check(&m, &format!("{what} nearest"))?;
                lanes(&m, self.rays, done, t, &format!("{what} nearest"))
            }
            3 => {
                let m = RayMarcher::new(vol, mode, TriquadraticBSpline, ftb, step).map_err(err)?;
                self.check(&m, &format!("{what} bspline"))?;
                lanes(&m, self.rays, never, t, &format!("{what} bspline"))
            }
            _ => {
                let m =
                    RayMarcher::new(vol, mode, Trilinear::new(), BackToFront, step).map_err(err)?;
                self.check(&m, &format!("{what} back to front"))
            }
        }
    }

    /// Packets, `cast_rays` and `render_into` of every instance against the baseline's
    /// single rays.
    fn check<V, M, F, O, S>(
        &self,
        m: &RayMarcher<'_, V, M, F, O, S>,
        what: &str,
    ) -> Result<(), String>
    where
        V: Voxel,
        M: Mode<V>,
        F: Filter,
        O: Order,
        S: Skipping,
        for<'a> RayMarcher<'a, V, M, F, O, S>: Copy,
    {
        let base = m.with_isa(Isa::BASELINE);
        for isa in Isa::available() {
            let m = m.with_isa(isa);
            let what = format!("{what}, {isa}");
            for four in self.rays.chunks_exact(4) {
                let four: [Ray; 4] = [four[0], four[1], four[2], four[3]];
                for (ray, (got, n)) in four.iter().zip(m.cast4(&four)) {
                    let (want, k) = base.cast_counted(ray);
                    if !(same(&got, &want) && n == k) {
                        return Err(format!(
                            "{what}: {ray:?}: packet {got:?} ({n} samples) vs single {want:?} ({k})"
                        ));
                    }
                }
            }
            for len in 0..=self.rays.len() {
                let mut out = vec![Sample::TRANSPARENT; len];
                m.cast_rays(&self.rays[..len], &mut out)
                    .map_err(|e| format!("{what}: cast_rays: {e}"))?;
                for (ray, got) in self.rays.iter().zip(&out) {
                    let want = base.cast(ray);
                    if !same(got, &want) {
                        return Err(format!(
                            "{what}: cast_rays of {len} {ray:?}: {got:?} vs single {want:?}"
                        ));
                    }
                }
            }
            if let Some(cam) = &self.cam {
                let (w, h) = (5, 3);
                let mut img = vec![Sample::TRANSPARENT; w * h];
                m.render_into(cam, w, h, &mut img)
                    .map_err(|e| format!("{what}: render_into: {e}"))?;
                for (k, got) in img.iter().enumerate() {
                    let ray = cam.ray(k % w, k / w, w, h);
                    let want = base.cast(&ray);
                    if !same(got, &want) {
                        return Err(format!(
                            "{what}: render_into pixel {k} {ray:?}: {got:?} vs single {want:?}"
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Front to back: `cast_counted` of every instance against the per-sample kernel one sample at
/// a time (stopping after the sample at which `done` holds, then over `bg`), counts included.
fn lanes<V, M, F, O, S>(
    m: &RayMarcher<'_, V, M, F, O, S>,
    rays: &[Ray],
    done: impl Fn(f32) -> bool,
    bg: Sample,
    what: &str,
) -> Result<(), String>
where
    V: Voxel,
    M: Mode<V>,
    F: Filter,
    O: Order,
    S: Skipping,
    for<'a> RayMarcher<'a, V, M, F, O, S>: Copy,
{
    for ray in rays {
        let (t_first, n) = m.sample_range(ray);
        let d = m.step().d();
        let mut acc = Sample::TRANSPARENT;
        let mut k = n;
        for j in 0..n {
            acc = front_to_back(acc, m.sample(ray.at(t_first + j as f32 * d)));
            if done(acc.a) {
                k = j + 1;
                break;
            }
        }
        let want = over(acc, bg);
        for isa in Isa::available() {
            let (got, c) = m.with_isa(isa).cast_counted(ray);
            if !(same(&got, &want) && c == k) {
                return Err(format!(
                    "{what}, {isa}: {ray:?}: lanes {got:?} ({c} samples) vs one at a time {want:?} ({k})"
                ));
            }
        }
    }
    Ok(())
}
