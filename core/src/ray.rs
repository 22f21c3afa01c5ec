//! Rays, ray–box clipping and cameras.
//!
//! Coordinates are voxel units: voxel centres at integers, the volume box `[−½, n − ½]` per
//! axis. A ray direction is unit length, so ray parameters `t` are distances.

use crate::each::Each;
use crate::error::Error;

type V3 = [f32; 3];

#[inline(always)]
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline(always)]
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline(always)]
fn scale(a: V3, s: f32) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f32 {
    libm::sqrtf(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
}
fn finite(a: V3) -> bool {
    a.iter().all(|x| x.is_finite())
}
/// `a/|a|`, or `None` for a zero or non-finite vector.
// (Inlined on x86-64, as `clip`.)
#[cfg_attr(target_arch = "x86_64", inline)]
fn normalize(a: V3) -> Option<V3> {
    if !finite(a) {
        return None;
    }
    let n = norm(a);
    if n.is_finite() && n > 1.0e-18 && n < 1.0e18 {
        return Some(scale(a, 1.0 / n));
    }
    // `|a|²` overflowed or (nearly) underflowed: every finite non-zero vector has a direction,
    // so divide by the largest component first (then `1 ≤ |a| ≤ √3`). Without this a finite
    // direction such as `[1e20, 0, 0]` or `[1e-30, 0, 0]` was rejected as invalid.
    let m = a.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    if m > 0.0 {
        let b = a.each(|x| x / m);
        Some(scale(b, 1.0 / norm(b)))
    } else {
        None
    }
}

/// A ray `origin + t·dir`, `t ≥ 0`, with a unit direction.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ray {
    origin: V3,
    dir: V3,
}

impl Ray {
    /// A ray from `origin` along `dir` (normalised here).
    ///
    /// # Errors
    /// [`Error::InvalidRay`] for a non-finite origin or a zero or non-finite direction.
    pub fn new(origin: V3, dir: V3) -> Result<Self, Error> {
        let dir = normalize(dir).ok_or(Error::InvalidRay)?;
        if !finite(origin) {
            return Err(Error::InvalidRay);
        }
        Ok(Self { origin, dir })
    }

    /// The origin.
    pub fn origin(&self) -> V3 {
        self.origin
    }

    /// The unit direction.
    pub fn dir(&self) -> V3 {
        self.dir
    }

    /// The point at distance `t`.
    #[inline(always)]
    pub fn at(&self, t: f32) -> V3 {
        add(self.origin, scale(self.dir, t))
    }

    /// The parameter interval `[t0, t1]`, `t0 ≥ 0`, where the ray is inside the box of a
    /// volume with dimensions `dims` (`[−½, n − ½]` per axis), or `None` if it misses.
    ///
    /// Slab method; an axis with a zero direction component constrains nothing when the
    /// origin lies inside its slab (boundary included) and rejects the ray otherwise. A ray
    /// touching the box in one point gives `t0 = t1`.
    // On x86-64 inlined where it is used, so that it is compiled in the instruction set of
    // the caller (a camera's rays and each ray's sample range, computed inside the marcher's
    // AVX2 entry, ran as calls to baseline code; the performance log, 2026-12-07
    // (afternoon)); elsewhere left to the compiler, for code size.
    #[cfg_attr(target_arch = "x86_64", inline)]
    pub fn clip(&self, dims: [usize; 3]) -> Option<(f32, f32)> {
        let mut t0 = 0.0f32;
        let mut t1 = f32::INFINITY;
        for ((&o, &d), &n) in self.origin.iter().zip(self.dir.iter()).zip(dims.iter()) {
            let lo = -0.5f32;
            let hi = n as f32 - 0.5;
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d;
            let (a, b) = ((lo - o) * inv, (hi - o) * inv);
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            t0 = t0.max(near);
            t1 = t1.min(far);
        }
        (t0 <= t1).then_some((t0, t1))
    }
}

/// Something that gives the ray through each pixel of a `width × height` image
/// (pixel `(i, j)`, `j = 0` the top row, through the pixel centre).
pub trait Camera {
    /// The ray through pixel `(i, j)`.
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray;
}

/// An orthographic camera: parallel rays from an image plane.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Orthographic {
    eye: V3,
    dir: V3,
    right: V3,
    up: V3,
    extent: f32,
}

impl Orthographic {
    /// Image plane centred at `eye`, rays along `dir`, `up` giving the image's vertical, and
    /// `extent` the world width of the image (the height follows the aspect ratio).
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] for non-finite input, a zero `dir`, `up` parallel to `dir`,
    /// or `extent ≤ 0`.
    pub fn new(eye: V3, dir: V3, up: V3, extent: f32) -> Result<Self, Error> {
        let dir = normalize(dir).ok_or(Error::InvalidCamera)?;
        let right = normalize(cross(dir, up)).ok_or(Error::InvalidCamera)?;
        let up = cross(right, dir);
        if !(finite(eye) && extent.is_finite() && extent > 0.0) {
            return Err(Error::InvalidCamera);
        }
        Ok(Self {
            eye,
            dir,
            right,
            up,
            extent,
        })
    }

    /// An axis-aligned camera looking along `+z` at a volume of `dims`, whose image covers
    /// the volume's `x–y` extent exactly: in an `nx × ny` image, pixel `(i, j)` looks down the
    /// voxel column `(x, y) = (i, j)` (`up` is `−y`, so image rows follow voxel rows).
    ///
    /// # Errors
    /// None for valid volume dimensions; [`Error::InvalidCamera`] if they overflow `f32`.
    pub fn looking_down_z(dims: [usize; 3]) -> Result<Self, Error> {
        let [nx, ny, _] = dims.each(|n| n as f32);
        let eye = [nx * 0.5 - 0.5, ny * 0.5 - 0.5, -1.0];
        Self::new(eye, [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], nx)
    }
}

impl Camera for Orthographic {
    #[inline]
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray {
        let (w, h) = (width as f32, height as f32);
        let u = ((i as f32 + 0.5) / w - 0.5) * self.extent;
        let v = (0.5 - (j as f32 + 0.5) / h) * self.extent * h / w;
        Ray {
            origin: add(self.eye, add(scale(self.right, u), scale(self.up, v))),
            dir: self.dir,
        }
    }
}

/// A pinhole perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Perspective {
    eye: V3,
    fwd: V3,
    right: V3,
    up: V3,
    tan_half: f32,
}

impl Perspective {
    /// Eye at `eye` looking at `target`, `up` the image vertical, vertical field of view
    /// `fov_y` in radians.
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] for non-finite input, `eye = target`, `up` parallel to the
    /// view direction, or `fov_y` outside `(0, π)`.
    pub fn new(eye: V3, target: V3, up: V3, fov_y: f32) -> Result<Self, Error> {
        let fwd = normalize(sub(target, eye)).ok_or(Error::InvalidCamera)?;
        let right = normalize(cross(fwd, up)).ok_or(Error::InvalidCamera)?;
        let up = cross(right, fwd);
        if !(fov_y > 0.0 && fov_y < core::f32::consts::PI) {
            return Err(Error::InvalidCamera);
        }
        let tan_half = libm::tanf(0.5 * fov_y);
        if !tan_half.is_finite() {
            return Err(Error::InvalidCamera);
        }
        Ok(Self {
            eye,
            fwd,
            right,
            up,
            tan_half,
        })
    }
}

impl Camera for Perspective {
    #[inline]
    fn ray(&self, i: usize, j: usize, width: usize, height: usize) -> Ray {
        let (w, h) = (width as f32, height as f32);
        let px = (2.0 * (i as f32 + 0.5) / w - 1.0) * self.tan_half * (w / h);
        let py = (1.0 - 2.0 * (j as f32 + 0.5) / h) * self.tan_half;
        let d = add(self.fwd, add(scale(self.right, px), scale(self.up, py)));
        Ray {
            origin: self.eye,
            dir: normalize(d).unwrap_or(self.fwd),
        }
    }
}
