//! Drawing one rock: frustum culling, size LOD (disc splat, 20-face or 80-face mesh),
//! per-face texture projection and flat shading.

use super::materials::RockMaterial;
use super::pass::DrawPass;
use super::scene::{ROCK_TEXELS_PER_M, RenderScene, RockInstance};
use super::tri::{ClipVertex, Projector, Target, draw_clipped, draw_projected, uv_area};
use super::view::View;

/// Rocks smaller than this on screen (radius, px) use the 20-face mesh.
const ROCK_LOW_POLY_PX: f32 = 6.0;
/// Rocks smaller than this on screen (radius, px) are drawn as a small flat disc.
const ROCK_SPLAT_PX: f32 = 2.0;
/// Rocks smaller than this on screen (radius, px) are skipped.
const ROCK_MIN_PX: f32 = 0.3;

/// Draws a rock a few pixels wide as a disc of radius `r_px` around its projected top, at the
/// top's depth, its lower half a little darker (lit from above).
fn splat_rock(
    rock: &RockInstance,
    view: &View,
    proj: &Projector,
    r_px: f32,
    target: &mut Target<'_>,
) {
    let p = view.to_camera(rock.top);
    if p[2] < proj.near {
        return;
    }
    let sv = proj.project(&ClipVertex {
        p,
        ..Default::default()
    });
    let r = r_px.max(0.5);
    let (w, h) = (target.width as f32, target.height as f32);
    let y0 = (sv.y - r).ceil().clamp(0.0, h) as usize;
    let y1 = ((sv.y + r).floor() + 1.0).clamp(0.0, h) as usize;
    let x0 = (sv.x - r).ceil().clamp(0.0, w) as usize;
    let x1 = ((sv.x + r).floor() + 1.0).clamp(0.0, w) as usize;
    let lit = rock.splat_value;
    let shadow = lit - lit / 5;
    for y in y0..y1 {
        let dy = y as f32 - sv.y;
        for x in x0..x1 {
            let dx = x as f32 - sv.x;
            if dx * dx + dy * dy <= r * r {
                let z = &mut target.zbuf[y * target.width + x];
                if sv.iz > *z {
                    *z = sv.iz;
                    target.out[y * target.stride + x] = if dy > 0.0 { shadow } else { lit };
                }
            }
        }
    }
}

/// Draws one rock (culling and LOD included); returns the number of triangles submitted.
pub(crate) fn draw_rock(
    scene: &RenderScene,
    ri: usize,
    focal: f32,
    pass: &mut DrawPass<'_>,
    target: &mut Target<'_>,
    mat: &RockMaterial<'_>,
) -> u32 {
    let DrawPass {
        view,
        proj,
        clip,
        screen,
    } = pass;
    let rock = &scene.rocks[ri];
    if !view.sphere_visible(rock.center, rock.radius) {
        return 0;
    }
    let radius_px = focal * rock.radius / view.distance(rock.center).max(proj.near);
    if radius_px < ROCK_MIN_PX {
        return 0;
    }
    if radius_px < ROCK_SPLAT_PX {
        splat_rock(rock, view, proj, 0.8 * radius_px, target);
        return 1;
    }
    let (faces, axis_off, nverts) = if radius_px < ROCK_LOW_POLY_PX {
        (&scene.rock_faces_lo, scene.rock_faces_hi.len(), 12)
    } else {
        (&scene.rock_faces_hi, 0, scene.rock_vertex_count)
    };
    let v0 = rock.first_vertex as usize;
    let verts = &scene.rock_vertices[v0..v0 + nverts];
    for (k, rv) in verts.iter().enumerate() {
        let cv = ClipVertex {
            p: view.to_camera(rv.p),
            u: 0.0,
            v: 0.0,
            s: 1.0,
        };
        if cv.p[2] >= proj.near {
            screen[k] = proj.project(&cv);
        }
        clip[k] = cv;
    }
    let face_data = &scene.rock_faces[rock.first_axis as usize + axis_off..];
    let near = proj.near;
    for (f, fd) in faces.iter().zip(face_data) {
        let axis = usize::from(fd.axis);
        let (ua, va) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut cv = [ClipVertex::default(); 3];
        for (c, &vi) in cv.iter_mut().zip(f) {
            let vi = usize::from(vi);
            let wp = verts[vi].p;
            *c = clip[vi];
            c.u = wp[ua] * ROCK_TEXELS_PER_M + rock.uv_offset[0];
            c.v = wp[va] * ROCK_TEXELS_PER_M + rock.uv_offset[1];
            c.s = fd.s;
        }
        let area = uv_area(&cv[0], &cv[1], &cv[2]);
        if cv.iter().all(|c| c.p[2] >= near) {
            let sv = [0, 1, 2].map(|i| {
                let mut s = screen[usize::from(f[i])];
                s.uz = cv[i].u * s.iz;
                s.vz = cv[i].v * s.iz;
                s.u = cv[i].u;
                s.v = cv[i].v;
                s.sz = fd.s * s.iz;
                s.s = fd.s;
                s
            });
            draw_projected(target, mat, &sv[0], &sv[1], &sv[2], area);
        } else {
            draw_clipped(target, mat, proj, [&cv[0], &cv[1], &cv[2]]);
        }
    }
    faces.len() as u32
}
