//! Triangle meshes of the terrain and the rocks (deterministic).
//!
//! Winding: counter-clockwise seen from outside (terrain: from above), so face normals
//! `(p1 − p0) × (p2 − p0)` point outward / up.
//!
//! ```
//! use hopnav_world::mesh::icosphere;
//! let m = icosphere(1);
//! assert_eq!((m.positions_m.len(), m.triangles.len()), (42, 80));
//! ```

use crate::rng::{Rng, mix64};
use crate::rocks::Rock;
use crate::terrain::Heightfield;

/// An indexed triangle mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriMesh {
    /// Vertex positions, metres.
    pub positions_m: Vec<[f64; 3]>,
    /// Vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Full-resolution terrain mesh: one vertex per node (row-major, like the heights), two
/// triangles per cell split along the (i, j)–(i+1, j+1) diagonal.
pub fn terrain_mesh(hf: &Heightfield) -> TriMesh {
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut positions_m = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let [x, y] = hf.node_xy_m(i, j);
            positions_m.push([x, y, hf.node_height_m(i, j)]);
        }
    }
    let mut triangles = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let k00 = (j * nx + i) as u32;
            let k10 = k00 + 1;
            let k01 = k00 + nx as u32;
            let k11 = k01 + 1;
            triangles.push([k00, k10, k11]);
            triangles.push([k00, k11, k01]);
        }
    }
    TriMesh {
        positions_m,
        triangles,
    }
}

/// Unit icosahedron (12 vertices, 20 faces).
fn icosahedron() -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let raw = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let positions_m = raw.iter().map(|p| normalize(*p)).collect();
    let triangles = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    TriMesh {
        positions_m,
        triangles,
    }
}

fn normalize(p: [f64; 3]) -> [f64; 3] {
    let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    if n > 0.0 {
        [p[0] / n, p[1] / n, p[2] / n]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Unit icosphere with `subdivisions` levels (0: 12 vertices; 1: 42; 2: 162).
/// The first 12 vertices are always the icosahedron's, so level-0 faces index into any level.
pub fn icosphere(subdivisions: u32) -> TriMesh {
    let mut mesh = icosahedron();
    for _ in 0..subdivisions.min(4) {
        let mut edges: Vec<((u32, u32), u32)> = Vec::new();
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<[f64; 3]>| -> u32 {
            let key = (a.min(b), a.max(b));
            if let Some(&(_, idx)) = edges.iter().find(|(k, _)| *k == key) {
                return idx;
            }
            let (pa, pb) = (pos[a as usize], pos[b as usize]);
            pos.push(normalize([
                (pa[0] + pb[0]) / 2.0,
                (pa[1] + pb[1]) / 2.0,
                (pa[2] + pb[2]) / 2.0,
            ]));
            let idx = (pos.len() - 1) as u32;
            edges.push((key, idx));
            idx
        };
        let mut tris = Vec::with_capacity(mesh.triangles.len() * 4);
        for &[a, b, c] in &mesh.triangles {
            let ab = midpoint(a, b, &mut mesh.positions_m);
            let bc = midpoint(b, c, &mut mesh.positions_m);
            let ca = midpoint(c, a, &mut mesh.positions_m);
            tris.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        mesh.triangles = tris;
    }
    mesh
}

/// Radial shape factors of a rock: a few smooth lumps plus per-vertex jitter (angular facets),
/// one factor around 1 per unit-sphere vertex.
fn lumps(seed: u64, unit: &[[f64; 3]]) -> Vec<f64> {
    let mut rng = Rng::new(seed, 0x6c75_6d70);
    let waves: Vec<([f64; 3], f64, f64, f64)> = (0..5)
        .map(|_| {
            let w = normalize([rng.normal(), rng.normal(), rng.normal()]);
            (
                w,
                rng.uniform(1.5, 3.5),
                rng.uniform(0.0, std::f64::consts::TAU),
                rng.uniform(0.04, 0.1),
            )
        })
        .collect();
    unit.iter()
        .map(|v| {
            let smooth: f64 = waves
                .iter()
                .map(|(w, freq, phase, amp)| {
                    amp * (freq * (w[0] * v[0] + w[1] * v[1] + w[2] * v[2]) + phase).cos()
                })
                .sum();
            1.0 + smooth + rng.uniform(-0.1, 0.1)
        })
        .collect()
}

/// Mesh of one rock: an icosphere (level 1: 42 vertices, 80 faces) scaled to the rock's
/// ellipsoid, yawed, made lumpy and angular by its `shape_seed`, flattened a little on top and
/// centred on `rock.center_m` (the lower half is buried). The highest vertex is exactly
/// `rock.height_m` above the centre. Its convex hull is a good collider.
pub fn rock_mesh(rock: &Rock) -> TriMesh {
    let mut mesh = icosphere(1);
    let [a, b, c] = rock.half_extents_m;
    let (s, co) = rock.yaw_rad.sin_cos();
    let factors = lumps(mix64(rock.shape_seed), &mesh.positions_m);
    let mut local: Vec<[f64; 3]> = mesh
        .positions_m
        .iter()
        .zip(&factors)
        .map(|(p, f)| {
            // Soft flattening of the upper cap (rocks rarely have domed tops).
            let z = if p[2] > 0.6 {
                0.6 + (p[2] - 0.6) * 0.5
            } else {
                p[2]
            };
            [a * p[0] * f, b * p[1] * f, c * z * f]
        })
        .collect();
    let top = local.iter().map(|p| p[2]).fold(f64::MIN, f64::max);
    let zscale = if top > 0.0 { c / top } else { 1.0 };
    for (p, l) in mesh.positions_m.iter_mut().zip(&mut local) {
        l[2] *= zscale;
        *p = [
            rock.center_m[0] + co * l[0] - s * l[1],
            rock.center_m[1] + s * l[0] + co * l[1],
            rock.center_m[2] + l[2],
        ];
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_is_closed_and_outward() {
        let m = icosphere(1);
        for t in &m.triangles {
            let [p0, p1, p2] = t.map(|k| m.positions_m[k as usize]);
            let e1 = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
            let e2 = [p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]];
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            assert!(n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2] > 0.0);
        }
        // Euler: V - E + F = 2 with E = 3F/2.
        assert_eq!(m.positions_m.len() as i64 - 120 + 80, 2);
    }

    #[test]
    fn rock_mesh_has_the_rock_height() {
        let rock = Rock {
            center_m: [1.0, 2.0, 0.5],
            diameter_m: 1.0,
            height_m: 0.45,
            half_extents_m: [0.55, 0.45, 0.45],
            yaw_rad: 0.3,
            shape_seed: 9,
            source: crate::rocks::RockSource::Golombek,
        };
        let m = rock_mesh(&rock);
        let top = m.positions_m.iter().map(|p| p[2]).fold(f64::MIN, f64::max);
        assert!((top - rock.top_z_m()).abs() < 1e-12);
        assert_eq!(m, rock_mesh(&rock));
    }

    #[test]
    fn terrain_mesh_faces_up() {
        let hf = Heightfield::flat(4, 3, 1.0, 0.0);
        let m = terrain_mesh(&hf);
        assert_eq!(m.triangles.len(), 2 * 3 * 2);
        let [p0, p1, p2] = m.triangles[1].map(|k| m.positions_m[k as usize]);
        let z = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
        assert!(z > 0.0);
    }
}
