//! Two launches at once do not see each other's samples.

mod common;

use common::*;

#[test]
fn two_concurrent_launches_do_not_interfere() {
    let out = out_dir("parallel");
    let runs = [run_id("par-a"), run_id("par-b")];
    let children: Vec<_> = runs
        .iter()
        .map(|run| {
            launch_command(
                &out,
                run,
                &[&probe_config(), "--lockstep", "--frames", "400"],
            )
            .spawn()
            .expect("spawn")
        })
        .collect();
    for (run, child) in runs.iter().zip(children) {
        let output = child.wait_with_output().expect("wait");
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let report = report(&out, run);
        assert_eq!(report["frames_completed"], 400, "{run}");
        assert_eq!(report["frames_degraded"], 0, "{run}");
        assert_eq!(report["leftover_files"], 0, "{run}");
        assert!(
            report["stale_runs_cleaned"]
                .as_array()
                .unwrap()
                .iter()
                .all(|id| !runs.contains(&id.as_str().unwrap_or("").to_owned())),
            "a live launch was cleaned up by the other"
        );
        for name in ["probe_source", "probe_sink"] {
            // A sample from the other launch would be a sequence or pattern error here.
            assert_eq!(
                process(&report, name)["rejected_samples"],
                0,
                "{run} {name}"
            );
            assert_eq!(
                process(&report, name)["frames_completed"],
                400,
                "{run} {name}"
            );
        }
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains("verified 400 probe images, 0 corrupt, 0 missing"),
            "{stderr}"
        );
    }
}

#[test]
fn a_second_launch_with_a_live_run_id_is_refused_and_the_first_goes_on() {
    let out = out_dir("same-id");
    let run = run_id("same-id");
    // Real time, 100 frames at 10 Hz: running for ~10 s, long enough to be found alive.
    let first = launch_command(&out, &run, &[&probe_config(), "--frames", "100"])
        .spawn()
        .expect("spawn");
    let started = out.join(&run).join("config.toml");
    assert!(
        wait_until(std::time::Duration::from_secs(60), || started.exists()),
        "the first launch never started"
    );
    let second_out = out_dir("same-id-second");
    let second = launch(&second_out, &run, &[&probe_config(), "--frames", "20"]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "the second launch ran: {stderr}");
    assert!(
        stderr.contains("is in use by a launch that is still running"),
        "{stderr}"
    );
    assert!(
        !second_out.join(&run).exists(),
        "the refused launch wrote a run folder"
    );
    let output = first.wait_with_output().expect("wait");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(report(&out, &run)["outcome"], "completed");
}
