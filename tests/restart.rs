//! A child hit by kill -9 is restarted and the launch still completes.

mod common;

use std::path::Path;
use std::process::Child;
use std::time::Duration;

use common::*;

/// A lockstep launch of `frames` frames of `config`, running in the background.
fn spawn_lockstep(out: &Path, run: &str, config: &str, frames: &str) -> Child {
    spawn_launch(out, run, &[config, "--lockstep", "--frames", frames])
}

/// The probe graph with one restart allowed and a short watchdog.
fn strict_supervision() -> String {
    fixture_config("valid/strict_supervision.toml")
}

/// The pids of `run`'s probe sinks that serve (a prepared standby does not).
fn serving_sinks(run: &str) -> Vec<i32> {
    serving_pids_with_args(&["run", "probe_sink", run])
}

/// Waits until `run` has exactly one serving probe sink, lets it work for `settle`, and
/// returns its pid.
fn the_serving_sink(run: &str, settle: Duration) -> i32 {
    assert!(
        wait_until(Duration::from_secs(20), || serving_sinks(run).len() == 1),
        "the sink never started"
    );
    std::thread::sleep(settle);
    let sinks = serving_sinks(run);
    assert_eq!(sinks.len(), 1);
    sinks[0]
}

#[test]
fn killed_child_is_restarted_and_the_launch_completes() {
    let (out, run) = out_and_run("restart");
    // Lockstep, long enough that the kill lands mid-run even on a fast machine.
    let mut child = spawn_lockstep(&out, &run, &probe_config(), "3000");
    let victim = the_serving_sink(&run, Duration::from_millis(300));
    signal(victim, libc::SIGKILL);

    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "report: {report:#}");
    assert_eq!(report["outcome"], "completed");
    assert_eq!(
        report["frames_completed"], 3000,
        "lockstep waits for the restarted sink"
    );
    let sink_report = process(&report, "probe_sink");
    assert_eq!(sink_report["restarts"], 1);
    let exit = &sink_report["exits"][0];
    assert_eq!(exit["reason"], "killed by signal 9");
    assert!(exit["recovered_after_s"].as_f64().is_some(), "{exit}");
    // Lockstep starts once the standbys have prepared: the restart is a promotion.
    assert_eq!(exit["restart"], "standby", "{exit}");
    assert!(exit["startup_s"].as_f64().is_some(), "{exit}");
    assert_nothing_left(&report, &run);
}

#[test]
fn crash_loop_exceeding_restart_intensity_stops_the_launch_without_orphans() {
    let (out, run) = out_and_run("crash-loop");
    let mut child = spawn_lockstep(&out, &run, &strict_supervision(), "100000");
    for _ in 0..2 {
        let victim = the_serving_sink(&run, Duration::from_millis(200));
        signal(victim, libc::SIGKILL);
        assert!(wait_until(Duration::from_secs(10), || {
            !serving_sinks(&run).contains(&victim)
        }));
    }
    let status = wait_with_limit(&mut child, Duration::from_secs(60)).expect("launch stopped");
    assert_eq!(status.code(), Some(1));
    let report = report(&out, &run);
    let outcome = report["outcome"].as_str().unwrap();
    assert!(
        outcome.starts_with("stopped: probe_sink killed by signal 9"),
        "{outcome}"
    );
    assert!(outcome.contains("restart.max_restarts = 1"), "{outcome}");
    assert_nothing_left(&report, &run);
}

#[test]
fn a_hung_child_is_detected_by_the_watchdog_killed_and_restarted() {
    let (out, run) = out_and_run("hang");
    let mut child = spawn_lockstep(&out, &run, &strict_supervision(), "3000");
    let frozen = the_serving_sink(&run, Duration::from_millis(200));
    signal(frozen, libc::SIGSTOP); // alive but silent: a hang
    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "{report:#}");
    assert_eq!(report["frames_completed"], 3000);
    let sink_report = process(&report, "probe_sink");
    assert_eq!(sink_report["hangs_detected"], 1);
    assert_eq!(sink_report["restarts"], 1);
    let reason = sink_report["exits"][0]["reason"].as_str().unwrap();
    assert!(
        reason.starts_with("hung (stopped, no heartbeat for"),
        "{reason}"
    );
    assert!(pids_with_args(&[&run]).is_empty());
}

#[test]
fn a_dead_standby_leaves_cold_restarts_and_the_launch_completes() {
    let (out, run) = out_and_run("dead-standby");
    let mut child = spawn_lockstep(&out, &run, &probe_config(), "3000");
    let all_sinks = || pids_with_args(&["run", "probe_sink", &run]);
    let serving = || serving_sinks(&run);
    assert!(
        wait_until(Duration::from_secs(20), || all_sinks().len() == 2),
        "sink and its standby never started"
    );
    let standby: Vec<i32> = all_sinks()
        .into_iter()
        .filter(|pid| !serving().contains(pid))
        .collect();
    assert_eq!(standby.len(), 1);
    signal(standby[0], libc::SIGKILL);
    assert!(wait_until(Duration::from_secs(10), || all_sinks().len() == 1));
    let victims = serving();
    assert_eq!(victims.len(), 1);
    signal(victims[0], libc::SIGKILL);

    let status = wait_with_limit(&mut child, Duration::from_secs(300)).expect("launch finished");
    let report = report(&out, &run);
    assert!(status.success(), "report: {report:#}");
    assert_eq!(report["frames_completed"], 3000);
    let exit = &process(&report, "probe_sink")["exits"][0];
    assert_eq!(exit["restart"], "cold", "{exit}");
    assert_nothing_left(&report, &run);
}
