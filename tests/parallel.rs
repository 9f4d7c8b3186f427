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
