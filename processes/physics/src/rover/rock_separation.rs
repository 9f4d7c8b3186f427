//! When a rover touching or overlapping a blocking rock may still move: out of it, away from
//! it, or along it, never ratcheting deeper.

use rapier3d::math::Pose;
use rapier3d::parry::query::contact;
use rapier3d::parry::shape::Cuboid;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld};

/// The footprint counts as touching a rock within this distance, metres.
const TOUCH_PREDICTION_M: f32 = 0.05;

/// A move away from a touched rock may leave the footprint overlapping it by up to this much
/// in all (see `separates_from_rock`), metres: a bound on the overlap, not on each step's
/// growth, so that backing away while a corner swings in cannot ratchet the rover into it.
const AWAY_OVERLAP_M: f32 = 0.05;

/// A move slides along a touched rock when its step points toward the rock by at most this
/// fraction of its length (about 6°) …
const SLIDE_TOWARD_FRACTION: f32 = 0.1;
/// … and it leaves the overlap no deeper than [`AWAY_OVERLAP_M`], or than now plus this
/// (rounding), metres.
const SLIDE_DEPTH_TOLERANCE_M: f32 = 1e-5;

/// True when a rover at `current`, touching or overlapping the blocking rock compound `rock`,
/// may go to `next`: the move reduces the overlap by at least `min_reduction_m`; or it steps
/// away from the rock (against the contact normal) and leaves an overlap of at most
/// [`AWAY_OVERLAP_M`] (or no deeper than now); or it slides along the rock
/// ([`SLIDE_TOWARD_FRACTION`]) under the same bound. The footprint box reaches below the
/// ground, so a wheel rolling off a small rock
/// pitches its lower corners a few centimetres into a big rock the rover touches; without
/// the second rule, backing away from it was refused and the rover wedged for good. Without
/// the third, a rover whose flank overlapped a rock beside it could not drive on along it: the
/// overlap of a flat side sliding past a rock does not shrink, and every move was refused
/// (compare seed 13 froze for 120 s). The second rule once bounded each step's growth of the
/// overlap instead of the overlap: a rover reversing in a turn stepped "away" while a corner
/// swung 1–3 mm deeper every substep, and ended 16.5 cm into a rock, frozen (compare seed 20).
/// The third rule once allowed no deepening at all: a rover 3 cm into a rock at its flank,
/// steering a few milliradians as it drove on along it, deepened by 0.1 mm a substep, and
/// every move, forward, back or turning, was refused for 290 s (boulder-fields seed 8).
pub(super) fn separates_from_rock(
    pw: &PhysicsWorld,
    rock: ColliderHandle,
    footprint: &Cuboid,
    (current, next): (&Pose, &Pose),
    min_reduction_m: f32,
) -> bool {
    let Some(collider) = pw.colliders.get(rock) else {
        return false;
    };
    let touch = |pose: &Pose, prediction_m: f32| {
        contact(
            pose,
            footprint,
            collider.position(),
            collider.shape(),
            prediction_m,
        )
        .ok()
        .flatten()
    };
    let Some(now) = touch(current, TOUCH_PREDICTION_M) else {
        return false;
    };
    let current_depth_m = (-now.dist).max(0.0);
    let next_depth_m = touch(next, 0.0).map_or(0.0, |hit| (-hit.dist).max(0.0));
    if current_depth_m > 0.0 && next_depth_m <= current_depth_m - min_reduction_m {
        return true;
    }
    // normal1 points from the footprint toward the rock.
    let step = next.translation - current.translation;
    let toward_m = step.dot(now.normal1);
    let away = toward_m < 0.0 && next_depth_m <= current_depth_m.max(AWAY_OVERLAP_M);
    let slides = toward_m <= SLIDE_TOWARD_FRACTION * step.length()
        && next_depth_m <= (current_depth_m + SLIDE_DEPTH_TOLERANCE_M).max(AWAY_OVERLAP_M);
    away || slides
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Quat, Vec3};
    use rapier3d::prelude::ColliderBuilder;

    /// A rock ball of radius 0.27 m whose side overlaps the left flank of a 1 m × 0.7 m
    /// footprint at the origin (yaw 0) by 2 cm, `along_m` ahead of its middle.
    fn rock_beside_the_flank(along_m: f32) -> (PhysicsWorld, ColliderHandle, Cuboid, Pose) {
        let footprint = Cuboid::new(Vec3::new(0.5, 0.35, 0.2));
        let mut pw = PhysicsWorld::new();
        let rock = pw.insert_collider(
            ColliderBuilder::ball(0.27)
                .translation(Vec3::new(along_m, 0.35 + 0.27 - 0.02, 0.0))
                .build(),
            None,
        );
        (pw, rock, footprint, Pose::IDENTITY)
    }

    /// Takes up to `steps` moves `step` from `start` while the rule allows each; returns the
    /// deepest overlap with `rock` reached, metres.
    fn deepest_allowed_m(
        pw: &PhysicsWorld,
        rock: ColliderHandle,
        footprint: &Cuboid,
        start: Pose,
        steps: usize,
        step: impl Fn(&Pose) -> Pose,
    ) -> f32 {
        let mut current = start;
        let mut deepest_m: f32 = 0.0;
        for _ in 0..steps {
            let next = step(&current);
            if !separates_from_rock(pw, rock, footprint, (&current, &next), 1e-4) {
                break;
            }
            current = next;
            deepest_m = deepest_m.max(depth_m(pw, rock, footprint, &current));
        }
        deepest_m
    }

    /// How deep `footprint` at `pose` is in `rock`, metres.
    fn depth_m(pw: &PhysicsWorld, rock: ColliderHandle, footprint: &Cuboid, pose: &Pose) -> f32 {
        let collider = &pw.colliders[rock];
        contact(pose, footprint, collider.position(), collider.shape(), 0.0)
            .ok()
            .flatten()
            .map_or(0.0, |hit| -hit.dist)
    }

    #[test]
    fn a_flank_overlapping_a_rock_may_drive_on_along_it_but_not_into_it() {
        let (pw, rock, footprint, current) = rock_beside_the_flank(-0.04);
        let moved = |dx: f32, dy: f32| Pose::from_translation(Vec3::new(dx, dy, 0.0));
        let may = |next: Pose| separates_from_rock(&pw, rock, &footprint, (&current, &next), 1e-4);
        // One 10 ms substep at 0.25 m/s, forward and backward along the rock.
        assert!(may(moved(0.0025, 0.0)), "forward along the rock refused");
        assert!(may(moved(-0.0025, 0.0)), "backward along the rock refused");
        // Into it, even at a slant, is refused; straight out of it is allowed.
        assert!(!may(moved(0.0025, 0.0005)));
        assert!(!may(moved(0.0, 0.0025)));
        assert!(may(moved(0.0, -0.0025)));
    }

    #[test]
    fn driving_on_along_a_rock_while_steering_a_little_may_deepen_only_to_the_bound() {
        // The rock touches the flank 0.3 m ahead of the middle; each substep drives 2.5 mm on
        // and yaws 2 mrad toward it, which swings the flank 0.6 mm deeper.
        let (pw, rock, footprint, current) = rock_beside_the_flank(0.3);
        let step = |pose: &Pose| {
            Pose::from_parts(
                pose.translation + Vec3::new(0.0025, 0.0, 0.0),
                (Quat::from_rotation_z(0.002) * pose.rotation).normalize(),
            )
        };
        let first = step(&current);
        assert!(
            depth_m(&pw, rock, &footprint, &first) > depth_m(&pw, rock, &footprint, &current),
            "the test no longer deepens"
        );
        assert!(
            separates_from_rock(&pw, rock, &footprint, (&current, &first), 1e-4),
            "a slight steer along the rock froze the rover"
        );
        let deepest_m = deepest_allowed_m(&pw, rock, &footprint, current, 400, step);
        assert!(
            deepest_m > 0.04,
            "the test no longer nears the bound: {deepest_m} m"
        );
        assert!(
            deepest_m <= AWAY_OVERLAP_M + 0.001,
            "ratcheted {deepest_m} m into the rock"
        );
    }

    #[test]
    fn stepping_away_while_a_corner_swings_in_cannot_ratchet_into_the_rock() {
        let (pw, rock, footprint, start) = rock_beside_the_flank(-0.45);
        // Each substep backs the centre 1 mm away from the rock beside the rear-left corner
        // while a 0.01 rad clockwise yaw swings that corner 5 mm in: the overlap grows at every
        // step the rule allows.
        let deepest_m = deepest_allowed_m(&pw, rock, &footprint, start, 100, |pose| {
            Pose::from_parts(
                pose.translation + Vec3::new(0.0, -0.001, 0.0),
                (Quat::from_rotation_z(-0.01) * pose.rotation).normalize(),
            )
        });
        assert!(
            deepest_m > 0.03,
            "the test no longer deepens: {deepest_m} m"
        );
        assert!(
            deepest_m <= AWAY_OVERLAP_M + 0.005,
            "ratcheted {deepest_m} m into the rock"
        );
    }
}
