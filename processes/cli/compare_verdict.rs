//! What `hopnav compare` prints about its paired runs, in words that cannot be misread: every
//! change carries its direction ("3.2 % less", "8.1 % more"), never a bare signed ratio, and
//! every figure is a median with its worst seed beside it. Targets come only from an
//! `--expect` file ([`crate::compare_expect`]); each says whether it was met.

use crate::compare_expect::Expectations;
use crate::compare_pair::{Comparison, ComparisonKind, RatioSpread};

/// How much smaller the subject is than the reference, percent of the reference (negative:
/// larger), from the ratio subject / reference.
pub fn reduction_percent(ratio: f64) -> f64 {
    100.0 * (1.0 - ratio)
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

/// How one figure relates, e.g. "3.2 % less than rover-only", "8.1 % more replans than base",
/// or `same` ("as many replans as") when the median is unchanged.
struct Figure<'a> {
    /// What the subject did: "drove", "needed".
    verb: &'a str,
    smaller: &'a str,
    larger: &'a str,
    /// After the amount: "" or " replans".
    noun: &'a str,
    same: &'a str,
}

const PATH: Figure = Figure {
    verb: "drove",
    smaller: "less",
    larger: "more",
    noun: "",
    same: "as far as",
};
const REPLANS: Figure = Figure {
    verb: "needed",
    smaller: "fewer",
    larger: "more",
    noun: " replans",
    same: "as many replans as",
};
const ROUTE_CHANGES: Figure = Figure {
    verb: "had",
    smaller: "fewer",
    larger: "more",
    noun: " route changes",
    same: "as many route changes as",
};

/// "cooperative drove 3.2 % less than rover-only (median over 14 seeds both reached B; worst
/// seed 8.1 % more)".
fn figure_sentence(c: &Comparison, figure: &Figure, spread: &RatioSpread) -> String {
    let median = reduction_percent(spread.median);
    let relation = match change_words(median, figure.smaller, figure.larger).as_str() {
        "unchanged" => format!("{} {}", figure.same, c.reference),
        words => format!("{words}{} than {}", figure.noun, c.reference),
    };
    let left_out = match spread.left_out {
        0 => String::new(),
        n => format!(
            "; {n} {} where {} had none left out",
            plural(n, "seed"),
            c.reference
        ),
    };
    format!(
        "{} {} {relation} (median over {} {} both reached B; worst seed {}{left_out})",
        c.subject,
        figure.verb,
        spread.seeds,
        plural(spread.seeds, "seed"),
        change_words(
            reduction_percent(spread.worst),
            figure.smaller,
            figure.larger
        ),
    )
}

fn plural(count: usize, word: &str) -> String {
    if count == 1 {
        word.to_owned()
    } else {
        format!("{word}s")
    }
}

fn seed_list(seeds: &[u64]) -> String {
    let list: Vec<String> = seeds.iter().map(u64::to_string).collect();
    format!("{} {}", plural(seeds.len(), "seed"), list.join(", "))
}

/// The lines of one comparison: heading, successes, the three figures, the means, and the
/// seeds that could not be paired.
pub fn comparison_lines(c: &Comparison) -> Vec<String> {
    let mut lines = vec![
        format!("{}:", c.heading),
        format!(
            "  reached B: {} on {} and {} on {} of the {} {} both ran",
            c.subject,
            c.subject_reached,
            c.reference,
            c.reference_reached,
            c.seeds_both_ran,
            plural(c.seeds_both_ran, "seed")
        ),
    ];
    let figures = [
        ("path", &PATH, c.path),
        ("replans", &REPLANS, c.replans),
        ("route changes", &ROUTE_CHANGES, c.route_changes),
    ];
    if c.both_reached == 0 {
        lines.push("  no seed where both reached B: no paired figures".to_owned());
    }
    for (name, figure, spread) in figures {
        if let Some(spread) = spread {
            lines.push(format!("  {name}: {}", figure_sentence(c, figure, &spread)));
        }
    }
    if let Some((subject_m, reference_m)) = c.mean_path_m {
        let full_knowledge = c.mean_full_knowledge_m.map_or(String::new(), |m| {
            format!("; full-knowledge path {m:.1} m (every rock known from the start)")
        });
        let built_map = c.mean_built_map_m.map_or(String::new(), |(s, r)| {
            format!(
                "; built-map path (the final map known from the start) {} {s:.1} m, {} {r:.1} m",
                c.subject, c.reference
            )
        });
        lines.push(format!(
            "  means over those {} {}: {} drove {subject_m:.1} m, {} {reference_m:.1} m{full_knowledge}{built_map}",
            c.both_reached,
            plural(c.both_reached, "seed"),
            c.subject,
            c.reference
        ));
    }
    let mut unpaired = Vec::new();
    for (seeds, side) in [(&c.missing.0, &c.subject), (&c.missing.1, &c.reference)] {
        if !seeds.is_empty() {
            unpaired.push(format!("no {side} run for {}", seed_list(seeds)));
        }
    }
    for (seeds, side) in [(&c.failed.0, &c.subject), (&c.failed.1, &c.reference)] {
        if !seeds.is_empty() {
            unpaired.push(format!("{side} launch failed on {}", seed_list(seeds)));
        }
    }
    if !unpaired.is_empty() {
        lines.push(format!("  not paired: {}", unpaired.join("; ")));
    }
    lines
}

fn met(is_met: bool) -> &'static str {
    if is_met { "met" } else { "NOT met" }
}

/// One "at least N % smaller" target against a median ratio.
fn reduction_target(
    name: &str,
    target_percent: f64,
    spread: Option<RatioSpread>,
    (smaller, larger): (&str, &str),
) -> (bool, String) {
    match spread {
        Some(spread) => {
            let reduction = reduction_percent(spread.median);
            // A median exactly at the target is met whatever the float rounding (1 - 0.8).
            let is_met = reduction >= target_percent - 1e-9;
            let line = format!(
                "  {name}: median {}, target at least {target_percent} % {smaller}: {}",
                change_words(reduction, smaller, larger),
                met(is_met)
            );
            (is_met, line)
        }
        None => (
            false,
            format!(
                "  {name}: no seed where both reached B, target at least {target_percent} % {smaller}: NOT met (cannot be judged)"
            ),
        ),
    }
}

/// The verdict of `expect` on a cooperative-vs-rover-only comparison: one line per target,
/// then how many were met. Other comparisons get no verdict (empty).
pub fn verdict_lines(expect: &Expectations, source: &str, c: &Comparison) -> Vec<String> {
    if c.kind != ComparisonKind::CooperativeVsRoverOnly {
        return Vec::new();
    }
    let mut judged = Vec::new();
    if let Some(target) = expect.path_shorter_by_percent {
        judged.push(reduction_target(
            "path",
            target,
            c.path,
            ("shorter", "longer"),
        ));
    }
    if let Some(target) = expect.replans_fewer_by_percent {
        judged.push(reduction_target(
            "replans",
            target,
            c.replans,
            ("fewer", "more"),
        ));
    }
    if let Some(target) = expect.route_changes_fewer_by_percent {
        judged.push(reduction_target(
            "route changes",
            target,
            c.route_changes,
            ("fewer", "more"),
        ));
    }
    if expect.success_at_least_rover_only {
        let is_met = c.subject_reached >= c.reference_reached;
        judged.push((
            is_met,
            format!(
                "  success: {} reached B on {} seeds, {} on {}, target at least as many: {}",
                c.subject,
                c.subject_reached,
                c.reference,
                c.reference_reached,
                met(is_met)
            ),
        ));
    }
    let met_count = judged.iter().filter(|(is_met, _)| *is_met).count();
    let mut lines = vec![format!("targets of {source}, {}:", c.heading)];
    let total = judged.len();
    lines.extend(judged.into_iter().map(|(_, line)| line));
    lines.push(format!("  targets met: {met_count} of {total}"));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare_pair::comparisons;
    use crate::compare_rows::RunSet;
    use crate::compare_rows::tests::row;

    fn base_comparison() -> Comparison {
        let base = RunSet {
            label: "base".into(),
            rows: vec![
                row(1, "cooperative", Some((true, 96.8, 12))),
                row(1, "rover-only", Some((true, 100.0, 10))),
                row(2, "cooperative", Some((true, 108.1, 8))),
                row(2, "rover-only", Some((true, 100.0, 10))),
                row(3, "cooperative", Some((true, 90.0, 5))),
                row(3, "rover-only", Some((true, 100.0, 10))),
                row(4, "cooperative", Some((false, 200.0, 5))),
                row(4, "rover-only", None),
            ],
        };
        comparisons(&base, &[]).remove(0)
    }

    #[test]
    fn directions_are_words_with_median_and_worst() {
        let lines = comparison_lines(&base_comparison());
        assert_eq!(lines[0], "cooperative vs rover-only in base:");
        assert_eq!(
            lines[1],
            "  reached B: cooperative on 3 and rover-only on 3 of the 4 seeds both ran"
        );
        assert_eq!(
            lines[2],
            "  path: cooperative drove 3.2 % less than rover-only (median over 3 seeds both reached B; worst seed 8.1 % more)"
        );
        assert_eq!(
            lines[3],
            "  replans: cooperative needed 20.0 % fewer replans than rover-only (median over 3 seeds both reached B; worst seed 20.0 % more)"
        );
        assert_eq!(
            lines[5],
            "  means over those 3 seeds: cooperative drove 98.3 m, rover-only 100.0 m"
        );
        assert_eq!(lines[6], "  not paired: rover-only launch failed on seed 4");
        for line in &lines {
            let signed = line
                .as_bytes()
                .windows(2)
                .any(|w| matches!(w[0], b'-' | b'+') && w[1].is_ascii_digit());
            assert!(!signed, "no signed figure: {line}");
        }
    }

    #[test]
    fn an_unchanged_median_reads_as_far_as() {
        let mut c = base_comparison();
        c.path = Some(RatioSpread {
            median: 1.0,
            worst: 0.97,
            seeds: 1,
            left_out: 0,
        });
        let line = figure_sentence(&c, &PATH, &c.path.expect("set"));
        assert_eq!(
            line,
            "cooperative drove as far as rover-only (median over 1 seed both reached B; worst seed 3.0 % less)"
        );
        assert_eq!(change_words(-2.0, "shorter", "longer"), "2.0 % longer");
        assert_eq!(change_words(0.0, "fewer", "more"), "unchanged");
    }

    #[test]
    fn targets_from_the_file_are_judged_on_the_median() {
        let expect = Expectations {
            path_shorter_by_percent: Some(15.0),
            replans_fewer_by_percent: Some(20.0),
            route_changes_fewer_by_percent: None,
            success_at_least_rover_only: true,
        };
        let lines = verdict_lines(&expect, "t.toml", &base_comparison());
        assert_eq!(
            lines[0],
            "targets of t.toml, cooperative vs rover-only in base:"
        );
        assert_eq!(
            lines[1],
            "  path: median 3.2 % shorter, target at least 15 % shorter: NOT met"
        );
        assert_eq!(
            lines[2],
            "  replans: median 20.0 % fewer, target at least 20 % fewer: met"
        );
        assert!(
            lines[3].ends_with("target at least as many: met"),
            "{}",
            lines[3]
        );
        assert_eq!(lines[4], "  targets met: 2 of 3");
    }

    #[test]
    fn no_target_file_no_verdict_for_variant_comparisons() {
        let mut c = base_comparison();
        c.kind = ComparisonKind::VariantVsBase;
        let expect = Expectations {
            success_at_least_rover_only: true,
            ..Expectations::default()
        };
        assert!(verdict_lines(&expect, "t.toml", &c).is_empty());
    }
}
