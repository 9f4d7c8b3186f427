//! The verdict of `hopnav compare` against issue #6's targets, in words that cannot be
//! misread: a change is printed with its direction ("2.0 % longer", "12.5 % fewer"), never as
//! a signed "−2.0 % shorter", and every target says whether it was met.
//!
//! The targets: over the seeds both modes reached, cooperative mode drives a path at least
//! 15 % shorter and needs at least 30 % fewer replans than rover-only, and it reaches B at
//! least as often.

/// Path shortening cooperative mode must reach, percent of rover-only's path.
pub const MIN_PATH_SHORTENING_PERCENT: f64 = 15.0;
/// Replan reduction cooperative mode must reach, percent of rover-only's replans.
pub const MIN_REPLAN_REDUCTION_PERCENT: f64 = 30.0;

/// Means over the seeds both modes reached, and each mode's successes over all seeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairedOutcome {
    /// Seeds both modes reached B on (the means are over these).
    pub paired_seeds: usize,
    /// Seeds each mode ran.
    pub seeds_per_mode: usize,
    /// Missions that reached B, cooperative.
    pub cooperative_reached: usize,
    /// Missions that reached B, rover-only.
    pub rover_only_reached: usize,
    /// (cooperative, rover-only) mean executed path, metres.
    pub path_m: (f64, f64),
    /// (cooperative, rover-only) mean replans.
    pub replans: (f64, f64),
    /// (cooperative, rover-only) mean replans that moved the route.
    pub route_changes: (f64, f64),
}

/// How much smaller `cooperative` is than `rover_only`, percent (negative: larger). Zero when
/// rover-only's value is not positive (nothing to reduce).
pub fn reduction_percent((cooperative, rover_only): (f64, f64)) -> f64 {
    if rover_only > 0.0 {
        100.0 * (1.0 - cooperative / rover_only)
    } else {
        0.0
    }
}

/// A reduction in words: "12.5 % fewer", "2.0 % more", "unchanged".
pub fn change_words(reduction_percent: f64, smaller_word: &str, larger_word: &str) -> String {
    if reduction_percent.abs() < 0.05 {
        "unchanged".to_owned()
    } else if reduction_percent > 0.0 {
        format!("{reduction_percent:.1} % {smaller_word}")
    } else {
        format!("{:.1} % {larger_word}", -reduction_percent)
    }
}

fn met(is_met: bool) -> &'static str {
    if is_met { "met" } else { "NOT met" }
}

/// The verdict lines: one per target, then how many were met.
pub fn verdict_lines(outcome: &PairedOutcome) -> Vec<String> {
    let path_reduction = reduction_percent(outcome.path_m);
    let replan_reduction = reduction_percent(outcome.replans);
    let path_met = path_reduction >= MIN_PATH_SHORTENING_PERCENT;
    let replans_met = replan_reduction >= MIN_REPLAN_REDUCTION_PERCENT;
    let success_met = outcome.cooperative_reached >= outcome.rover_only_reached;
    let met_count = [path_met, replans_met, success_met]
        .iter()
        .filter(|&&is_met| is_met)
        .count();
    vec![
        format!(
            "paired over {} seeds both reached: cooperative path {:.1} m against rover-only {:.1} m, {} (target: at least {MIN_PATH_SHORTENING_PERCENT:.0} % shorter, {})",
            outcome.paired_seeds,
            outcome.path_m.0,
            outcome.path_m.1,
            change_words(path_reduction, "shorter", "longer"),
            met(path_met)
        ),
        format!(
            "  replans {:.1} against {:.1}, {} (target: at least {MIN_REPLAN_REDUCTION_PERCENT:.0} % fewer, {}); route changes {:.1} against {:.1}, {}",
            outcome.replans.0,
            outcome.replans.1,
            change_words(replan_reduction, "fewer", "more"),
            met(replans_met),
            outcome.route_changes.0,
            outcome.route_changes.1,
            change_words(reduction_percent(outcome.route_changes), "fewer", "more"),
        ),
        format!(
            "  reached B: cooperative {}/{n}, rover-only {}/{n} (target: equal or better, {})",
            outcome.cooperative_reached,
            outcome.rover_only_reached,
            met(success_met),
            n = outcome.seeds_per_mode
        ),
        format!("  targets met: {met_count} of 3"),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(path_m: (f64, f64), replans: (f64, f64), reached: (usize, usize)) -> PairedOutcome {
        PairedOutcome {
            paired_seeds: 13,
            seeds_per_mode: 20,
            cooperative_reached: reached.0,
            rover_only_reached: reached.1,
            path_m,
            replans,
            route_changes: (10.0, 10.0),
        }
    }

    #[test]
    fn a_longer_cooperative_path_reads_longer_not_negative_shorter() {
        let lines = verdict_lines(&outcome((41.2, 40.4), (29.1, 22.5), (15, 15)));
        assert!(lines[0].contains("2.0 % longer"), "{}", lines[0]);
        assert!(!lines[0].contains("-2.0"), "{}", lines[0]);
        assert!(lines[0].ends_with("NOT met)"), "{}", lines[0]);
        assert!(lines[1].contains("29.3 % more"), "{}", lines[1]);
        assert!(lines[1].contains("route changes 10.0 against 10.0, unchanged"));
        assert!(lines[2].ends_with("equal or better, met)"), "{}", lines[2]);
        assert_eq!(lines[3], "  targets met: 1 of 3");
    }

    #[test]
    fn every_target_met_at_its_bound() {
        let lines = verdict_lines(&outcome((85.0, 100.0), (14.0, 20.0), (16, 16)));
        assert!(lines[0].contains("15.0 % shorter"), "{}", lines[0]);
        assert!(lines[0].ends_with(", met)"), "{}", lines[0]);
        assert!(lines[1].contains("30.0 % fewer"), "{}", lines[1]);
        assert_eq!(lines[3], "  targets met: 3 of 3");
    }

    #[test]
    fn fewer_successes_fail_the_success_target() {
        let lines = verdict_lines(&outcome((50.0, 100.0), (5.0, 20.0), (14, 15)));
        assert!(lines[2].contains("cooperative 14/20, rover-only 15/20"));
        assert!(lines[2].ends_with("NOT met)"), "{}", lines[2]);
        assert_eq!(lines[3], "  targets met: 2 of 3");
    }

    #[test]
    fn nothing_to_reduce_is_no_reduction() {
        assert_eq!(reduction_percent((3.0, 0.0)), 0.0);
        assert_eq!(change_words(0.0, "fewer", "more"), "unchanged");
    }
}
