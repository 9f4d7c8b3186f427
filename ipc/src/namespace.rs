//! One iceoryx2 namespace per launch, and the clean-up of launches that died.
//!
//! The run id becomes the iceoryx2 file prefix (`hopnav_<run id>_`), so parallel launches and
//! tests never see each other's services. A launch killed with SIGKILL leaves its shared-memory
//! files behind; the next launch finds those namespaces, asks iceoryx2 which nodes are dead
//! (`Node::list`) and removes their stale resources.

use std::path::{Path, PathBuf};

use iceoryx2::config::Config;
use iceoryx2::node::{Node, NodeBuilder, NodeState};
use iceoryx2::prelude::{
    CallbackProgression, FileName, NodeName, SemanticString, SignalHandlingMode,
};

use crate::IpcService;

/// Prefix of every hopnav file in the iceoryx2 and shared-memory directories.
pub const FILE_PREFIX: &str = "hopnav_";
/// Where iceoryx2 keeps its node and service files (its default is /tmp/iceoryx2, on disk):
/// on tmpfs beside the shared memory, so creating a node or a port never waits for a disk
/// journal (a restart creates a dozen of these files), and nothing outlives a reboot.
pub const ROOT_PATH: &str = "/dev/shm/hopnav-iceoryx2/";

/// Longest accepted run id (iceoryx2 file names are limited).
pub const MAX_RUN_ID_LEN: usize = 48;

/// Why a namespace or node could not be made.
#[derive(Debug, thiserror::Error)]
pub enum NamespaceError {
    /// The run id has characters outside `[A-Za-z0-9_-]`, is empty or too long.
    #[error("run id {0:?} must be 1..={MAX_RUN_ID_LEN} characters of [A-Za-z0-9_-]")]
    BadRunId(String),
    /// A node name iceoryx2 refuses.
    #[error("node name {0:?} is not valid for iceoryx2")]
    BadNodeName(String),
    /// Another live launch holds this run id: the two would share every topic.
    #[error("run id {0:?} is in use by a launch that is still running (choose another --run-id)")]
    RunIdInUse(String),
    /// The run id's claim file could not be made.
    #[error("cannot claim run id {run_id:?} ({path}): {source}")]
    Claim {
        /// Run id.
        run_id: String,
        /// Claim file.
        path: PathBuf,
        /// OS error.
        source: std::io::Error,
    },
    /// iceoryx2 could not create the node.
    #[error("could not create node {name:?}: {reason}")]
    NodeCreation {
        /// Node name.
        name: String,
        /// iceoryx2's reason.
        reason: String,
    },
}

/// The iceoryx2 configuration of one launch.
#[derive(Debug, Clone)]
pub struct Namespace {
    run_id: String,
    config: Config,
}

impl Namespace {
    /// The namespace of run `run_id`.
    pub fn new(run_id: &str) -> Result<Self, NamespaceError> {
        let valid_chars = run_id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        if run_id.is_empty() || run_id.len() > MAX_RUN_ID_LEN || !valid_chars {
            return Err(NamespaceError::BadRunId(run_id.to_owned()));
        }
        let mut config = root_config();
        let prefix = format!("{FILE_PREFIX}{run_id}_");
        config.global.prefix = FileName::new(prefix.as_bytes())
            .map_err(|_| NamespaceError::BadRunId(run_id.to_owned()))?;
        config.global.node.cleanup_dead_nodes_on_creation = true;
        config.global.node.cleanup_dead_nodes_on_destruction = true;
        config.global.service.cleanup_dead_nodes_on_open = true;
        Ok(Self {
            run_id: run_id.to_owned(),
            config,
        })
    }

    /// The same namespace without iceoryx2's dead-node scans on node creation and on every
    /// service open: for the supervisor's children. The supervisor removes a dead child's
    /// resources as soon as it reaps it, before the restart, and the next launch removes those
    /// of a dead supervisor, so the scans (a few file opens per node, per service) only slow a
    /// restart down.
    pub fn without_dead_node_scans(mut self) -> Self {
        self.config.global.node.cleanup_dead_nodes_on_creation = false;
        self.config.global.service.cleanup_dead_nodes_on_open = false;
        self
    }

    /// Claims the run id for this process until the claim is dropped: two launches with the
    /// same run id share every topic and drive each other's rover (an advisory lock, freed by
    /// the OS when the process dies however it dies).
    pub fn claim(&self) -> Result<RunIdClaim, NamespaceError> {
        let dir = Path::new(ROOT_PATH).join(CLAIM_DIRECTORY);
        let path = dir.join(format!("{}.lock", self.run_id));
        let claim_error = |source| NamespaceError::Claim {
            run_id: self.run_id.clone(),
            path: path.clone(),
            source,
        };
        std::fs::create_dir_all(&dir).map_err(claim_error)?;
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(claim_error)?;
        match file.try_lock() {
            Ok(()) => Ok(RunIdClaim { file, path }),
            Err(std::fs::TryLockError::WouldBlock) => {
                Err(NamespaceError::RunIdInUse(self.run_id.clone()))
            }
            Err(std::fs::TryLockError::Error(source)) => Err(claim_error(source)),
        }
    }

    /// The run id this namespace belongs to.
    pub fn run_id(&self) -> &str {
        &self.run_id
    }

    /// The iceoryx2 configuration (pass it to every node; no config file is ever read).
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// A node named `name` in this namespace. Termination signals are left to hopnav's loops,
    /// which ask iceoryx2's handler through the WaitSet.
    pub fn create_node(&self, name: &str) -> Result<Node<IpcService>, NamespaceError> {
        let node_name =
            NodeName::new(name).map_err(|_| NamespaceError::BadNodeName(name.to_owned()))?;
        let node = NodeBuilder::new()
            .name(&node_name)
            .config(&self.config)
            .signal_handling_mode(SignalHandlingMode::HandleTerminationRequests)
            .create::<IpcService>()
            .map_err(|error| NamespaceError::NodeCreation {
                name: name.to_owned(),
                reason: format!("{error:?}"),
            })?;
        self.restrict_to_owner();
        Ok(node)
    }

    /// Takes group and other access away from this namespace's files. iceoryx2 creates its
    /// per-domain management segment world-accessible on purpose (cross-user setups); a
    /// launch belongs to one user, and its data segments are owner-only already.
    fn restrict_to_owner(&self) {
        use std::os::unix::fs::PermissionsExt;
        for path in self.leftover_files() {
            let Ok(metadata) = std::fs::metadata(&path) else {
                continue; // removed meanwhile
            };
            let mode = metadata.permissions().mode();
            if mode & 0o077 != 0 {
                // Best effort: a file another process owns or just removed stays as it is.
                let _ =
                    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(mode & 0o700));
            }
        }
    }

    /// Counts the live and dead nodes of this namespace and removes the dead ones' resources.
    pub fn remove_dead_nodes(&self) -> NodeCensus {
        let mut census = NodeCensus::default();
        let _ = Node::<IpcService>::list(&self.config, |state| {
            match state {
                NodeState::Alive(_) => census.alive += 1,
                NodeState::Dead(dead) => {
                    census.dead += 1;
                    if dead.try_remove_stale_resources().is_ok() {
                        census.removed += 1;
                    }
                }
                NodeState::Inaccessible(_) | NodeState::Undefined(_) => census.unknown += 1,
            }
            CallbackProgression::Continue
        });
        census
    }

    /// Removes this namespace's remaining files when none of its nodes is alive (iceoryx2
    /// keeps a management segment per prefix after the last node is gone). Returns the
    /// number of files removed; nothing is touched while a node lives.
    pub fn remove_files_if_unused(&self) -> usize {
        let census = self.remove_dead_nodes();
        if census.alive > 0 || census.unknown > 0 {
            return 0;
        }
        self.leftover_files()
            .iter()
            .filter(|path| std::fs::remove_file(path).is_ok())
            .count()
    }

    /// Time since the newest file of this namespace was modified (`None` without files).
    pub fn newest_file_age(&self) -> Option<std::time::Duration> {
        self.leftover_files()
            .iter()
            .filter_map(|path| std::fs::metadata(path).ok()?.modified().ok())
            .max()
            .map(|newest| newest.elapsed().unwrap_or_default())
    }

    /// Files of this namespace still on disk (shared memory and iceoryx2 bookkeeping).
    pub fn leftover_files(&self) -> Vec<PathBuf> {
        let prefix = format!("{FILE_PREFIX}{}_", self.run_id);
        hopnav_files()
            .into_iter()
            .filter(|path| file_name_starts_with(path, &prefix))
            .collect()
    }
}

/// Folder of the run-id claim files, under [`ROOT_PATH`].
const CLAIM_DIRECTORY: &str = "claims";

/// A run id held by this process (see [`Namespace::claim`]); dropping it frees the run id.
#[derive(Debug)]
pub struct RunIdClaim {
    file: std::fs::File,
    path: PathBuf,
}

impl Drop for RunIdClaim {
    fn drop(&mut self) {
        // Best effort: the lock goes with the file handle; the empty file is only tidied up,
        // and removed while still locked, so no launch that opened it can take it over.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// Nodes found in a namespace.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct NodeCensus {
    /// Nodes whose process lives.
    pub alive: usize,
    /// Nodes whose process died without cleaning up.
    pub dead: usize,
    /// Dead nodes whose resources were removed.
    pub removed: usize,
    /// Nodes whose state could not be determined.
    pub unknown: usize,
}

/// What the clean-up of earlier launches found and did.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct StaleCleanup {
    /// Run ids whose nodes were all dead.
    pub dead_runs: Vec<String>,
    /// Dead nodes whose resources were removed.
    pub removed_nodes: usize,
    /// Leftover files removed after the node clean-up.
    pub removed_files: usize,
}

/// Finds namespaces of earlier launches that have no live node left and removes their
/// resources; namespaces with a live node (a parallel launch) are left alone.
pub fn cleanup_dead_runs() -> StaleCleanup {
    let mut report = StaleCleanup::default();
    for run_id in run_ids_on_disk() {
        let Ok(namespace) = Namespace::new(&run_id) else {
            continue;
        };
        let census = namespace.remove_dead_nodes();
        if census.alive > 0 || census.unknown > 0 {
            continue;
        }
        // Files but no node at all: either a launch that died before its first node, or one
        // starting right now (its node is being created). Only the first kind is stale, and
        // its files are not fresh.
        if census.dead == 0
            && namespace
                .newest_file_age()
                .is_none_or(|age| age < FRESH_RUN_AGE)
        {
            continue;
        }
        report.removed_nodes += census.removed;
        // Files iceoryx2 could not attribute to a node (e.g. a service created by a process
        // killed mid-creation) belong to no one now that no node of the run lives.
        report.removed_files += namespace.remove_files_if_unused();
        report.dead_runs.push(run_id);
    }
    report
}

/// Node-less files younger than this may belong to a launch that is starting.
const FRESH_RUN_AGE: std::time::Duration = std::time::Duration::from_secs(10);

/// iceoryx2's default configuration with hopnav's [`ROOT_PATH`].
fn root_config() -> Config {
    let mut config = Config::default();
    if let Ok(root) = iceoryx2::prelude::Path::new(ROOT_PATH.as_bytes()) {
        config.global.set_root_path(&root);
    }
    config
}

/// Every hopnav file in the iceoryx2 root directories and in /dev/shm.
pub fn hopnav_files() -> Vec<PathBuf> {
    let config = root_config();
    let root = PathBuf::from(config.global.root_path().to_string());
    let mut dirs = vec![PathBuf::from("/dev/shm"), root.clone()];
    dirs.push(root.join(config.global.node.directory.to_string()));
    dirs.push(root.join(config.global.service.directory.to_string()));
    let mut files = Vec::new();
    for dir in dirs {
        collect_prefixed(&dir, &mut files, 2);
    }
    files.sort();
    files.dedup();
    files
}

fn collect_prefixed(dir: &Path, files: &mut Vec<PathBuf>, depth: u32) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let is_dir = entry.file_type().map(|t| t.is_dir()).unwrap_or(false);
        if file_name_starts_with(&path, FILE_PREFIX) {
            if is_dir {
                collect_all(&path, files, depth);
            } else {
                files.push(path);
            }
        } else if is_dir && depth > 0 {
            collect_prefixed(&path, files, depth - 1);
        }
    }
}

fn collect_all(dir: &Path, files: &mut Vec<PathBuf>, depth: u32) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if entry.file_type().map(|t| t.is_dir()).unwrap_or(false) {
            if depth > 0 {
                collect_all(&path, files, depth - 1);
            }
        } else {
            files.push(path);
        }
    }
}

fn file_name_starts_with(path: &Path, prefix: &str) -> bool {
    path.file_name()
        .and_then(|name| name.to_str())
        .is_some_and(|name| name.starts_with(prefix))
}

/// Run ids that have files on disk, live or dead, sorted.
pub(crate) fn run_ids_on_disk() -> Vec<String> {
    let mut run_ids: Vec<String> = hopnav_files()
        .iter()
        .filter_map(|path| path.file_name()?.to_str().map(str::to_owned))
        .filter_map(|name| run_id_of(&name))
        .collect();
    run_ids.sort();
    run_ids.dedup();
    run_ids
}

/// The run id encoded in a file name `hopnav_<run id>_<rest>`. Run ids made by
/// [`new_run_id`] contain no `_`, so the first `_` after the prefix ends the id.
fn run_id_of(file_name: &str) -> Option<String> {
    let rest = file_name.strip_prefix(FILE_PREFIX)?;
    let end = rest.find('_')?;
    (end > 0).then(|| rest[..end].to_owned())
}

/// A fresh run id: UTC date and time, then the pid and a counter so two launches in the same
/// second never collide. Contains no `_` (see [`run_id_of`]).
pub fn new_run_id() -> String {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    let seconds = now.as_secs();
    let (days, day_seconds) = (seconds / 86_400, seconds % 86_400);
    let (year, month, day) = civil_from_days(days as i64);
    format!(
        "{year:04}{month:02}{day:02}-{:02}{:02}{:02}-{}-{:03}",
        day_seconds / 3600,
        (day_seconds / 60) % 60,
        day_seconds % 60,
        std::process::id(),
        now.subsec_millis()
    )
}

/// Days since 1970-01-01 to (year, month, day), proleptic Gregorian (H. Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * month_index + 2) / 5 + 1) as u32;
    let month = if month_index < 10 {
        month_index + 3
    } else {
        month_index - 9
    } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_ids_are_validated() {
        assert!(Namespace::new("20261121-120000-42-001").is_ok());
        assert!(Namespace::new("").is_err());
        assert!(Namespace::new("a/b").is_err());
        assert!(Namespace::new(&"x".repeat(MAX_RUN_ID_LEN + 1)).is_err());
    }

    #[test]
    fn new_run_ids_round_trip_through_file_names() {
        let run_id = new_run_id();
        assert!(!run_id.contains('_'));
        let file = format!("{FILE_PREFIX}{run_id}_abc.data");
        assert_eq!(run_id_of(&file), Some(run_id));
        assert_eq!(run_id_of("iox2_something"), None);
    }

    #[test]
    fn civil_dates_are_right() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_413), (2025, 11, 21));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
    }
}
