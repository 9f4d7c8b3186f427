//! Where the navigator steers: the waypoint along the planned path that the rover's body
//! reaches clear of every rock, on the way and in the turn toward it, and the cells near the
//! rover it plans from.

use super::super::bumper::RoverPose;
use super::super::scout::distance_m;
use super::Navigator;
use crate::grid::Cell;

/// The steer toward the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Steer {
    /// Where to drive.
    pub waypoint_m: [f64; 2],
    /// The turn on the spot toward the waypoint swings the body past no rock.
    pub turn_clear: bool,
}

impl Navigator {
    /// Pure pursuit: the first path point at least `lookahead_m` from the rover, or a nearer
    /// one, such that the straight drive from the rover's actual position to it crosses no
    /// obstacle cell (a segment from the cell centre could cut a corner the rover then hits)
    /// and, with `footprint_check`, sweeps the body past no rock, neither on the way nor in
    /// the turn on the spot toward it; the goal itself at the end of the path.
    pub(super) fn steer(&self, rover: RoverPose) -> Steer {
        let rover_m = rover.xy_m;
        let ahead = self.path.iter().position(|&cell| {
            distance_m(self.geometry.center_of(cell), rover_m) >= self.config.lookahead_m
        });
        let Some(index) = ahead else {
            return Steer {
                waypoint_m: self.goal_m,
                turn_clear: true,
            };
        };
        let candidates = || {
            (1..=index)
                .rev()
                .map(|candidate| self.geometry.center_of(self.path[candidate]))
                .filter(|&target_m| {
                    self.geometry
                        .segment_is_clear(self.planner.grid(), rover_m, target_m)
                })
        };
        // Rock cells the body already touches do not count against a turn or a back-off:
        // they are where the rover is, and moving off is what it must do.
        let touched = if self.config.footprint_check {
            self.geometry
                .cells_under_body(rover_m, rover.yaw_rad, self.half_extents_m())
        } else {
            Vec::new()
        };
        if let Some(waypoint_m) = candidates().find(|&target_m| {
            self.footprint_fits(rover_m, target_m) && self.turn_fits(rover, target_m, &touched)
        }) {
            return Steer {
                waypoint_m,
                turn_clear: true,
            };
        }
        // None fits whole: the farthest the centre reaches, as without the sweep (a rover
        // that waited for a clear footprint would never move); the caller backs off first
        // when the turn toward it is not clear.
        let waypoint_m = candidates()
            .next()
            .unwrap_or_else(|| self.geometry.center_of(self.path[0]));
        Steer {
            waypoint_m,
            turn_clear: self.turn_fits(rover, waypoint_m, &touched),
        }
    }

    /// Half the rover's footprint length and width, metres.
    fn half_extents_m(&self) -> [f64; 2] {
        let body = &self.config.rover_body;
        [
            0.5 * body.footprint_length_m(),
            0.5 * body.footprint_width_m(),
        ]
    }

    /// The cell is a rock for the footprint checks: the mapper says so, or the rover bumped
    /// into it.
    fn is_rock_cell(&self, cell: Cell) -> bool {
        self.cell_index(cell)
            .is_some_and(|index| self.rock[index] || self.is_bumped[index])
    }

    /// The rover's body, driven straight from `from_m` to `to_m`, touches no rock cell
    /// (always true with `footprint_check` off).
    fn footprint_fits(&self, from_m: [f64; 2], to_m: [f64; 2]) -> bool {
        !self.config.footprint_check
            || self
                .geometry
                .footprint_is_clear(from_m, to_m, self.half_extents_m(), |cell| {
                    self.is_rock_cell(cell)
                })
    }

    /// The rover's body, turned on the spot from its heading toward `to_m` the short way
    /// round, touches no rock cell but those in `tolerated` (always true with
    /// `footprint_check` off).
    fn turn_fits(&self, rover: RoverPose, to_m: [f64; 2], tolerated: &[Cell]) -> bool {
        let heading_rad = (to_m[1] - rover.xy_m[1]).atan2(to_m[0] - rover.xy_m[0]);
        !self.config.footprint_check
            || self.geometry.turn_is_clear(
                rover.xy_m,
                (rover.yaw_rad, heading_rad),
                self.half_extents_m(),
                |cell| self.is_rock_cell(cell) && !tolerated.contains(&cell),
            )
    }

    /// How many cells of the path, from its start, lie within `range_m` of the rover.
    pub(super) fn path_cells_within(&self, rover_m: [f64; 2], range_m: f64) -> usize {
        self.path
            .iter()
            .position(|&cell| distance_m(self.geometry.center_of(cell), rover_m) > range_m)
            .unwrap_or(self.path.len())
    }

    /// `cell` if traversable, else the traversable cell within three rings whose centre is
    /// nearest the rover's actual position.
    pub(super) fn nearest_traversable(&self, cell: Cell, rover_m: [f64; 2]) -> Option<Cell> {
        let grid = self.planner.grid();
        if grid.is_traversable(cell) {
            return Some(cell);
        }
        const MAX_RING: i64 = 3;
        for ring in 1..=MAX_RING {
            let mut best: Option<(f64, Cell)> = None;
            for dy in -ring..=ring {
                for dx in -ring..=ring {
                    if dx.abs().max(dy.abs()) != ring {
                        continue;
                    }
                    let (x, y) = (i64::from(cell.x) + dx, i64::from(cell.y) + dy);
                    if x < 0 || y < 0 || x > i64::from(u32::MAX) || y > i64::from(u32::MAX) {
                        continue;
                    }
                    let candidate = Cell::new(x as u32, y as u32);
                    if !(grid.contains(candidate) && grid.is_traversable(candidate)) {
                        continue;
                    }
                    let distance = distance_m(self.geometry.center_of(candidate), rover_m);
                    if best.is_none_or(|(best_m, _)| distance < best_m) {
                        best = Some((distance, candidate));
                    }
                }
            }
            if let Some((_, found)) = best {
                return Some(found);
            }
        }
        None
    }

    /// A back-off has begun: of the bumper's ways out, the first whose turn and drive sweep
    /// the body past no rock (cells it touches now aside); the bumper's own first choice when
    /// none does.
    pub(super) fn choose_way_out(&mut self, rover: RoverPose) {
        if !self.config.footprint_check {
            return;
        }
        let touched =
            self.geometry
                .cells_under_body(rover.xy_m, rover.yaw_rad, self.half_extents_m());
        let clear = self
            .bumper
            .back_off_options(rover)
            .into_iter()
            .find(|&(target_m, forward)| self.way_out_fits(rover, target_m, forward, &touched));
        if let Some(way_out) = clear {
            self.bumper.redirect_back_off(way_out);
        }
    }

    /// The body turns toward `to_m` (its rear toward it unless `forward`) and drives there
    /// straight, touching no rock cell but those in `tolerated`.
    fn way_out_fits(
        &self,
        rover: RoverPose,
        to_m: [f64; 2],
        forward: bool,
        tolerated: &[Cell],
    ) -> bool {
        let towards_rad = (to_m[1] - rover.xy_m[1]).atan2(to_m[0] - rover.xy_m[0]);
        let facing_rad = if forward {
            towards_rad
        } else {
            towards_rad + std::f64::consts::PI
        };
        let blocked = |cell: Cell| self.is_rock_cell(cell) && !tolerated.contains(&cell);
        self.geometry.turn_is_clear(
            rover.xy_m,
            (rover.yaw_rad, facing_rad),
            self.half_extents_m(),
            blocked,
        ) && self
            .geometry
            .footprint_is_clear(rover.xy_m, to_m, self.half_extents_m(), blocked)
    }

    /// Where the rover can back off to make room for a turn: back along its own track (known
    /// ground; behind it lies what its forward camera never saw), when the body sweeps past
    /// no rock on the way (`None` otherwise: the turn is then made as it is).
    pub(super) fn room_to_turn(&self, rover: RoverPose) -> Option<([f64; 2], bool)> {
        let back_m = self.bumper.track_behind(rover)?;
        let touched =
            self.geometry
                .cells_under_body(rover.xy_m, rover.yaw_rad, self.half_extents_m());
        self.way_out_fits(rover, back_m, false, &touched)
            .then_some((back_m, false))
    }
}
