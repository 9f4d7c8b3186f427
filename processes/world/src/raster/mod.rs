//! Software rasterizer: textured terrain and rocks into an 8-bit grayscale buffer.
//!
//! - z-buffer of `1/z`, perspective-correct texturing, back-face culling;
//! - triangles crossing the near plane are clipped, not dropped;
//! - terrain split into 16×16-cell chunks: frustum culling by bounding box, front-to-back
//!   order, and geometric LOD (step 1…16 nodes, the coarsest whose height error projects
//!   below `lod_error_px`) with crack-free stitching of edges towards coarser neighbours;
//! - rocks culled per chunk and per bounding sphere, low-poly when small on screen;
//! - sky (pixels no triangle covers) is a plain constant;
//! - seeded Gaussian pixel noise on the ground.
//!
//! All buffers live in the [`Renderer`]; a frame allocates nothing (the per-chunk lists grow
//! once, the first time a scene with more chunks than before is drawn; [`Renderer::prepare`]
//! does it up front). The caller owns the output: any `&mut [u8]` with a row stride, e.g. a
//! loaned shared-memory sample.

mod draw_rocks;
mod draw_terrain;
mod materials;
mod pass;
mod pixel_noise;
mod scene;
mod tri;
mod view;

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

pub use scene::RenderScene;

use crate::camera::{CameraConfig, PinholeCamera, stereo_right};
use crate::config::Interval;
use crate::error::{ConfigError, RenderError};
use draw_rocks::draw_rock;
use draw_terrain::draw_chunk;
use materials::{FlatMaterial, RockMaterial, TerrainMaterial};
use pass::DrawPass;
use pixel_noise::PixelNoise;
use scene::CHUNK_CELLS;
use tri::{ClipVertex, Projector, ScreenVertex, Target, draw_clipped};
use view::{Frame, View};

/// Key mixed into the noise key of the right view of a stereo pair.
const RIGHT_VIEW_KEY: u64 = 0x0052_4947_4854; // "RIGHT"

/// Rendering options of one camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderConfig {
    /// Standard deviation of the Gaussian pixel noise, digital numbers (0 = none).
    pub noise_sigma_dn: f64,
    /// Seed of the pixel noise (combined with the per-frame noise key).
    pub noise_seed: u64,
    /// Value of sky pixels.
    pub sky_dn: u8,
    /// Largest on-screen height error allowed by terrain LOD, pixels.
    pub lod_error_px: f64,
    /// Multiply the fine-detail texture onto close terrain.
    pub detail_texture: bool,
}

impl Default for RenderConfig {
    fn default() -> Self {
        Self {
            noise_sigma_dn: 2.0,
            noise_seed: 0,
            sky_dn: 215,
            lod_error_px: 0.5,
            detail_texture: true,
        }
    }
}

impl RenderConfig {
    /// Checks the values; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> Result<(), ConfigError> {
        Interval::closed(0.0, 64.0).check(prefix, "noise_sigma_dn", self.noise_sigma_dn)?;
        Interval::closed(0.0, 16.0).check(prefix, "lod_error_px", self.lod_error_px)?;
        Ok(())
    }
}

/// What one frame drew (for diagnostics and benchmarks).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Terrain chunks inside the frustum.
    pub chunks_drawn: u32,
    /// Triangles submitted to setup (terrain, rocks, markers).
    pub triangles: u32,
    /// Rocks drawn.
    pub rocks_drawn: u32,
}

/// A renderer for one camera: intrinsics, z-buffer and scratch buffers.
#[derive(Debug, Clone)]
pub struct Renderer {
    camera: PinholeCamera,
    cfg: RenderConfig,
    zbuf: Vec<f32>,
    clip: Vec<ClipVertex>,
    screen: Vec<ScreenVertex>,
    order: Vec<(f32, u32)>,
    lod: Vec<u8>,
    noise: PixelNoise,
}

impl Renderer {
    /// Validates the configs (keys `camera.*`, `render.*`) and allocates all buffers.
    pub fn new(camera: &CameraConfig, cfg: &RenderConfig) -> Result<Self, ConfigError> {
        Self::with_prefix(camera, cfg, "camera", "render")
    }

    /// Like [`new`](Self::new), with the key prefixes used in error messages.
    pub fn with_prefix(
        camera: &CameraConfig,
        cfg: &RenderConfig,
        camera_prefix: &str,
        render_prefix: &str,
    ) -> Result<Self, ConfigError> {
        let cam = PinholeCamera::from_config(camera, camera_prefix)?;
        cfg.validate(render_prefix)?;
        let verts = (CHUNK_CELLS + 1) * (CHUNK_CELLS + 1);
        Ok(Self {
            camera: cam,
            cfg: cfg.clone(),
            zbuf: vec![0.0; cam.width_px as usize * cam.height_px as usize],
            clip: vec![ClipVertex::default(); verts.max(64)],
            screen: vec![ScreenVertex::default(); verts.max(64)],
            order: Vec::with_capacity(1024),
            lod: Vec::with_capacity(1024),
            noise: PixelNoise::new(cfg.noise_sigma_dn, cfg.noise_seed),
        })
    }

    /// The pinhole model (intrinsics) of this renderer.
    pub fn camera(&self) -> &PinholeCamera {
        &self.camera
    }

    /// Bytes one image needs at `stride`: `stride · (height − 1) + width`.
    pub fn required_len(&self, stride: usize) -> usize {
        let (w, h) = (
            self.camera.width_px as usize,
            self.camera.height_px as usize,
        );
        stride.saturating_mul(h.saturating_sub(1)).saturating_add(w)
    }

    /// Grows the per-chunk lists for `scene` so later frames never allocate.
    pub fn prepare(&mut self, scene: &RenderScene) {
        let n = scene.chunks.len();
        if self.order.capacity() < n {
            self.order.reserve(n - self.order.len());
        }
        if self.lod.capacity() < n {
            self.lod.reserve(n - self.lod.len());
        }
    }

    /// Depth buffer of the last frame: `1/z` per pixel (0 = sky), row-major, `width` per row.
    pub fn inverse_depth(&self) -> &[f32] {
        &self.zbuf
    }

    /// Renders `scene` seen from `world_from_camera` into `out` (8-bit, `stride` bytes per row).
    /// `noise_key` selects the pixel-noise pattern (e.g. the frame index): same key, same image.
    pub fn render(
        &mut self,
        scene: &RenderScene,
        world_from_camera: &Isometry3<f64>,
        noise_key: u64,
        out: &mut [u8],
        stride: usize,
    ) -> Result<RenderStats, RenderError> {
        let (w, h) = self.check_target(world_from_camera, out.len(), stride)?;
        self.prepare(scene);

        self.clear(out, stride, (w, h));
        let frame = self.frame((w, h));
        let view = View::new(world_from_camera, &frame);
        let proj = frame.projector();
        let focal = frame.fx.max(frame.fy);
        let mut stats = RenderStats::default();

        self.choose_lods(scene, &view, focal);

        let mut target = Target {
            zbuf: &mut self.zbuf,
            out,
            stride,
            width: w,
            height: h,
        };
        let terrain_mat = TerrainMaterial {
            atlas: &scene.atlas,
            detail: self
                .cfg
                .detail_texture
                .then_some((&scene.detail, scene.detail_per_atlas)),
        };
        let rock_mat = RockMaterial {
            tex: &scene.rock_tex,
        };
        let mut pass = DrawPass {
            view: &view,
            proj: &proj,
            clip: &mut self.clip,
            screen: &mut self.screen,
        };
        for &(_, k) in &self.order {
            let k = k as usize;
            stats.chunks_drawn += 1;
            // Rocks first: the terrain they hide then fails the depth test cheaply.
            let (r0, r1) = scene.chunks[k].rocks;
            for &ri in &scene.chunk_rocks[r0 as usize..r1 as usize] {
                let n = draw_rock(scene, ri as usize, focal, &mut pass, &mut target, &rock_mat);
                if n > 0 {
                    stats.rocks_drawn += 1;
                    stats.triangles += n;
                }
            }
            stats.triangles +=
                draw_chunk(scene, k, &self.lod, &mut pass, &mut target, &terrain_mat);
        }
        stats.triangles += draw_markers(scene, &view, &proj, &mut target);
        let Target { zbuf, out, .. } = target;
        self.noise.apply(noise_key, zbuf, out, stride, w);
        Ok(stats)
    }

    /// Empties the depth buffer and paints the image with the sky.
    fn clear(&mut self, out: &mut [u8], stride: usize, (w, h): (usize, usize)) {
        self.zbuf.fill(0.0);
        for row in 0..h {
            out[row * stride..row * stride + w].fill(self.cfg.sky_dn);
        }
    }

    /// The camera's intrinsics for an image of `w`×`h` pixels, in `f32`.
    fn frame(&self, (w, h): (usize, usize)) -> Frame {
        let cam = &self.camera;
        Frame {
            fx: cam.fx_px as f32,
            fy: cam.fy_px as f32,
            cx: cam.cx_px as f32,
            cy: cam.cy_px as f32,
            width: w as f32,
            height: h as f32,
            near: cam.near_m as f32,
        }
    }

    /// The image size, once the output buffer is large enough for it at `stride` and the
    /// pose is finite.
    fn check_target(
        &self,
        world_from_camera: &Isometry3<f64>,
        out_len: usize,
        stride: usize,
    ) -> Result<(usize, usize), RenderError> {
        let (w, h) = (
            self.camera.width_px as usize,
            self.camera.height_px as usize,
        );
        if stride < w {
            return Err(RenderError::StrideTooSmall {
                stride_bytes: stride,
                width_px: w,
            });
        }
        let needed = self.required_len(stride);
        if out_len < needed {
            return Err(RenderError::BufferTooSmall {
                needed_bytes: needed,
                got_bytes: out_len,
            });
        }
        let t = &world_from_camera.translation.vector;
        let q = world_from_camera.rotation.coords;
        if !(t.iter().all(|v| v.is_finite()) && q.iter().all(|v| v.is_finite())) {
            return Err(RenderError::NonFinitePose);
        }
        Ok((w, h))
    }

    /// The level of detail of every chunk (neighbours are needed for stitching), then the
    /// visible ones nearest first. The coarsest step whose vertical error projects below
    /// `lod_error_px` at the chunk's nearest point, and whose cells stay under a quarter of
    /// that distance (so one mip level per triangle stays right).
    fn choose_lods(&mut self, scene: &RenderScene, view: &View, focal: f32) {
        let tau = self.cfg.lod_error_px as f32;
        self.lod.clear();
        self.order.clear();
        for (k, ch) in scene.chunks.iter().enumerate() {
            let d = view.box_distance(ch.min, ch.max);
            let mut l = 0u8;
            while l < ch.max_lod {
                let next = usize::from(l + 1);
                let cell_m = (1u32 << next) as f32 * scene.spacing;
                if cell_m > 0.25 * d || focal * ch.lod_error[next] > tau * d {
                    break;
                }
                l += 1;
            }
            self.lod.push(l);
            if view.box_visible(ch.min, ch.max) {
                self.order.push((d, k as u32));
            }
        }
        self.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    }

    /// Renders a stereo pair: the right camera sits `baseline_m` along the left camera's +x.
    /// Each view has its own noise pattern.
    #[allow(clippy::too_many_arguments)]
    pub fn render_stereo(
        &mut self,
        scene: &RenderScene,
        world_from_left: &Isometry3<f64>,
        baseline_m: f64,
        noise_key: u64,
        left: &mut [u8],
        right: &mut [u8],
        stride: usize,
    ) -> Result<[RenderStats; 2], RenderError> {
        let l = self.render(scene, world_from_left, noise_key, left, stride)?;
        let right_pose = stereo_right(world_from_left, baseline_m);
        let r = self.render(
            scene,
            &right_pose,
            noise_key ^ RIGHT_VIEW_KEY,
            right,
            stride,
        )?;
        Ok([l, r])
    }

    /// Renders a stereo pair into one slice holding the two views stacked, left first (the
    /// layout of the image samples): the left view occupies `stride · height` bytes, the right
    /// view follows.
    pub fn render_stereo_stacked(
        &mut self,
        scene: &RenderScene,
        world_from_left: &Isometry3<f64>,
        baseline_m: f64,
        noise_key: u64,
        out: &mut [u8],
        stride: usize,
    ) -> Result<[RenderStats; 2], RenderError> {
        let view = stride.saturating_mul(self.camera.height_px as usize);
        let needed = view.saturating_add(self.required_len(stride));
        if out.len() < needed {
            return Err(RenderError::BufferTooSmall {
                needed_bytes: needed,
                got_bytes: out.len(),
            });
        }
        let (left, right) = out.split_at_mut(view);
        self.render_stereo(
            scene,
            world_from_left,
            baseline_m,
            noise_key,
            left,
            right,
            stride,
        )
    }
}

/// Draws the scene's marker squares (two triangles each); returns the triangle count.
fn draw_markers(scene: &RenderScene, view: &View, proj: &Projector, target: &mut Target) -> u32 {
    let mut triangles = 0;
    for m in &scene.markers {
        let cv = m.corners.map(|p| ClipVertex {
            p: view.to_camera(p),
            ..Default::default()
        });
        let mat = FlatMaterial(m.value);
        draw_clipped(target, &mat, proj, [&cv[0], &cv[1], &cv[2]]);
        draw_clipped(target, &mat, proj, [&cv[0], &cv[2], &cv[3]]);
        triangles += 2;
    }
    triangles
}
