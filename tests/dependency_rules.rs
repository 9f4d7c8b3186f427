//! The layering of docs/ARCHITECTURE.md, checked from `cargo metadata` so it stays true:
//! the runtime imports no algorithm, no process crate imports another, and evaluation sits
//! outside the process graph.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The layer a workspace crate belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layer {
    /// Messages, config, the supervisor: launches and measures, knows no algorithm.
    Runtime,
    /// Libraries several processes share (terrain, vision geometry, metrics and plots).
    SharedLibrary,
    /// One crate per process: algorithms in plain modules, wired to topics in `process.rs`.
    Process,
    /// Compares runs with the truth.
    Evaluation,
    /// The `hopnav` binary.
    Cli,
}

fn layer_of(name: &str) -> Option<Layer> {
    Some(match name {
        "hopnav-ipc" | "hopnav-config" | "hopnav-supervisor" => Layer::Runtime,
        "hopnav-world" | "hopnav-vision" | "hopnav-metrics" | "hopnav-robot" => {
            Layer::SharedLibrary
        }
        "hopnav-physics" | "hopnav-camera" | "hopnav-jumper-vo" | "hopnav-rover-vo"
        | "hopnav-mapper" | "hopnav-planner" | "hopnav-recorder" | "hopnav-probe"
        | "hopnav-ipc-bench" => Layer::Process,
        "hopnav-eval" => Layer::Evaluation,
        "hopnav" => Layer::Cli,
        _ => return None,
    })
}

/// Whether crate `from_name` (of layer `from`) may depend on `to_name` (of layer `to`), as a
/// normal or build dependency (tests may use anything).
fn allowed(from: Layer, from_name: &str, to: Layer, to_name: &str) -> bool {
    let supervisor = to_name == "hopnav-supervisor";
    match (from, to) {
        (_, Layer::Cli) => false,
        // The config reads nothing of hopnav; the message layer reads the config; the
        // supervisor reads both. Nothing below the CLI but the evaluation reads the supervisor.
        (Layer::Runtime, Layer::Runtime) => from_name != "hopnav-config" && !supervisor,
        (Layer::Runtime, _) => false,
        // A shared library may read the config (the robot's body does), nothing else of the
        // runtime.
        (Layer::SharedLibrary, to) => to == Layer::SharedLibrary || to_name == "hopnav-config",
        (Layer::Process, to) => to == Layer::SharedLibrary || to == Layer::Runtime && !supervisor,
        (Layer::Evaluation, to) => to != Layer::Evaluation,
        (Layer::Cli, _) => true,
    }
}

/// Every workspace member's hopnav dependencies (not dev-dependencies), from `cargo metadata`.
fn workspace_dependencies() -> BTreeMap<String, Vec<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let output = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("cargo metadata prints JSON");
    let members: Vec<&str> = metadata["workspace_members"]
        .as_array()
        .expect("workspace_members")
        .iter()
        .filter_map(|id| id.as_str())
        .collect();
    let mut graph = BTreeMap::new();
    for package in metadata["packages"].as_array().expect("packages") {
        let id = package["id"].as_str().unwrap_or_default();
        if !members.contains(&id) {
            continue;
        }
        let name = package["name"].as_str().expect("name").to_owned();
        let dependencies = package["dependencies"]
            .as_array()
            .expect("dependencies")
            .iter()
            .filter(|dependency| dependency["kind"].as_str() != Some("dev"))
            .filter_map(|dependency| dependency["name"].as_str())
            .filter(|dependency| dependency.starts_with("hopnav"))
            .map(str::to_owned)
            .collect();
        graph.insert(name, dependencies);
    }
    graph
}

#[test]
fn every_workspace_crate_has_a_layer() {
    let graph = workspace_dependencies();
    assert!(graph.len() >= 10, "too few members found: {graph:?}");
    let unplaced: Vec<&String> = graph
        .keys()
        .filter(|name| layer_of(name).is_none())
        .collect();
    assert!(
        unplaced.is_empty(),
        "place these crates in a layer (tests/dependency_rules.rs, docs/ARCHITECTURE.md): {unplaced:?}"
    );
}

#[test]
fn every_dependency_follows_the_layering() {
    let mut broken = Vec::new();
    for (name, dependencies) in workspace_dependencies() {
        let Some(from) = layer_of(&name) else {
            continue;
        };
        for dependency in dependencies {
            let Some(to) = layer_of(&dependency) else {
                continue;
            };
            if !allowed(from, &name, to, &dependency) {
                broken.push(format!("{name} ({from:?}) -> {dependency} ({to:?})"));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "dependencies across the layering: {broken:#?}"
    );
}

#[test]
fn the_rules_reject_what_the_architecture_forbids() {
    use Layer::*;
    // The supervisor imports no algorithm and no evaluation; it reads messages and config.
    assert!(!allowed(
        Runtime,
        "hopnav-supervisor",
        Process,
        "hopnav-mapper"
    ));
    assert!(!allowed(
        Runtime,
        "hopnav-supervisor",
        SharedLibrary,
        "hopnav-world"
    ));
    assert!(!allowed(
        Runtime,
        "hopnav-supervisor",
        Evaluation,
        "hopnav-eval"
    ));
    assert!(allowed(Runtime, "hopnav-supervisor", Runtime, "hopnav-ipc"));
    // The message layer knows no supervisor; the config knows nothing.
    assert!(!allowed(
        Runtime,
        "hopnav-ipc",
        Runtime,
        "hopnav-supervisor"
    ));
    assert!(!allowed(Runtime, "hopnav-config", Runtime, "hopnav-ipc"));
    // No process crate imports another, the supervisor or the evaluation.
    assert!(!allowed(
        Process,
        "hopnav-mapper",
        Process,
        "hopnav-planner"
    ));
    assert!(!allowed(
        Process,
        "hopnav-mapper",
        Runtime,
        "hopnav-supervisor"
    ));
    assert!(!allowed(
        Process,
        "hopnav-mapper",
        Evaluation,
        "hopnav-eval"
    ));
    assert!(allowed(
        Process,
        "hopnav-mapper",
        SharedLibrary,
        "hopnav-world"
    ));
    assert!(!allowed(
        SharedLibrary,
        "hopnav-world",
        Process,
        "hopnav-physics"
    ));
    assert!(!allowed(
        SharedLibrary,
        "hopnav-world",
        Runtime,
        "hopnav-ipc"
    ));
    // The evaluation reads the runtime's record and the algorithms; nothing imports the binary.
    assert!(allowed(
        Evaluation,
        "hopnav-eval",
        Runtime,
        "hopnav-supervisor"
    ));
    assert!(!allowed(Evaluation, "hopnav-eval", Cli, "hopnav"));
}

/// The evaluation reads algorithms, never a process's wiring to topics: no `process` module
/// of any crate appears in its sources.
#[test]
fn the_evaluation_uses_no_process_wiring() {
    let source_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("processes/eval/src");
    let mut offenders = Vec::new();
    for entry in std::fs::read_dir(&source_dir).expect("processes/eval/src") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("readable source");
        for (number, line) in text.lines().enumerate() {
            if line.contains("::process::") || line.contains("::process;") {
                offenders.push(format!("{}:{}: {line}", path.display(), number + 1));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "evaluation reads process wiring: {offenders:#?}"
    );
}
