//! `hopnav bench realtime`: bad options are clear errors; a short run reports the unloaded
//! and the loaded launch side by side (behaviour only: no timing is asserted).

mod common;

use common::{hopnav, stdout_of_success};

#[test]
fn a_duration_out_of_range_is_exit_2_naming_the_option() {
    for duration in ["0", "-3", "nan"] {
        let output = hopnav()
            .args(["bench", "realtime", &format!("--duration={duration}")])
            .output()
            .expect("run");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{duration}: {stderr}");
        assert!(stderr.contains("--duration"), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    let output = hopnav()
        .args(["bench", "realtime", "--hog", "0"])
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn a_short_run_reports_the_unloaded_and_the_loaded_launch() {
    let dir = std::env::temp_dir().join(format!("hopnav-bench-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let stdout = stdout_of_success(
        hopnav()
            .current_dir(&dir)
            .args([
                "bench",
                "realtime",
                "--duration",
                "2",
                "--hog",
                "1",
                "--out",
            ])
            .arg(&dir),
        "hopnav bench realtime",
    );
    assert!(
        stdout.contains("e2e p99 ms") && stdout.contains("loaded / unloaded"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(dir.join("bench_realtime.json")).expect("json written");
    let runs: serde_json::Value = serde_json::from_str(&text).expect("valid json");
    let runs = runs.as_array().expect("one entry per launch");
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[0]["hogs"], 0);
    assert_eq!(runs[1]["hogs"], 1);
    assert!(
        runs[1]["hog_rounds"]
            .as_u64()
            .is_some_and(|rounds| rounds > 0)
    );
    for run in runs {
        assert!(
            run["frames_completed"]
                .as_u64()
                .is_some_and(|frames| frames > 0)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
