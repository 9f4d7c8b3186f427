//! The `traversability` model's rocks as domes: each cell keeps the last few points that stood
//! at least half the climb limit tall in it; the cells holding such points that touch form
//! one rock, fitted with a dome ([`crate::dome`]) whose base covers the ground the rock
//! stands on, its unseen back included.
//!
//! Memory: a bounded point buffer per cell that ever held a tall point, and one dome per
//! such cell (both bounded by the grid).

use std::collections::{HashMap, HashSet};

use serde::{Deserialize, Serialize};

use crate::belief::BeliefClass;
use crate::dirty::DirtySet;
use crate::dome::{self, DomeFit, RockPoint};
use crate::foot;
use crate::geometry::GridGeometry;

/// Points kept per cell (the newest replace the oldest: the rover's closer look wins).
pub const POINTS_PER_CELL: usize = 8;
/// A group of touching cells larger than this is not one rock (a scarp, a cluster, a
/// misplaced cloud's wall): no dome, the cells' own beliefs decide.
const MAX_ROCK_CELLS: usize = 48;
/// Domes wider than this are not trusted, metres (no Golombek rock the rover meets is).
const MAX_BASE_RADIUS_M: f64 = 1.5;
/// A fit whose height is less certain than this says nothing, metres.
const MAX_HEIGHT_SIGMA_M: f64 = 0.1;
/// Ground seen this much lower than the dome's surface above it refutes the dome, metres
/// (beyond two of the ground's sigmas).
const REFUTING_GAP_M: f64 = 0.05;

/// What the map knows of a cell, for the rocks fitted over it.
pub trait RockEvidence {
    /// The cell's points still count (no ray refuted them).
    fn usable(&self, cell: usize) -> bool;
    /// The horizontal direction the rover's camera looked at the cell's tall points.
    fn view_direction(&self, cell: usize) -> Option<[f32; 2]>;
    /// The top of what was seen in the cell and its sigma, metres above the local ground
    /// (`None` when nothing was).
    fn seen_top(&self, cell: usize) -> Option<(f32, f32)>;
    /// What a rock of this height and sigma makes of the ground under it.
    fn judge(&self, height_m: f32, sigma_m: f32) -> BeliefClass;
}

/// A cell's newest tall points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct CellPoints {
    points: [RockPoint; POINTS_PER_CELL],
    len: u8,
    next: u8,
}

impl CellPoints {
    fn push(&mut self, point: RockPoint) {
        self.points[usize::from(self.next)] = point;
        self.next = ((usize::from(self.next) + 1) % POINTS_PER_CELL) as u8;
        self.len = (usize::from(self.len) + 1).min(POINTS_PER_CELL) as u8;
    }

    /// The points held, oldest first after a wrap (evaluation and snapshots read them).
    pub fn as_slice(&self) -> &[RockPoint] {
        &self.points[..usize::from(self.len).min(POINTS_PER_CELL)]
    }
}

/// A fitted rock as the cells it was fitted from keep it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dome {
    /// Centre of its base, world metres.
    pub centre_m: [f32; 2],
    /// Base radius, metres.
    pub base_radius_m: f32,
    /// Height above the local ground, metres.
    pub height_m: f32,
    /// One-sigma uncertainty of the height, metres.
    pub height_sigma_m: f32,
    /// How far its downhill foot stands below the ground at its centre, metres
    /// ([`crate::foot`]).
    pub foot_drop_m: f32,
}

/// A refit whose base lies within this of the rock it replaces keeps that rock, metres …
const SETTLED_M: f32 = 0.03;
/// … when its height and height sigma moved less than this plus a quarter of the old
/// sigma, metres (they decide whether the rock is too tall, within its sigma anyway).
const SETTLED_HEIGHT_M: f32 = 0.005;

impl Dome {
    /// Within [`SETTLED_M`] of `old` in centre and radius, [`SETTLED_HEIGHT_M`] and a
    /// quarter of its sigma in height and height sigma.
    fn settled_near(&self, old: &Self) -> bool {
        let moved_m =
            (self.centre_m[0] - old.centre_m[0]).hypot(self.centre_m[1] - old.centre_m[1]);
        let height_tolerance_m = SETTLED_HEIGHT_M + 0.25 * old.height_sigma_m;
        moved_m < SETTLED_M
            && (self.base_radius_m - old.base_radius_m).abs() < SETTLED_M
            && (self.height_m - old.height_m).abs() < height_tolerance_m
            && (self.height_sigma_m - old.height_sigma_m).abs() < height_tolerance_m
    }

    fn from_fit(fit: &DomeFit, points: &[RockPoint]) -> Self {
        Self {
            centre_m: [fit.centre_m[0] as f32, fit.centre_m[1] as f32],
            base_radius_m: fit.base_radius_m as f32,
            height_m: fit.height_m as f32,
            height_sigma_m: fit.height_sigma_m as f32,
            foot_drop_m: foot::foot_drop_m(points, fit.base_radius_m) as f32,
        }
    }

    /// The step the rock makes from its downhill foot: what a wheel meets coming from below,
    /// and what decides whether the rover can climb it.
    pub fn step_height_m(&self) -> f32 {
        self.height_m + self.foot_drop_m
    }

    /// What `evidence` makes of the ground under this rock.
    pub fn judged_by(&self, evidence: &impl RockEvidence) -> BeliefClass {
        evidence.judge(self.step_height_m(), self.height_sigma_m)
    }
}

/// Tall points and fitted domes over the grid.
#[derive(Debug)]
pub struct DomeLayer {
    base_per_height: f64,
    min_height_m: f32,
    points: HashMap<u32, CellPoints>,
    /// Per cell: 1 + the slot in `rocks` of the rock it belongs to (0: none).
    rock_of_cell: Vec<u32>,
    /// Fitted rocks and their cells; `None` slots are free (listed in `free`).
    rocks: Vec<Option<(Dome, Vec<u32>)>>,
    free: Vec<u32>,
    pending: DirtySet,
}

/// Where a refit must reclassify cells and restate their costs.
pub struct Changed<'a> {
    /// Cells whose class may change (under a rock's base).
    pub reclassify: &'a mut DirtySet,
    /// Cells whose cost may change (within the inflation of a rock's base).
    pub restate: &'a mut DirtySet,
    /// How far from a rock's base its costs reach, metres.
    pub inflation_m: f64,
}

impl DomeLayer {
    /// No points yet, for a grid of `cells` cells; rocks' base radius is `base_per_height`
    /// times their height; points lower than `min_height_m` are ground.
    pub fn new(cells: usize, base_per_height: f64, min_height_m: f32) -> Self {
        Self {
            base_per_height,
            min_height_m,
            points: HashMap::new(),
            rock_of_cell: vec![0; cells],
            rocks: Vec::new(),
            free: Vec::new(),
            pending: DirtySet::new(cells),
        }
    }

    /// A point of the rover's stereo in cell `index`; kept when it stands at least the minimum
    /// height tall. (The jumper's points carry metres of pose drift: a dome fitted to them
    /// lands beside the rock. They count in the cells' own beliefs.)
    pub fn add_point(&mut self, index: usize, point: RockPoint) {
        if !(point.height_m >= self.min_height_m && point.sigma_m > 0.0)
            || index >= self.rock_of_cell.len()
        {
            return;
        }
        self.points.entry(index as u32).or_default().push(point);
        self.pending.insert(index);
    }

    /// The rock around cell `index` must be fitted again (its evidence changed).
    pub fn mark(&mut self, index: usize) {
        if index < self.rock_of_cell.len() && self.points.contains_key(&(index as u32)) {
            self.pending.insert(index);
        }
    }

    /// Refits the rocks of the cells marked since the last call against the cells'
    /// `evidence`.
    pub fn refit(
        &mut self,
        geometry: &GridGeometry,
        evidence: &impl RockEvidence,
        changed: &mut Changed<'_>,
    ) {
        let mut done: HashSet<u32> = HashSet::new();
        let mut queue: Vec<u32> = self.pending.as_slice().to_vec();
        self.pending.clear();
        while let Some(start) = queue.pop() {
            if !done.insert(start) {
                continue;
            }
            let rock = self.rock_cells(geometry, start, evidence);
            done.extend(rock.iter().copied());
            // The rocks these cells belonged to go; their other cells are fitted again.
            let mut released: Vec<Dome> = Vec::new();
            for &cell in rock.iter().chain(std::iter::once(&start)) {
                if let Some((old, cells)) = self.release(self.rock_of_cell[cell as usize]) {
                    released.push(old);
                    queue.extend(cells.into_iter().filter(|c| !done.contains(c)));
                }
            }
            let fit = self
                .fit(&rock, evidence)
                .filter(|dome| !contradicted(geometry, dome, &self.points, evidence));
            // A new point moves a fitted rock by millimetres: the rock it was stays, and the
            // map and the planner are spared a restate of its whole inflation every frame.
            let fit = match (fit, released.as_slice()) {
                (Some(new), [old])
                    if new.settled_near(old)
                        && new.judged_by(evidence) == old.judged_by(evidence) =>
                {
                    Some(*old)
                }
                (fit, _) => {
                    for old in released.iter().chain(fit.iter()) {
                        mark_covered(geometry, old, changed);
                    }
                    fit
                }
            };
            if let Some(dome) = fit {
                let slot = match self.free.pop() {
                    Some(slot) => slot,
                    None => {
                        self.rocks.push(None);
                        (self.rocks.len() - 1) as u32
                    }
                };
                for &cell in &rock {
                    self.rock_of_cell[cell as usize] = slot + 1;
                }
                self.rocks[slot as usize] = Some((dome, rock));
            }
        }
    }

    /// Frees the rock of id `id` (1 + slot; 0 is none), returning it.
    fn release(&mut self, id: u32) -> Option<(Dome, Vec<u32>)> {
        let slot = id.checked_sub(1)?;
        let (dome, cells) = self.rocks.get_mut(slot as usize)?.take()?;
        for &cell in &cells {
            self.rock_of_cell[cell as usize] = 0;
        }
        self.free.push(slot);
        Some((dome, cells))
    }

    /// The touching usable cells with points around `start` (empty when `start` itself is
    /// not usable), at most [`MAX_ROCK_CELLS`] + 1 (more means: not one rock).
    fn rock_cells(
        &self,
        geometry: &GridGeometry,
        start: u32,
        evidence: &impl RockEvidence,
    ) -> Vec<u32> {
        let holds = |cell: u32| self.points.contains_key(&cell) && evidence.usable(cell as usize);
        if !holds(start) {
            return Vec::new();
        }
        let mut rock = vec![start];
        let mut next = 0;
        while next < rock.len() && rock.len() <= MAX_ROCK_CELLS {
            let (x, y) = geometry.coords(rock[next] as usize);
            next += 1;
            let (x0, y0, x1, y1) = geometry.window(x, y, 1);
            for ny in y0..=y1 {
                for nx in x0..=x1 {
                    let cell = geometry.index(nx, ny) as u32;
                    if holds(cell) && !rock.contains(&cell) {
                        rock.push(cell);
                    }
                }
            }
        }
        rock
    }

    /// The dome of `rock`'s points.
    fn fit(&self, rock: &[u32], evidence: &impl RockEvidence) -> Option<Dome> {
        if rock.is_empty() || rock.len() > MAX_ROCK_CELLS {
            return None;
        }
        let points: Vec<RockPoint> = rock
            .iter()
            .filter_map(|cell| self.points.get(cell))
            .flat_map(CellPoints::as_slice)
            .copied()
            .collect();
        let mut sum = [0.0f64; 2];
        for direction in rock
            .iter()
            .filter_map(|&cell| evidence.view_direction(cell as usize))
        {
            sum[0] += f64::from(direction[0]);
            sum[1] += f64::from(direction[1]);
        }
        let fit = dome::fit_dome(&points, self.base_per_height, Some(sum))?;
        (fit.base_radius_m <= MAX_BASE_RADIUS_M && fit.height_sigma_m <= MAX_HEIGHT_SIGMA_M)
            .then(|| Dome::from_fit(&fit, &points))
    }

    /// The rocks whose base lies within `reach_m` of the centre of cell `index`, with the
    /// distance from that centre to the base's edge (≤ 0 inside), metres.
    pub fn near(
        &self,
        geometry: &GridGeometry,
        index: usize,
        reach_m: f64,
        mut each: impl FnMut(&Dome, f64),
    ) {
        if self.rocks.is_empty() {
            return;
        }
        let (x, y) = geometry.coords(index);
        let (cx, cy) = geometry.centre_m(x, y);
        let window = ((MAX_BASE_RADIUS_M + reach_m) / geometry.cell_size_m).ceil() as u32;
        let (x0, y0, x1, y1) = geometry.window(x, y, window);
        let mut seen: [u32; 16] = [0; 16];
        let mut seen_len = 0;
        for ny in y0..=y1 {
            for nx in x0..=x1 {
                let id = self.rock_of_cell[geometry.index(nx, ny)];
                if id == 0 || seen[..seen_len].contains(&id) {
                    continue;
                }
                if seen_len < seen.len() {
                    seen[seen_len] = id;
                    seen_len += 1;
                }
                let Some(Some((dome, _))) = self.rocks.get(id as usize - 1) else {
                    continue;
                };
                let gap_m = (cx - f64::from(dome.centre_m[0]))
                    .hypot(cy - f64::from(dome.centre_m[1]))
                    - f64::from(dome.base_radius_m);
                if gap_m <= reach_m {
                    each(dome, gap_m);
                }
            }
        }
    }

    /// Every fitted rock.
    pub fn rocks(&self) -> impl Iterator<Item = &Dome> {
        self.rocks.iter().flatten().map(|(dome, _)| dome)
    }

    /// Replaces `out` by the cells' stored points, for snapshots (sorted by cell; `out`'s
    /// allocation is reused).
    pub fn stored_points_into(&self, out: &mut Vec<(u32, CellPoints)>) {
        out.clear();
        out.extend(self.points.iter().map(|(&cell, &points)| (cell, points)));
        out.sort_by_key(|&(cell, _)| cell);
    }

    /// Restores a snapshot's points (cells outside the grid are dropped); every rock is
    /// refitted on the next [`Self::refit`].
    pub fn set_stored_points(&mut self, cells: &[(u32, CellPoints)]) {
        self.points.clear();
        self.rocks.clear();
        self.free.clear();
        self.rock_of_cell.fill(0);
        let cell_count = self.rock_of_cell.len();
        for &(cell, points) in cells
            .iter()
            .filter(|(cell, _)| (*cell as usize) < cell_count)
        {
            self.points.insert(cell, points);
            self.pending.insert(cell as usize);
        }
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.points.capacity() * (size_of::<u32>() + size_of::<CellPoints>())
            + self.rock_of_cell.capacity() * size_of::<u32>()
            + self.rocks.capacity() * size_of::<Option<(Dome, Vec<u32>)>>()
    }
}

/// Some cell under `dome` was seen clearly lower than the dome's surface above it: the
/// points were the flank of something smaller (a low rock's noisy points read as the edge
/// of a big dome), not a rock's face.
fn contradicted(
    geometry: &GridGeometry,
    dome: &Dome,
    points: &HashMap<u32, CellPoints>,
    evidence: &impl RockEvidence,
) -> bool {
    let centre = [f64::from(dome.centre_m[0]), f64::from(dome.centre_m[1])];
    let (height_m, base_m) = (f64::from(dome.height_m), f64::from(dome.base_radius_m));
    // The fitted shape, not the prior's: a squat rock's surface falls off slower.
    let base_per_height = if height_m > 0.0 {
        base_m / height_m
    } else {
        return false;
    };
    let mut refuted = false;
    for_cells_within(geometry, centre, base_m, |index| {
        let Some((top_m, sigma_m)) = evidence.seen_top(index) else {
            return;
        };
        let (x, y) = geometry.coords(index);
        let (cx, cy) = geometry.centre_m(x, y);
        // The dome's lowest surface over the cell: at its corner farthest from the centre.
        let far_m = (cx - centre[0]).hypot(cy - centre[1]) + geometry.cell_size_m * 0.5_f64.sqrt();
        let surface_m = (height_m * height_m - (far_m / base_per_height).powi(2))
            .max(0.0)
            .sqrt();
        let below = |height_m: f32, sigma_m: f32| {
            f64::from(height_m) + 2.0 * f64::from(sigma_m) + REFUTING_GAP_M < surface_m
        };
        // A cell's fused top can stay on the ground while a rock's scattered points wait to
        // confirm a new top: its own tall points speak for it.
        let tall_point_fits = points.get(&(index as u32)).is_some_and(|cell| {
            cell.as_slice()
                .iter()
                .any(|p| !below(p.height_m, p.sigma_m))
        });
        refuted |= below(top_m, sigma_m) && !tall_point_fits;
    });
    refuted
}

/// Queues the cells under `dome`'s base for reclassification and those within its
/// inflation for new costs (clamped to the grid).
fn mark_covered(geometry: &GridGeometry, dome: &Dome, changed: &mut Changed<'_>) {
    let centre = [f64::from(dome.centre_m[0]), f64::from(dome.centre_m[1])];
    let base_m = f64::from(dome.base_radius_m) + geometry.cell_size_m;
    for_cells_within(geometry, centre, base_m, |index| {
        changed.reclassify.insert(index)
    });
    let reach_m = base_m + changed.inflation_m;
    for_cells_within(geometry, centre, reach_m, |index| {
        changed.restate.insert(index)
    });
}

/// Calls `each` with every cell of the square of half-side `half_m` around `centre_m`.
fn for_cells_within(
    geometry: &GridGeometry,
    centre_m: [f64; 2],
    half_m: f64,
    mut each: impl FnMut(usize),
) {
    if !(centre_m.iter().all(|v| v.is_finite()) && half_m.is_finite()) {
        return;
    }
    let cell = |v: f64, origin: f64, cells: u32| {
        ((v - origin) / geometry.cell_size_m)
            .floor()
            .clamp(0.0, f64::from(cells.saturating_sub(1))) as u32
    };
    let (gx, gy, w, h) = (
        geometry.origin_x_m,
        geometry.origin_y_m,
        geometry.width_cells,
        geometry.height_cells,
    );
    let (x0, x1) = (
        cell(centre_m[0] - half_m, gx, w),
        cell(centre_m[0] + half_m, gx, w),
    );
    let (y0, y1) = (
        cell(centre_m[1] - half_m, gy, h),
        cell(centre_m[1] + half_m, gy, h),
    );
    for y in y0..=y1 {
        for x in x0..=x1 {
            each(geometry.index(x, y));
        }
    }
}

#[cfg(test)]
#[path = "dome_layer_tests.rs"]
mod tests;
