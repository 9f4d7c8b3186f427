//! Every invalid config fixture exits with code 2 and names its key; valid ones run.
//! An invalid fixture's first line is `# expect: <text the error must contain>`.

mod common;

use std::path::PathBuf;

use common::*;

fn fixtures(kind: &str) -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/config")
        .join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("fixture dir")
        .flatten()
        .map(|entry| entry.path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no fixtures in {}", dir.display());
    files
}

#[test]
fn invalid_configs_exit_2_and_name_the_key() {
    let out = out_dir("bad-config");
    for file in fixtures("invalid") {
        let text = std::fs::read_to_string(&file).expect("read fixture");
        let expected = text
            .lines()
            .next()
            .and_then(|line| line.strip_prefix("# expect: "))
            .unwrap_or_else(|| panic!("{} lacks an '# expect:' line", file.display()));
        let output = hopnav()
            .arg("launch")
            .arg(&file)
            .args(["--frames", "1", "--quiet", "--out"])
            .arg(&out)
            .output()
            .expect("run");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{}: {stderr}",
            file.display()
        );
        assert!(
            stderr.contains(expected),
            "{}: expected {expected:?} in {stderr}",
            file.display()
        );
        assert!(!stderr.contains("panicked"), "{}: {stderr}", file.display());
    }
}

#[test]
fn valid_configs_run() {
    let out = out_dir("good-config");
    for (index, file) in fixtures("valid").into_iter().enumerate() {
        let run = run_id(&format!("good{index}"));
        let mut command = launch_command(&out, &run, &["--lockstep", "--frames", "3"]);
        stdout_of_success(command.arg(&file), &file.display().to_string());
    }
}

#[test]
fn missing_config_file_is_a_clear_error() {
    let output = hopnav()
        .args(["launch", "/nonexistent/hopnav.toml", "--frames", "1"])
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("/nonexistent/hopnav.toml"));
}

#[test]
fn shipped_scenarios_pass_launch_validation() {
    let out = out_dir("scenarios");
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("config/scenarios");
    for name in ["default", "rocky", "fig6"] {
        let run = run_id(&format!("scenario-{name}"));
        let mut command = launch_command(&out, &run, &["--lockstep", "--frames", "2"]);
        stdout_of_success(command.arg(dir.join(format!("{name}.toml"))), name);
    }
}
