//! Cameras: the primary ray of each pixel.

use super::ray::RefRay;
use super::vec3::{add, cross, normalize, scale, sub};

/// A camera for an image of `w × h` pixels; pixel `(i, j)` with `j = 0` the top row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefCamera {
    /// Parallel rays.
    Orthographic {
        /// Centre of the image plane.
        eye: [f64; 3],
        /// Viewing direction (normalized by the caller).
        dir: [f64; 3],
        /// Approximate up vector (not parallel to `dir`).
        up: [f64; 3],
        /// World width of the image; the height is `extent·h/w`.
        extent: f64,
    },
    /// Rays from one eye point.
    Perspective {
        /// Eye position (origin of every ray).
        eye: [f64; 3],
        /// Point the image centre looks at.
        target: [f64; 3],
        /// Approximate up vector (not parallel to `target − eye`).
        up: [f64; 3],
        /// Vertical field of view in radians.
        fov_y: f64,
    },
}

/// Ray of pixel `(i, j)` in a `width × height` image.
///
/// - Orthographic: `right = normalize(dir × up)`, `up2 = right × dir`,
///   `u = ((i + ½)/w − ½)·extent`, `v = (½ − (j + ½)/h)·extent·h/w`,
///   origin `eye + u·right + v·up2`, direction `dir`.
/// - Perspective: `f = normalize(target − eye)`, `right = normalize(f × up)`, `up2 = right × f`,
///   `px = (2(i + ½)/w − 1)·tan(fov_y/2)·(w/h)`, `py = (1 − 2(j + ½)/h)·tan(fov_y/2)`,
///   direction `normalize(f + px·right + py·up2)`, origin `eye`.
pub fn camera_ray(camera: &RefCamera, width: usize, height: usize, i: usize, j: usize) -> RefRay {
    let (w, h) = (width as f64, height as f64);
    let (fi, fj) = (i as f64 + 0.5, j as f64 + 0.5);
    match *camera {
        RefCamera::Orthographic {
            eye,
            dir,
            up,
            extent,
        } => {
            let right = normalize(cross(dir, up));
            let up2 = cross(right, dir);
            let u = (fi / w - 0.5) * extent;
            let v = (0.5 - fj / h) * extent * h / w;
            RefRay {
                origin: add(add(eye, scale(u, right)), scale(v, up2)),
                dir,
            }
        }
        RefCamera::Perspective {
            eye,
            target,
            up,
            fov_y,
        } => {
            let f = normalize(sub(target, eye));
            let right = normalize(cross(f, up));
            let up2 = cross(right, f);
            let aspect = w / h;
            let tan_half = (fov_y / 2.0).tan();
            let px = (2.0 * fi / w - 1.0) * tan_half * aspect;
            let py = (1.0 - 2.0 * fj / h) * tan_half;
            RefRay {
                origin: eye,
                dir: normalize(add(add(f, scale(px, right)), scale(py, up2))),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::vec3::dot;
    use super::*;

    #[test]
    fn orthographic_layout() {
        let cam = RefCamera::Orthographic {
            eye: [1.0, 2.0, 10.0],
            dir: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            extent: 4.0,
        };
        // Centre pixel of a 3×3 image sits at the eye.
        let c = camera_ray(&cam, 3, 3, 1, 1);
        assert_eq!(c.origin, [1.0, 2.0, 10.0]);
        assert_eq!(c.dir, [0.0, 0.0, -1.0]);
        // 4×2 image, extent 4: pixel pitch 1, height 2. Top-left pixel centre: (−1.5, +0.5).
        let tl = camera_ray(&cam, 4, 2, 0, 0);
        assert_eq!(tl.origin, [-0.5, 2.5, 10.0]);
        let br = camera_ray(&cam, 4, 2, 3, 1);
        assert_eq!(br.origin, [2.5, 1.5, 10.0]);
    }

    #[test]
    fn perspective_layout() {
        let fov = 60f64.to_radians();
        let cam = RefCamera::Perspective {
            eye: [0.0, 0.0, 5.0],
            target: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov_y: fov,
        };
        let c = camera_ray(&cam, 5, 5, 2, 2);
        assert_eq!(c.origin, [0.0, 0.0, 5.0]);
        assert!((dot(c.dir, [0.0, 0.0, -1.0]) - 1.0).abs() < 1e-15);
        // Top-centre pixel of a 5×h image: tan(angle) = (1 − 1/h)·tan(fov/2), pointing up.
        let h = 4;
        let t = camera_ray(&cam, 5, h, 2, 0);
        assert!(t.dir[1] > 0.0 && t.dir[0].abs() < 1e-15);
        let tan = t.dir[1] / -t.dir[2];
        assert!((tan - (1.0 - 1.0 / h as f64) * (fov / 2.0).tan()).abs() < 1e-15);
        assert!((dot(t.dir, t.dir) - 1.0).abs() < 1e-15);
        // Right edge pixel of a 4×2 image: x = (1 − 1/4)·tan·2.
        let r = camera_ray(&cam, 4, 2, 3, 0);
        let tx = r.dir[0] / -r.dir[2];
        assert!((tx - 0.75 * (fov / 2.0).tan() * 2.0).abs() < 1e-15);
    }
}
