//! Each rock contact of the rover against the truth: which unclimbable rock its body met, how
//! tall that rock is, and what the map said of the rock's ground at that moment. A contact
//! with a rock the map held lethal is the drive's fault (a turn or a sweep that ignored it);
//! one with a rock it held uncertain, open or unseen is the map's.

use hopnav_ipc::messages::CellClass;
use hopnav_supervisor::contact_log::RecordedContact;
use serde::{Deserialize, Serialize};

use crate::traversability::{Footprint, RockOutline};

/// A rock whose outline lies farther than this from the rover's body is not the one it met,
/// metres (the refused move's pose stands a substep short of the rock).
const TOUCH_GAP_M: f64 = 0.15;
/// Points sampled along each side of the rover's footprint.
const POINTS_PER_SIDE: usize = 8;

/// What the map said of the rock's ground when the rover met it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MapVerdict {
    /// A cell of the rock was an obstacle or lethal.
    Lethal,
    /// The worst of its cells was uncertain.
    Uncertain,
    /// Its cells were mapped and traversable (free or only costly).
    Open,
    /// None of its cells was mapped.
    Unseen,
    /// No unclimbable rock lies at the rover's body (a contact the truth cannot place).
    NoRock,
}

impl MapVerdict {
    /// Every verdict, in report order.
    pub const ALL: [Self; 5] = [
        Self::Lethal,
        Self::Uncertain,
        Self::Open,
        Self::Unseen,
        Self::NoRock,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Lethal => "lethal",
            Self::Uncertain => "uncertain",
            Self::Open => "open",
            Self::Unseen => "unseen",
            Self::NoRock => "no rock",
        }
    }
}

/// One contact, judged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JudgedContact {
    /// Simulation time, seconds.
    pub time_s: f64,
    /// `driving`, `reversing`, `turning` or `unknown`.
    pub motion: String,
    /// Height of the rock met (`None` with [`MapVerdict::NoRock`]), metres.
    pub rock_height_m: Option<f64>,
    /// What the map said of it then.
    pub map: MapVerdict,
}

/// The grid the contacts' cells are on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGrid {
    /// World position of cell (0, 0)'s corner, metres.
    pub origin_m: (f64, f64),
    /// Cell edge, metres.
    pub cell_size_m: f64,
}

/// Judges each of `contacts` against the unclimbable `rocks`, for a rover whose footprint
/// has `half_extents_m` (along, across its heading).
pub fn judge_contacts(
    contacts: &[RecordedContact],
    rocks: &[RockOutline],
    grid: ContactGrid,
    half_extents_m: [f64; 2],
) -> Vec<JudgedContact> {
    contacts
        .iter()
        .map(|contact| {
            let body = footprint_points(contact.rover_m, contact.yaw_rad, half_extents_m);
            let met = rocks
                .iter()
                .map(|rock| (gap_to_body_m(rock, &body), rock))
                .filter(|(gap_m, _)| *gap_m <= TOUCH_GAP_M)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, rock)| rock);
            JudgedContact {
                time_s: contact.time_s,
                motion: contact.motion.name().to_owned(),
                rock_height_m: met.map(|rock| rock.height_m),
                map: met.map_or(MapVerdict::NoRock, |rock| verdict(rock, contact, grid)),
            }
        })
        .collect()
}

/// The map's word on `rock`'s own ground: the worst class among the cells around the contact
/// whose centres lie inside its outline or within half a cell of it.
fn verdict(rock: &RockOutline, contact: &RecordedContact, grid: ContactGrid) -> MapVerdict {
    let size_m = grid.cell_size_m;
    let mut worst = MapVerdict::Unseen;
    for cell in &contact.cells_around {
        let centre_m = [
            grid.origin_m.0 + (f64::from(cell.x) + 0.5) * size_m,
            grid.origin_m.1 + (f64::from(cell.y) + 0.5) * size_m,
        ];
        if rock.gap_m(centre_m) > 0.5 * size_m {
            continue;
        }
        let said = match cell.class {
            CellClass::Obstacle | CellClass::Lethal => MapVerdict::Lethal,
            CellClass::Uncertain => MapVerdict::Uncertain,
            CellClass::Free | CellClass::Inflated => MapVerdict::Open,
            CellClass::Unknown => MapVerdict::Unseen,
        };
        if severity(said) > severity(worst) {
            worst = said;
        }
    }
    worst
}

fn severity(verdict: MapVerdict) -> u8 {
    match verdict {
        MapVerdict::NoRock | MapVerdict::Unseen => 0,
        MapVerdict::Open => 1,
        MapVerdict::Uncertain => 2,
        MapVerdict::Lethal => 3,
    }
}

/// Points along the edges of the rover's footprint at `centre_m`, heading `yaw_rad`.
fn footprint_points(centre_m: [f64; 2], yaw_rad: f64, half_extents_m: [f64; 2]) -> Vec<[f64; 2]> {
    let (sin, cos) = yaw_rad.sin_cos();
    let [along_m, across_m] = half_extents_m;
    let corners = [
        [along_m, across_m],
        [-along_m, across_m],
        [-along_m, -across_m],
        [along_m, -across_m],
    ];
    let mut points = Vec::with_capacity(4 * POINTS_PER_SIDE);
    for side in 0..4 {
        let (a, b) = (corners[side], corners[(side + 1) % 4]);
        for step in 0..POINTS_PER_SIDE {
            let t = step as f64 / POINTS_PER_SIDE as f64;
            let (u, v) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
            points.push([
                centre_m[0] + u * cos - v * sin,
                centre_m[1] + u * sin + v * cos,
            ]);
        }
    }
    points
}

/// How far `rock`'s outline lies from the body's edge points (negative when one is inside).
fn gap_to_body_m(rock: &RockOutline, body: &[[f64; 2]]) -> f64 {
    body.iter()
        .map(|&point| rock.gap_m(point))
        .fold(f64::INFINITY, f64::min)
}

/// How many of `contacts` fall under each verdict, in [`MapVerdict::ALL`] order.
pub fn count_by_verdict<'a>(contacts: impl IntoIterator<Item = &'a JudgedContact>) -> [usize; 5] {
    let mut counts = [0; 5];
    for contact in contacts {
        if let Some(index) = MapVerdict::ALL.iter().position(|&v| v == contact.map) {
            counts[index] += 1;
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopnav_supervisor::mission_record::RecordedCell;
    use hopnav_supervisor::rover_motion::RoverMotion;

    const GRID: ContactGrid = ContactGrid {
        origin_m: (0.0, 0.0),
        cell_size_m: 0.25,
    };

    /// A square rock of `half_m` around `centre_m`.
    fn rock(centre_m: [f64; 2], half_m: f64, height_m: f64) -> RockOutline {
        let [x, y] = centre_m;
        RockOutline {
            outline_m: vec![
                [x - half_m, y - half_m],
                [x + half_m, y - half_m],
                [x + half_m, y + half_m],
                [x - half_m, y + half_m],
            ],
            center_m: centre_m,
            height_m,
        }
    }

    fn cell_at(centre_m: [f64; 2], class: CellClass) -> RecordedCell {
        RecordedCell {
            x: (centre_m[0] / GRID.cell_size_m) as u32,
            y: (centre_m[1] / GRID.cell_size_m) as u32,
            class,
            observed_by: 2,
            extra_cost: 0,
        }
    }

    /// A rover at (2, 2) heading +x, half extents 0.5 × 0.35 m: its front edge at x 2.5.
    fn contact(cells: Vec<RecordedCell>) -> RecordedContact {
        RecordedContact {
            time_s: 4.0,
            rover_m: [2.0, 2.0],
            yaw_rad: 0.0,
            motion: RoverMotion::Driving,
            cells_around: cells,
        }
    }

    #[test]
    fn the_rock_at_the_front_edge_is_named_with_the_worst_class_of_its_cells() {
        let touched = rock([2.65, 2.0], 0.12, 0.23);
        let far = rock([5.0, 5.0], 0.3, 0.5);
        let cells = vec![
            cell_at([2.625, 2.125], CellClass::Free),
            cell_at([2.625, 1.875], CellClass::Uncertain),
            // Lethal, but in front of the rover's flank, not on this rock.
            cell_at([2.125, 2.875], CellClass::Lethal),
        ];
        let judged = judge_contacts(&[contact(cells)], &[far, touched], GRID, [0.5, 0.35]);
        assert_eq!(judged.len(), 1);
        assert_eq!(judged[0].map, MapVerdict::Uncertain);
        assert_eq!(judged[0].rock_height_m, Some(0.23));
        assert_eq!(judged[0].motion, "driving");
    }

    #[test]
    fn a_rock_behind_the_body_is_met_too_and_no_rock_nearby_is_said() {
        // Turned 180°: the rock at x 1.35 is now in front; unmapped.
        let mut turned = contact(Vec::new());
        turned.yaw_rad = std::f64::consts::PI;
        let judged = judge_contacts(
            &[turned],
            &[rock([1.35, 2.0], 0.12, 0.3)],
            GRID,
            [0.5, 0.35],
        );
        assert_eq!(judged[0].map, MapVerdict::Unseen);
        let alone = judge_contacts(
            &[contact(Vec::new())],
            &[rock([4.0, 4.0], 0.1, 0.3)],
            GRID,
            [0.5, 0.35],
        );
        assert_eq!(alone[0].map, MapVerdict::NoRock);
        assert_eq!(alone[0].rock_height_m, None);
        assert_eq!(
            count_by_verdict(judged.iter().chain(&alone)),
            [0, 0, 0, 1, 1]
        );
    }
}
