//! The camera every view-dependent stage shares, with VTK's conventions (vertical view angle in
//! degrees, parallel scale as half the view height, azimuth/elevation/roll as vtkCamera does them).

use crate::geom::{cross, dot, sub, Aabb};

/// Where visibility is judged from: a perspective eye point, or an orthographic view direction
/// (pointing from the camera into the scene).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viewpoint {
    Eye([f64; 3]),
    Direction([f64; 3]),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: [f64; 3],
    pub focal: [f64; 3],
    pub up: [f64; 3],
    /// Full vertical opening angle in degrees (perspective).
    pub view_angle: f64,
    /// Orthographic projection when true.
    pub parallel: bool,
    /// Half the height of the view in world units (orthographic).
    pub parallel_scale: f64,
}

impl Default for Camera {
    /// VTK's default camera: at (0,0,1) looking at the origin, y up, 30 degrees.
    fn default() -> Self {
        Camera {
            position: [0.0, 0.0, 1.0],
            focal: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            view_angle: 30.0,
            parallel: false,
            parallel_scale: 1.0,
        }
    }
}

/// Euclidean length, scaled by the largest component first so that coordinates near f64's range
/// (a mesh with points at 1e200) do not overflow the squares.
fn norm(v: &[f64; 3]) -> f64 {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m > 0.0 && m.is_finite() {
        let u = v.map(|x| x / m);
        m * dot(&u, &u).sqrt()
    } else {
        dot(v, v).sqrt()
    }
}

fn normalize(v: &[f64; 3]) -> [f64; 3] {
    let n = norm(v);
    if n > 0.0 {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        *v
    }
}

/// Rotates `v` about unit `axis` by `deg` degrees (Rodrigues).
fn rotate(v: &[f64; 3], axis: &[f64; 3], deg: f64) -> [f64; 3] {
    let (s, c) = deg.to_radians().sin_cos();
    let k = axis;
    let kxv = cross(k, v);
    let kdv = dot(k, v);
    [0, 1, 2].map(|i| v[i] * c + kxv[i] * s + k[i] * kdv * (1.0 - c))
}

impl Camera {
    /// Unit vector from the position towards the focal point.
    pub fn direction(&self) -> [f64; 3] {
        normalize(&sub(&self.focal, &self.position))
    }

    pub fn distance(&self) -> f64 {
        norm(&sub(&self.focal, &self.position))
    }

    pub fn viewpoint(&self) -> Viewpoint {
        if self.parallel {
            Viewpoint::Direction(sub(&self.focal, &self.position))
        } else {
            Viewpoint::Eye(self.position)
        }
    }

    /// Like ParaView's reset: keeps the view direction and up, looks at the box centre from a
    /// distance at which the box's bounding sphere fills the view angle.
    pub fn reset_to(&mut self, bounds: &Aabb) {
        let dir = self.direction();
        let center = bounds.center();
        let e = bounds.extent();
        let mut radius = 0.5 * norm(&e);
        if radius == 0.0 || !radius.is_finite() {
            radius = 0.5;
        }
        let half = (0.5 * self.view_angle).to_radians();
        let distance = radius / half.sin();
        self.focal = center;
        self.position = [0, 1, 2].map(|k| center[k] - distance * dir[k]);
        self.parallel_scale = radius;
        self.orthogonalize_up();
    }

    /// Makes `up` perpendicular to the view direction (vtkCamera::OrthogonalizeViewUp).
    pub fn orthogonalize_up(&mut self) {
        self.up = self.up_across(&self.direction());
    }

    /// The view-up made perpendicular to the unit direction `d` (not finite when the up is
    /// parallel to it).
    fn up_across(&self, d: &[f64; 3]) -> [f64; 3] {
        let right = normalize(&cross(d, &self.up));
        normalize(&cross(&right, d))
    }

    /// Rotates the position about the up vector through the focal point.
    pub fn azimuth(&mut self, deg: f64) {
        let axis = normalize(&self.up);
        let rel = sub(&self.position, &self.focal);
        let r = rotate(&rel, &axis, deg);
        self.position = [0, 1, 2].map(|k| self.focal[k] + r[k]);
    }

    /// Turns the camera rigidly (position and view-up) by `deg` degrees about `axis` through
    /// the focal point: what `--orbit` does between frames.
    pub fn turn(&mut self, axis: &[f64; 3], deg: f64) {
        let axis = normalize(axis);
        let rel = sub(&self.position, &self.focal);
        let r = rotate(&rel, &axis, deg);
        self.position = [0, 1, 2].map(|k| self.focal[k] + r[k]);
        self.up = rotate(&self.up, &axis, deg);
    }

    /// Rotates the position about the camera's left axis through the focal point, so positive
    /// angles look from above (vtkCamera::Elevation, followed by OrthogonalizeViewUp as ParaView
    /// does).
    pub fn elevation(&mut self, deg: f64) {
        let axis = normalize(&cross(&sub(&self.position, &self.focal), &self.up));
        let rel = sub(&self.position, &self.focal);
        let r = rotate(&rel, &axis, deg);
        self.position = [0, 1, 2].map(|k| self.focal[k] + r[k]);
        // Orthogonalized against the rotated offset itself, not against focal - position: far
        // from the origin (UTM, 1e9) the position's rounding can drop the offset's small
        // component that keeps it off the old up (an elevation of 90 degrees leaves cos(90) =
        // 6e-17 of it), which left a zero up where the same view at the origin was fine.
        let up = self.up_across(&normalize(&r.map(|x| -x)));
        if up.iter().all(|x| x.is_finite()) && dot(&up, &up) > 0.5 {
            self.up = up;
        } else {
            self.orthogonalize_up();
        }
    }

    /// Rotates `up` about the view direction.
    pub fn roll(&mut self, deg: f64) {
        let d = self.direction();
        self.up = rotate(&self.up, &d, deg);
    }

    /// Magnifies by `factor`: narrows the view angle (perspective) or the parallel scale.
    pub fn zoom(&mut self, factor: f64) {
        if factor > 0.0 && factor.is_finite() {
            if self.parallel {
                self.parallel_scale /= factor;
            } else {
                self.view_angle /= factor;
            }
        }
    }

    /// Orthonormal camera frame: `(right, up, forward)`.
    pub fn frame(&self) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let f = self.direction();
        let r = normalize(&cross(&f, &self.up));
        let u = cross(&r, &f);
        (r, u, f)
    }

    /// Ray through pixel coordinates `(px, py)` (origin at the top-left corner, y down; pixel
    /// centres at half-integers) of a `width x height` image: `(origin, unit direction)`.
    pub fn pixel_ray(&self, px: f64, py: f64, width: u32, height: u32) -> ([f64; 3], [f64; 3]) {
        self.pixel_ray_in_frame(&self.frame(), px, py, width, height)
    }

    /// [`Camera::pixel_ray`] with the camera frame (from [`Camera::frame`]) computed once by the
    /// caller, for per-pixel loops.
    pub fn pixel_ray_in_frame(
        &self,
        frame: &([f64; 3], [f64; 3], [f64; 3]),
        px: f64,
        py: f64,
        width: u32,
        height: u32,
    ) -> ([f64; 3], [f64; 3]) {
        let (r, u, f) = *frame;
        let aspect = width as f64 / height as f64;
        let sx = (2.0 * px / width as f64 - 1.0) * aspect;
        let sy = 1.0 - 2.0 * py / height as f64;
        if self.parallel {
            let s = self.parallel_scale;
            let o = [0, 1, 2].map(|k| self.position[k] + s * (sx * r[k] + sy * u[k]));
            (o, f)
        } else {
            let t = (0.5 * self.view_angle).to_radians().tan();
            let d = [0, 1, 2].map(|k| f[k] + t * (sx * r[k] + sy * u[k]));
            (self.position, normalize(&d))
        }
    }

    /// Projects a world point to `(px, py, depth)`: pixel coordinates as in [`Camera::pixel_ray`]
    /// and depth along the view direction from the camera position. Perspective points at or
    /// behind the eye give a non-positive depth and meaningless pixel coordinates.
    pub fn project(&self, p: &[f64; 3], width: u32, height: u32) -> [f64; 3] {
        let (r, u, f) = self.frame();
        let rel = sub(p, &self.position);
        let (x, y, z) = (dot(&rel, &r), dot(&rel, &u), dot(&rel, &f));
        let aspect = width as f64 / height as f64;
        let (sx, sy) = if self.parallel {
            (x / self.parallel_scale, y / self.parallel_scale)
        } else {
            let t = (0.5 * self.view_angle).to_radians().tan();
            (x / (z * t), y / (z * t))
        };
        [
            (sx / aspect + 1.0) * 0.5 * width as f64,
            (1.0 - sy) * 0.5 * height as f64,
            z,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn project_inverts_pixel_ray() {
        for parallel in [false, true] {
            let cam = Camera {
                position: [1.0, 2.0, 5.0],
                focal: [0.5, 0.0, 0.0],
                up: [0.0, 1.0, 0.0],
                view_angle: 40.0,
                parallel,
                parallel_scale: 2.0,
            };
            let (o, d) = cam.pixel_ray(100.5, 30.5, 320, 200);
            let p = [0, 1, 2].map(|k| o[k] + 3.0 * d[k]);
            let q = cam.project(&p, 320, 200);
            assert!(
                (q[0] - 100.5).abs() < 1e-9 && (q[1] - 30.5).abs() < 1e-9,
                "{q:?}"
            );
        }
    }

    #[test]
    fn reset_fits_and_keeps_direction() {
        let mut cam = Camera::default();
        let b = Aabb {
            min: [10.0, 10.0, 10.0],
            max: [12.0, 14.0, 11.0],
        };
        cam.reset_to(&b);
        assert_eq!(cam.focal, b.center());
        assert!(cam.position[2] > 11.0 && cam.direction()[2] < -0.999);
        cam.azimuth(90.0);
        assert!(
            (cam.direction()[0] + 1.0).abs() < 1e-12,
            "{:?}",
            cam.direction()
        );
    }
}
