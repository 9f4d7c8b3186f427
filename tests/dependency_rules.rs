//! The layering of docs/ARCHITECTURE.md, checked from `cargo metadata` so it stays true:
//! the runtime imports no algorithm; a process is an algorithm crate (no IPC wiring) and a node
//! crate that binds it to topics; no process's crates import another process's; and the
//! evaluation sits outside the process graph, reading algorithms, never a node.

mod common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use common::stdout_of_success;

/// The layer a workspace crate belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layer {
    /// Messages, config, the supervisor: launches and measures, knows no algorithm.
    Runtime,
    /// Libraries several processes share (terrain, vision geometry, metrics and plots).
    SharedLibrary,
    /// A process's algorithms in plain modules, without its wiring to topics
    /// (`processes/<name>`, `hopnav-<name>`).
    Algorithm,
    /// A process's wiring to topics (`processes/<name>/node`, `hopnav-<name>-node`, which binds
    /// the algorithm crate of the same name), or a process that is wiring only (recorder,
    /// probe, ipc_bench).
    Node,
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
        | "hopnav-mapper" | "hopnav-planner" => Layer::Algorithm,
        "hopnav-physics-node"
        | "hopnav-camera-node"
        | "hopnav-jumper-vo-node"
        | "hopnav-rover-vo-node"
        | "hopnav-mapper-node"
        | "hopnav-planner-node"
        | "hopnav-recorder"
        | "hopnav-probe"
        | "hopnav-ipc-bench" => Layer::Node,
        "hopnav-eval" => Layer::Evaluation,
        "hopnav" => Layer::Cli,
        _ => return None,
    })
}

/// The algorithm crates whose data are message types (the mapper's clouds and cells, physics'
/// resume state in `wire.rs`), so they depend on hopnav-ipc and, as messages and transport
/// share that crate, link iceoryx2. Every other algorithm crate stays off it.
const READS_MESSAGES: &[&str] = &["hopnav-mapper", "hopnav-physics"];

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
        // An algorithm crate reads shared libraries and config, and messages only where its
        // data are message types: never another process's algorithms, a node, the supervisor
        // or the evaluation.
        (Layer::Algorithm, to) => {
            to == Layer::SharedLibrary
                || to_name == "hopnav-config"
                || to_name == "hopnav-ipc" && READS_MESSAGES.contains(&from_name)
        }
        // A node binds its own process's algorithm crate (`hopnav-X-node` -> `hopnav-X`) and
        // nothing of another process: no other algorithm crate, no other node.
        (Layer::Node, Layer::Algorithm) => from_name.strip_suffix("-node") == Some(to_name),
        (Layer::Node, to) => to == Layer::SharedLibrary || to == Layer::Runtime && !supervisor,
        // The evaluation reads the runtime's record and the algorithms, never a node's wiring.
        (Layer::Evaluation, to) => !matches!(to, Layer::Node | Layer::Evaluation),
        (Layer::Cli, _) => true,
    }
}

/// Whether crate `name` (of layer `layer`) may use iceoryx2 itself rather than through
/// hopnav-ipc's transport: the runtime, and the IPC benchmark (it measures raw iceoryx2 as the
/// floor under hopnav's topics).
fn may_use_iceoryx2_directly(layer: Layer, name: &str) -> bool {
    layer == Layer::Runtime || name == "hopnav-ipc-bench"
}

/// Every workspace member's dependencies (not dev-dependencies), from `cargo metadata`.
fn workspace_dependencies() -> BTreeMap<String, Vec<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let stdout = stdout_of_success(
        Command::new(cargo)
            .args([
                "metadata",
                "--format-version",
                "1",
                "--no-deps",
                "--offline",
            ])
            .current_dir(env!("CARGO_MANIFEST_DIR")),
        "cargo metadata",
    );
    let metadata: serde_json::Value =
        serde_json::from_str(&stdout).expect("cargo metadata prints JSON");
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
fn only_the_runtime_uses_iceoryx2_directly() {
    let mut broken = Vec::new();
    for (name, dependencies) in workspace_dependencies() {
        let Some(layer) = layer_of(&name) else {
            continue;
        };
        for dependency in dependencies {
            if dependency.starts_with("iceoryx2") && !may_use_iceoryx2_directly(layer, &name) {
                broken.push(format!("{name} ({layer:?}) -> {dependency}"));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "iceoryx2 outside the runtime (use hopnav-ipc's transport in a node): {broken:#?}"
    );
}

/// Whether a dependency is expected to pass the rules.
const ALLOWED: bool = true;
const FORBIDDEN: bool = false;

/// Asserts the rules' verdict on each dependency `(from crate, to crate, expected)`, listing
/// every one they judge otherwise.
fn assert_verdicts(cases: &[(&str, &str, bool)]) {
    let layer = |name: &str| layer_of(name).unwrap_or_else(|| panic!("{name} has no layer"));
    let wrong: Vec<String> = cases
        .iter()
        .filter(|&&(from, to, expected)| allowed(layer(from), from, layer(to), to) != expected)
        .map(|(from, to, expected)| format!("{from} -> {to}: expected allowed = {expected}"))
        .collect();
    assert!(wrong.is_empty(), "the rules judge otherwise: {wrong:#?}");
}

#[test]
fn the_runtime_imports_no_algorithm() {
    assert_verdicts(&[
        // The supervisor imports no algorithm and no evaluation; it reads messages and config.
        ("hopnav-supervisor", "hopnav-mapper", FORBIDDEN),
        ("hopnav-supervisor", "hopnav-mapper-node", FORBIDDEN),
        ("hopnav-supervisor", "hopnav-world", FORBIDDEN),
        ("hopnav-supervisor", "hopnav-eval", FORBIDDEN),
        ("hopnav-supervisor", "hopnav-ipc", ALLOWED),
        // The message layer knows no supervisor; the config knows nothing.
        ("hopnav-ipc", "hopnav-supervisor", FORBIDDEN),
        ("hopnav-config", "hopnav-ipc", FORBIDDEN),
    ]);
}

#[test]
fn an_algorithm_crate_imports_nothing_of_another_process() {
    assert_verdicts(&[
        // No algorithm crate imports another process's algorithms, a node, the supervisor or the
        // evaluation.
        ("hopnav-mapper", "hopnav-planner", FORBIDDEN),
        ("hopnav-mapper", "hopnav-mapper-node", FORBIDDEN),
        ("hopnav-mapper", "hopnav-planner-node", FORBIDDEN),
        ("hopnav-mapper", "hopnav-supervisor", FORBIDDEN),
        ("hopnav-mapper", "hopnav-eval", FORBIDDEN),
        ("hopnav-mapper", "hopnav-world", ALLOWED),
        ("hopnav-mapper", "hopnav-ipc", ALLOWED),
        ("hopnav-planner", "hopnav-ipc", FORBIDDEN),
        ("hopnav-planner", "hopnav-config", ALLOWED),
    ]);
}

#[test]
fn a_node_binds_only_its_own_algorithms() {
    assert_verdicts(&[
        // A node binds its own algorithms and nothing of another process.
        ("hopnav-mapper-node", "hopnav-mapper", ALLOWED),
        ("hopnav-mapper-node", "hopnav-planner", FORBIDDEN),
        ("hopnav-mapper-node", "hopnav-planner-node", FORBIDDEN),
        ("hopnav-recorder", "hopnav-mapper", FORBIDDEN),
        ("hopnav-mapper-node", "hopnav-supervisor", FORBIDDEN),
        ("hopnav-mapper-node", "hopnav-eval", FORBIDDEN),
        ("hopnav-mapper-node", "hopnav-ipc", ALLOWED),
    ]);
}

#[test]
fn a_shared_library_reads_no_process_and_no_message() {
    assert_verdicts(&[
        // A shared library reads no process's crates and no messages (of the runtime, only
        // the config).
        ("hopnav-world", "hopnav-physics", FORBIDDEN),
        ("hopnav-world", "hopnav-ipc", FORBIDDEN),
    ]);
}

#[test]
fn the_evaluation_reads_algorithms_never_a_node() {
    assert_verdicts(&[
        // The evaluation reads the runtime's record and the algorithms, never a node; nothing
        // imports the binary.
        ("hopnav-eval", "hopnav-supervisor", ALLOWED),
        ("hopnav-eval", "hopnav-jumper-vo", ALLOWED),
        ("hopnav-eval", "hopnav-mapper-node", FORBIDDEN),
        ("hopnav-eval", "hopnav-recorder", FORBIDDEN),
        ("hopnav-eval", "hopnav", FORBIDDEN),
    ]);
}

#[test]
fn the_iceoryx2_rule_admits_the_runtime_alone() {
    use Layer::*;
    // Only the runtime (and the benchmark of raw iceoryx2) touches iceoryx2 itself.
    assert!(may_use_iceoryx2_directly(Runtime, "hopnav-ipc"));
    assert!(!may_use_iceoryx2_directly(Evaluation, "hopnav-eval"));
    assert!(!may_use_iceoryx2_directly(Node, "hopnav-mapper-node"));
    assert!(!may_use_iceoryx2_directly(Algorithm, "hopnav-mapper"));
}

/// Every `.rs` file under `dir`, in subfolders too.
fn rust_sources(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).expect("readable folder") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            files.extend(rust_sources(&path));
        } else if path.extension().is_some_and(|extension| extension == "rs") {
            files.push(path);
        }
    }
    files
}

/// The evaluation reads algorithms, never a process's wiring to topics: no `process` module
/// or node crate of any process appears in its sources.
#[test]
fn the_evaluation_uses_no_process_wiring() {
    let source_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("processes/eval/src");
    let mut offenders = Vec::new();
    for path in rust_sources(&source_dir) {
        let text = std::fs::read_to_string(&path).expect("readable source");
        for (number, line) in text.lines().enumerate() {
            if line.contains("::process::")
                || line.contains("::process;")
                || line.contains("_node::")
            {
                offenders.push(format!("{}:{}: {line}", path.display(), number + 1));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "evaluation reads process wiring: {offenders:#?}"
    );
}
