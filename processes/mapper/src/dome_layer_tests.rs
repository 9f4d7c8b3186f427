//! Tests of the dome layer: a rock fitted once and kept while new points agree, and which points it keeps.

use super::*;

/// Every cell usable, seen from −x, nothing seen of the ground.
struct Unrefuted;

impl RockEvidence for Unrefuted {
    fn usable(&self, _: usize) -> bool {
        true
    }
    fn view_direction(&self, _: usize) -> Option<[f32; 2]> {
        Some([1.0, 0.0])
    }
    fn seen_top(&self, _: usize) -> Option<(f32, f32)> {
        None
    }
    fn judge(&self, height_m: f32, _: f32) -> BeliefClass {
        if height_m > 0.2 {
            BeliefClass::Lethal
        } else {
            BeliefClass::Traversable
        }
    }
}

fn geometry() -> GridGeometry {
    GridGeometry {
        origin_x_m: 0.0,
        origin_y_m: 0.0,
        cell_size_m: 0.25,
        width_cells: 40,
        height_cells: 40,
    }
}

/// Adds the near-face points of a 0.3 m dome at (5, 5), each `offset_m` higher.
fn add_face(layer: &mut DomeLayer, geometry: &GridGeometry, offset_m: f32) {
    for (dx, dy) in [
        (-0.25, 0.0),
        (-0.2, 0.12),
        (-0.2, -0.12),
        (-0.1, 0.05),
        (-0.15, -0.2),
    ] {
        let (x, y) = (5.0 + dx, 5.0 + dy);
        let (cx, cy) = geometry
            .cell_of(f64::from(x), f64::from(y))
            .expect("inside");
        let height_m = (0.09f32 - dx * dx - dy * dy).sqrt() + offset_m;
        layer.add_point(
            geometry.index(cx, cy),
            RockPoint {
                xy_m: [x, y],
                height_m,
                sigma_m: 0.02,
                ground_z_m: 0.0,
            },
        );
    }
}

fn refit(layer: &mut DomeLayer, geometry: &GridGeometry) -> (usize, usize) {
    let cells = geometry.cell_count();
    let (mut reclassify, mut restate) = (DirtySet::new(cells), DirtySet::new(cells));
    layer.refit(
        geometry,
        &Unrefuted,
        &mut Changed {
            reclassify: &mut reclassify,
            restate: &mut restate,
            inflation_m: 1.0,
        },
    );
    (reclassify.len(), restate.len())
}

#[test]
fn a_rock_is_fitted_once_and_kept_while_new_points_agree() {
    let geometry = geometry();
    let mut layer = DomeLayer::new(geometry.cell_count(), 1.0, 0.1);
    add_face(&mut layer, &geometry, 0.0);
    let (reclassify, restate) = refit(&mut layer, &geometry);
    assert!(reclassify > 0 && restate > reclassify);
    let rocks: Vec<Dome> = layer.rocks().copied().collect();
    assert_eq!(rocks.len(), 1);
    // One more point on the same face: the rock stays, nothing is restated.
    let (cx, cy) = geometry.cell_of(4.85, 5.0).expect("inside");
    let point = RockPoint {
        xy_m: [4.85, 5.0],
        height_m: (0.09f32 - 0.15 * 0.15).sqrt(),
        sigma_m: 0.02,
        ground_z_m: 0.0,
    };
    layer.add_point(geometry.index(cx, cy), point);
    assert_eq!(refit(&mut layer, &geometry), (0, 0));
    assert_eq!(layer.rocks().copied().collect::<Vec<_>>(), rocks);
    // Seen 10 cm taller: the rock is fitted anew.
    add_face(&mut layer, &geometry, 0.1);
    add_face(&mut layer, &geometry, 0.1);
    assert_ne!(refit(&mut layer, &geometry), (0, 0));
    assert!(layer.rocks().all(|rock| rock.height_m > rocks[0].height_m));
}

#[test]
fn low_and_bad_points_are_not_kept() {
    let geometry = geometry();
    let mut layer = DomeLayer::new(geometry.cell_count(), 1.0, 0.1);
    for (height_m, sigma_m) in [(0.05, 0.02), (f32::NAN, 0.02), (0.3, 0.0), (0.3, f32::NAN)] {
        layer.add_point(
            3,
            RockPoint {
                xy_m: [0.8, 0.1],
                height_m,
                sigma_m,
                ground_z_m: 0.0,
            },
        );
    }
    layer.add_point(
        usize::MAX,
        RockPoint {
            xy_m: [0.0, 0.0],
            height_m: 0.3,
            sigma_m: 0.02,
            ground_z_m: 0.0,
        },
    );
    let mut out = Vec::new();
    layer.stored_points_into(&mut out);
    assert!(out.is_empty());
    assert_eq!(refit(&mut layer, &geometry), (0, 0));
}
