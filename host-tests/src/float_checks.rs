//! Float kernels against the independent f64 reference: the cases, the dispatch over every
//! mode × filter, and the error measures the property tests, the sweeps and the fuzz targets
//! share.

use volsample::{
    AssociatedF32, ControlPoint, ExtinctionF32, ExtinctionWeighted, Filter, FrontToBack, Mode,
    Nearest, OpacityWeighted, PostClassified, Preweighted, RayMarcher, Sample, Separate, Step,
    StraightF32, TransferFunction, Tree, Trilinear, TriquadraticBSpline, Volume, WeightedSum,
};

use crate::reference::{
    self, RefAssoc, RefAssocVolume, RefControlPoint, RefExtinction, RefFilter, RefMode,
    RefScalarVolume, RefSource, RefTransferFunction, RefVolume, RefVoxel,
};

/// Capacity of the transfer functions the float cases use.
pub const TF_CAP: usize = 8;

/// Every sampling mode, as a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModeKind {
    /// [`Separate`].
    Separate,
    /// [`OpacityWeighted`].
    OpacityWeighted,
    /// [`Preweighted`] on `f32` associated voxels.
    Preweighted,
    /// [`ExtinctionWeighted`] on `f32` extinction voxels.
    ExtinctionWeighted,
    /// [`PostClassified`] on `f32` scalars.
    PostClassified,
}

impl ModeKind {
    /// All modes.
    pub const ALL: [ModeKind; 5] = [
        ModeKind::Separate,
        ModeKind::OpacityWeighted,
        ModeKind::Preweighted,
        ModeKind::ExtinctionWeighted,
        ModeKind::PostClassified,
    ];

    fn reference(self) -> RefMode {
        match self {
            ModeKind::Separate => RefMode::Separate,
            ModeKind::OpacityWeighted => RefMode::OpacityWeighted,
            ModeKind::Preweighted => RefMode::Preweighted,
            ModeKind::ExtinctionWeighted => RefMode::ExtinctionWeighted,
            ModeKind::PostClassified => RefMode::PostClassified,
        }
    }
}

/// Every filter (and trilinear evaluation order), as a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FilterKind {
    /// [`Nearest`].
    Nearest,
    /// [`Trilinear`] as a lerp tree.
    TrilinearTree,
    /// [`Trilinear`] as a weighted sum.
    TrilinearSum,
    /// [`TriquadraticBSpline`].
    BSpline,
}

impl FilterKind {
    /// All filters.
    pub const ALL: [FilterKind; 4] = [
        FilterKind::Nearest,
        FilterKind::TrilinearTree,
        FilterKind::TrilinearSum,
        FilterKind::BSpline,
    ];

    /// The reference filter.
    pub fn reference(self) -> RefFilter {
        match self {
            FilterKind::Nearest => RefFilter::Nearest,
            FilterKind::TrilinearTree | FilterKind::TrilinearSum => RefFilter::Trilinear,
            FilterKind::BSpline => RefFilter::TriquadraticBSpline,
        }
    }

    /// Taps per sample.
    pub fn taps(self) -> usize {
        match self {
            FilterKind::Nearest => 1,
            FilterKind::TrilinearTree | FilterKind::TrilinearSum => 8,
            FilterKind::BSpline => 27,
        }
    }
}

/// One float test case: a volume in every storage form, and a transfer function.
///
/// All storage forms derive from `voxels` in `f32`; the reference reads the *stored* `f32`
/// values (converted exactly to `f64`), so a comparison measures the kernel, not the storage.
#[derive(Debug, Clone)]
pub struct FloatCase {
    /// Volume dimensions.
    pub dims: [usize; 3],
    /// Straight voxels.
    pub voxels: Vec<StraightF32>,
    /// Scalars for `PostClassified`.
    pub scalars: Vec<f32>,
    /// Transfer-function control points (strictly increasing `s`).
    pub tf: Vec<ControlPoint>,
    /// Reference distance `d′`.
    pub d_ref: f32,
}

impl FloatCase {
    /// The associated voxels, rounded to `f32` as a user would store them.
    pub fn associated(&self) -> Vec<AssociatedF32> {
        self.voxels
            .iter()
            .map(|&v| AssociatedF32::from_straight(v))
            .collect()
    }

    /// The extinction voxels, converted in `f32` as a user would store them.
    pub fn extinction(&self) -> Vec<ExtinctionF32> {
        self.voxels
            .iter()
            .map(|&v| ExtinctionF32::from_straight(v, self.d_ref))
            .collect()
    }

    /// The core transfer function.
    ///
    /// # Panics
    /// If the control points are invalid (a bad test case).
    pub fn transfer_function(&self) -> TransferFunction<TF_CAP> {
        TransferFunction::new(&self.tf).expect("valid test transfer function")
    }

    fn ref_straight(&self) -> RefVolume {
        let vox = self
            .voxels
            .iter()
            .map(|v| RefVoxel::new(v.c.map(f64::from), f64::from(v.a)))
            .collect();
        RefVolume::new(self.dims, vox, f64::from(self.d_ref))
    }

    fn ref_tf(&self) -> RefTransferFunction {
        RefTransferFunction::new(
            self.tf
                .iter()
                .map(|p| RefControlPoint::new(f64::from(p.s), p.c.map(f64::from), f64::from(p.a)))
                .collect(),
        )
    }

    /// The reference sample of `mode` with `filter` at `pos` for step `d`, computed from the
    /// same stored `f32` values the core reads.
    pub fn reference_sample(
        &self,
        mode: ModeKind,
        filter: FilterKind,
        pos: [f32; 3],
        d: f32,
    ) -> RefAssoc {
        let pos = pos.map(f64::from);
        let d = f64::from(d);
        let f = filter.reference();
        match mode {
            ModeKind::Separate | ModeKind::OpacityWeighted => reference::sample(
                RefSource::Straight(&self.ref_straight()),
                mode.reference(),
                f,
                pos,
                d,
            ),
            ModeKind::Preweighted => {
                let vox = self
                    .associated()
                    .iter()
                    .map(|v| RefAssoc::new(v.c.map(f64::from), f64::from(v.a)))
                    .collect();
                let vol = RefAssocVolume::new(self.dims, vox, f64::from(self.d_ref));
                reference::sample(RefSource::Associated(&vol), RefMode::Preweighted, f, pos, d)
            }
            ModeKind::ExtinctionWeighted => {
                // Interpolate the stored (τ, C^τ) with the reference taps, then integrate.
                let ext = self.extinction();
                let mut e = RefExtinction {
                    tau: 0.0,
                    color_tau: [0.0; 3],
                };
                for (i, w) in reference::taps(self.dims, f, pos) {
                    e.tau += w * f64::from(ext[i].tau);
                    for k in 0..3 {
                        e.color_tau[k] += w * f64::from(ext[i].c_tau[k]);
                    }
                }
                reference::extinction_sample(e, d)
            }
            ModeKind::PostClassified => {
                let sv = RefScalarVolume::new(
                    self.dims,
                    self.scalars.iter().map(|&s| f64::from(s)).collect(),
                    f64::from(self.d_ref),
                );
                let tf = self.ref_tf();
                reference::sample(
                    RefSource::Scalar(&sv, &tf),
                    RefMode::PostClassified,
                    f,
                    pos,
                    d,
                )
            }
        }
    }

    /// The core sample of `mode` with `filter` at `pos` for step `d` (through
    /// [`RayMarcher::sample`], so opacity correction is included when `d ≠ d′`).
    ///
    /// # Panics
    /// If the core rejects the case (a bad test case).
    pub fn core_sample(&self, mode: ModeKind, filter: FilterKind, pos: [f32; 3], d: f32) -> Sample {
        let step = Step::new(d).expect("valid step");
        match mode {
            ModeKind::Separate => self.with_filter(&self.voxels, Separate, filter, step, pos),
            ModeKind::OpacityWeighted => {
                self.with_filter(&self.voxels, OpacityWeighted, filter, step, pos)
            }
            ModeKind::Preweighted => {
                self.with_filter(&self.associated(), Preweighted, filter, step, pos)
            }
            ModeKind::ExtinctionWeighted => {
                self.with_filter(&self.extinction(), ExtinctionWeighted, filter, step, pos)
            }
            ModeKind::PostClassified => {
                let tf = self.transfer_function();
                self.with_filter(&self.scalars, PostClassified::new(&tf), filter, step, pos)
            }
        }
    }

    fn with_filter<V: volsample::voxel::Voxel, M: Mode<V> + Copy>(
        &self,
        data: &[V],
        mode: M,
        filter: FilterKind,
        step: Step,
        pos: [f32; 3],
    ) -> Sample {
        match filter {
            FilterKind::Nearest => self.run(data, mode, Nearest, step, pos),
            FilterKind::TrilinearTree => self.run(data, mode, Trilinear(Tree), step, pos),
            FilterKind::TrilinearSum => self.run(data, mode, Trilinear(WeightedSum), step, pos),
            FilterKind::BSpline => self.run(data, mode, TriquadraticBSpline, step, pos),
        }
    }

    fn run<V: volsample::voxel::Voxel, M: Mode<V> + Copy, F: Filter>(
        &self,
        data: &[V],
        mode: M,
        filter: F,
        step: Step,
        pos: [f32; 3],
    ) -> Sample {
        let vol = Volume::new(data, self.dims)
            .and_then(|v| v.with_reference_distance(self.d_ref))
            .expect("valid test volume");
        RayMarcher::new(vol, mode, filter, FrontToBack::new(), step)
            .expect("valid pipeline")
            .sample(pos)
    }
}

/// Largest absolute difference over `α` and the three `C̃` channels.
pub fn max_abs_diff(core: Sample, reference: RefAssoc) -> f64 {
    let mut m = (f64::from(core.a) - reference.alpha).abs();
    for k in 0..3 {
        m = m.max((f64::from(core.c[k]) - reference.color[k]).abs());
    }
    m
}

/// A camera for a render comparison, in both the core's and the reference's form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraSpec {
    /// [`volsample::Orthographic`] with `eye, dir, up, extent`.
    Orthographic([f32; 3], [f32; 3], [f32; 3], f32),
    /// [`volsample::Perspective`] with `eye, target, up, fov_y`.
    Perspective([f32; 3], [f32; 3], [f32; 3], f32),
}

/// Everything a whole-image comparison needs besides the volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSpec {
    /// The camera.
    pub camera: CameraSpec,
    /// Image width.
    pub width: usize,
    /// Image height.
    pub height: usize,
    /// Step `d`.
    pub step: f32,
    /// Phase in `[0, 1)`.
    pub phase: f32,
    /// Associated background.
    pub background: Sample,
    /// Early-termination threshold (`1.0`: none).
    pub a_stop: f32,
    /// Composite back to front instead (needs `a_stop = 1`).
    pub back_to_front: bool,
}

/// The render comparisons (feature `checks`: the fuzz targets and the tests).
#[cfg(feature = "checks")]
impl FloatCase {
    /// The core's image of `mode` with `filter` for `spec`.
    ///
    /// # Panics
    /// If the core rejects the case (a bad test case).
    pub fn core_render(
        &self,
        mode: ModeKind,
        filter: FilterKind,
        spec: &RenderSpec,
    ) -> Vec<Sample> {
        match mode {
            ModeKind::Separate => self.render_filter(&self.voxels, Separate, filter, spec),
            ModeKind::OpacityWeighted => {
                self.render_filter(&self.voxels, OpacityWeighted, filter, spec)
            }
            ModeKind::Preweighted => {
                self.render_filter(&self.associated(), Preweighted, filter, spec)
            }
            ModeKind::ExtinctionWeighted => {
                self.render_filter(&self.extinction(), ExtinctionWeighted, filter, spec)
            }
            ModeKind::PostClassified => {
                let tf = self.transfer_function();
                self.render_filter(&self.scalars, PostClassified::new(&tf), filter, spec)
            }
        }
    }

    fn render_filter<V: volsample::voxel::Voxel, M: Mode<V> + Copy>(
        &self,
        data: &[V],
        mode: M,
        filter: FilterKind,
        spec: &RenderSpec,
    ) -> Vec<Sample> {
        match filter {
            FilterKind::Nearest => self.render_order(data, mode, Nearest, spec),
            FilterKind::TrilinearTree => self.render_order(data, mode, Trilinear(Tree), spec),
            FilterKind::TrilinearSum => self.render_order(data, mode, Trilinear(WeightedSum), spec),
            FilterKind::BSpline => self.render_order(data, mode, TriquadraticBSpline, spec),
        }
    }

    fn render_order<V: volsample::voxel::Voxel, M: Mode<V> + Copy, F: Filter>(
        &self,
        data: &[V],
        mode: M,
        filter: F,
        spec: &RenderSpec,
    ) -> Vec<Sample> {
        if spec.back_to_front {
            self.render_with(data, mode, filter, volsample::BackToFront, spec)
        } else if spec.a_stop < 1.0 {
            let order = FrontToBack::with_threshold(spec.a_stop).expect("valid threshold");
            self.render_with(data, mode, filter, order, spec)
        } else {
            self.render_with(data, mode, filter, FrontToBack::new(), spec)
        }
    }

    fn render_with<V, M, F, O>(
        &self,
        data: &[V],
        mode: M,
        filter: F,
        order: O,
        spec: &RenderSpec,
    ) -> Vec<Sample>
    where
        V: volsample::voxel::Voxel,
        M: Mode<V> + Copy,
        F: Filter,
        O: volsample::composite::Order,
    {
        let vol = Volume::new(data, self.dims)
            .and_then(|v| v.with_reference_distance(self.d_ref))
            .expect("valid test volume");
        let step = Step::new(spec.step)
            .and_then(|s| s.with_phase(spec.phase))
            .expect("valid step");
        let marcher = RayMarcher::new(vol, mode, filter, order, step)
            .and_then(|m| m.with_background(spec.background))
            .expect("valid pipeline");
        let mut image = vec![Sample::TRANSPARENT; spec.width * spec.height];
        let result = match spec.camera {
            CameraSpec::Orthographic(eye, dir, up, extent) => {
                let cam = volsample::Orthographic::new(eye, dir, up, extent).expect("valid camera");
                marcher.render_into(&cam, spec.width, spec.height, &mut image)
            }
            CameraSpec::Perspective(eye, target, up, fov) => {
                let cam = volsample::Perspective::new(eye, target, up, fov).expect("valid camera");
                marcher.render_into(&cam, spec.width, spec.height, &mut image)
            }
        };
        result.expect("valid image");
        image
    }

    /// The reference image of `mode` with `filter` for `spec` (straight or scalar source; the
    /// reference premultiplies and converts to extinction in `f64`).
    pub fn reference_render(
        &self,
        mode: ModeKind,
        filter: FilterKind,
        spec: &RenderSpec,
    ) -> Vec<RefAssoc> {
        let v3 = |v: [f32; 3]| v.map(f64::from);
        let camera = ref_camera(spec);
        let mut params = reference::RefRenderParams::new(spec.width, spec.height);
        params.mode = mode.reference();
        params.filter = filter.reference();
        params.step = f64::from(spec.step);
        params.phase = f64::from(spec.phase);
        params.background = RefAssoc::new(v3(spec.background.c), f64::from(spec.background.a));
        params.a_stop = f64::from(spec.a_stop);
        let straight = self.ref_straight();
        let scalars = RefScalarVolume::new(
            self.dims,
            self.scalars.iter().map(|&s| f64::from(s)).collect(),
            f64::from(self.d_ref),
        );
        let tf = self.ref_tf();
        let source = match mode {
            ModeKind::PostClassified => RefSource::Scalar(&scalars, &tf),
            _ => RefSource::Straight(&straight),
        };
        reference::render_reference(&camera, source, &params)
    }

    /// `mode` with `filter` rendered by the core and by the reference for `spec`, pixel by
    /// pixel within [`tolerance::render_pixel_bound`](crate::tolerance::render_pixel_bound),
    /// every core pixel valid; pixels with a decision within [`RENDER_AMBIGUITY`] of its
    /// boundary ([`FloatCase::ambiguous_pixel`]) are left out. Returns how many pixels were
    /// compared and how many left out.
    ///
    /// # Errors
    /// The first pixel out of its bound (or invalid), with both values.
    ///
    /// # Panics
    /// If the core rejects the case (a bad test case).
    pub fn compare_render(
        &self,
        mode: ModeKind,
        filter: FilterKind,
        spec: &RenderSpec,
    ) -> Result<(usize, usize), String> {
        self.compare_image(mode, filter, spec, &self.core_render(mode, filter, spec))
    }

    /// [`FloatCase::compare_render`] of an image the caller rendered (`core`, row-major,
    /// `spec.width × spec.height`), for callers that hold their own marcher.
    ///
    /// # Errors
    /// The first pixel out of its bound (or invalid), with both values; a wrong image size.
    pub fn compare_image(
        &self,
        mode: ModeKind,
        filter: FilterKind,
        spec: &RenderSpec,
        core: &[Sample],
    ) -> Result<(usize, usize), String> {
        if core.len() != spec.width * spec.height {
            return Err(format!(
                "image of {} pixels for {} × {}",
                core.len(),
                spec.width,
                spec.height
            ));
        }
        let want = self.reference_render(mode, filter, spec);
        let bound = crate::tolerance::render_pixel_bound(self, mode, filter, spec);
        let (mut compared, mut skipped) = (0, 0);
        for (k, (c, r)) in core.iter().zip(want.iter()).enumerate() {
            if !c.is_valid() {
                return Err(format!("{mode:?} {filter:?} pixel {k}: invalid {c:?}"));
            }
            if self.ambiguous_pixel(spec, filter, k % spec.width, k / spec.width) {
                skipped += 1;
                continue;
            }
            compared += 1;
            let err = max_abs_diff(*c, *r);
            if err > bound {
                return Err(format!(
                    "{mode:?} {filter:?} pixel {k}: {err:e} > {bound:e}\ncore {c:?}\nref {r:?}"
                ));
            }
        }
        Ok((compared, skipped))
    }

    /// `true` when pixel `(i, j)`'s ray has a sample-count or nearest-voxel decision within
    /// [`RENDER_AMBIGUITY`] of its boundary: the sample count at the ray's ends and the voxel
    /// `Nearest` picks are discontinuous in the position, so an `f32` and an `f64` ray may
    /// legitimately disagree there.
    pub fn ambiguous_pixel(
        &self,
        spec: &RenderSpec,
        filter: FilterKind,
        i: usize,
        j: usize,
    ) -> bool {
        let ray = reference::camera_ray(&ref_camera(spec), spec.width, spec.height, i, j);
        let (d, phase) = (f64::from(spec.step), f64::from(spec.phase));
        let Some((t0, t1)) = reference::clip_ray(self.dims, &ray) else {
            return false;
        };
        let near_integer = |x: f64| (x - x.round()).abs() < RENDER_AMBIGUITY;
        if near_integer(t0 / d - phase) || near_integer(t1 / d - phase) {
            return true;
        }
        filter == FilterKind::Nearest
            && reference::sample_positions(self.dims, &ray, d, phase)
                .iter()
                .any(|p| p.iter().any(|&x| near_integer(x + 0.5)))
    }
}

/// How close (in units of the step) a sample may come to a decision boundary before a pixel
/// is left out of a render comparison ([`FloatCase::ambiguous_pixel`]).
#[cfg(feature = "checks")]
pub const RENDER_AMBIGUITY: f64 = 1e-4;

/// The reference's form of `spec`'s camera.
#[cfg(feature = "checks")]
fn ref_camera(spec: &RenderSpec) -> reference::RefCamera {
    let v3 = |v: [f32; 3]| v.map(f64::from);
    match spec.camera {
        CameraSpec::Orthographic(eye, dir, up, extent) => reference::RefCamera::Orthographic {
            eye: v3(eye),
            dir: v3(dir),
            up: v3(up),
            extent: f64::from(extent),
        },
        CameraSpec::Perspective(eye, target, up, fov) => reference::RefCamera::Perspective {
            eye: v3(eye),
            target: v3(target),
            up: v3(up),
            fov_y: f64::from(fov),
        },
    }
}
