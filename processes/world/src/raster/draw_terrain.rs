//! Drawing one terrain chunk: vertices at the chunk's LOD step (edges stitched to coarser
//! neighbours), camera transform, projection, and two triangles per cell.

use super::materials::TerrainMaterial;
use super::pass::DrawPass;
use super::scene::RenderScene;
use super::tri::{ClipVertex, Projector, ScreenVertex, Target, draw_clipped, draw_projected};

/// Draws one terrain chunk at its LOD; returns the number of triangles submitted.
pub(crate) fn draw_chunk(
    scene: &RenderScene,
    k: usize,
    lod: &[u8],
    pass: &mut DrawPass<'_>,
    target: &mut Target<'_>,
    mat: &TerrainMaterial<'_>,
) -> u32 {
    let ch = &scene.chunks[k];
    let s = 1usize << lod[k];
    let nv = (ch.ci / s + 1, ch.cj / s + 1);
    transform_vertices(scene, k, lod, pass);
    let sp = scene.spacing;
    let (tu, tv) = (sp * scene.inv_texel[0], sp * scene.inv_texel[1]);
    let cell_uv_area = 0.5 * (s as f32 * tu) * (s as f32 * tv);
    draw_cells(
        nv,
        cell_uv_area,
        pass.proj,
        pass.clip,
        pass.screen,
        target,
        mat,
    )
}

/// LOD levels of a chunk's four neighbours (0 where there is none).
struct NeighbourLods {
    left: u8,
    right: u8,
    down: u8,
    up: u8,
}

impl NeighbourLods {
    fn of(scene: &RenderScene, lod: &[u8], k: usize) -> Self {
        let (cx, cy) = (k % scene.chunks_x, k / scene.chunks_x);
        let neighbour = |cond: bool, idx: usize| if cond { lod[idx] } else { 0 };
        Self {
            left: neighbour(cx > 0, k.wrapping_sub(1)),
            right: neighbour(cx + 1 < scene.chunks_x, k + 1),
            down: neighbour(cy > 0, k.wrapping_sub(scene.chunks_x)),
            up: neighbour(cy + 1 < scene.chunks_y, k + scene.chunks_x),
        }
    }
}

/// Heightmap lookups, clamped to the grid.
struct Heights<'a> {
    heights: &'a [f32],
    nx: usize,
    max_i: usize,
    max_j: usize,
}

impl<'a> Heights<'a> {
    fn of(scene: &'a RenderScene) -> Self {
        Self {
            heights: &scene.heights,
            nx: scene.nx,
            max_i: scene.nx - 1,
            max_j: scene.ny - 1,
        }
    }

    #[inline(always)]
    fn at(&self, i: usize, j: usize) -> f32 {
        self.heights[j.min(self.max_j) * self.nx + i.min(self.max_i)]
    }

    /// Height on an edge along j shared with a coarser neighbour of step 2^nl.
    #[inline(always)]
    fn along_j(&self, i: usize, j: usize, nl: u8) -> f32 {
        on_coarse_edge(j, nl, |j| self.at(i, j))
    }

    /// Height on an edge along i shared with a coarser neighbour of step 2^nl.
    #[inline(always)]
    fn along_i(&self, i: usize, j: usize, nl: u8) -> f32 {
        on_coarse_edge(i, nl, |i| self.at(i, j))
    }
}

/// Height at node `pos` of an edge drawn with step 2^nl: interpolated between the coarse
/// step's nodes, so the finer chunk leaves no crack against its coarser neighbour.
#[inline(always)]
fn on_coarse_edge(pos: usize, nl: u8, at: impl Fn(usize) -> f32) -> f32 {
    let big = 1usize << nl;
    let r = pos % big;
    if r == 0 {
        at(pos)
    } else {
        let f = r as f32 / big as f32;
        at(pos - r) * (1.0 - f) + at(pos - r + big) * f
    }
}

/// Fills `clip` with chunk `k`'s vertices in camera space (edges stitched to coarser
/// neighbours) and `screen` with the projections of those in front of the near plane.
fn transform_vertices(scene: &RenderScene, k: usize, lod: &[u8], pass: &mut DrawPass<'_>) {
    let DrawPass {
        view,
        proj,
        clip,
        screen,
    } = pass;
    let ch = &scene.chunks[k];
    let l = lod[k];
    let s = 1usize << l;
    let (nvx, nvy) = (ch.ci / s + 1, ch.cj / s + 1);
    let around = NeighbourLods::of(scene, lod, k);
    let heights = Heights::of(scene);
    let sp = scene.spacing;
    let (tu, tv) = (sp * scene.inv_texel[0], sp * scene.inv_texel[1]);
    let u_off = (scene.origin[0] - scene.atlas_origin[0]) * scene.inv_texel[0];
    let v_off = (scene.origin[1] - scene.atlas_origin[1]) * scene.inv_texel[1];
    let mut idx = 0;
    for b in 0..nvy {
        let gj = ch.j0 + b * s;
        for a in 0..nvx {
            let gi = ch.i0 + a * s;
            let mut z = heights.at(gi, gj);
            if a == 0 && around.left > l {
                z = heights.along_j(gi, gj, around.left);
            } else if a + 1 == nvx && around.right > l {
                z = heights.along_j(gi, gj, around.right);
            }
            if b == 0 && around.down > l {
                z = heights.along_i(gi, gj, around.down);
            } else if b + 1 == nvy && around.up > l {
                z = heights.along_i(gi, gj, around.up);
            }
            let p = [
                scene.origin[0] + gi as f32 * sp,
                scene.origin[1] + gj as f32 * sp,
                z,
            ];
            let cv = ClipVertex {
                p: view.to_camera(p),
                u: u_off + gi as f32 * tu,
                v: v_off + gj as f32 * tv,
                s: 1.0,
            };
            if cv.p[2] >= proj.near {
                screen[idx] = proj.project(&cv);
            }
            clip[idx] = cv;
            idx += 1;
        }
    }
}

/// Draws two triangles per cell of an `nv.0` × `nv.1` vertex grid: projected when all three
/// corners are in front of the near plane, clipped when some are; returns how many.
fn draw_cells(
    (nvx, nvy): (usize, usize),
    cell_uv_area: f32,
    proj: &Projector,
    clip: &[ClipVertex],
    screen: &[ScreenVertex],
    target: &mut Target<'_>,
    mat: &TerrainMaterial<'_>,
) -> u32 {
    let near = proj.near;
    let mut count = 0;
    for b in 0..nvy - 1 {
        for a in 0..nvx - 1 {
            let k00 = b * nvx + a;
            let (k10, k01, k11) = (k00 + 1, k00 + nvx, k00 + nvx + 1);
            for [i0, i1, i2] in [[k00, k10, k11], [k00, k11, k01]] {
                count += 1;
                let front = [i0, i1, i2].map(|i| clip[i].p[2] >= near);
                if front[0] && front[1] && front[2] {
                    draw_projected(
                        target,
                        mat,
                        &screen[i0],
                        &screen[i1],
                        &screen[i2],
                        cell_uv_area,
                    );
                } else if front[0] || front[1] || front[2] {
                    draw_clipped(target, mat, proj, [&clip[i0], &clip[i1], &clip[i2]]);
                }
            }
        }
    }
    count
}
