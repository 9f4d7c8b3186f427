//! Render-ready data derived once from a [`World`]: terrain chunks with bounding boxes,
//! baked textures, rock vertices with baked shading, and marker quads.

use crate::World;
use crate::bake::{bake_detail_texture, bake_rock_texture, bake_terrain_texture};
use crate::error::WorldError;
use crate::mesh::{icosphere, rock_mesh};
use crate::rng::mix64;
use crate::texture::{MipTexture, ROCK_TEXEL_M};

/// Cells per chunk side (a power of two: the coarsest LOD step).
pub(crate) const CHUNK_CELLS: usize = 16;
/// Unit-sphere z below which a rock face counts as buried and is never drawn.
const BURIED_Z: f64 = -0.45;

/// A square block of terrain cells with its bounding box and rocks.
#[derive(Debug, Clone)]
pub(crate) struct Chunk {
    /// First node (column, row).
    pub i0: usize,
    pub j0: usize,
    /// Cells along x and y.
    pub ci: usize,
    pub cj: usize,
    /// Bounding box (terrain and rocks), world metres.
    pub min: [f32; 3],
    pub max: [f32; 3],
    /// log2 of the coarsest step dividing both `ci` and `cj` (≤ log2 CHUNK_CELLS).
    pub max_lod: u8,
    /// Largest vertical error, metres, of drawing the chunk with step `2^l` (index `l`).
    pub lod_error: [f32; 5],
    /// Range into `RenderScene::chunk_rocks`.
    pub rocks: (u32, u32),
}

/// One rock ready to draw.
#[derive(Debug, Clone)]
pub(crate) struct RockInstance {
    /// First vertex in `RenderScene::rock_vertices`.
    pub first_vertex: u32,
    /// First entry in `RenderScene::rock_faces` (hi faces, then lo faces).
    pub first_axis: u32,
    /// Bounding-sphere centre and radius, world metres.
    pub center: [f32; 3],
    pub radius: f32,
    /// Texture offset (rock-tile texels), so rocks do not look alike.
    pub uv_offset: [f32; 2],
    /// Top point, world metres, and its brightness, for rocks smaller than a pixel.
    pub top: [f32; 3],
    pub splat_value: u8,
}

/// A rock vertex: world position.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RockVertex {
    pub p: [f32; 3],
}

/// Per-face data of a rock: texture projection axis and flat brightness
/// (albedo × Lambert shading / 128), which gives rocks their angular, faceted look.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RockFace {
    /// World axis the face's texture is projected along (0 = x, 1 = y, 2 = z).
    pub axis: u8,
    pub s: f32,
}

/// A flat square marker.
#[derive(Debug, Clone)]
pub(crate) struct MarkerQuad {
    pub corners: [[f32; 3]; 4],
    pub value: u8,
}

/// Everything the renderer needs, built once per world (textures take ~1 s for 64 m × 64 m
/// at 2 cm texels in release builds).
#[derive(Debug, Clone)]
pub struct RenderScene {
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) spacing: f32,
    pub(crate) origin: [f32; 2],
    pub(crate) heights: Vec<f32>,
    pub(crate) chunks_x: usize,
    pub(crate) chunks_y: usize,
    pub(crate) chunks: Vec<Chunk>,
    pub(crate) atlas: MipTexture,
    pub(crate) atlas_origin: [f32; 2],
    pub(crate) inv_texel: [f32; 2],
    pub(crate) detail: MipTexture,
    /// Detail-tile texels per atlas texel, along u and v.
    pub(crate) detail_per_atlas: [f32; 2],
    pub(crate) rock_tex: MipTexture,
    pub(crate) rocks: Vec<RockInstance>,
    pub(crate) rock_vertices: Vec<RockVertex>,
    pub(crate) rock_faces: Vec<RockFace>,
    pub(crate) rock_faces_hi: Vec<[u16; 3]>,
    pub(crate) rock_faces_lo: Vec<[u16; 3]>,
    pub(crate) rock_vertex_count: usize,
    pub(crate) chunk_rocks: Vec<u32>,
    pub(crate) markers: Vec<MarkerQuad>,
}

/// Vertical error of each LOD level of a chunk: the largest distance between a node's height
/// and the coarse triangles (same diagonal split as the renderer) through it.
fn lod_errors(
    heights: &[f32],
    nx: usize,
    origin: (usize, usize),
    cells: (usize, usize),
    max_lod: u8,
) -> [f32; 5] {
    let h = |i: usize, j: usize| heights[j * nx + i];
    let mut err = [0f32; 5];
    for l in 1..=max_lod.min(4) {
        let s = 1usize << l;
        let mut e = 0f32;
        for j in 0..=cells.1 {
            for i in 0..=cells.0 {
                let (ci, cj) = (
                    (i / s).min(cells.0 / s - 1) * s,
                    (j / s).min(cells.1 / s - 1) * s,
                );
                let fx = (i - ci) as f32 / s as f32;
                let fy = (j - cj) as f32 / s as f32;
                let (gi, gj) = (origin.0 + ci, origin.1 + cj);
                let (h00, h10) = (h(gi, gj), h(gi + s, gj));
                let (h01, h11) = (h(gi, gj + s), h(gi + s, gj + s));
                let approx = if fx >= fy {
                    h00 + fx * (h10 - h00) + fy * (h11 - h10)
                } else {
                    h00 + fy * (h01 - h00) + fx * (h11 - h01)
                };
                e = e.max((h(origin.0 + i, origin.1 + j) - approx).abs());
            }
        }
        err[l as usize] = e.max(err[l as usize - 1]);
    }
    err
}

fn visible_faces(level: u32) -> (Vec<[u16; 3]>, usize) {
    let m = icosphere(level);
    let faces = m
        .triangles
        .iter()
        .filter(|t| t.iter().any(|&k| m.positions_m[k as usize][2] > BURIED_Z))
        .map(|t| t.map(|k| k as u16))
        .collect();
    (faces, m.positions_m.len())
}

fn dominant_axis(n: [f64; 3]) -> u8 {
    let a = n.map(f64::abs);
    if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    }
}

/// The terrain's chunks of up to `CHUNK_CELLS`² cells, row by row: each with its height
/// range, bounding box, coarsest level of detail and its errors (no rocks yet).
fn terrain_chunks(
    heights: &[f32],
    (nx, ny): (usize, usize),
    spacing: f32,
    origin: [f32; 2],
) -> Vec<Chunk> {
    let chunks_x = (nx - 1).div_ceil(CHUNK_CELLS);
    let chunks_y = (ny - 1).div_ceil(CHUNK_CELLS);
    let mut chunks = Vec::with_capacity(chunks_x * chunks_y);
    for cy in 0..chunks_y {
        for cx in 0..chunks_x {
            let (i0, j0) = (cx * CHUNK_CELLS, cy * CHUNK_CELLS);
            let ci = CHUNK_CELLS.min(nx - 1 - i0);
            let cj = CHUNK_CELLS.min(ny - 1 - j0);
            let (mut zmin, mut zmax) = (f32::INFINITY, f32::NEG_INFINITY);
            for j in j0..=j0 + cj {
                for i in i0..=i0 + ci {
                    let z = heights[j * nx + i];
                    zmin = zmin.min(z);
                    zmax = zmax.max(z);
                }
            }
            let mut max_lod = 0u8;
            while (1usize << (max_lod + 1)) <= CHUNK_CELLS
                && ci.is_multiple_of(1 << (max_lod + 1))
                && cj.is_multiple_of(1 << (max_lod + 1))
            {
                max_lod += 1;
            }
            chunks.push(Chunk {
                i0,
                j0,
                ci,
                cj,
                min: [
                    origin[0] + i0 as f32 * spacing,
                    origin[1] + j0 as f32 * spacing,
                    zmin,
                ],
                max: [
                    origin[0] + (i0 + ci) as f32 * spacing,
                    origin[1] + (j0 + cj) as f32 * spacing,
                    zmax,
                ],
                max_lod,
                lod_error: lod_errors(heights, nx, (i0, j0), (ci, cj), max_lod),
                rocks: (0, 0),
            });
        }
    }
    chunks
}

/// The rocks' draw data and where they are binned.
struct RockGeometry {
    rocks: Vec<RockInstance>,
    vertices: Vec<RockVertex>,
    faces: Vec<RockFace>,
    /// Rock indices, chunk by chunk (each chunk's `rocks` range points in here).
    chunk_rocks: Vec<u32>,
}

/// Rocks: vertices with baked shading, per-face texture projection axes, chunk bins. Each
/// rock is binned by the chunk under its centre, whose box grows to hold it.
fn rock_geometry(
    world: &World,
    (rock_faces_hi, rock_faces_lo, rock_vertex_count): (&[[u16; 3]], &[[u16; 3]], usize),
    chunks: &mut [Chunk],
    (chunks_x, chunks_y): (usize, usize),
    (spacing, origin): (f32, [f32; 2]),
) -> RockGeometry {
    let cfg = world.config();
    let light = &cfg.lighting;
    let sun = light.sun_direction();
    let flat_shade = light.ambient + (1.0 - light.ambient) * sun[2];
    let mut rocks = Vec::with_capacity(world.rocks().len());
    let mut rock_vertices = Vec::with_capacity(world.rocks().len() * rock_vertex_count);
    let mut rock_faces =
        Vec::with_capacity(world.rocks().len() * (rock_faces_hi.len() + rock_faces_lo.len()));
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); chunks.len()];
    for (idx, rock) in world.rocks().iter().enumerate() {
        let mesh = rock_mesh(rock);
        let h = mix64(rock.shape_seed ^ 0x00A1_BED0);
        let albedo = cfg.texture.rock_albedo_dn * (0.8 + 0.4 * crate::rng::unit_f64(h));
        let first_vertex = rock_vertices.len() as u32;
        for p in &mesh.positions_m {
            rock_vertices.push(RockVertex {
                p: p.map(|v| v as f32),
            });
        }
        let first_axis = rock_faces.len() as u32;
        for t in rock_faces_hi.iter().chain(rock_faces_lo) {
            let n = face_normal(&mesh.positions_m, t.map(u32::from));
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
            let lambert = ((n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2]) / len).max(0.0);
            let shade = (light.ambient + (1.0 - light.ambient) * lambert) / flat_shade;
            rock_faces.push(RockFace {
                axis: dominant_axis(n),
                s: (albedo * shade / 128.0) as f32,
            });
        }
        let radius = rock.bounding_radius_m().max(rock.height_m) * 1.3;
        let center = [rock.center_m[0], rock.center_m[1], rock.center_m[2]];
        rocks.push(RockInstance {
            first_vertex,
            first_axis,
            center: center.map(|v| v as f32),
            radius: radius as f32,
            uv_offset: [
                (h & 0xffff) as f32 / 65536.0 * 256.0,
                ((h >> 16) & 0xffff) as f32 / 65536.0 * 256.0,
            ],
            top: [
                rock.center_m[0] as f32,
                rock.center_m[1] as f32,
                rock.top_z_m() as f32,
            ],
            splat_value: albedo.round().clamp(0.0, 255.0) as u8,
        });
        // Bin by the chunk under the centre; grow that chunk's box to hold the rock.
        let k = chunk_under(rock.center_m, (chunks_x, chunks_y), (spacing, origin));
        bins[k].push(idx as u32);
        grow_to_hold(&mut chunks[k], center.map(|v| v as f32), radius as f32);
    }
    let mut chunk_rocks = Vec::with_capacity(rocks.len());
    for (c, bin) in chunks.iter_mut().zip(&bins) {
        let start = chunk_rocks.len() as u32;
        chunk_rocks.extend_from_slice(bin);
        c.rocks = (start, chunk_rocks.len() as u32);
    }
    RockGeometry {
        rocks,
        vertices: rock_vertices,
        faces: rock_faces,
        chunk_rocks,
    }
}

/// The (unnormalised) normal of triangle `t` of a mesh with vertices `positions_m`.
fn face_normal(positions_m: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [p0, p1, p2] = t.map(|k| positions_m[k as usize]);
    let e1 = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
    let e2 = [p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]];
    [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ]
}

/// Index of the chunk under the horizontal position of `center_m` (clamped to the grid).
fn chunk_under(
    center_m: [f64; 3],
    (chunks_x, chunks_y): (usize, usize),
    (spacing, origin): (f32, [f32; 2]),
) -> usize {
    let ci = (((center_m[0] - f64::from(origin[0])) / f64::from(spacing)) as usize / CHUNK_CELLS)
        .min(chunks_x - 1);
    let cj = (((center_m[1] - f64::from(origin[1])) / f64::from(spacing)) as usize / CHUNK_CELLS)
        .min(chunks_y - 1);
    cj * chunks_x + ci
}

/// Grows the chunk's box to hold a sphere of radius `r` about `center`.
fn grow_to_hold(c: &mut Chunk, center: [f32; 3], r: f32) {
    c.min = [
        c.min[0].min(center[0] - r),
        c.min[1].min(center[1] - r),
        c.min[2].min(center[2] - r),
    ];
    c.max = [
        c.max[0].max(center[0] + r),
        c.max[1].max(center[1] + r),
        c.max[2].max(center[2] + r),
    ];
}

/// The flat marker squares, as four corners each.
fn marker_quads(world: &World) -> Vec<MarkerQuad> {
    world
        .markers()
        .iter()
        .map(|m| {
            let [x, y, z] = m.center_m.map(|v| v as f32);
            let s = m.half_size_m as f32;
            MarkerQuad {
                corners: [
                    [x - s, y - s, z],
                    [x + s, y - s, z],
                    [x + s, y + s, z],
                    [x - s, y + s, z],
                ],
                value: m.value_dn,
            }
        })
        .collect()
}

impl RenderScene {
    /// Bakes textures and builds chunks and rock geometry for `world`.
    pub fn new(world: &World) -> Result<Self, WorldError> {
        world.config().validate()?;
        let hf = world.terrain();
        let cfg = world.config();
        let (nx, ny) = (hf.nx(), hf.ny());
        let heights: Vec<f32> = hf.heights_m().iter().map(|&h| h as f32).collect();
        let spacing = hf.spacing_m() as f32;
        let origin = hf.origin_m().map(|v| v as f32);

        let tex = bake_terrain_texture(world);
        let detail = bake_detail_texture(cfg.seed, &cfg.texture, cfg.lighting.sun_direction());
        let rock_tex = bake_rock_texture(cfg.seed);
        let detail_per_atlas = [
            (tex.texel_m[0] / cfg.texture.detail_texel_m) as f32,
            (tex.texel_m[1] / cfg.texture.detail_texel_m) as f32,
        ];

        let (chunks_x, chunks_y) = (
            (nx - 1).div_ceil(CHUNK_CELLS),
            (ny - 1).div_ceil(CHUNK_CELLS),
        );
        let mut chunks = terrain_chunks(&heights, (nx, ny), spacing, origin);

        let (rock_faces_hi, rock_vertex_count) = visible_faces(1);
        let (rock_faces_lo, _) = visible_faces(0);
        let rock_geometry = rock_geometry(
            world,
            (&rock_faces_hi, &rock_faces_lo, rock_vertex_count),
            &mut chunks,
            (chunks_x, chunks_y),
            (spacing, origin),
        );
        let (rocks, rock_vertices, rock_faces, chunk_rocks) = (
            rock_geometry.rocks,
            rock_geometry.vertices,
            rock_geometry.faces,
            rock_geometry.chunk_rocks,
        );

        let markers = marker_quads(world);

        Ok(Self {
            nx,
            ny,
            spacing,
            origin,
            heights,
            chunks_x,
            chunks_y,
            chunks,
            atlas: tex.atlas,
            atlas_origin: tex.origin_m.map(|v| v as f32),
            inv_texel: tex.texel_m.map(|v| (1.0 / v) as f32),
            detail,
            detail_per_atlas,
            rock_tex,
            rocks,
            rock_vertices,
            rock_faces,
            rock_faces_hi,
            rock_faces_lo,
            rock_vertex_count,
            chunk_rocks,
            markers,
        })
    }

    /// Number of terrain chunks.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// Number of rocks.
    pub fn rock_count(&self) -> usize {
        self.rocks.len()
    }

    /// Bytes held by the baked textures (all mip levels).
    pub fn texture_bytes(&self) -> usize {
        [&self.atlas, &self.detail, &self.rock_tex]
            .iter()
            .map(|t| {
                (0..t.level_count())
                    .map(|l| t.level(l).data.len())
                    .sum::<usize>()
            })
            .sum()
    }
}

/// Rock-tile texels per metre.
pub(crate) const ROCK_TEXELS_PER_M: f32 = (1.0 / ROCK_TEXEL_M) as f32;
