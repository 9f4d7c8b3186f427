//! How much ground the final map shuts the rover's centre out of, against how much the rocks
//! really do (evaluation only).
//!
//! Over the cells the rover observed within [`NEAR_TRACK_M`] (mapped, not unknown, and in
//! its camera's horizontal field of view within that range of the camera at some true pose:
//! [`Reach::InView`]; [`Reach::NearTrack`] judges every mapped cell that near the track,
//! whichever way the camera looked): a cell is **truly lethal** when its centre lies within the rover's inscribed radius
//! of the footprint of a rock taller than the climb limit (the body would touch the rock
//! whatever its heading); it is **mapped lethal** when the map makes it an obstacle or a
//! lethal margin. The blocked-area ratio is mapped over truly lethal area (1 is perfect,
//! the first mapper's rules gave 2–4); **missed** cells are truly lethal and mapped
//! traversable, **uncertain** ones truly lethal and mapped as maybe too tall (a finite cost
//! the rover's closer look is meant to settle), **false** ones mapped lethal and truly not.
//!
//! ```
//! use hopnav_eval::traversability::{MapCell, Reach, RockEllipse, blocked_area};
//! let rock = RockEllipse::round([0.0, 0.0], 0.3, 0.4);
//! // A 0.25 m grid around the rock, every cell mapped as the truth has it.
//! let cells: Vec<MapCell> = (-8..8)
//!     .flat_map(|y| (-8..8).map(move |x| (x, y)))
//!     .map(|(x, y)| {
//!         let centre_m = [0.125 + 0.25 * x as f64, 0.125 + 0.25 * y as f64];
//!         let lethal = centre_m[0].hypot(centre_m[1]) < 0.7;
//!         MapCell { centre_m, lethal, uncertain: false, costly: false }
//!     })
//!     .collect();
//! let track = Reach::NearTrack(&[[0.0, -1.5], [0.0, 1.5]]);
//! let result = blocked_area(&cells, &[rock], &track, 0.25, 0.2, 0.4, |_| false);
//! assert_eq!(result.blocked_area_ratio, Some(1.0));
//! assert_eq!((result.missed_lethal_cells, result.false_lethal_cells), (0, 0));
//! ```

use serde::{Deserialize, Serialize};

/// A rock's footprint as an ellipse (the world's rocks are ellipsoids), for the blocked area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockEllipse {
    /// Centre (x, y), world metres.
    pub center_m: [f64; 2],
    /// Semi-axes along the rock's yawed x and y, metres.
    pub semi_axes_m: [f64; 2],
    /// Yaw of the footprint about world z, radians.
    pub yaw_rad: f64,
    /// Height above its base, metres.
    pub height_m: f64,
}

impl RockEllipse {
    /// A round rock of `radius_m`.
    pub fn round(center_m: [f64; 2], radius_m: f64, height_m: f64) -> Self {
        Self {
            center_m,
            semi_axes_m: [radius_m, radius_m],
            yaw_rad: 0.0,
            height_m,
        }
    }

    /// Distance from `point_m` to the footprint's edge along the ray from its centre (exact
    /// for a circle, close for the world's mildly elongated rocks), metres; ≤ 0 inside.
    pub fn gap_m(&self, point_m: [f64; 2]) -> f64 {
        let (dx, dy) = (point_m[0] - self.center_m[0], point_m[1] - self.center_m[1]);
        let (sin, cos) = self.yaw_rad.sin_cos();
        let (u, v) = (dx * cos + dy * sin, -dx * sin + dy * cos);
        let distance_m = u.hypot(v);
        let [a, b] = self.semi_axes_m;
        if distance_m <= 1e-12 {
            return -a.min(b);
        }
        // The ellipse's radius in the direction of the point.
        let (cu, sv) = (u / distance_m, v / distance_m);
        let radius_m = a * b / ((b * cu).powi(2) + (a * sv).powi(2)).sqrt();
        distance_m - radius_m
    }
}

/// Cells farther than this from the rover's true track are not judged, metres.
pub const NEAR_TRACK_M: f64 = 5.0;

/// Where the rover's camera was and which way it looked, at one true pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraView {
    /// The camera's position (x, y), world metres.
    pub position_m: [f64; 2],
    /// Its viewing direction about world z, radians.
    pub yaw_rad: f64,
}

/// Which cells the judge looks at.
#[derive(Debug, Clone, Copy)]
pub enum Reach<'a> {
    /// Cells within [`NEAR_TRACK_M`] of any of these points (the true track), world metres.
    NearTrack(&'a [[f64; 2]]),
    /// Cells within [`NEAR_TRACK_M`] of one of these camera views and inside its horizontal
    /// field of view (occlusion aside): the cells the rover observed within that range.
    InView {
        /// The camera at each true pose.
        views: &'a [CameraView],
        /// Half the camera's horizontal field of view, radians.
        half_fov_rad: f64,
    },
}

impl Reach<'_> {
    /// The judge looks at the ground at `point_m`.
    pub fn covers(&self, point_m: [f64; 2]) -> bool {
        let reach_m2 = NEAR_TRACK_M * NEAR_TRACK_M;
        match *self {
            Reach::NearTrack(track_m) => track_m.iter().any(|p| {
                let (dx, dy) = (p[0] - point_m[0], p[1] - point_m[1]);
                dx * dx + dy * dy <= reach_m2
            }),
            Reach::InView {
                views,
                half_fov_rad,
            } => {
                let cos_half = half_fov_rad.cos();
                views.iter().any(|view| {
                    let (dx, dy) = (
                        point_m[0] - view.position_m[0],
                        point_m[1] - view.position_m[1],
                    );
                    let distance_m2 = dx * dx + dy * dy;
                    let (sin, cos) = view.yaw_rad.sin_cos();
                    distance_m2 <= reach_m2 && dx * cos + dy * sin >= distance_m2.sqrt() * cos_half
                })
            }
        }
    }
}

/// One mapped cell as the judge needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapCell {
    /// Centre, world metres.
    pub centre_m: [f64; 2],
    /// The map shuts the rover's centre out of it (an obstacle or a lethal margin).
    pub lethal: bool,
    /// The map holds it maybe too tall, or within the body's reach of such a rock whatever
    /// the heading (its class is uncertain, not traversable).
    pub uncertain: bool,
    /// The map charges an extra cost to enter it (inflation, or maybe too tall).
    pub costly: bool,
}

/// The map's blocked ground against the truth's, near the rover's track.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct BlockedArea {
    /// Mapped cells within reach of the track that were judged.
    pub judged_cells: usize,
    /// Of them, mapped lethal, m².
    pub mapped_lethal_m2: f64,
    /// Of them, truly lethal for the rover's centre, m².
    pub true_lethal_m2: f64,
    /// `mapped_lethal_m2 / true_lethal_m2` (`None` when nothing there is truly lethal).
    pub blocked_area_ratio: Option<f64>,
    /// Truly lethal cells the map left traversable (neither lethal nor uncertain).
    pub missed_lethal_cells: usize,
    /// Truly lethal cells the map holds uncertain (maybe too tall, at a finite cost).
    #[serde(default)]
    pub uncertain_lethal_cells: usize,
    /// Truly lethal cells judged.
    pub true_lethal_cells: usize,
    /// Cells mapped lethal that are not truly lethal.
    pub false_lethal_cells: usize,
    /// Rocks the rover cannot climb whose centre lies near the track, by what the map made
    /// of the cells over them: [lethal, only costly, seen and left free, not seen].
    #[serde(default)]
    pub rocks_by_outcome: [usize; 4],
}

impl BlockedArea {
    /// Missed lethal cells in % of the truly lethal ones (`None` without any).
    pub fn missed_lethal_percent(&self) -> Option<f64> {
        self.percent_of_true_lethal(self.missed_lethal_cells)
    }

    /// Truly lethal cells held uncertain, in % of the truly lethal ones.
    pub fn uncertain_lethal_percent(&self) -> Option<f64> {
        self.percent_of_true_lethal(self.uncertain_lethal_cells)
    }

    /// Truly lethal cells the rover's centre may enter (missed or uncertain), in % of the
    /// truly lethal ones: the figure reported as "missed" before the map had an uncertain
    /// class.
    pub fn open_lethal_percent(&self) -> Option<f64> {
        self.percent_of_true_lethal(self.missed_lethal_cells + self.uncertain_lethal_cells)
    }

    fn percent_of_true_lethal(&self, cells: usize) -> Option<f64> {
        (self.true_lethal_cells > 0).then(|| 100.0 * cells as f64 / self.true_lethal_cells as f64)
    }
}

/// Judges the `cells` (a grid of `cell_size_m`) that `reach` covers against the `rocks`
/// taller than `climb_limit_m`, for a rover of `inscribed_m`, and against the ground
/// `too_steep(centre_m)` says the rover's centre cannot stand on.
pub fn blocked_area(
    cells: &[MapCell],
    rocks: &[RockEllipse],
    reach: &Reach<'_>,
    cell_size_m: f64,
    climb_limit_m: f64,
    inscribed_m: f64,
    too_steep: impl Fn([f64; 2]) -> bool,
) -> BlockedArea {
    let blocking: Vec<&RockEllipse> = rocks
        .iter()
        .filter(|rock| rock.height_m > climb_limit_m)
        .collect();
    let cell_m2 = cell_size_m * cell_size_m;
    let mut result = BlockedArea::default();
    for cell in cells {
        if !reach.covers(cell.centre_m) {
            continue;
        }
        result.judged_cells += 1;
        let truly_lethal = too_steep(cell.centre_m)
            || blocking
                .iter()
                .any(|rock| rock.gap_m(cell.centre_m) < inscribed_m);
        if cell.lethal {
            result.mapped_lethal_m2 += cell_m2;
        }
        if truly_lethal {
            result.true_lethal_m2 += cell_m2;
            result.true_lethal_cells += 1;
        }
        match (cell.lethal, truly_lethal) {
            (false, true) if cell.uncertain => result.uncertain_lethal_cells += 1,
            (false, true) => result.missed_lethal_cells += 1,
            (true, false) => result.false_lethal_cells += 1,
            _ => {}
        }
    }
    result.blocked_area_ratio =
        (result.true_lethal_m2 > 0.0).then(|| result.mapped_lethal_m2 / result.true_lethal_m2);
    for rock in blocking.iter().filter(|rock| reach.covers(rock.center_m)) {
        // The cells over the rock (a cell counts when its centre is within half a cell of it).
        let over: Vec<&MapCell> = cells
            .iter()
            .filter(|cell| rock.gap_m(cell.centre_m) <= 0.5 * cell_size_m)
            .collect();
        let outcome = if over.iter().any(|cell| cell.lethal) {
            0
        } else if over.iter().any(|cell| cell.costly) {
            1
        } else if !over.is_empty() {
            2
        } else {
            3
        };
        result.rocks_by_outcome[outcome] += 1;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rock(x: f64, y: f64, radius_m: f64, height_m: f64) -> RockEllipse {
        RockEllipse::round([x, y], radius_m, height_m)
    }

    #[test]
    fn the_gap_to_an_elongated_rock_follows_its_yawed_ellipse() {
        let rock = RockEllipse {
            center_m: [1.0, 1.0],
            semi_axes_m: [0.6, 0.2],
            yaw_rad: std::f64::consts::FRAC_PI_2,
            height_m: 0.4,
        };
        // Yawed a quarter turn: the long axis runs along world y.
        assert!((rock.gap_m([1.0, 2.0]) - 0.4).abs() < 1e-9);
        assert!((rock.gap_m([2.0, 1.0]) - 0.8).abs() < 1e-9);
        assert!(rock.gap_m([1.0, 1.1]) < 0.0);
    }

    fn grid(lethal: impl Fn([f64; 2]) -> bool) -> Vec<MapCell> {
        (-20..20)
            .flat_map(|y| (-20..20).map(move |x| (x, y)))
            .map(|(x, y)| {
                let centre_m = [0.125 + 0.25 * f64::from(x), 0.125 + 0.25 * f64::from(y)];
                MapCell {
                    centre_m,
                    lethal: lethal(centre_m),
                    uncertain: false,
                    costly: false,
                }
            })
            .collect()
    }

    /// `blocked_area` over a 0.25 m grid near a one-point track, for a rover that climbs
    /// 0.2 m with a 0.4 m inscribed radius.
    fn judged_near_track(cells: &[MapCell], rocks: &[RockEllipse], track: [f64; 2]) -> BlockedArea {
        blocked_area(
            cells,
            rocks,
            &Reach::NearTrack(&[track]),
            0.25,
            0.2,
            0.4,
            |_| false,
        )
    }

    #[test]
    fn a_map_that_blocks_twice_the_ground_has_a_ratio_near_two_and_no_misses() {
        let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
        let cells = grid(|c| c[0].hypot(c[1]) < 0.7 * std::f64::consts::SQRT_2);
        let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
        let ratio = result.blocked_area_ratio.unwrap();
        assert!((1.7..2.3).contains(&ratio), "{ratio}");
        assert_eq!(result.missed_lethal_cells, 0);
        assert!(result.false_lethal_cells > 0);
    }

    #[test]
    fn a_climbable_rock_is_not_lethal_and_a_missed_rock_is_counted() {
        let rocks = [rock(0.0, 0.0, 0.3, 0.15), rock(2.0, 0.0, 0.3, 0.5)];
        let result = judged_near_track(&grid(|_| false), &rocks, [0.0, 0.0]);
        assert!(result.true_lethal_cells > 0, "the tall rock only");
        assert_eq!(result.missed_lethal_cells, result.true_lethal_cells);
        assert_eq!(result.missed_lethal_percent(), Some(100.0));
        assert_eq!(result.blocked_area_ratio, Some(0.0));
    }

    #[test]
    fn a_rock_held_uncertain_is_counted_apart_from_the_missed_ones() {
        // The right half of a tall rock's lethal disc is mapped maybe too tall, the left half
        // traversable.
        let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
        let mut cells = grid(|_| false);
        for cell in &mut cells {
            cell.uncertain =
                cell.centre_m[0] > 0.0 && cell.centre_m[0].hypot(cell.centre_m[1]) < 1.0;
            cell.costly = cell.uncertain;
        }
        let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
        assert!(result.uncertain_lethal_cells > 0);
        assert_eq!(
            result.missed_lethal_cells + result.uncertain_lethal_cells,
            result.true_lethal_cells
        );
        assert_eq!(
            result.missed_lethal_cells, result.uncertain_lethal_cells,
            "the disc is symmetric"
        );
        assert_eq!(result.open_lethal_percent(), Some(100.0));
        assert_eq!(result.missed_lethal_percent(), Some(50.0));
        assert_eq!(
            result.blocked_area_ratio,
            Some(0.0),
            "uncertain is not lethal"
        );
    }

    #[test]
    fn ground_too_steep_to_stand_on_is_truly_lethal_without_a_rock() {
        // A crater's wall along x > 1: a map that shuts it is right, one that leaves it open
        // misses it.
        let steep = |centre_m: [f64; 2]| centre_m[0] > 1.0;
        let judged = |cells: &[MapCell]| {
            blocked_area(
                cells,
                &[],
                &Reach::NearTrack(&[[0.0, 0.0]]),
                0.25,
                0.2,
                0.4,
                steep,
            )
        };
        let shut = judged(&grid(|c| c[0] > 1.0));
        assert!(shut.true_lethal_cells > 0);
        assert_eq!((shut.missed_lethal_cells, shut.false_lethal_cells), (0, 0));
        let open = judged(&grid(|_| false));
        assert_eq!(open.missed_lethal_cells, open.true_lethal_cells);
    }

    #[test]
    fn cells_far_from_the_track_are_not_judged() {
        let rocks = [rock(0.0, 0.0, 0.3, 0.5)];
        let result = judged_near_track(&grid(|_| true), &rocks, [100.0, 100.0]);
        assert_eq!(result.judged_cells, 0);
        assert_eq!(result.blocked_area_ratio, None);
    }

    #[test]
    fn each_rock_near_the_track_is_counted_by_what_the_map_made_of_it() {
        let rocks = [
            rock(0.0, 0.0, 0.3, 0.5),
            rock(2.0, 0.0, 0.3, 0.5),
            rock(-2.0, 0.0, 0.3, 0.5),
            rock(0.0, 30.0, 0.3, 0.5),
        ];
        let mut cells = grid(|c| c[0].hypot(c[1]) < 0.2);
        for cell in &mut cells {
            cell.costly = (cell.centre_m[0] - 2.0).hypot(cell.centre_m[1]) < 0.2;
        }
        cells.retain(|cell| cell.centre_m[0] < 3.0 || cell.centre_m[1].abs() > 1.0);
        cells.retain(|cell| (cell.centre_m[0] + 2.0).hypot(cell.centre_m[1]) > 0.6);
        let result = judged_near_track(&cells, &rocks, [0.0, 0.0]);
        // Lethal, only costly, not seen; the fourth is beyond 5 m of the track.
        assert_eq!(result.rocks_by_outcome, [1, 1, 0, 1]);
    }

    #[test]
    fn only_cells_the_camera_looked_at_within_reach_are_judged() {
        // The camera at the origin looks along +x with a 60° field of view.
        let views = [CameraView {
            position_m: [0.0, 0.0],
            yaw_rad: 0.0,
        }];
        let reach = Reach::InView {
            views: &views,
            half_fov_rad: 30_f64.to_radians(),
        };
        assert!(reach.covers([3.0, 1.0]));
        assert!(!reach.covers([3.0, 2.5]), "outside the field of view");
        assert!(!reach.covers([-3.0, 0.0]), "behind the camera");
        assert!(!reach.covers([5.5, 0.0]), "beyond reach");
        let rocks = [rock(3.0, 0.0, 0.3, 0.5), rock(-3.0, 0.0, 0.3, 0.5)];
        let result = blocked_area(&grid(|_| false), &rocks, &reach, 0.25, 0.2, 0.4, |_| false);
        // Only the rock ahead counts, missed.
        assert_eq!(result.rocks_by_outcome, [0, 0, 1, 0]);
        assert!(result.true_lethal_cells > 0);
        assert_eq!(result.missed_lethal_cells, result.true_lethal_cells);
    }
}
