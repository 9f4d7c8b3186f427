//! `hopnav plan` on a MovingAI fixture: costs match the published optimum; bad maps are
//! clear errors.

mod common;

use common::hopnav;

fn fixture(name: &str) -> String {
    format!(
        "{}/processes/planner/tests/fixtures/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// `hopnav plan` on the tiny fixture and its scenarios, with `extra` options; its output,
/// after it succeeded.
fn plan_tiny(extra: &[&str]) -> String {
    let output = hopnav()
        .args([
            "plan",
            "--map",
            &fixture("tiny.map"),
            "--scen",
            &fixture("tiny.map.scen"),
        ])
        .args(extra)
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(output.status.success(), "{stdout}");
    stdout
}

#[test]
fn static_scenarios_match_their_optimum() {
    let stdout = plan_tiny(&[]);
    assert!(stdout.contains("6 scenarios, 0 mismatches"), "{stdout}");
}

#[test]
fn dynamic_mode_compares_dstar_lite_with_repeated_astar() {
    let stdout = plan_tiny(&["--dynamic", "3"]);
    assert!(
        stdout.contains("D* Lite ") && stdout.contains("A* (every change)"),
        "{stdout}"
    );
    assert!(
        stdout.contains("6/6"),
        "every traverse reaches its goal: {stdout}"
    );
}

#[test]
fn malformed_map_is_exit_2_with_the_line() {
    let dir = std::env::temp_dir().join(format!("hopnav-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let map = dir.join("bad.map");
    std::fs::write(&map, "type octile\nheight 2\nwidth 3\nmap\n..\n...\n").expect("write");
    let output = hopnav()
        .args(["plan", "--map"])
        .arg(&map)
        .args(["--scen", &fixture("tiny.map.scen")])
        .output()
        .expect("run");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("line 5"), "{stderr}");
    assert!(!stderr.contains("panicked"));
    std::fs::remove_dir_all(&dir).ok();
}
