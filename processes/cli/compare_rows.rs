//! The rows of a `hopnav compare`: one per mission, written to `compare.json` and read back
//! by `hopnav compare --pair`, grouped into sets (the base and each variant).

use std::fmt;
use std::path::{Path, PathBuf};

use hopnav_config::MissionMode;
use hopnav_supervisor::mission_report::MissionReport;
use serde::{Deserialize, Serialize};

/// One mission of a comparison: a row of `compare.csv` and an element of `compare.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareRow {
    pub seed: u64,
    pub golombek_k: f64,
    pub mode: String,
    pub run_dir: String,
    pub runtime_ok: bool,
    /// `None` when the launch failed before the mission reported.
    pub mission: Option<MissionReport>,
}

/// The runs of one `compare` (or of its variant), with the name the tables give it.
#[derive(Debug, Clone)]
pub struct RunSet {
    /// "base", "variant", "variant 2", …
    pub label: String,
    pub rows: Vec<CompareRow>,
}

/// Why a compare folder's runs cannot be read.
#[derive(Debug)]
pub enum ReadRowsError {
    /// `compare.json` is missing or unreadable.
    Io { path: PathBuf, message: String },
    /// `compare.json` is not a list of compare rows.
    Format { path: PathBuf, message: String },
}

impl fmt::Display for ReadRowsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadRowsError::Io { path, message } => {
                write!(f, "cannot read {}: {message}", path.display())
            }
            ReadRowsError::Format { path, message } => write!(
                f,
                "{} is not the compare.json of a `hopnav compare` run: {message}",
                path.display()
            ),
        }
    }
}

impl std::error::Error for ReadRowsError {}

/// The rows of `dir/compare.json`.
pub fn read_rows(dir: &Path) -> Result<Vec<CompareRow>, ReadRowsError> {
    let path = dir.join("compare.json");
    let text = std::fs::read_to_string(&path).map_err(|error| ReadRowsError::Io {
        path: path.clone(),
        message: error.to_string(),
    })?;
    parse_rows(&text).map_err(|message| ReadRowsError::Format { path, message })
}

/// Parses the text of a `compare.json`: known modes only, each (seed, mode) once.
pub fn parse_rows(text: &str) -> Result<Vec<CompareRow>, String> {
    let rows: Vec<CompareRow> = serde_json::from_str(text).map_err(|error| error.to_string())?;
    for (index, row) in rows.iter().enumerate() {
        if mode_of(&row.mode).is_none() {
            return Err(format!(
                "row {index}: unknown mode {:?} (cooperative or rover-only)",
                row.mode
            ));
        }
        if rows[..index]
            .iter()
            .any(|other| other.seed == row.seed && other.mode == row.mode)
        {
            return Err(format!(
                "row {index}: seed {} {} appears twice",
                row.seed, row.mode
            ));
        }
    }
    Ok(rows)
}

fn mode_of(name: &str) -> Option<MissionMode> {
    [MissionMode::Cooperative, MissionMode::RoverOnly]
        .into_iter()
        .find(|mode| mode.name() == name)
}

impl RunSet {
    /// The rows of one mode.
    pub fn of_mode(&self, mode: MissionMode) -> Vec<&CompareRow> {
        self.rows
            .iter()
            .filter(|row| row.mode == mode.name())
            .collect()
    }

    /// The modes this set ran, in the order cooperative, rover-only.
    pub fn modes(&self) -> Vec<MissionMode> {
        [MissionMode::Cooperative, MissionMode::RoverOnly]
            .into_iter()
            .filter(|mode| !self.of_mode(*mode).is_empty())
            .collect()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn row(seed: u64, mode: &str, result: Option<(bool, f64, u64)>) -> CompareRow {
        CompareRow {
            seed,
            golombek_k: 0.1,
            mode: mode.to_owned(),
            run_dir: format!("runs/{seed}-{mode}"),
            runtime_ok: result.is_some(),
            mission: result.map(|(goal_reached, executed_path_m, replans)| MissionReport {
                mode: mode.to_owned(),
                goal_reached,
                final_state: "GoalReached".into(),
                mission_time_s: 100.0,
                executed_path_m,
                replans,
                route_changes: replans / 2,
                node_expansions: 1000,
                jump_requests: 0,
                jumper_hops: 0,
                collisions: 0,
                rover_motion_times: None,
                mapped_cells: 0,
                obstacle_cells: 0,
                inflated_cells: 0,
                evaluation: serde_json::Map::new(),
            }),
        }
    }

    #[test]
    fn rows_round_trip_and_corrupt_compare_json_is_an_error() {
        let rows = vec![
            row(1, "cooperative", Some((true, 90.0, 4))),
            row(1, "rover-only", None),
        ];
        let text = serde_json::to_string_pretty(&rows).expect("serialize");
        assert_eq!(parse_rows(&text).expect("round trip"), rows);
        assert!(parse_rows("[{\"seed\": 1}").is_err());
        assert!(parse_rows("{\"rows\": []}").is_err());
        let twice = serde_json::to_string(&[&rows[0], &rows[0]]).expect("serialize");
        assert!(
            parse_rows(&twice)
                .expect_err("dup")
                .contains("appears twice")
        );
        let dir = std::env::temp_dir().join(format!("hopnav-pair-corrupt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let missing = read_rows(&dir).expect_err("no compare.json yet");
        assert!(missing.to_string().contains("compare.json"), "{missing}");
        std::fs::write(dir.join("compare.json"), "[{\"seed\": ").expect("write");
        let corrupt = read_rows(&dir).expect_err("corrupt");
        assert!(matches!(corrupt, ReadRowsError::Format { .. }));
        assert!(
            corrupt
                .to_string()
                .contains(&dir.join("compare.json").display().to_string())
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
