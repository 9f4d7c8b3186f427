//! Drawing one terrain chunk: vertices at the chunk's LOD step (edges stitched to coarser
//! neighbours), camera transform, projection, and two triangles per cell.

use super::materials::TerrainMaterial;
use super::scene::RenderScene;
use super::tri::{ClipVertex, Projector, ScreenVertex, Target, draw_clipped, draw_projected};
use super::view::View;

/// Draws one terrain chunk at its LOD; returns the number of triangles submitted.
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw_chunk(
    scene: &RenderScene,
    k: usize,
    lod: &[u8],
    view: &View,
    proj: &Projector,
    clip: &mut [ClipVertex],
    screen: &mut [ScreenVertex],
    target: &mut Target<'_>,
    mat: &TerrainMaterial<'_>,
) -> u32 {
    let ch = &scene.chunks[k];
    let l = lod[k];
    let s = 1usize << l;
    let (nvx, nvy) = (ch.ci / s + 1, ch.cj / s + 1);
    let (cx, cy) = (k % scene.chunks_x, k / scene.chunks_x);
    let neighbour = |cond: bool, idx: usize| if cond { lod[idx] } else { 0 };
    let l_left = neighbour(cx > 0, k.wrapping_sub(1));
    let l_right = neighbour(cx + 1 < scene.chunks_x, k + 1);
    let l_down = neighbour(cy > 0, k.wrapping_sub(scene.chunks_x));
    let l_up = neighbour(cy + 1 < scene.chunks_y, k + scene.chunks_x);
    let nx = scene.nx;
    let hmax_i = scene.nx - 1;
    let hmax_j = scene.ny - 1;
    let h = |i: usize, j: usize| scene.heights[j.min(hmax_j) * nx + i.min(hmax_i)];
    // Height on an edge shared with a coarser neighbour of step 2^nl: interpolate along it.
    let along_j = |i: usize, j: usize, nl: u8| {
        let big = 1usize << nl;
        let r = j % big;
        if r == 0 {
            h(i, j)
        } else {
            let f = r as f32 / big as f32;
            h(i, j - r) * (1.0 - f) + h(i, j - r + big) * f
        }
    };
    let along_i = |i: usize, j: usize, nl: u8| {
        let big = 1usize << nl;
        let r = i % big;
        if r == 0 {
            h(i, j)
        } else {
            let f = r as f32 / big as f32;
            h(i - r, j) * (1.0 - f) + h(i - r + big, j) * f
        }
    };
    let sp = scene.spacing;
    let (tu, tv) = (sp * scene.inv_texel[0], sp * scene.inv_texel[1]);
    let u_off = (scene.origin[0] - scene.atlas_origin[0]) * scene.inv_texel[0];
    let v_off = (scene.origin[1] - scene.atlas_origin[1]) * scene.inv_texel[1];
    let mut idx = 0;
    for b in 0..nvy {
        let gj = ch.j0 + b * s;
        for a in 0..nvx {
            let gi = ch.i0 + a * s;
            let mut z = h(gi, gj);
            if a == 0 && l_left > l {
                z = along_j(gi, gj, l_left);
            } else if a + 1 == nvx && l_right > l {
                z = along_j(gi, gj, l_right);
            }
            if b == 0 && l_down > l {
                z = along_i(gi, gj, l_down);
            } else if b + 1 == nvy && l_up > l {
                z = along_i(gi, gj, l_up);
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
    let cell_uv_area = 0.5 * (s as f32 * tu) * (s as f32 * tv);
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
