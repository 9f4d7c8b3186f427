//! The chaos run's tables: per run (faults, detection, recovery, files, panics, mission) and
//! the missions against the unfaulted one.

use std::io::Write;

use hopnav_eval::faulted_mission::{FaultedMission, MissionOutcome, Verdict};
use hopnav_supervisor::fault_injector::FaultRecord;

use super::ChaosRun;
use crate::compare_quality::median_and_worst;

pub(super) fn print_reference(reference: Option<&MissionOutcome>, frames: u64) {
    match reference {
        Some(mission) if mission.goal_reached => eprintln!(
            "[unfaulted] B reached in {} frames, {:.1} m driven; faults are drawn inside those frames",
            mission.frames, mission.executed_path_m
        ),
        Some(mission) => eprintln!(
            "[unfaulted] B not reached in {frames} frames ({:.1} m driven): missions are not judged; give --frames enough for the mission",
            mission.executed_path_m
        ),
        None => eprintln!("[unfaulted] this graph runs no mission: missions are not judged"),
    }
}

/// The mission column of a run: the verdict against the unfaulted mission.
fn mission_cell(run: &ChaosRun) -> String {
    let Some(judged) = run.vs_unfaulted else {
        return run.mission.clone().unwrap_or_else(|| "-".into());
    };
    let percent = |excess: Option<f64>| excess.map_or("?".into(), |e| format!("{:+.1} %", e * 1e2));
    match judged.verdict {
        Verdict::Reached => format!(
            "B in {} f, path {}",
            judged.outcome.frames,
            percent(judged.path_excess)
        ),
        Verdict::ReachedLate => format!(
            "B late: {} f > {} allowed, path {}",
            judged.outcome.frames,
            judged.allowed_frames.unwrap_or(0),
            percent(judged.path_excess)
        ),
        Verdict::Lost => format!(
            "lost: {}",
            run.mission.as_deref().unwrap_or("B not reached")
        ),
        Verdict::NoReference => run.mission.clone().unwrap_or_else(|| "-".into()),
    }
}

/// The missions against the unfaulted one: reached, late, lost; path and time excess.
pub(super) fn print_missions(runs: &[ChaosRun], reference: Option<&MissionOutcome>) {
    let Some(reference) = reference.filter(|mission| mission.goal_reached) else {
        return;
    };
    let judged: Vec<&FaultedMission> = runs
        .iter()
        .filter_map(|run| run.vs_unfaulted.as_ref())
        .collect();
    let count = |verdict: Verdict| judged.iter().filter(|j| j.verdict == verdict).count();
    let mut paths: Vec<f64> = judged.iter().filter_map(|j| j.path_excess).collect();
    let mut times: Vec<f64> = judged.iter().filter_map(|j| j.time_excess).collect();
    let spread = |values: &mut [f64]| {
        median_and_worst(values).map_or("-".to_owned(), |(median, worst)| {
            format!("median {:+.1} %, worst {:+.1} %", median * 1e2, worst * 1e2)
        })
    };
    println!(
        "missions against the unfaulted one (B in {} frames, {:.1} m): B reached in time {}/{}, late {}, lost {}; path {}; frames to B {}",
        reference.frames,
        reference.executed_path_m,
        count(Verdict::Reached),
        judged.len(),
        count(Verdict::ReachedLate),
        count(Verdict::Lost),
        spread(&mut paths),
        spread(&mut times),
    );
}

/// A duration in seconds as a whole number of milliseconds, `-` when there is none.
fn ms_cell(value: Option<&f64>) -> String {
    value.map_or("-".to_owned(), |s| format!("{:.0} ms", s * 1e3))
}

/// How many hangs were detected, and kills recovered from, within two frame periods.
#[derive(Debug, Default)]
struct FastResponses {
    hangs: usize,
    hangs_fast: usize,
    kills: usize,
    kills_fast: usize,
}

impl FastResponses {
    /// Counts one fault that fired.
    fn count(&mut self, fault: &FaultRecord, frame_period_s: f64) {
        // A freeze longer than two frame periods is a hang the watchdog must catch.
        let freeze_ms = fault
            .fault
            .parse::<hopnav_config::fault::FaultSpec>()
            .ok()
            .and_then(|spec| match spec.kind {
                hopnav_config::fault::FaultKind::Stall { duration_ms } => Some(duration_ms),
                _ => None,
            });
        if freeze_ms.is_some_and(|ms| ms as f64 > 2e3 * frame_period_s) {
            self.hangs += 1;
            if fault
                .detected_after_s
                .is_some_and(|s| s <= 2.0 * frame_period_s)
            {
                self.hangs_fast += 1;
            }
        }
        if fault.fault.starts_with("kill:") {
            self.kills += 1;
            if fault
                .recovered_after_s
                .is_some_and(|s| s <= 2.0 * frame_period_s)
            {
                self.kills_fast += 1;
            }
        }
    }
}

/// What the table's closing lines sum over all runs.
#[derive(Default)]
struct Totals {
    recoveries: Vec<f64>,
    detections: Vec<f64>,
    injected: usize,
    recovered: usize,
    fast: FastResponses,
}

pub(super) fn print_table(runs: &[ChaosRun], frame_period_s: f64) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "\n{:>4} {:>8} {:>8} {:>9} {:>13} {:>13} {:>12} {:>7} {:<36} outcome",
        "run",
        "injected",
        "detected",
        "recovered",
        "recover p50",
        "recover max",
        "files b/a",
        "panics",
        "mission"
    );
    let mut totals = Totals::default();
    for run in runs {
        print_run_row(&mut out, run, frame_period_s, &mut totals);
    }
    print_totals(&mut out, runs, totals);
}

/// One run's row; adds its faults to `totals`.
fn print_run_row(out: &mut impl Write, run: &ChaosRun, frame_period_s: f64, totals: &mut Totals) {
    let fired: Vec<&FaultRecord> = run
        .faults
        .iter()
        .filter(|fault| fault.injected_frame.is_some())
        .collect();
    let detected = fired
        .iter()
        .filter(|fault| fault.detected_after_s.is_some())
        .count();
    let mut recoveries: Vec<f64> = fired
        .iter()
        .filter_map(|fault| fault.recovered_after_s)
        .collect();
    recoveries.sort_by(f64::total_cmp);
    totals
        .detections
        .extend(fired.iter().filter_map(|fault| fault.detected_after_s));
    for fault in &fired {
        totals.fast.count(fault, frame_period_s);
    }
    totals.injected += run.faults.len();
    totals.recovered += recoveries.len();
    totals.recoveries.extend(recoveries.iter().copied());
    let _ = writeln!(
        out,
        "{:>4} {:>8} {:>8} {:>9} {:>13} {:>13} {:>12} {:>7} {:<36} {}",
        run.run,
        run.faults.len(),
        detected,
        format!("{}/{}", recoveries.len(), fired.len()),
        ms_cell(recoveries.get(recoveries.len() / 2)),
        ms_cell(recoveries.last()),
        format!("{}/{}", run.hopnav_files_before, run.hopnav_files_after),
        run.panics,
        mission_cell(run),
        run.outcome
    );
}

/// The closing lines: faults, recoveries and detections over all runs.
fn print_totals(out: &mut impl Write, runs: &[ChaosRun], mut totals: Totals) {
    totals.recoveries.sort_by(f64::total_cmp);
    let leaked: usize = runs.iter().map(|run| run.leftover_files).sum();
    let _ = writeln!(
        out,
        "\n{} faults injected ({} fired with a time), {} recovered; recovery p50 {}, max {}; kills recovered within 2 frame periods: {}/{}; leaked files {leaked}; panics {}",
        totals.injected,
        runs.iter()
            .flat_map(|run| &run.faults)
            .filter(|fault| fault.injected_frame.is_some())
            .count(),
        totals.recovered,
        ms_cell(totals.recoveries.get(totals.recoveries.len() / 2)),
        ms_cell(totals.recoveries.last()),
        totals.fast.kills_fast,
        totals.fast.kills,
        runs.iter().map(|run| run.panics).sum::<usize>()
    );
    totals.detections.sort_by(f64::total_cmp);
    let _ = writeln!(
        out,
        "detection p50 {}, max {}; hangs detected within 2 frame periods: {}/{}",
        ms_cell(totals.detections.get(totals.detections.len() / 2)),
        ms_cell(totals.detections.last()),
        totals.fast.hangs_fast,
        totals.fast.hangs,
    );
}
