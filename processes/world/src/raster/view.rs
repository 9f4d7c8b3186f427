//! Per-frame view: the camera transform in `f32`, the frustum planes, culling and LOD tests.

use nalgebra::Isometry3;

use super::tri::Projector;

/// The camera of one frame in `f32`: centre and axes in world coordinates, frustum planes.
pub(crate) struct View {
    /// Camera centre, world metres.
    pub c: [f32; 3],
    /// Camera x, y, z axes in world coordinates (rows of `camera_from_world`).
    pub axes: [[f32; 3]; 3],
    /// Inward unit normals and offsets: a point p is inside when `n·(p − c) ≥ d`.
    planes: [([f32; 3], f32); 5],
}

#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalized(v: [f32; 3]) -> [f32; 3] {
    let n = dot(v, v).sqrt();
    if n > 0.0 {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        v
    }
}

/// Image geometry needed for the frustum.
pub(crate) struct Frame {
    pub fx: f32,
    pub fy: f32,
    pub cx: f32,
    pub cy: f32,
    pub width: f32,
    pub height: f32,
    pub near: f32,
}

impl Frame {
    /// The projection of camera-space vertices onto this image.
    pub fn projector(&self) -> Projector {
        Projector {
            fx: self.fx,
            fy: self.fy,
            cx: self.cx,
            cy: self.cy,
            near: self.near,
        }
    }
}

impl View {
    pub fn new(world_from_camera: &Isometry3<f64>, f: &Frame) -> Self {
        let m = world_from_camera.rotation.to_rotation_matrix();
        let m = m.matrix();
        let col = |k: usize| [m[(0, k)] as f32, m[(1, k)] as f32, m[(2, k)] as f32];
        let axes = [col(0), col(1), col(2)];
        let t = &world_from_camera.translation.vector;
        let c = [t.x as f32, t.y as f32, t.z as f32];
        // Camera-frame normals (x right, y down, z forward) mapped to world.
        let to_world = |n: [f32; 3]| {
            normalized([
                axes[0][0] * n[0] + axes[1][0] * n[1] + axes[2][0] * n[2],
                axes[0][1] * n[0] + axes[1][1] * n[1] + axes[2][1] * n[2],
                axes[0][2] * n[0] + axes[1][2] * n[1] + axes[2][2] * n[2],
            ])
        };
        let planes = [
            (axes[2], f.near),
            (to_world([f.fx, 0.0, f.cx + 0.5]), 0.0),
            (to_world([-f.fx, 0.0, f.width - 0.5 - f.cx]), 0.0),
            (to_world([0.0, f.fy, f.cy + 0.5]), 0.0),
            (to_world([0.0, -f.fy, f.height - 0.5 - f.cy]), 0.0),
        ];
        Self { c, axes, planes }
    }

    /// World point to camera frame.
    #[inline(always)]
    pub fn to_camera(&self, p: [f32; 3]) -> [f32; 3] {
        let d = [p[0] - self.c[0], p[1] - self.c[1], p[2] - self.c[2]];
        [
            dot(self.axes[0], d),
            dot(self.axes[1], d),
            dot(self.axes[2], d),
        ]
    }

    /// Whether an axis-aligned box may intersect the frustum (conservative).
    pub fn box_visible(&self, min: [f32; 3], max: [f32; 3]) -> bool {
        self.planes.iter().all(|(n, d)| {
            let p = [
                if n[0] >= 0.0 { max[0] } else { min[0] },
                if n[1] >= 0.0 { max[1] } else { min[1] },
                if n[2] >= 0.0 { max[2] } else { min[2] },
            ];
            dot(*n, [p[0] - self.c[0], p[1] - self.c[1], p[2] - self.c[2]]) >= *d
        })
    }

    /// Whether a sphere may intersect the frustum.
    pub fn sphere_visible(&self, center: [f32; 3], radius: f32) -> bool {
        let d = [
            center[0] - self.c[0],
            center[1] - self.c[1],
            center[2] - self.c[2],
        ];
        self.planes
            .iter()
            .all(|(n, off)| dot(*n, d) >= *off - radius)
    }

    /// Distance from the camera centre to a box (0 inside), metres.
    pub fn box_distance(&self, min: [f32; 3], max: [f32; 3]) -> f32 {
        let mut s = 0.0;
        for k in 0..3 {
            let v = self.c[k];
            let e = if v < min[k] {
                min[k] - v
            } else if v > max[k] {
                v - max[k]
            } else {
                0.0
            };
            s += e * e;
        }
        s.sqrt()
    }

    /// Distance from the camera centre to a point, metres.
    pub fn distance(&self, p: [f32; 3]) -> f32 {
        let d = [p[0] - self.c[0], p[1] - self.c[1], p[2] - self.c[2]];
        dot(d, d).sqrt()
    }
}
