//! How much ground the final map shuts the rover's centre out of, against how much the rocks
//! really do (evaluation only).
//!
//! Over the cells the rover observed within [`NEAR_TRACK_M`] (mapped, not unknown, and in
//! its camera's sight within that range at some true pose: [`Reach::InSight`];
//! [`Reach::InView`] takes every cell in the horizontal field of view, hidden or not, and
//! [`Reach::NearTrack`] every mapped cell that near the track, whichever way the camera
//! looked): a cell is **truly lethal** when its centre lies within the rover's inscribed radius
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
//!         MapCell { centre_m, lethal, uncertain: false, costly: false, unobserved: false }
//!     })
//!     .collect();
//! let track = Reach::NearTrack(&[[0.0, -1.5], [0.0, 1.5]]);
//! let result = blocked_area(&cells, &[rock], &track, 0.25, 0.2, 0.4, |_| false);
//! assert_eq!(result.blocked_area_ratio, Some(1.0));
//! assert_eq!((result.missed_lethal_cells, result.false_lethal_cells), (0, 0));
//! ```

use serde::{Deserialize, Serialize};

use crate::line_of_sight::SeenCells;

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

/// What the judge needs of a rock's footprint.
pub trait Footprint {
    /// Distance from `point_m` to the footprint's edge, metres; ≤ 0 inside.
    fn gap_m(&self, point_m: [f64; 2]) -> f64;
    /// A point inside it (its centre), world metres.
    fn centre_m(&self) -> [f64; 2];
    /// Height above its base, metres.
    fn height_m(&self) -> f64;
}

impl Footprint for RockEllipse {
    fn gap_m(&self, point_m: [f64; 2]) -> f64 {
        RockEllipse::gap_m(self, point_m)
    }
    fn centre_m(&self) -> [f64; 2] {
        self.center_m
    }
    fn height_m(&self) -> f64 {
        self.height_m
    }
}

/// A rock's footprint as the physics' collision hull has it: a convex polygon (see
/// `hopnav_world::footprint::rock_outline_m`).
#[derive(Debug, Clone, PartialEq)]
pub struct RockOutline {
    /// The outline, counter-clockwise, world metres.
    pub outline_m: Vec<[f64; 2]>,
    /// Centre of the rock's base, world metres.
    pub center_m: [f64; 2],
    /// Height above its base, metres.
    pub height_m: f64,
}

impl Footprint for RockOutline {
    /// Exact for the convex polygon: the distance to its nearest edge, negative inside.
    fn gap_m(&self, point_m: [f64; 2]) -> f64 {
        let n = self.outline_m.len();
        if n < 3 {
            return f64::INFINITY;
        }
        let mut nearest_m = f64::INFINITY;
        let mut inside = true;
        for i in 0..n {
            let (a, b) = (self.outline_m[i], self.outline_m[(i + 1) % n]);
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let (px, py) = (point_m[0] - a[0], point_m[1] - a[1]);
            if ex * py - ey * px < 0.0 {
                inside = false;
            }
            let length2 = ex * ex + ey * ey;
            let t = if length2 > 0.0 {
                ((px * ex + py * ey) / length2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            nearest_m = nearest_m.min((px - t * ex).hypot(py - t * ey));
        }
        if inside { -nearest_m } else { nearest_m }
    }
    fn centre_m(&self) -> [f64; 2] {
        self.center_m
    }
    fn height_m(&self) -> f64 {
        self.height_m
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
    /// Cells the camera had in sight within [`NEAR_TRACK_M`] (the true world rendered from
    /// its true poses, [`crate::line_of_sight`]): ground hidden behind a rock is left out.
    InSight(&'a SeenCells),
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
            Reach::InSight(seen) => seen.contains(point_m),
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
    /// No feature of either robot landed in it: its class comes from the rocks around it
    /// (their inflation) or it is unknown.
    pub unobserved: bool,
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
    /// Where the missed cells are: what tells a disc drawn too small from a rock not found.
    #[serde(default)]
    pub missed_by_cause: MissedCauses,
}

/// The missed cells (truly lethal, mapped traversable), by the rock that makes each lethal
/// (the one whose footprint is nearest) and what the map made of that rock.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MissedCauses {
    /// The rock is lethal on the map and the cell lies in the outermost cell's width of its
    /// truly lethal disc: the mapped disc is drawn a little too small.
    pub rim_of_lethal_rock: usize,
    /// The rock is lethal on the map, the cell deeper inside its truly lethal disc: the
    /// mapped rock is much smaller than the true one, or off to one side.
    pub inside_of_lethal_rock: usize,
    /// The map holds the rock only costly (maybe too tall, or a band).
    pub rock_only_costly: usize,
    /// The map saw the rock's ground and left it free.
    pub rock_seen_free: usize,
    /// No mapped cell over the rock.
    pub rock_not_seen: usize,
    /// No rock: ground too steep.
    pub too_steep: usize,
    /// Of all the missed cells, those of rocks within 5 cm of the climb limit.
    pub near_limit_rock: usize,
    /// Of all the missed cells, those no feature landed in (the map had nothing of its own
    /// there: ground hidden behind a rock or a crater's rim, or bare of texture).
    #[serde(default)]
    pub unobserved: usize,
}

impl MissedCauses {
    /// The missed cells counted (each has one cause among the first six fields).
    pub fn missed(&self) -> usize {
        self.rim_of_lethal_rock
            + self.inside_of_lethal_rock
            + self.rock_only_costly
            + self.rock_seen_free
            + self.rock_not_seen
            + self.too_steep
    }
}

impl std::ops::AddAssign for MissedCauses {
    fn add_assign(&mut self, other: Self) {
        self.rim_of_lethal_rock += other.rim_of_lethal_rock;
        self.inside_of_lethal_rock += other.inside_of_lethal_rock;
        self.rock_only_costly += other.rock_only_costly;
        self.rock_seen_free += other.rock_seen_free;
        self.rock_not_seen += other.rock_not_seen;
        self.too_steep += other.too_steep;
        self.near_limit_rock += other.near_limit_rock;
        self.unobserved += other.unobserved;
    }
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
pub fn blocked_area<R: Footprint>(
    cells: &[MapCell],
    rocks: &[R],
    reach: &Reach<'_>,
    cell_size_m: f64,
    climb_limit_m: f64,
    inscribed_m: f64,
    too_steep: impl Fn([f64; 2]) -> bool,
) -> BlockedArea {
    let blocking: Vec<&R> = rocks
        .iter()
        .filter(|rock| rock.height_m() > climb_limit_m)
        .collect();
    let cell_m2 = cell_size_m * cell_size_m;
    let mut result = BlockedArea::default();
    let mut outcomes: Vec<Option<usize>> = vec![None; blocking.len()];
    for cell in cells {
        if !reach.covers(cell.centre_m) {
            continue;
        }
        result.judged_cells += 1;
        // The rock whose body the rover's centre here would touch (the nearest one).
        let touched =
            nearest_rock(&blocking, cell.centre_m).filter(|&(_, gap_m)| gap_m < inscribed_m);
        let truly_lethal = touched.is_some() || too_steep(cell.centre_m);
        if cell.lethal {
            result.mapped_lethal_m2 += cell_m2;
        }
        if truly_lethal {
            result.true_lethal_m2 += cell_m2;
            result.true_lethal_cells += 1;
        }
        match (cell.lethal, truly_lethal) {
            (false, true) if cell.uncertain => result.uncertain_lethal_cells += 1,
            (false, true) => {
                result.missed_lethal_cells += 1;
                result.missed_by_cause.unobserved += usize::from(cell.unobserved);
                let causes = &mut result.missed_by_cause;
                let Some((rock_index, gap_m)) = touched else {
                    causes.too_steep += 1;
                    continue;
                };
                let rock = blocking[rock_index];
                let outcome = *outcomes[rock_index]
                    .get_or_insert_with(|| rock_outcome(cells, rock, cell_size_m));
                match outcome {
                    0 if gap_m >= inscribed_m - cell_size_m => causes.rim_of_lethal_rock += 1,
                    0 => causes.inside_of_lethal_rock += 1,
                    1 => causes.rock_only_costly += 1,
                    2 => causes.rock_seen_free += 1,
                    _ => causes.rock_not_seen += 1,
                }
                if rock.height_m() < climb_limit_m + NEAR_LIMIT_M {
                    causes.near_limit_rock += 1;
                }
            }
            (true, false) => result.false_lethal_cells += 1,
            _ => {}
        }
    }
    result.blocked_area_ratio =
        (result.true_lethal_m2 > 0.0).then(|| result.mapped_lethal_m2 / result.true_lethal_m2);
    for rock in blocking.iter().filter(|rock| reach.covers(rock.centre_m())) {
        result.rocks_by_outcome[rock_outcome(cells, *rock, cell_size_m)] += 1;
    }
    result
}

/// Rocks this close above the climb limit count as near-limit, metres.
const NEAR_LIMIT_M: f64 = 0.05;

/// The blocking rock whose footprint is nearest `point_m`, and the gap to it, metres.
fn nearest_rock<R: Footprint>(blocking: &[&R], point_m: [f64; 2]) -> Option<(usize, f64)> {
    blocking
        .iter()
        .map(|rock| rock.gap_m(point_m))
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// What the map made of the cells over `rock` (a cell counts when its centre is within half a
/// cell of it): 0 lethal, 1 only costly, 2 seen and left free, 3 not seen.
fn rock_outcome<R: Footprint>(cells: &[MapCell], rock: &R, cell_size_m: f64) -> usize {
    let over = || {
        cells
            .iter()
            .filter(|cell| rock.gap_m(cell.centre_m) <= 0.5 * cell_size_m)
    };
    if over().any(|cell| cell.lethal) {
        0
    } else if over().any(|cell| cell.costly) {
        1
    } else if over().next().is_some() {
        2
    } else {
        3
    }
}

#[cfg(test)]
#[path = "traversability_tests.rs"]
mod tests;
