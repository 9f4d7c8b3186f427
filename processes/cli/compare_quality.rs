//! Per set and mode of `hopnav compare`: how often the rover got to B, how often it hit a
//! rock, how its drive compares with the full-knowledge path, and how much ground its map
//! blocked against what the rocks block (median and worst over the seeds, never a mean
//! alone).

use hopnav_config::MissionMode;
use hopnav_eval::MissionEvaluation;

use crate::compare_rows::RunSet;

/// Median and largest of `values` (`None` when empty).
pub fn median_and_worst(values: &mut [f64]) -> Option<(f64, f64)> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    let median = if values.len().is_multiple_of(2) {
        0.5 * (values[middle - 1] + values[middle])
    } else {
        values[middle]
    };
    Some((median, values[values.len() - 1]))
}

/// "median …, worst …" of `values` in `unit`, or "-" when empty.
pub fn spread(values: &mut [f64], unit: &str) -> String {
    median_and_worst(values).map_or("-".to_owned(), |(median, worst)| {
        format!("median {median:.2}{unit}, worst {worst:.2}{unit}")
    })
}

/// The lines for one set, a line per mode that ran.
pub fn quality_lines(set: &RunSet) -> Vec<String> {
    let mut lines = Vec::new();
    for mode in [MissionMode::RoverOnly, MissionMode::Cooperative] {
        let rows: Vec<_> = set
            .rows
            .iter()
            .filter(|row| row.mode == mode.name())
            .collect();
        if rows.is_empty() {
            continue;
        }
        let missions: Vec<_> = rows.iter().filter_map(|row| row.mission.as_ref()).collect();
        let reached = missions.iter().filter(|m| m.goal_reached).count();
        let collisions: u32 = missions.iter().map(|m| m.collisions).sum();
        let evaluations: Vec<_> = missions
            .iter()
            .map(|mission| (mission, MissionEvaluation::of(mission)))
            .collect();
        let mut path_over_best: Vec<f64> = evaluations
            .iter()
            .filter(|(mission, _)| mission.goal_reached)
            .filter_map(|(mission, evaluation)| {
                let best_m = evaluation.full_knowledge_path_m?;
                (best_m > 0.0).then(|| mission.executed_path_m / best_m)
            })
            .collect();
        let mut best_m: Vec<f64> = evaluations
            .iter()
            .filter_map(|(_, evaluation)| evaluation.full_knowledge_path_m)
            .collect();
        let mut ratios: Vec<f64> = evaluations
            .iter()
            .filter_map(|(_, evaluation)| evaluation.blocked_area?.blocked_area_ratio)
            .collect();
        let mut missed: Vec<f64> = evaluations
            .iter()
            .filter_map(|(_, evaluation)| evaluation.blocked_area?.missed_lethal_percent())
            .collect();
        let mut uncertain: Vec<f64> = evaluations
            .iter()
            .filter_map(|(_, evaluation)| evaluation.blocked_area?.uncertain_lethal_percent())
            .collect();
        lines.push(format!(
            "{} {}: reached B {reached}/{}, {collisions} collisions ({:.2} per mission); executed / full-knowledge path {} over the seeds it reached; full-knowledge path {}; blocked-area ratio (map / rocks) {}; truly lethal cells left traversable {}, held uncertain {}",
            set.label,
            mode.name(),
            rows.len(),
            f64::from(collisions) / missions.len().max(1) as f64,
            spread(&mut path_over_best, "×"),
            spread(&mut best_m, " m"),
            spread(&mut ratios, ""),
            spread(&mut missed, " %"),
            spread(&mut uncertain, " %"),
        ));
        let contacts: Vec<_> = evaluations
            .iter()
            .flat_map(|(_, evaluation)| &evaluation.contacts)
            .collect();
        lines.extend(motion_line(&set.label, mode.name(), &missions));
        if !contacts.is_empty() {
            lines.push(format!(
                "{} {}: {}",
                set.label,
                mode.name(),
                hopnav_eval::mission::contacts_line(contacts.iter().copied())
            ));
        }
        if mode == MissionMode::RoverOnly {
            lines.extend(headroom_line(&set.label, &mut path_over_best));
        } else {
            let jumper: Vec<_> = evaluations
                .iter()
                .flat_map(|(_, evaluation)| evaluation.vo.iter().filter(|vo| vo.robot == "jumper"))
                .collect();
            lines.extend(jumper_line(&set.label, &jumper));
        }
    }
    lines
}

/// How the rover's time split over the missions of one mode: each motion's share of each
/// mission's time, median and worst (largest) over the missions.
fn motion_line(
    label: &str,
    mode: &str,
    missions: &[&hopnav_supervisor::mission_report::MissionReport],
) -> Option<String> {
    let times: Vec<_> = missions
        .iter()
        .filter_map(|mission| mission.rover_motion_times)
        .filter(|times| times.total_s() > 0.0)
        .collect();
    if times.is_empty() {
        return None;
    }
    let share = |part: fn(&hopnav_supervisor::rover_motion::MotionTimes) -> f64| {
        let mut shares: Vec<f64> = times
            .iter()
            .map(|times| 100.0 * part(times) / times.total_s())
            .collect();
        median_and_worst(&mut shares).map_or("-".to_owned(), |(median, worst)| {
            format!("{median:.0} % (up to {worst:.0} %)")
        })
    };
    Some(format!(
        "{label} {mode}: rover's time, median share of a mission: driving {}, reversing {}, turning on the spot {}, standing still {}",
        share(|times| times.driving_s),
        share(|times| times.reversing_s),
        share(|times| times.turning_s),
        share(|times| times.still_s),
    ))
}

/// How far the jumper's VO strayed over the cooperative missions: its unaligned RMSE per
/// mission and its error at each rest after a hop.
fn jumper_line(label: &str, jumper: &[&hopnav_eval::vo_accuracy::VoAccuracy]) -> Option<String> {
    if jumper.is_empty() {
        return None;
    }
    let mut rmse: Vec<f64> = jumper.iter().map(|vo| vo.unaligned_rmse_m).collect();
    let mut rests: Vec<f64> = jumper
        .iter()
        .flat_map(|vo| vo.rest_errors_m.iter().copied())
        .collect();
    let rest_count = rests.len();
    Some(format!(
        "{label} jumper VO: unaligned RMSE per mission {}; error at rest after a hop {} over {rest_count} hops",
        spread(&mut rmse, " m"),
        spread(&mut rests, " m"),
    ))
}

/// What a scout could win on this terrain at most: how much longer the rover-only drive was
/// than the full-knowledge path (`executed / full-knowledge − 1`), over the seeds rover-only
/// reached B. The scouting suite keeps a terrain whose median is at least 25 %.
fn headroom_line(label: &str, path_over_best: &mut [f64]) -> Option<String> {
    let (median, largest) = median_and_worst(path_over_best)?;
    let smallest = path_over_best.iter().copied().fold(f64::INFINITY, f64::min);
    let percent = |ratio: f64| 100.0 * (ratio - 1.0);
    Some(format!(
        "{label} full-knowledge headroom (rover-only executed / full-knowledge path - 1, over the {} seeds rover-only reached B): median {:.1} %, smallest {:.1} %, largest {:.1} %",
        path_over_best.len(),
        percent(median),
        percent(smallest),
        percent(largest),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_headroom_is_the_rover_only_detour_over_the_full_knowledge_path() {
        let line = headroom_line("base", &mut [1.5, 1.1, 1.3]).expect("a line");
        assert!(line.contains("over the 3 seeds"), "{line}");
        assert!(
            line.contains("median 30.0 %, smallest 10.0 %, largest 50.0 %"),
            "{line}"
        );
        assert_eq!(headroom_line("base", &mut []), None);
    }

    #[test]
    fn the_median_of_an_even_count_is_the_mean_of_the_middle_two() {
        assert_eq!(
            median_and_worst(&mut [3.0, 1.0, 2.0, 10.0]),
            Some((2.5, 10.0))
        );
        assert_eq!(median_and_worst(&mut [2.0]), Some((2.0, 2.0)));
        assert_eq!(median_and_worst(&mut []), None);
        assert_eq!(spread(&mut [], " m"), "-");
    }
}
