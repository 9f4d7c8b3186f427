//! A rock's footprint as the rover's body meets it: the outline, seen from above, of the part
//! of its collision hull above the ground it rests on.
//!
//! The physics collides the rover with the convex hull of the rock's lumpy render mesh
//! ([`rock_mesh`]), not with the ellipse of its half extents; the lumps move the outline by
//! about ±5 cm around that ellipse. Judging a map against the ellipse would count those
//! centimetres as the map's error.

use crate::mesh::rock_mesh;
use crate::rocks::Rock;

/// The outline of `rock`'s hull above its base plane (`rock.center_m[2]`), projected on the
/// ground: a convex polygon, counter-clockwise, world metres. The rock's buried lower half is
/// left out; where the mesh crosses the base plane, the crossing points are kept.
pub fn rock_outline_m(rock: &Rock) -> Vec<[f64; 2]> {
    let mesh = rock_mesh(rock);
    let base_z = rock.center_m[2];
    let mut points: Vec<[f64; 2]> = mesh
        .positions_m
        .iter()
        .filter(|p| p[2] >= base_z)
        .map(|p| [p[0], p[1]])
        .collect();
    for triangle in &mesh.triangles {
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let a = mesh.positions_m[triangle[i] as usize];
            let b = mesh.positions_m[triangle[j] as usize];
            if (a[2] - base_z) * (b[2] - base_z) < 0.0 {
                let s = (base_z - a[2]) / (b[2] - a[2]);
                points.push([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]);
            }
        }
    }
    convex_hull(points)
}

/// The convex hull of `points`, counter-clockwise (Andrew's monotone chain); collinear points
/// are dropped.
pub fn convex_hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.retain(|p| p[0].is_finite() && p[1].is_finite());
    points.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(points.len() + 1);
    // The lower chain left to right, then the upper chain right to left.
    let n = points.len();
    for upper in [false, true] {
        let start = hull.len();
        for i in 0..n {
            let p = points[if upper { n - 1 - i } else { i }];
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        // Each chain's last point starts the other.
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rocks::RockSource;

    #[test]
    fn the_hull_of_a_square_with_inner_points_is_its_corners_counter_clockwise() {
        let hull = convex_hull(vec![
            [0.0, 0.0],
            [1.0, 1.0],
            [0.5, 0.5],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
        ]);
        assert_eq!(hull, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert!(convex_hull(vec![[f64::NAN, 0.0], [1.0, 1.0]]).len() == 1);
    }

    #[test]
    fn a_rocks_outline_stays_within_a_few_centimetres_of_its_ellipse() {
        let rock = Rock {
            center_m: [3.0, -2.0, 0.1],
            diameter_m: 0.6,
            height_m: 0.3,
            half_extents_m: [0.36, 0.25, 0.3],
            yaw_rad: 0.7,
            shape_seed: 42,
            source: RockSource::Explicit(0),
        };
        let outline = rock_outline_m(&rock);
        assert!(outline.len() >= 8);
        let (sin, cos) = rock.yaw_rad.sin_cos();
        for p in &outline {
            let (dx, dy) = (p[0] - rock.center_m[0], p[1] - rock.center_m[1]);
            let (u, v) = (dx * cos + dy * sin, -dx * sin + dy * cos);
            // Its elliptic radius: 1 on the ellipse; the lumps stay within about ±30 %.
            let r = (u / 0.36).hypot(v / 0.25);
            assert!((0.6..1.4).contains(&r), "{p:?} at {r}");
        }
    }
}
