//! Deterministic synthetic data for tests and benchmarks: textured images under known affine
//! warps, and two-view point correspondences under known motion.
//!
//! The texture is a continuous function (Gaussian blobs of log-uniform size, 1.5–8.5 px, over a
//! smooth sinusoidal background), so a
//! warped frame is rendered exactly rather than resampled: a tracker's sub-pixel error can be
//! measured against the true warp.
//!
//! ```
//! use hopnav_vision::synthetic::{BlobTexture, AffineWarp};
//! let tex = BlobTexture::random(64, 64, 60, 1);
//! let mut frame = vec![0u8; 64 * 64];
//! tex.render(64, 64, &AffineWarp::translation(0.5, -0.25), &mut frame);
//! assert!(frame.iter().any(|&v| v != frame[0]));
//! ```

use crate::camera::PinholeCamera;
use crate::rng::XorShiftRng;
use nalgebra::{Isometry3, Point3, Vector2};

/// `p_dst = A p_src + b` (pixel coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineWarp {
    /// Linear part, row-major `[[a00, a01], [a10, a11]]`.
    pub a: [[f64; 2]; 2],
    /// Translation in pixels.
    pub b: [f64; 2],
}

impl AffineWarp {
    /// Identity warp.
    pub fn identity() -> Self {
        Self::translation(0.0, 0.0)
    }

    /// Pure shift by `(dx_px, dy_px)`.
    pub fn translation(dx_px: f64, dy_px: f64) -> Self {
        Self {
            a: [[1.0, 0.0], [0.0, 1.0]],
            b: [dx_px, dy_px],
        }
    }

    /// Rotation by `angle_rad` about `(cx_px, cy_px)` followed by a shift.
    pub fn rotation_about(angle_rad: f64, cx_px: f64, cy_px: f64, dx_px: f64, dy_px: f64) -> Self {
        let (s, c) = angle_rad.sin_cos();
        let a = [[c, -s], [s, c]];
        let b = [
            cx_px - (c * cx_px - s * cy_px) + dx_px,
            cy_px - (s * cx_px + c * cy_px) + dy_px,
        ];
        Self { a, b }
    }

    /// Maps a source point to the destination frame.
    pub fn apply(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.a[0][0] * x + self.a[0][1] * y + self.b[0],
            self.a[1][0] * x + self.a[1][1] * y + self.b[1],
        )
    }

    fn inverse_linear(&self) -> Option<[[f64; 2]; 2]> {
        let det = self.a[0][0] * self.a[1][1] - self.a[0][1] * self.a[1][0];
        if det.abs() < 1e-12 {
            return None;
        }
        Some([
            [self.a[1][1] / det, -self.a[0][1] / det],
            [-self.a[1][0] / det, self.a[0][0] / det],
        ])
    }
}

#[derive(Debug, Clone, Copy)]
struct Blob {
    x: f64,
    y: f64,
    sigma: f64,
    amplitude: f64,
}

/// Continuous random texture: Gaussian blobs on a low-contrast sinusoidal background.
#[derive(Debug, Clone)]
pub struct BlobTexture {
    blobs: Vec<Blob>,
    waves: [(f64, f64, f64, f64); 3],
}

impl BlobTexture {
    /// `count` blobs scattered over (and a little beyond) a `width` x `height` area.
    pub fn random(width: usize, height: usize, count: usize, seed: u64) -> Self {
        let mut rng = XorShiftRng::new(seed);
        let margin = 20.0;
        let blobs = (0..count)
            .map(|_| Blob {
                x: rng.uniform(-margin, width as f64 + margin),
                y: rng.uniform(-margin, height as f64 + margin),
                // Log-uniform scale: structure at every pyramid level, as in natural images.
                sigma: 1.5 * (rng.uniform(0.0, 2.0f64.ln() * 2.5)).exp(),
                amplitude: rng.uniform(35.0, 90.0) * if rng.below(2) == 0 { 1.0 } else { -1.0 },
            })
            .collect();
        let mut wave = || {
            let angle = rng.uniform(0.0, std::f64::consts::PI);
            let period = rng.uniform(60.0, 120.0);
            let k = 2.0 * std::f64::consts::PI / period;
            (
                k * angle.cos(),
                k * angle.sin(),
                rng.uniform(0.0, std::f64::consts::TAU),
                8.0,
            )
        };
        let waves = [wave(), wave(), wave()];
        Self { blobs, waves }
    }

    /// Renders the texture seen through `warp` (texture point `p` appears at `warp(p)`) into a
    /// packed `width` x `height` buffer. Does nothing if `out` is too short or the warp singular.
    pub fn render(&self, width: usize, height: usize, warp: &AffineWarp, out: &mut [u8]) {
        let Some(inv) = warp.inverse_linear() else {
            return;
        };
        if out.len() < width * height {
            return;
        }
        let mut acc = vec![128.0f64; width * height];
        // Background: evaluated at the source position of each pixel.
        for y in 0..height {
            for x in 0..width {
                let dx = x as f64 - warp.b[0];
                let dy = y as f64 - warp.b[1];
                let sx = inv[0][0] * dx + inv[0][1] * dy;
                let sy = inv[1][0] * dx + inv[1][1] * dy;
                let mut v = 0.0;
                for &(kx, ky, phase, amp) in &self.waves {
                    v += amp * (kx * sx + ky * sy + phase).sin();
                }
                acc[y * width + x] += v;
            }
        }
        let gain = warp.a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())) * 1.5;
        for blob in &self.blobs {
            let (cx, cy) = warp.apply(blob.x, blob.y);
            let radius = 3.5 * blob.sigma * gain.max(1.0);
            let x0 = (cx - radius).floor().max(0.0) as usize;
            let y0 = (cy - radius).floor().max(0.0) as usize;
            let x1 = ((cx + radius).ceil().max(0.0) as usize).min(width);
            let y1 = ((cy + radius).ceil().max(0.0) as usize).min(height);
            let inv_two_var = 1.0 / (2.0 * blob.sigma * blob.sigma);
            for y in y0..y1 {
                for x in x0..x1 {
                    let dx = x as f64 - cx;
                    let dy = y as f64 - cy;
                    let sx = inv[0][0] * dx + inv[0][1] * dy;
                    let sy = inv[1][0] * dx + inv[1][1] * dy;
                    acc[y * width + x] +=
                        blob.amplitude * (-(sx * sx + sy * sy) * inv_two_var).exp();
                }
            }
        }
        for (o, v) in out.iter_mut().zip(&acc) {
            *o = v.round().clamp(0.0, 255.0) as u8;
        }
    }
}

/// Two views of a point set with known motion.
#[derive(Debug, Clone)]
pub struct TwoViewScene {
    /// True motion: `p_cam2 = cam2_from_cam1 * p_cam1`.
    pub cam2_from_cam1: Isometry3<f64>,
    /// Points in camera-1 coordinates.
    pub points_cam1: Vec<Point3<f64>>,
    /// Noisy normalized coordinates in view 1.
    pub x1_norm: Vec<Vector2<f64>>,
    /// Noisy normalized coordinates in view 2.
    pub x2_norm: Vec<Vector2<f64>>,
    /// Which correspondences were replaced by outliers.
    pub is_outlier: Vec<bool>,
}

impl TwoViewScene {
    /// Projects `points_cam1` into both views (keeping those visible in both, inside the image),
    /// adds Gaussian pixel noise of `noise_px`, and replaces a fraction `outlier_ratio` of the
    /// second-view observations by uniform random pixels.
    pub fn from_points(
        camera: &PinholeCamera,
        cam2_from_cam1: Isometry3<f64>,
        points_cam1: &[Point3<f64>],
        noise_px: f64,
        outlier_ratio: f64,
        seed: u64,
    ) -> Self {
        let mut rng = XorShiftRng::new(seed);
        let mut scene = Self {
            cam2_from_cam1,
            points_cam1: Vec::new(),
            x1_norm: Vec::new(),
            x2_norm: Vec::new(),
            is_outlier: Vec::new(),
        };
        for p in points_cam1 {
            let q = cam2_from_cam1 * p;
            let (Some(u1), Some(u2)) = (camera.project(p), camera.project(&q)) else {
                continue;
            };
            if !camera.contains_pixel(u1) || !camera.contains_pixel(u2) {
                continue;
            }
            let mut n1 = u1;
            let mut n2 = u2;
            n1.x += noise_px * rng.gaussian();
            n1.y += noise_px * rng.gaussian();
            n2.x += noise_px * rng.gaussian();
            n2.y += noise_px * rng.gaussian();
            let outlier = rng.unit_f64() < outlier_ratio;
            if outlier {
                n2.x = rng.uniform(0.0, f64::from(camera.width_px) - 1.0);
                n2.y = rng.uniform(0.0, f64::from(camera.height_px) - 1.0);
            }
            scene.points_cam1.push(*p);
            scene.x1_norm.push(camera.pixel_to_normalized(n1));
            scene.x2_norm.push(camera.pixel_to_normalized(n2));
            scene.is_outlier.push(outlier);
        }
        scene
    }
}

/// Exact normalised coordinates of `points_cam1` in camera 1 and, moved by `cam2_from_cam1`,
/// in camera 2 (no noise, no visibility test).
pub fn exact_views(
    cam2_from_cam1: &Isometry3<f64>,
    points_cam1: &[Point3<f64>],
) -> (Vec<Vector2<f64>>, Vec<Vector2<f64>>) {
    let project = |p: &Point3<f64>| Vector2::new(p.x / p.z, p.y / p.z);
    let x1 = points_cam1.iter().map(project).collect();
    let x2 = points_cam1
        .iter()
        .map(|p| project(&(cam2_from_cam1 * p)))
        .collect();
    (x1, x2)
}

/// `count` random points in a box in front of camera 1: `x, y ∈ ±half_extent_m`, `z ∈ [z_min_m, z_max_m]`.
pub fn random_points_in_box(
    count: usize,
    half_extent_m: f64,
    z_min_m: f64,
    z_max_m: f64,
    seed: u64,
) -> Vec<Point3<f64>> {
    let mut rng = XorShiftRng::new(seed);
    (0..count)
        .map(|_| {
            Point3::new(
                rng.uniform(-half_extent_m, half_extent_m),
                rng.uniform(-half_extent_m, half_extent_m),
                rng.uniform(z_min_m, z_max_m),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warp_rotation_about_fixes_centre() {
        let w = AffineWarp::rotation_about(0.3, 10.0, 20.0, 0.0, 0.0);
        let (x, y) = w.apply(10.0, 20.0);
        assert!((x - 10.0).abs() < 1e-12 && (y - 20.0).abs() < 1e-12);
    }

    #[test]
    fn render_is_deterministic() {
        let tex = BlobTexture::random(32, 32, 20, 3);
        let mut a = vec![0u8; 32 * 32];
        let mut b = vec![0u8; 32 * 32];
        tex.render(32, 32, &AffineWarp::identity(), &mut a);
        BlobTexture::random(32, 32, 20, 3).render(32, 32, &AffineWarp::identity(), &mut b);
        assert_eq!(a, b);
    }
}
