//! Viewing a volume as its users expect: a camera in physical (world) space that frames the
//! volume, the volume's index-to-world mapping, and a fast threaded renderer
//! ([`render`]).
//!
//! # Conventions
//! World coordinates are **RAS+** millimetres, as NIfTI and nibabel use them (`x` towards the
//! patient's right, `y` anterior, `z` superior); a loader converts LPS files (NRRD, DICOM)
//! into RAS. An [`Affine`] maps a voxel index `(i, j, k)` (voxel centres at integers) to a
//! world point. The default [`View`] is the anterior view of 3D Slicer and ParaView's
//! "+Y" view: the eye in front of the patient looking posterior, superior up, so the
//! patient's right is on the image's left.
//!
//! The core marches rays in voxel index space; a [`VoxelCamera`] maps each world-space ray
//! of a core [`Orthographic`] or [`Perspective`] camera there. Distances along a ray in index
//! space are not millimetres where the spacing is anisotropic, so the renderer converts the
//! physical step and the physical unit distance of the opacities into index-space lengths
//! along the view direction ([`Framed::index_length`]): the opacity of a segment depends on
//! its physical length only, so a resampled or anisotropic volume looks the same.
//!
//! ```
//! use volsample_host::view::{Affine, View};
//! // A 64 × 64 × 32 volume with 1 × 1 × 2 mm voxels, seen from the front.
//! let affine = Affine::scaled([1.0, 1.0, 2.0]);
//! let framed = View::default().frame(&affine, [64, 64, 32])?;
//! // Along the view direction (posterior, the y axis), one index unit is 1 mm.
//! assert!((framed.index_length(1.0) - 1.0).abs() < 1e-6);
//! # Ok::<(), String>(())
//! ```

pub mod render;

use volsample::{Camera, Orthographic, Perspective, Ray};

/// A voxel-index-to-world mapping: `world = M·(i, j, k) + t`, `M` the 3 × 3 linear part
/// (columns: the world step of one voxel along each index axis), `t` the world position of
/// voxel `(0, 0, 0)`'s centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// Rows of `[M | t]`.
    pub rows: [[f64; 4]; 3],
}

impl Default for Affine {
    fn default() -> Self {
        Self::scaled([1.0; 3])
    }
}

impl Affine {
    /// Voxel spacing `s` along the three axes, axis-aligned, voxel 0 at the origin.
    pub fn scaled(s: [f64; 3]) -> Self {
        Self {
            rows: [
                [s[0], 0.0, 0.0, 0.0],
                [0.0, s[1], 0.0, 0.0],
                [0.0, 0.0, s[2], 0.0],
            ],
        }
    }

    /// From the linear part's columns (one per index axis) and the origin.
    pub fn from_columns(columns: [[f64; 3]; 3], origin: [f64; 3]) -> Self {
        let mut rows = [[0.0; 4]; 3];
        for (r, row) in rows.iter_mut().enumerate() {
            for (c, col) in columns.iter().enumerate() {
                row[c] = col[r];
            }
            row[3] = origin[r];
        }
        Self { rows }
    }

    /// The world point of index position `p`.
    pub fn point(&self, p: [f64; 3]) -> [f64; 3] {
        self.rows
            .map(|r| r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3])
    }

    /// The world vector of an index-space vector `v` (the linear part only).
    pub fn vector(&self, v: [f64; 3]) -> [f64; 3] {
        self.rows.map(|r| r[0] * v[0] + r[1] * v[1] + r[2] * v[2])
    }

    /// The voxel spacing: the length of each column of the linear part.
    pub fn spacing(&self) -> [f64; 3] {
        [0, 1, 2].map(|c| norm(self.rows.map(|r| r[c])))
    }

    /// The inverse mapping (world to index).
    ///
    /// # Errors
    /// A singular or non-finite linear part, as text.
    pub fn inverse(&self) -> Result<Affine, String> {
        let m = self.rows.map(|r| [r[0], r[1], r[2]]);
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        let scale = self.spacing().iter().product::<f64>();
        if !det.is_finite() || !scale.is_finite() || det.abs() <= 1e-12 * scale {
            return Err("the voxel-to-world matrix is singular or not finite".into());
        }
        let cof = |r0: usize, r1: usize, c0: usize, c1: usize| {
            m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
        };
        // The adjugate over the determinant.
        let inv = [
            [cof(1, 2, 1, 2), -cof(0, 2, 1, 2), cof(0, 1, 1, 2)],
            [-cof(1, 2, 0, 2), cof(0, 2, 0, 2), -cof(0, 1, 0, 2)],
            [cof(1, 2, 0, 1), -cof(0, 2, 0, 1), cof(0, 1, 0, 1)],
        ]
        .map(|r| r.map(|x| x / det));
        let t = [self.rows[0][3], self.rows[1][3], self.rows[2][3]];
        let mut rows = [[0.0; 4]; 3];
        for (row, r) in rows.iter_mut().zip(inv) {
            *row = [r[0], r[1], r[2], -(r[0] * t[0] + r[1] * t[1] + r[2] * t[2])];
        }
        Ok(Affine { rows })
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(v);
    (n.is_finite() && n > 0.0).then(|| v.map(|x| x / n))
}

/// `a × b`.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a · b`.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn to_f32(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

/// Parallel or perspective rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Parallel rays (the default: distances and sizes stay comparable across the image).
    Orthographic,
    /// A pinhole camera with this vertical field of view in degrees, `(0, 180)`.
    Perspective {
        /// Vertical field of view, degrees.
        fov_y_deg: f64,
    },
}

/// Where the camera looks from and how it frames the volume, in world (RAS) space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Degrees about the up axis from the anterior view: 90 looks from the patient's right
    /// (the eye on `+x`), −90 from the left, 180 from behind.
    pub azimuth_deg: f64,
    /// Degrees above the horizontal plane: 90 looks down from above (superior).
    pub elevation_deg: f64,
    /// The view direction (from the eye into the scene) as a world vector; replaces azimuth
    /// and elevation when set.
    pub direction: Option<[f64; 3]>,
    /// The world vector that points up in the image (default superior, `+z`); where it is
    /// parallel to the view direction, anterior (`+y`) or posterior is used instead.
    pub up: [f64; 3],
    /// Magnification: 1 frames the whole volume with a small margin, 2 shows half of it.
    pub zoom: f64,
    /// Orthographic or perspective.
    pub projection: Projection,
}

impl Default for View {
    fn default() -> Self {
        Self {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            direction: None,
            up: [0.0, 0.0, 1.0],
            zoom: 1.0,
            projection: Projection::Orthographic,
        }
    }
}

/// Margin around the framed volume: the image spans this much more than its projection.
pub const FRAME_MARGIN: f64 = 1.05;

/// A world-space camera of the core.
#[derive(Debug, Clone, Copy)]
pub enum WorldCamera {
    /// Parallel rays.
    Orthographic(Orthographic),
    /// A pinhole.
    Perspective(Perspective),
}

impl Camera for WorldCamera {
    #[inline]
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray {
        match self {
            WorldCamera::Orthographic(c) => c.ray(i, j, width, height),
            WorldCamera::Perspective(c) => c.ray(i, j, width, height),
        }
    }
}

/// A [`View`] fitted to a volume: the world camera, the world-to-index mapping, and the
/// index-space lengths of physical distances along the rays.
#[derive(Debug, Clone, Copy)]
pub struct Framed {
    /// The world-space camera.
    pub world: WorldCamera,
    /// World to voxel index.
    pub to_index: Affine,
    /// Index to world.
    pub to_world: Affine,
    /// World millimetres per index-space unit along the central ray.
    pub mm_per_unit: f64,
    /// The largest relative difference of `mm_per_unit` between the central ray and the
    /// image corners: 0 for orthographic views and for isotropic spacing; for a perspective
    /// view of an anisotropic volume, the relative error of the step lengths (and so of the
    /// segments' optical depths) away from the centre.
    pub spread: f64,
}

impl View {
    /// The view direction (from the eye into the scene), unit length.
    ///
    /// # Errors
    /// A zero or non-finite direction, as text.
    pub fn direction(&self) -> Result<[f64; 3], String> {
        let d = match self.direction {
            Some(d) => d,
            None => {
                let (az, el) = (
                    self.azimuth_deg.to_radians(),
                    self.elevation_deg.to_radians(),
                );
                // The eye's direction from the centre; the view looks the other way.
                let eye = [az.sin() * el.cos(), az.cos() * el.cos(), el.sin()];
                eye.map(|x| -x)
            }
        };
        normalized(d).ok_or_else(|| format!("view direction {d:?} is zero or not finite"))
    }

    /// Frames a volume of `dims` voxels placed in the world by `affine`, for `width ×
    /// height` images: the camera looks at the centre of the volume's box (voxel centres
    /// `0 ..= n − 1`, extended by half a voxel) and the box's projection fills the image
    /// with a margin of [`FRAME_MARGIN`], divided by the zoom.
    ///
    /// # Errors
    /// A bad direction, up vector, zoom or field of view, or a singular affine, as text.
    pub fn frame(&self, affine: &Affine, dims: [usize; 3]) -> Result<Framed, String> {
        self.frame_image(affine, dims, [1, 1])
    }

    /// [`frame`](Self::frame) for an image of `[width, height]` pixels (the aspect ratio
    /// decides which of the box's projected extents fills the image).
    ///
    /// # Errors
    /// As [`frame`](Self::frame); a zero image size.
    pub fn frame_image(
        &self,
        affine: &Affine,
        dims: [usize; 3],
        [width, height]: [usize; 2],
    ) -> Result<Framed, String> {
        if width == 0 || height == 0 {
            return Err("the image needs a positive width and height".into());
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            return Err(format!("zoom must be positive, not {}", self.zoom));
        }
        let to_index = affine.inverse()?;
        let dir = self.direction()?;
        let up0 = normalized(self.up).ok_or("the up vector is zero or not finite")?;
        // Up must not be parallel to the view direction: fall back to anterior, then
        // posterior (looking straight down or up with the default superior up).
        let right = [up0, [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]
            .into_iter()
            .find_map(|u| {
                let r = cross(dir, u);
                (norm(r) > 1e-6).then(|| normalized(r)).flatten()
            })
            .ok_or("the up vector is parallel to the view direction")?;
        let up = cross(right, dir);
        // The box corners in world space.
        let corners: Vec<[f64; 3]> = (0..8)
            .map(|c| {
                let p = [0, 1, 2].map(|k| {
                    if c >> k & 1 == 0 {
                        -0.5
                    } else {
                        dims[k] as f64 - 0.5
                    }
                });
                affine.point(p)
            })
            .collect();
        let centre = affine.point(dims.map(|n| (n as f64 - 1.0) * 0.5));
        let rel = |p: [f64; 3]| [0, 1, 2].map(|k| p[k] - centre[k]);
        let radius = corners.iter().map(|&p| norm(rel(p))).fold(0.0, f64::max);
        let half_w = corners
            .iter()
            .map(|&p| dot(rel(p), right).abs())
            .fold(0.0, f64::max);
        let half_h = corners
            .iter()
            .map(|&p| dot(rel(p), up).abs())
            .fold(0.0, f64::max);
        let aspect = width as f64 / height as f64;
        // Half the image's width in world units at the centre.
        let half_extent = half_w.max(half_h * aspect) * FRAME_MARGIN / self.zoom;
        let world = match self.projection {
            Projection::Orthographic => {
                // The image plane in front of the whole box.
                let eye = [0, 1, 2].map(|k| centre[k] - dir[k] * radius * 1.01);
                WorldCamera::Orthographic(
                    Orthographic::new(
                        to_f32(eye),
                        to_f32(dir),
                        to_f32(up),
                        (2.0 * half_extent) as f32,
                    )
                    .map_err(|e| format!("camera: {e}"))?,
                )
            }
            Projection::Perspective { fov_y_deg } => {
                if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
                    return Err(format!(
                        "field of view must lie in (0, 180) degrees, not {fov_y_deg}"
                    ));
                }
                let tan_half = (fov_y_deg.to_radians() * 0.5).tan();
                // The distance at which the framed half height fills half the field of view;
                // at least the bounding sphere's radius ahead, so the eye is outside the box.
                let dist = (half_extent / aspect / tan_half + radius).max(radius * 1.01);
                let eye = [0, 1, 2].map(|k| centre[k] - dir[k] * dist);
                WorldCamera::Perspective(
                    Perspective::new(
                        to_f32(eye),
                        to_f32(centre),
                        to_f32(up),
                        fov_y_deg.to_radians() as f32,
                    )
                    .map_err(|e| format!("camera: {e}"))?,
                )
            }
        };
        let mm = |d: [f64; 3]| -> f64 {
            // A world unit direction becomes `to_index·d` in index space; one index unit
            // along it is `1 / |to_index·d|` millimetres.
            1.0 / norm(to_index.vector(d))
        };
        let mm_per_unit = mm(dir);
        let mut spread = 0.0f64;
        if let WorldCamera::Perspective(c) = world {
            for (i, j) in [
                (0, 0),
                (width - 1, 0),
                (0, height - 1),
                (width - 1, height - 1),
            ] {
                let r = c.ray(i, j, width, height);
                let l = mm(r.dir().map(f64::from));
                spread = spread.max((l / mm_per_unit - 1.0).abs());
            }
        }
        if !(mm_per_unit.is_finite() && mm_per_unit > 0.0) {
            return Err("the voxel-to-world matrix gives no finite length along the view".into());
        }
        Ok(Framed {
            world,
            to_index,
            to_world: *affine,
            mm_per_unit,
            spread,
        })
    }
}

impl Framed {
    /// The index-space length of `mm` millimetres along the central ray (exact along every
    /// ray of an orthographic view; within [`spread`](Self::spread) relatively along the
    /// others of a perspective one).
    pub fn index_length(&self, mm: f64) -> f64 {
        mm / self.mm_per_unit
    }

    /// The camera in voxel index space, for the core's ray marchers.
    pub fn voxel_camera(&self) -> VoxelCamera {
        VoxelCamera {
            world: self.world,
            to_index: self.to_index,
        }
    }
}

/// A world-space camera seen from voxel index space: each pixel's world ray mapped by the
/// world-to-index affine (directions renormalised by [`Ray::new`]).
#[derive(Debug, Clone, Copy)]
pub struct VoxelCamera {
    world: WorldCamera,
    to_index: Affine,
}

impl Camera for VoxelCamera {
    #[inline]
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray {
        let r = self.world.ray(i, j, width, height);
        let o = self.to_index.point(r.origin().map(f64::from));
        let d = self.to_index.vector(r.dir().map(f64::from));
        // The affine is invertible and finite (checked when framing), so the mapped ray is
        // valid; a ray that still failed would be drawn as the world ray (never seen).
        Ray::new(to_f32(o), to_f32(d)).unwrap_or(r)
    }
}

impl Framed {
    /// A camera given directly in voxel index space (a generated scene's own camera): world
    /// and index space coincide, one unit per voxel.
    ///
    /// # Errors
    /// An invalid camera, as text.
    pub fn from_index_camera(spec: &crate::float_checks::CameraSpec) -> Result<Self, String> {
        use crate::float_checks::CameraSpec;
        let e = |e: volsample::Error| format!("camera: {e}");
        let world = match *spec {
            CameraSpec::Orthographic(eye, dir, up, extent) => {
                WorldCamera::Orthographic(Orthographic::new(eye, dir, up, extent).map_err(e)?)
            }
            CameraSpec::Perspective(eye, target, up, fov) => {
                WorldCamera::Perspective(Perspective::new(eye, target, up, fov).map_err(e)?)
            }
        };
        Ok(Framed {
            world,
            to_index: Affine::default(),
            to_world: Affine::default(),
            mm_per_unit: 1.0,
            spread: 0.0,
        })
    }
}
