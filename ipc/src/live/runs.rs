//! Which launches are running, and picking the one a tool looks at.
//!
//! A launch is running while its supervisor's iceoryx2 node is alive: iceoryx2 tells a live
//! node from a dead one without taking any lock the launch holds.

use std::collections::HashMap;

use iceoryx2::identifiers::UniqueNodeId;
use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::prelude::CallbackProgression;

use crate::IpcService;
use crate::namespace::{self, Namespace};

/// The supervisor's node name (`processes/supervisor/src/launch.rs`).
const SUPERVISOR_NODE: &str = "supervisor";

/// Why no single launch could be picked.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunSelectError {
    /// No launch is running.
    #[error("no hopnav launch is running (start one with `hopnav launch`)")]
    NoLaunch,
    /// Several launches run and none was named.
    #[error("{} launches are running ({}): choose one with --run ID", .0.len(), .0.join(", "))]
    Ambiguous(Vec<String>),
    /// The named launch is not running.
    #[error("no running launch has run id {requested:?} (running: {})", running_list(.running))]
    NotRunning {
        /// The run id asked for.
        requested: String,
        /// The launches that do run.
        running: Vec<String>,
    },
}

fn running_list(running: &[String]) -> String {
    if running.is_empty() {
        "none".to_owned()
    } else {
        running.join(", ")
    }
}

/// Picks the launch among `running`: the `requested` one, or the only one.
pub fn select_run(running: &[String], requested: Option<&str>) -> Result<String, RunSelectError> {
    match (requested, running) {
        (Some(requested), _) if running.iter().any(|run| run == requested) => {
            Ok(requested.to_owned())
        }
        (Some(requested), _) => Err(RunSelectError::NotRunning {
            requested: requested.to_owned(),
            running: running.to_vec(),
        }),
        (None, []) => Err(RunSelectError::NoLaunch),
        (None, [only]) => Ok(only.clone()),
        (None, several) => Err(RunSelectError::Ambiguous(several.to_vec())),
    }
}

/// Run ids of the launches running now, sorted.
pub fn running_launches() -> Vec<String> {
    namespace::run_ids_on_disk()
        .into_iter()
        .filter(|run_id| Namespace::new(run_id).is_ok_and(|namespace| is_running(&namespace)))
        .collect()
}

/// The namespace of the launch a tool looks at: `requested`, or the only one running. The
/// namespace does no dead-node scans: clean-up is the launches' business, not a tool's.
pub fn find_launch(requested: Option<&str>) -> Result<Namespace, RunSelectError> {
    let run_id = select_run(&running_launches(), requested)?;
    Namespace::new(&run_id)
        .map(Namespace::without_dead_node_scans)
        .map_err(|_| RunSelectError::NotRunning {
            requested: run_id,
            running: Vec::new(),
        })
}

/// Whether the launch of `namespace` is still running (its supervisor node lives).
pub fn is_running(namespace: &Namespace) -> bool {
    live_node_names(namespace)
        .values()
        .any(|name| name == SUPERVISOR_NODE)
}

/// The live nodes of a namespace, by id: the processes of the launch (and tools).
pub(crate) fn live_node_names(namespace: &Namespace) -> HashMap<UniqueNodeId, String> {
    let mut names = HashMap::new();
    let _ = Node::<IpcService>::list(namespace.config(), |state| {
        if let NodeState::Alive(view) = state {
            let name = view
                .details()
                .as_ref()
                .map_or_else(|| "?".to_owned(), |details| details.name().to_string());
            names.insert(*view.id(), name);
        }
        CallbackProgression::Continue
    });
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    fn runs(ids: &[&str]) -> Vec<String> {
        ids.iter().map(|id| (*id).to_owned()).collect()
    }

    #[test]
    fn without_a_launch_the_error_says_so() {
        let error = select_run(&[], None).unwrap_err();
        assert_eq!(error, RunSelectError::NoLaunch);
        assert!(error.to_string().contains("no hopnav launch is running"));
    }

    #[test]
    fn the_only_launch_is_picked_by_itself() {
        assert_eq!(select_run(&runs(&["a"]), None).unwrap(), "a");
    }

    #[test]
    fn two_launches_need_a_run_id() {
        let running = runs(&["a", "b"]);
        let error = select_run(&running, None).unwrap_err();
        assert_eq!(error, RunSelectError::Ambiguous(running.clone()));
        assert!(error.to_string().contains("--run"), "{error}");
        assert!(error.to_string().contains("a, b"), "{error}");
        assert_eq!(select_run(&running, Some("b")).unwrap(), "b");
    }

    #[test]
    fn a_run_id_that_is_not_running_is_named() {
        let error = select_run(&runs(&["a"]), Some("z")).unwrap_err();
        assert!(error.to_string().contains("\"z\""), "{error}");
        assert!(error.to_string().contains("running: a"), "{error}");
        let error = select_run(&[], Some("z")).unwrap_err();
        assert!(error.to_string().contains("running: none"), "{error}");
    }

    #[test]
    fn a_namespace_without_nodes_is_not_running() {
        let namespace = Namespace::new(&format!("livetest-{}", std::process::id())).unwrap();
        assert!(!is_running(&namespace));
        assert!(!running_launches().contains(&namespace.run_id().to_owned()));
    }
}
