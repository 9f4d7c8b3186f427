//! The world simulation as launched by default: physics and camera (and the recorder) in
//! lockstep, exported as a dataset, bitwise reproducible.

mod common;

use std::path::Path;

use common::*;

fn files_in(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map(|entries| entries.flatten().map(|entry| entry.path()).collect())
        .unwrap_or_default();
    files.sort();
    files
}

fn export(out: &Path, name: &str, frames: &str) -> std::path::PathBuf {
    let run = run_id(name);
    let dataset = out.join(format!("{name}-dataset"));
    let output = launch_command(out, &run, &["--lockstep", "--frames", frames])
        .arg("--export-dataset")
        .arg(&dataset)
        .output()
        .expect("run hopnav");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let report = report(out, &run);
    assert_eq!(report["outcome"], "completed");
    for name in ["physics", "camera", "jumper_vo", "recorder"] {
        let process = process(&report, name);
        assert_eq!(process["rejected_samples"], 0, "{name}");
        assert_eq!(process["restarts"], 0, "{name}");
    }
    assert_no_leftover_files(&run);
    dataset
}

#[test]
fn lockstep_world_run_exports_a_complete_reproducible_dataset() {
    let out = out_dir("world");
    let first = export(&out, "world-a", "25");
    assert_camera_streams(&first);
    assert_truth_and_sensors(&first);
    assert_vo_starts_at_the_launch(&first);
    // The same config in lockstep gives bitwise-identical images, truth and sensors.
    let second = export(&out, "world-b", "25");
    for relative in [
        "jumper_cam/000000.pgm",
        "jumper_cam/000024.pgm",
        "rover_left/000012.pgm",
        "rover_right/000024.pgm",
        "groundtruth_jumper.tum",
        "groundtruth_rover.tum",
        "altimeter.csv",
        "imu.csv",
        "estimate_jumper_vo.tum",
    ] {
        let a = std::fs::read(first.join(relative)).expect("first");
        let b = std::fs::read(second.join(relative)).expect("second");
        assert!(a == b, "{relative} differs between two lockstep runs");
    }
}

/// Every camera stream of a 25-frame dataset has one PGM per frame and an index naming them.
fn assert_camera_streams(dataset: &Path) {
    for stream in ["jumper_cam", "rover_left", "rover_right"] {
        let pgms: Vec<_> = files_in(&dataset.join(stream))
            .into_iter()
            .filter(|path| path.extension().is_some_and(|ext| ext == "pgm"))
            .collect();
        assert_eq!(pgms.len(), 25, "{stream}");
        let index = std::fs::read_to_string(dataset.join(stream).join("index.csv")).expect("index");
        assert_eq!(index.lines().next(), Some("frame,t_s,file"));
        assert_eq!(index.lines().count(), 26, "{stream}");
        // Frame k shows the state at the end of its physics step: t = (k + 1) · 0.1 s.
        assert!(index.contains("24,2.500,000024.pgm"), "{stream}: {index}");
        let header = std::fs::read(&pgms[0]).expect("pgm");
        let expected: &[u8] = if stream == "jumper_cam" {
            b"P5\n320 320\n255\n"
        } else {
            b"P5\n320 240\n255\n"
        };
        assert!(header.starts_with(expected), "{stream}");
    }
}

/// Ground truth, sensor CSVs and camera intrinsics of a 25-frame dataset.
fn assert_truth_and_sensors(dataset: &Path) {
    // Ground truth in TUM: the Table 1 hop climbs ~0.8 m in the first frame.
    let truth = tum_positions(&dataset.join("groundtruth_jumper.tum"));
    assert_eq!(truth.len(), 25);
    assert!(
        truth[10].1[2] > truth[0].1[2] + 3.0,
        "the jumper is climbing"
    );
    // Sensor CSVs and intrinsics derived from the FOV (f = 160 / tan 22.5° = 386.27 px).
    let altimeter = std::fs::read_to_string(dataset.join("altimeter.csv")).expect("altimeter");
    assert_eq!(altimeter.lines().count(), 26);
    let imu = std::fs::read_to_string(dataset.join("imu.csv")).expect("imu");
    assert_eq!(imu.lines().count(), 26);
    let cameras: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dataset.join("cameras.json")).expect("cameras"),
    )
    .expect("json");
    assert!((cameras["jumper"]["fx_px"].as_f64().unwrap() - 386.274).abs() < 0.01);
    assert!((cameras["rover_stereo"]["baseline_m"].as_f64().unwrap() - 0.2).abs() < 1e-12);
}

/// The jumper VO published a pose for every frame after the launch, close to the truth at
/// the start (it starts from the commanded launch, not from ground truth).
fn assert_vo_starts_at_the_launch(dataset: &Path) {
    let truth = tum_positions(&dataset.join("groundtruth_jumper.tum"));
    let estimates = tum_positions(&dataset.join("estimate_jumper_vo.tum"));
    assert_eq!(estimates.len(), 25, "{estimates:?}");
    let start_error: f64 = estimates[0]
        .1
        .iter()
        .zip(truth[0].1)
        .map(|(e, t)| (e - t).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        start_error < 0.05,
        "VO starts at the commanded launch: {start_error} m off"
    );
}
