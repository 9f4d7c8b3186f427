//! Killing the supervisor leaves no child alive and the next launch starts clean; a polite
//! SIGTERM stops the launch with a report.

mod common;

use std::path::Path;
use std::process::Child;
use std::time::Duration;

use common::*;

/// A real-time launch of the probe graph, far longer than the test, `settle` after both its
/// children serve.
fn running_probe_graph(out: &Path, run: &str, settle: Duration) -> Child {
    let supervisor = spawn_launch(out, run, &[&probe_config(), "--frames", "100000"]);
    assert!(
        wait_until(Duration::from_secs(20), || {
            serving_pids_with_args(&["run", run]).len() == 2
        }),
        "children never started"
    );
    // Let the graph run a while before it is disturbed.
    std::thread::sleep(settle);
    supervisor
}

/// The live children of run `run`.
fn children(run: &str) -> Vec<i32> {
    pids_with_args(&["run", run])
}

#[test]
fn sigkill_of_the_supervisor_leaves_no_orphans_and_the_next_launch_cleans_up() {
    let (out, run) = out_and_run("sigkill");
    let mut supervisor = running_probe_graph(&out, &run, Duration::from_millis(300));
    assert!(
        !leftover_files(&run).is_empty(),
        "the run uses shared memory"
    );
    supervisor.kill().expect("SIGKILL supervisor");
    let _ = supervisor.wait();
    assert!(
        wait_until(Duration::from_secs(5), || children(&run).is_empty()),
        "orphans left: {:?}",
        children(&run)
    );

    let next = run_id("after-sigkill");
    let output = launch(
        &out,
        &next,
        &[&probe_config(), "--lockstep", "--frames", "5"],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("cleaned up"), "{stderr}");
    let report = report(&out, &next);
    assert!(
        report["stale_runs_cleaned"]
            .as_array()
            .unwrap()
            .iter()
            .any(|id| id == &serde_json::Value::String(run.clone())),
        "{report:#}"
    );
    assert_no_leftover_files(&run);
}

#[test]
fn sigterm_stops_the_launch_cleanly_with_a_report() {
    let (out, run) = out_and_run("sigterm");
    let mut supervisor = running_probe_graph(&out, &run, Duration::from_millis(500));
    signal(supervisor.id() as i32, libc::SIGTERM);
    let status = wait_with_limit(&mut supervisor, Duration::from_secs(30)).expect("stopped");
    assert_eq!(status.code(), Some(130));
    let report = report(&out, &run);
    assert_eq!(report["outcome"], "interrupted");
    assert!(report["frames_completed"].as_u64().unwrap() >= 1);
    assert!(children(&run).is_empty());
    assert_no_leftover_files(&run);
}
