//! Per-cell classification of the feature map: a cell's base class from its own features
//! (or its belief), its estimated high features, and its published state with the extra
//! cost from inflation, extents and fitted rocks.

use hopnav_ipc::messages::{CellClass, Robot};
use hopnav_robot::SlopeClass;

use super::{Base, BaseClass, CellState, FeatureMap};
use crate::belief::BeliefClass;
use crate::cell::CellStats;
use crate::ground::fit_ground;

impl FeatureMap {
    pub(super) fn classify(&mut self, index: usize) -> Base {
        if let Some(layer) = &self.beliefs {
            return self.classify_by_belief(index, layer.class(index));
        }
        let stats = self.stats[index];
        // The jumper's high features count only where enough of its clouds agree: a distorted
        // cloud (a keyframe pair with a wrong relative pose) reads bare ground as high
        // wherever it looks. Features of unknown height are judged against a ground fitted to
        // the neighbourhood instead and cast no vote.
        let t = self.thresholds;
        let jumper_clouds_agree = stats.high_clouds >= t.min_high_clouds
            && f64::from(stats.high_clouds)
                >= t.min_high_cloud_fraction * f64::from(stats.judged_clouds)
            && !self.rover_overrules_jumper(&stats);
        let mut high = if jumper_clouds_agree {
            stats.measured_high
        } else {
            stats.measured_high - stats.jumper_measured_high.min(stats.measured_high)
        };
        if stats.high_len > 0 {
            high = high.saturating_add(self.estimated_high(index, &stats));
        }
        let fraction_ok = stats
            .high_fraction(t.fraction_min_features, jumper_clouds_agree)
            .is_none_or(|fraction| fraction >= t.obstacle_min_fraction);
        let class = if high >= t.min_obstacle_support && fraction_ok {
            BaseClass::Obstacle
        } else if stats.count >= t.min_free_support {
            BaseClass::Free
        } else {
            BaseClass::Unknown
        };
        let support = if class == BaseClass::Obstacle {
            high
        } else {
            stats.count
        };
        Base {
            class,
            support,
            high,
        }
    }

    /// The `traversability` model's base class: the belief decides rocks; features decide
    /// whether the cell was observed at all.
    pub(super) fn classify_by_belief(&self, index: usize, belief: BeliefClass) -> Base {
        let stats = &self.stats[index];
        // A cell its own belief makes lethal needs no look at the fitted rocks around it.
        let rock = if belief == BeliefClass::Lethal {
            BeliefClass::Unknown
        } else {
            self.fitted_rock_class(index)
        };
        let class = match belief {
            BeliefClass::Lethal => BaseClass::Obstacle,
            _ if rock == BeliefClass::Lethal => BaseClass::Obstacle,
            _ if self.is_flank_of_lethal(index) => BaseClass::Obstacle,
            BeliefClass::Uncertain => BaseClass::Uncertain,
            _ if rock == BeliefClass::Uncertain => BaseClass::Uncertain,
            BeliefClass::Traversable | BeliefClass::Unknown => {
                if stats.count >= self.thresholds.min_free_support {
                    BaseClass::Free
                } else {
                    BaseClass::Unknown
                }
            }
        };
        Base {
            class,
            support: stats.count,
            high: 0,
        }
    }

    /// What the fitted rocks whose base covers cell `index` make of it (the tallest verdict;
    /// `Unknown` when none covers it).
    pub(super) fn fitted_rock_class(&self, index: usize) -> BeliefClass {
        let (Some(domes), Some(layer)) = (&self.domes, &self.beliefs) else {
            return BeliefClass::Unknown;
        };
        let mut class = BeliefClass::Unknown;
        domes.near(&self.geometry, index, 0.0, |dome, _| {
            match dome.judged_by(layer) {
                BeliefClass::Lethal => class = BeliefClass::Lethal,
                BeliefClass::Uncertain if class != BeliefClass::Lethal => {
                    class = BeliefClass::Uncertain;
                }
                _ => {}
            }
        });
        class
    }

    /// The cell stands confidently above half the climb limit next to a lethal cell or to
    /// another such flank: the flank of the same rock (a rock is about half as tall as it is
    /// wide, so its footprint reaches well beyond the part that is too tall), which the
    /// rover's body must not touch. Flanks grow a ring per update across the rock's cells.
    pub(super) fn is_flank_of_lethal(&self, index: usize) -> bool {
        let Some(layer) = &self.beliefs else {
            return false;
        };
        let Some(belief) = layer.belief(index) else {
            return false;
        };
        let flank_m = 0.5 * layer.climb_limit_m();
        // A flank that the evidence refuted (rays passed under it) is no flank.
        if belief.top_count == 0
            || belief.top_m - belief.top_sigma_m() < flank_m
            || belief.ray_cleared
        {
            return false;
        }
        let (x, y) = self.geometry.coords(index);
        let (x0, y0, x1, y1) = self.geometry.window(x, y, 1);
        (y0..=y1).any(|ny| {
            (x0..=x1).any(|nx| {
                let neighbour = self.geometry.index(nx, ny);
                neighbour != index
                    && (layer.class(neighbour) == BeliefClass::Lethal
                        || self.base[neighbour].class == BaseClass::Obstacle)
            })
        })
    }

    pub(super) fn reclassify_neighbours(&mut self, index: usize) {
        let (x, y) = self.geometry.coords(index);
        let (x0, y0, x1, y1) = self.geometry.window(x, y, 1);
        for ny in y0..=y1 {
            for nx in x0..=x1 {
                self.reclassify.insert(self.geometry.index(nx, ny));
            }
        }
    }

    /// The rover has looked at the cell closely enough that its stereo alone says whether a
    /// rock stands there.
    pub(super) fn rover_overrules_jumper(&self, stats: &CellStats) -> bool {
        let after = self.thresholds.rover_overrules_jumper_after;
        let rover_features = stats
            .count_by_robot
            .get(Robot::Rover.code() as usize)
            .copied()
            .unwrap_or(0);
        after > 0 && rover_features >= after
    }

    /// High features of unknown height that stand more than the traversable height above the
    /// local ground of the neighbourhood.
    pub(super) fn estimated_high(&mut self, index: usize, stats: &CellStats) -> u32 {
        let (x, y) = self.geometry.coords(index);
        let (x0, y0, x1, y1) = self
            .geometry
            .window(x, y, self.thresholds.ground_reach_cells);
        self.ground.samples.clear();
        for ny in y0..=y1 {
            for nx in x0..=x1 {
                let neighbour = &self.stats[self.geometry.index(nx, ny)];
                self.ground.samples.extend(
                    neighbour
                        .low_points()
                        .iter()
                        .map(|p| [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]),
                );
            }
        }
        let (cx, cy) = self.geometry.centre_m(x, y);
        let plane = fit_ground(&mut self.ground, cx, cy);
        self.ground_cache[index] = plane;
        let Some(plane) = plane else {
            return 0;
        };
        let t = self.thresholds;
        stats
            .high_points()
            .iter()
            .filter(|p| {
                let height =
                    (f64::from(p[2]) - plane.height_at(f64::from(p[0]), f64::from(p[1]))) as f32;
                height > t.traversable_height_m && height <= t.max_feature_height_m
            })
            .count() as u32
    }

    /// The `traversability` model's cost of cell `index` from the obstacle in cell `source`,
    /// measured from where in `source` its tall points stand (`Some((0, false))` when that is
    /// beyond the inflation; `None` without an extent: the kernel's whole-cell value holds).
    pub(super) fn cost_from_extent(&self, index: usize, source: usize) -> Option<(u32, bool)> {
        let costs = self.footprint_costs.as_ref()?;
        let belief = self.beliefs.as_ref()?.belief(source)?;
        let (mut min_m, mut max_m) = belief.extent_m()?;
        // The stereo sees a rock's near face only. Rocks are about as wide as twice their
        // height (Golombek, and the world's ellipsoids): with `rock_width_prior` the box of a
        // too-tall cell grows to hold a square of that fraction of the measured top as a
        // half-width (at most a metre), set behind the seen face.
        let layer = self.beliefs.as_ref()?;
        let half_m = if layer.class(source) == BeliefClass::Lethal {
            (self.thresholds.rock_width_prior * belief.top_m).clamp(0.0, 1.0)
        } else {
            // A flank is seen where it is.
            0.0
        };
        if half_m > 0.0 {
            // The rock (about `half_m` in radius) stands behind its seen face, away from the
            // camera when the rover saw it; without a viewpoint, around the face.
            let [dx, dy] = belief.view_direction().unwrap_or([0.0, 0.0]);
            let centre = [
                0.5 * (min_m[0] + max_m[0]) + dx * half_m,
                0.5 * (min_m[1] + max_m[1]) + dy * half_m,
            ];
            for axis in 0..2 {
                min_m[axis] = min_m[axis].min(centre[axis] - half_m);
                max_m[axis] = max_m[axis].max(centre[axis] + half_m);
            }
        }
        let (x, y) = self.geometry.coords(index);
        let (cx, cy) = self.geometry.centre_m(x, y);
        let gap = |c: f64, lo: f32, hi: f32| (f64::from(lo) - c).max(c - f64::from(hi)).max(0.0);
        let distance_m = gap(cx, min_m[0], max_m[0]).hypot(gap(cy, min_m[1], max_m[1]));
        Some(costs.at(distance_m).unwrap_or((0, false)))
    }

    /// Cell `index` is an obstacle only because a fitted rock's base covers it (no tall point
    /// of its own).
    pub(super) fn under_fitted_rock_only(&self, index: usize) -> bool {
        self.domes.is_some()
            && self
                .beliefs
                .as_ref()
                .and_then(|layer| layer.belief(index))
                .is_some_and(|belief| belief.extent_m().is_none() && !belief.lethal)
    }

    /// What the fitted rocks near cell `index` do to it, measured from their edges (the kernel
    /// measures from whole cells, which a rock's base covers only in part): lethal rocks at
    /// full cost, uncertain ones as [`Self::reach_of_uncertain`] says (`None` without fitted
    /// rocks).
    pub(super) fn reach_of_fitted_rocks(&self, index: usize) -> Option<Reach> {
        let (domes, layer, costs) = (
            self.domes.as_ref()?,
            self.beliefs.as_ref()?,
            self.footprint_costs.as_ref()?,
        );
        let mut worst: Option<Reach> = None;
        domes.near(&self.geometry, index, costs.radius_m, |dome, gap_m| {
            let reach = match dome.judged_by(layer) {
                BeliefClass::Lethal => costs.at(gap_m.max(0.0)).map(Reach::from_lethal),
                BeliefClass::Uncertain => costs
                    .at(gap_m.max(0.0))
                    .map(|share| self.reach_of_uncertain(share)),
                _ => None,
            };
            if let Some(reach) = reach {
                worst = Some(worst.unwrap_or_default().max(reach));
            }
        });
        worst
    }

    /// What a maybe-too-tall rock does to a cell where a surely-too-tall one would cost
    /// `(cost, lethal)`. Within the inscribed radius the body touches it whatever the heading:
    /// the cell is uncertain and costs `uncertain_cost`, as much a risk as driving onto the rock
    /// (half the band's cost made crossing its ring cheaper than crossing the rock, and the
    /// rover drove into such rocks). Farther out only some headings touch it: half the cost.
    fn reach_of_uncertain(&self, (cost, within_inscribed): (u32, bool)) -> Reach {
        Reach {
            cost: if within_inscribed {
                self.thresholds.uncertain_cost.max(cost / 2)
            } else {
                cost / 2
            },
            lethal: false,
            uncertain: within_inscribed,
        }
    }

    /// What the ground's slope under cell `(x, y)` does to the rover (`Level` without the
    /// `traversability` model).
    fn slope_class(&self, x: u32, y: u32) -> SlopeClass {
        match (&self.slope, &self.beliefs) {
            (Some(judge), Some(layer)) => {
                judge.class_at(&self.geometry, x, y, |index| layer.ground_z_m(index))
            }
            _ => SlopeClass::Level,
        }
    }

    pub(super) fn derive_state(&self, index: usize) -> CellState {
        let base = self.base[index];
        let observed_by = self.stats[index].observed_by;
        if base.class == BaseClass::Obstacle {
            return CellState {
                class: CellClass::Obstacle,
                extra_cost: 0,
                observed_by,
                support: base.support,
            };
        }
        let (x, y) = self.geometry.coords(index);
        let mut reach = Reach {
            uncertain: base.class == BaseClass::Uncertain,
            ..Reach::default()
        };
        for entry in &self.kernel {
            let (nx, ny) = (
                x as i64 + i64::from(entry.dx),
                y as i64 + i64::from(entry.dy),
            );
            if nx < 0
                || ny < 0
                || nx >= i64::from(self.geometry.width_cells)
                || ny >= i64::from(self.geometry.height_cells)
            {
                continue;
            }
            let neighbour = self.geometry.index(nx as u32, ny as u32);
            match self.base[neighbour].class {
                // Ground under a fitted rock's unseen back: its costs are measured from the
                // rock's edge (below), not from the whole cell.
                BaseClass::Obstacle if self.under_fitted_rock_only(neighbour) => {}
                BaseClass::Obstacle => {
                    let share = self
                        .cost_from_extent(index, neighbour)
                        .unwrap_or((entry.cost, entry.lethal));
                    reach = reach.max(Reach::from_lethal(share));
                }
                // Maybe too tall: the rover's body is kept off it at a finite cost, never
                // forbidden (the closer look settles it).
                BaseClass::Uncertain if self.beliefs.is_some() => {
                    let share = self
                        .cost_from_extent(index, neighbour)
                        .unwrap_or((entry.cost, entry.lethal));
                    reach = reach.max(self.reach_of_uncertain(share));
                }
                _ => {}
            }
        }
        if let Some(fitted) = self.reach_of_fitted_rocks(index) {
            reach = reach.max(fitted);
        }
        if base.class == BaseClass::Uncertain {
            reach.cost = reach.cost.max(self.thresholds.uncertain_cost);
        }
        match self.slope_class(x, y) {
            SlopeClass::TooSteep => reach.lethal = true,
            SlopeClass::Steep => {
                let band_cost = self.footprint_costs.as_ref().map_or(0, |c| c.band_cost);
                reach.cost = reach.cost.max(band_cost);
            }
            SlopeClass::Level => {}
        }
        let class = match (reach.cost > 0, base.class) {
            _ if reach.lethal => CellClass::Lethal,
            _ if reach.uncertain => CellClass::Uncertain,
            (true, _) => CellClass::Inflated,
            (false, BaseClass::Free | BaseClass::Uncertain) => CellClass::Free,
            (false, _) => CellClass::Unknown,
        };
        CellState {
            class,
            extra_cost: reach.cost,
            observed_by,
            support: base.support,
        }
    }
}

/// What the rocks near a cell do to the rover's centre there.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Reach {
    /// Extra cost of entering the cell, planner units.
    cost: u32,
    /// A rock too tall to climb touches the body whatever its heading.
    lethal: bool,
    /// A rock maybe too tall does (or the cell is that rock).
    uncertain: bool,
}

impl Reach {
    /// A surely-too-tall rock's `(cost, lethal)` share.
    fn from_lethal((cost, lethal): (u32, bool)) -> Self {
        Self {
            cost,
            lethal,
            uncertain: false,
        }
    }

    /// The worse of both on each count.
    fn max(self, other: Self) -> Self {
        Self {
            cost: self.cost.max(other.cost),
            lethal: self.lethal | other.lethal,
            uncertain: self.uncertain | other.uncertain,
        }
    }
}
