//! The harder `eval vo` cases run end to end on rendered hops.

use hopnav_eval::jumper_vo::cases::{TUMBLE_RADPS, hops_in_a_row, tumbling_launch};
use hopnav_jumper_vo::config::JumperVoConfig;

#[test]
fn hops_in_a_row_carry_each_landing_error_into_the_next_hop() {
    let outcome = hops_in_a_row(2, 2, &JumperVoConfig::default()).expect("runs");
    assert_eq!(outcome.error_after_hop_m.len(), 2);
    assert!(outcome.error_after_hop_m.iter().all(|e| e.is_finite()));
    // With the bundle adjustment a Table 1 hop lands within decimetres.
    assert!(outcome.error_after_hop_m[1] < 1.0, "{outcome:?}");
}

#[test]
fn a_tumbling_launch_is_drawn_in_range_and_ends_with_a_finite_estimate() {
    let outcome = tumbling_launch(4, &JumperVoConfig::default()).expect("runs");
    let spin = outcome.spin_radps.abs();
    assert!(
        (TUMBLE_RADPS.0..=TUMBLE_RADPS.1).contains(&spin),
        "{outcome:?}"
    );
    assert!(outcome.heading_error_rad.abs() <= 0.3);
    assert!(outcome.final_error_m.is_finite(), "{outcome:?}");
}
