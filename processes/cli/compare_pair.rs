//! Pairing of `hopnav compare` runs by seed: cooperative against rover-only within one set of
//! runs, and a variant against the base mode by mode. A set is what one `compare` wrote to
//! `compare.json` (or is writing now); `hopnav compare --pair DIR...` reads finished ones.
//!
//! Figures are per-seed ratios over the seeds both sides reached B (median and worst, so one
//! seed cannot hide in a mean), with success counted over the seeds both sides ran.

use hopnav_config::MissionMode;
use hopnav_eval::MissionEvaluation;
use hopnav_supervisor::mission_report::MissionReport;

use crate::compare_quality::median_and_worst;
use crate::compare_rows::{CompareRow, RunSet};

/// Which question a comparison answers (targets judge only the first).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComparisonKind {
    /// Cooperative against rover-only, within one set.
    CooperativeVsRoverOnly,
    /// A variant against the base, one mode.
    VariantVsBase,
}

/// Per-seed ratios subject / reference of one figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioSpread {
    pub median: f64,
    /// The largest ratio: the seed where the subject did worst (every figure here is better
    /// smaller).
    pub worst: f64,
    pub seeds: usize,
    /// Seeds left out because the reference counted zero and the subject did not.
    pub left_out: usize,
}

/// One side against the other, paired by seed.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    pub kind: ComparisonKind,
    pub heading: String,
    pub subject: String,
    pub reference: String,
    /// Seeds both sides have a row for.
    pub seeds_both_ran: usize,
    pub subject_reached: usize,
    pub reference_reached: usize,
    /// Seeds only one side has a row for: (seeds without a subject run, without a reference).
    pub missing: (Vec<u64>, Vec<u64>),
    /// Seeds whose launch failed before the mission reported: (subject, reference).
    pub failed: (Vec<u64>, Vec<u64>),
    /// Seeds both sides reached B: the ratios and means below are over these.
    pub both_reached: usize,
    pub path: Option<RatioSpread>,
    pub replans: Option<RatioSpread>,
    pub route_changes: Option<RatioSpread>,
    /// Mean executed path (subject, reference), metres.
    pub mean_path_m: Option<(f64, f64)>,
    /// Mean full-knowledge path (every rock known from the start), metres.
    pub mean_full_knowledge_m: Option<f64>,
    /// Mean built-map path (the final map known from the start) (subject, reference), metres.
    pub mean_built_map_m: Option<(f64, f64)>,
}

fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// Median and maximum of per-seed ratios `subject / reference`; both zero counts as 1.
fn spread(pairs: &[(f64, f64)]) -> Option<RatioSpread> {
    let mut ratios: Vec<f64> = pairs
        .iter()
        .filter_map(|&(subject, reference)| match (subject, reference) {
            (s, r) if r > 0.0 => Some(s / r),
            (s, _) if s <= 0.0 => Some(1.0),
            _ => None,
        })
        .collect();
    let (median, worst) = median_and_worst(&mut ratios)?;
    Some(RatioSpread {
        median,
        worst,
        seeds: ratios.len(),
        left_out: pairs.len() - ratios.len(),
    })
}

fn find<'a>(rows: &[&'a CompareRow], seed: u64) -> Option<&'a CompareRow> {
    rows.iter().find(|row| row.seed == seed).copied()
}

/// The mission of a row that reached B.
fn reached(row: &CompareRow) -> Option<&MissionReport> {
    row.mission.as_ref().filter(|mission| mission.goal_reached)
}

/// Pairs `subject` with `reference` by seed.
pub fn compare(
    kind: ComparisonKind,
    heading: String,
    (subject_name, subject): (&str, &[&CompareRow]),
    (reference_name, reference): (&str, &[&CompareRow]),
) -> Comparison {
    let mut seeds: Vec<u64> = subject.iter().chain(reference).map(|r| r.seed).collect();
    seeds.sort_unstable();
    seeds.dedup();
    let mut result = Comparison {
        kind,
        heading,
        subject: subject_name.to_owned(),
        reference: reference_name.to_owned(),
        seeds_both_ran: 0,
        subject_reached: 0,
        reference_reached: 0,
        missing: (Vec::new(), Vec::new()),
        failed: (Vec::new(), Vec::new()),
        both_reached: 0,
        path: None,
        replans: None,
        route_changes: None,
        mean_path_m: None,
        mean_full_knowledge_m: None,
        mean_built_map_m: None,
    };
    let mut reached_pairs: Vec<(&MissionReport, &MissionReport)> = Vec::new();
    for seed in seeds {
        let (Some(s), Some(r)) = (find(subject, seed), find(reference, seed)) else {
            match find(subject, seed) {
                None => result.missing.0.push(seed),
                Some(_) => result.missing.1.push(seed),
            }
            continue;
        };
        result.seeds_both_ran += 1;
        if s.mission.is_none() {
            result.failed.0.push(seed);
        }
        if r.mission.is_none() {
            result.failed.1.push(seed);
        }
        result.subject_reached += usize::from(reached(s).is_some());
        result.reference_reached += usize::from(reached(r).is_some());
        if let (Some(s), Some(r)) = (reached(s), reached(r)) {
            reached_pairs.push((s, r));
        }
    }
    result.both_reached = reached_pairs.len();
    let pairs_of = |field: fn(&MissionReport) -> f64| -> Vec<(f64, f64)> {
        reached_pairs
            .iter()
            .map(|(s, r)| (field(s), field(r)))
            .collect()
    };
    result.path = spread(&pairs_of(|m| m.executed_path_m));
    result.replans = spread(&pairs_of(|m| m.replans as f64));
    result.route_changes = spread(&pairs_of(|m| m.route_changes as f64));
    let paths = pairs_of(|m| m.executed_path_m);
    let subject_paths: Vec<f64> = paths.iter().map(|p| p.0).collect();
    let reference_paths: Vec<f64> = paths.iter().map(|p| p.1).collect();
    result.mean_path_m = mean(&subject_paths).zip(mean(&reference_paths));
    // The full-knowledge path is the terrain's: either side's evaluation gives it.
    let full_knowledge: Vec<f64> = reached_pairs
        .iter()
        .filter_map(|(s, r)| full_knowledge_m(r).or_else(|| full_knowledge_m(s)))
        .collect();
    result.mean_full_knowledge_m = mean(&full_knowledge);
    let built: Vec<(f64, f64)> = reached_pairs
        .iter()
        .filter_map(|(s, r)| built_map_m(s).zip(built_map_m(r)))
        .collect();
    if built.len() == reached_pairs.len() {
        let (subject_m, reference_m): (Vec<f64>, Vec<f64>) = built.into_iter().unzip();
        result.mean_built_map_m = mean(&subject_m).zip(mean(&reference_m));
    }
    result
}

/// The evaluator's full-knowledge path of a mission, metres.
pub fn full_knowledge_m(mission: &MissionReport) -> Option<f64> {
    MissionEvaluation::of(mission).full_knowledge_path_m
}

/// The evaluator's built-map path of a mission, metres.
pub fn built_map_m(mission: &MissionReport) -> Option<f64> {
    MissionEvaluation::of(mission).built_map_path_m
}

/// Every comparison of a base and its variants: cooperative against rover-only within each
/// set (a variant that ran one mode borrows the base's runs of the other), then each variant
/// against the base, mode by mode.
pub fn comparisons(base: &RunSet, variants: &[RunSet]) -> Vec<Comparison> {
    let (cooperative, rover_only) = (MissionMode::Cooperative, MissionMode::RoverOnly);
    let mut out = Vec::new();
    let mut within = |set: &RunSet, borrowed_from: Option<&RunSet>| {
        let side = |mode: MissionMode| match (set.of_mode(mode), borrowed_from) {
            (rows, Some(base)) if rows.is_empty() => (base.of_mode(mode), true),
            (rows, _) => (rows, false),
        };
        let ((c_rows, c_borrowed), (r_rows, r_borrowed)) = (side(cooperative), side(rover_only));
        let borrowed = match (c_borrowed, r_borrowed, borrowed_from) {
            (true, true, Some(base)) => format!(" (every run from {})", base.label),
            (true, _, Some(base)) => format!(" (its cooperative runs from {})", base.label),
            (_, true, Some(base)) => format!(" (its rover-only runs from {})", base.label),
            _ => String::new(),
        };
        out.push(compare(
            ComparisonKind::CooperativeVsRoverOnly,
            format!("cooperative vs rover-only in {}{borrowed}", set.label),
            (cooperative.name(), &c_rows),
            (rover_only.name(), &r_rows),
        ));
    };
    within(base, None);
    for variant in variants {
        within(variant, Some(base));
    }
    for variant in variants {
        for mode in variant.modes() {
            out.push(compare(
                ComparisonKind::VariantVsBase,
                format!("{} vs {}, {} runs", variant.label, base.label, mode.name()),
                (&variant.label, &variant.of_mode(mode)),
                (&base.label, &base.of_mode(mode)),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare_rows::tests::row;

    fn set(label: &str, rows: Vec<CompareRow>) -> RunSet {
        RunSet {
            label: label.into(),
            rows,
        }
    }

    #[test]
    fn pairs_by_seed_with_missing_and_failed_runs() {
        let base = set(
            "base",
            vec![
                row(1, "cooperative", Some((true, 90.0, 4))),
                row(1, "rover-only", Some((true, 100.0, 8))),
                row(2, "cooperative", Some((true, 120.0, 10))),
                row(2, "rover-only", Some((true, 100.0, 10))),
                row(3, "cooperative", None),
                row(3, "rover-only", Some((true, 100.0, 5))),
                row(4, "cooperative", Some((false, 300.0, 30))),
                row(4, "rover-only", Some((true, 100.0, 5))),
                row(5, "rover-only", Some((true, 100.0, 5))),
            ],
        );
        let all = comparisons(&base, &[]);
        assert_eq!(all.len(), 1);
        let c = &all[0];
        assert_eq!(c.kind, ComparisonKind::CooperativeVsRoverOnly);
        assert_eq!((c.seeds_both_ran, c.both_reached), (4, 2));
        assert_eq!((c.subject_reached, c.reference_reached), (2, 4));
        assert_eq!(c.missing, (vec![5], vec![]));
        assert_eq!(c.failed, (vec![3], vec![]));
        let path = c.path.expect("two seeds both reached");
        assert!((path.median - 1.05).abs() < 1e-12, "{path:?}");
        assert!((path.worst - 1.2).abs() < 1e-12, "{path:?}");
        assert_eq!(c.replans.map(|r| r.worst), Some(1.0));
        assert_eq!(c.mean_path_m, Some((105.0, 100.0)));
    }

    #[test]
    fn a_variant_pairs_by_seed_and_mode_and_borrows_the_other_mode() {
        let base = set(
            "base",
            vec![
                row(1, "cooperative", Some((true, 100.0, 4))),
                row(1, "rover-only", Some((true, 100.0, 8))),
                row(2, "cooperative", Some((true, 100.0, 4))),
                row(2, "rover-only", Some((true, 200.0, 8))),
            ],
        );
        let variant = set(
            "variant",
            vec![
                row(2, "cooperative", Some((true, 50.0, 2))),
                row(1, "cooperative", Some((false, 80.0, 2))),
            ],
        );
        let all = comparisons(&base, std::slice::from_ref(&variant));
        assert_eq!(all.len(), 3);
        assert!(all[1].heading.contains("its rover-only runs from base"));
        assert_eq!(all[1].both_reached, 1);
        assert_eq!(all[1].path.map(|p| p.median), Some(0.25));
        let across = &all[2];
        assert_eq!(across.kind, ComparisonKind::VariantVsBase);
        assert_eq!(across.heading, "variant vs base, cooperative runs");
        assert_eq!((across.subject_reached, across.reference_reached), (1, 2));
        assert_eq!(across.path.map(|p| p.median), Some(0.5));
    }

    #[test]
    fn zero_replans_on_both_sides_count_as_equal_and_from_zero_are_left_out() {
        let spread = spread(&[(0.0, 0.0), (3.0, 0.0), (2.0, 4.0)]).expect("two ratios");
        assert_eq!((spread.seeds, spread.left_out), (2, 1));
        assert_eq!((spread.median, spread.worst), (0.75, 1.0));
        assert_eq!(super::spread(&[(1.0, 0.0)]), None);
    }
}
