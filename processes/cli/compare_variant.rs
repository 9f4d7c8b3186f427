//! The configs of `hopnav compare`'s runs: the base (defaults, then the user's file), and with
//! `--variant overlay.toml` the variant, the overlay merged over the base table by table as
//! the config loader merges a file over the defaults. Each run then gets its seed, rock
//! abundance, mode and frame limit; an overlay may not set those (compare sets them per run).

use std::fmt;
use std::path::{Path, PathBuf};

use hopnav_config::{ConfigError, HopnavConfig, MissionMode};

use crate::registry;

/// Which modes the variant re-runs (the base always runs both).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum VariantMode {
    /// Only the cooperative missions; the variant borrows the base's rover-only runs.
    Cooperative,
    /// Only the rover-only missions; the variant borrows the base's cooperative runs.
    #[value(name = "rover-only")]
    RoverOnly,
    /// Both modes.
    #[default]
    Both,
}

impl VariantMode {
    /// The mission modes to run, cooperative first.
    pub fn modes(self) -> Vec<MissionMode> {
        match self {
            VariantMode::Cooperative => vec![MissionMode::Cooperative],
            VariantMode::RoverOnly => vec![MissionMode::RoverOnly],
            VariantMode::Both => vec![MissionMode::Cooperative, MissionMode::RoverOnly],
        }
    }
}

/// Keys `compare` sets on every run, with the option that sets them instead.
const SET_PER_RUN: &[(&[&str], &str)] = &[
    (&["world", "seed"], "--first-seed and --seeds"),
    (&["world", "rocks", "golombek_k"], "--k-min and --k-max"),
    (&["mission", "mode"], "--variant-mode"),
    (
        &["mission", "stop_on_goal"],
        "nothing: compare always stops at B",
    ),
    (
        &["run", "lockstep"],
        "nothing: compare always runs lockstep",
    ),
    (&["run", "frames"], "--frames"),
    (&["run", "out_dir"], "--out"),
];

/// A variant overlay that cannot be used; every variant names the file.
#[derive(Debug)]
pub enum VariantError {
    /// The file cannot be read.
    Io { path: PathBuf, message: String },
    /// The file is not valid TOML.
    Syntax { path: PathBuf, message: String },
    /// The overlay sets a key compare sets on every run.
    SetPerRun {
        path: PathBuf,
        key: String,
        instead: &'static str,
    },
    /// The merged config is rejected by the config validation (unknown key, wrong type, out
    /// of range), which names the key.
    Invalid { path: PathBuf, error: ConfigError },
}

impl fmt::Display for VariantError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VariantError::Io { path, message } => {
                write!(
                    f,
                    "variant overlay {}: cannot read: {message}",
                    path.display()
                )
            }
            VariantError::Syntax { path, message } => write!(
                f,
                "variant overlay {} is not valid TOML: {message}",
                path.display()
            ),
            VariantError::SetPerRun { path, key, instead } => write!(
                f,
                "variant overlay {}: key {key} is set by compare on every run (use {instead})",
                path.display()
            ),
            VariantError::Invalid { path, error } => {
                write!(f, "variant overlay {}: {error}", path.display())
            }
        }
    }
}

impl std::error::Error for VariantError {}

/// A parsed overlay: any subset of the config's keys.
#[derive(Debug, Clone)]
pub struct Overlay {
    pub path: PathBuf,
    /// The file as given (copied into the variant's folder).
    pub text: String,
    table: toml::Table,
}

/// Reads and parses the overlay at `path`.
pub fn read_overlay(path: &Path) -> Result<Overlay, VariantError> {
    let text = std::fs::read_to_string(path).map_err(|error| VariantError::Io {
        path: path.to_owned(),
        message: error.to_string(),
    })?;
    parse_overlay(path, text)
}

/// Parses an overlay's text; rejects the keys compare sets on every run.
pub fn parse_overlay(path: &Path, text: String) -> Result<Overlay, VariantError> {
    let table: toml::Table =
        text.parse()
            .map_err(|error: toml::de::Error| VariantError::Syntax {
                path: path.to_owned(),
                message: error.to_string(),
            })?;
    for (keys, instead) in SET_PER_RUN {
        let Some((last, parents)) = keys.split_last() else {
            continue;
        };
        let mut value = Some(&table);
        for key in parents {
            value = value.and_then(|table| table.get(*key)?.as_table());
        }
        if value.is_some_and(|table| table.contains_key(*last)) {
            return Err(VariantError::SetPerRun {
                path: path.to_owned(),
                key: keys.join("."),
                instead,
            });
        }
    }
    Ok(Overlay {
        path: path.to_owned(),
        text,
        table,
    })
}

/// `base` with `overlay` merged over it, validated like a config file (the keys of every
/// process's table included).
pub fn apply(base: &HopnavConfig, overlay: &Overlay) -> Result<HopnavConfig, VariantError> {
    let invalid = |error| VariantError::Invalid {
        path: overlay.path.clone(),
        error,
    };
    let mut table: toml::Table = hopnav_config::to_toml(base)
        .map_err(invalid)?
        .parse()
        .map_err(|error: toml::de::Error| invalid(ConfigError::Serialize(error.to_string())))?;
    hopnav_config::deep_merge(&mut table, overlay.table.clone());
    let text = toml::to_string(&table)
        .map_err(|error| invalid(ConfigError::Serialize(error.to_string())))?;
    let config = hopnav_config::load(Some(&text)).map_err(invalid)?;
    registry::check_sections(&config).map_err(invalid)?;
    Ok(config)
}

/// One set of runs to launch: the base or the variant.
#[derive(Debug, Clone)]
pub struct RunSetPlan {
    /// "base" or "variant".
    pub label: String,
    /// Where its run folders, compare.csv and compare.json go.
    pub out: PathBuf,
    /// The config every run of the set starts from.
    pub config: HopnavConfig,
    pub modes: Vec<MissionMode>,
}

/// The base (both modes, in `out`) and, if given, the variant (its modes, in `out/variant`).
pub fn run_set_plans(
    base: &HopnavConfig,
    out: &Path,
    variant: Option<(HopnavConfig, VariantMode)>,
) -> Vec<RunSetPlan> {
    let mut plans = vec![RunSetPlan {
        label: "base".into(),
        out: out.to_owned(),
        config: base.clone(),
        modes: VariantMode::Both.modes(),
    }];
    if let Some((config, mode)) = variant {
        plans.push(RunSetPlan {
            label: "variant".into(),
            out: out.join("variant"),
            config,
            modes: mode.modes(),
        });
    }
    plans
}

fn set_value(config: &mut HopnavConfig, path: &[&str], value: toml::Value) {
    let Some((last, parents)) = path.split_last() else {
        return;
    };
    let mut table = &mut config.sections;
    for key in parents {
        let entry = table
            .entry((*key).to_owned())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = toml::Value::Table(toml::Table::new());
        }
        let Some(next) = entry.as_table_mut() else {
            return;
        };
        table = next;
    }
    table.insert((*last).to_owned(), value);
}

/// The config of one mission: `plan`'s, with the seed, rock abundance k, mode and frame limit.
pub fn mission_config(
    plan: &RunSetPlan,
    frames: u64,
    seed: u64,
    k: f64,
    mode: MissionMode,
) -> HopnavConfig {
    let mut config = plan.config.clone();
    set_value(
        &mut config,
        &["world", "seed"],
        toml::Value::Integer(seed as i64),
    );
    set_value(
        &mut config,
        &["world", "rocks", "golombek_k"],
        toml::Value::Float(k),
    );
    config.mission.mode = mode;
    config.mission.stop_on_goal = true;
    config.run.lockstep = true;
    config.run.frames = frames;
    config.run.out_dir = plan.out.display().to_string();
    config
}

#[cfg(test)]
mod tests {
    use super::*;

    fn overlay(text: &str) -> Result<Overlay, VariantError> {
        parse_overlay(Path::new("over.toml"), text.to_owned())
    }

    fn oracle(config: &HopnavConfig) -> Option<bool> {
        config
            .sections
            .get("mapper")?
            .get("oracle_prior_map")?
            .as_bool()
    }

    #[test]
    fn the_overlay_reaches_only_the_variant_and_its_chosen_mode() {
        let base = hopnav_config::load(None).expect("defaults");
        let over = overlay("[mapper]\noracle_prior_map = true\n").expect("valid overlay");
        let variant = apply(&base, &over).expect("applies");
        let plans = run_set_plans(
            &base,
            Path::new("/tmp/cmp"),
            Some((variant, VariantMode::Cooperative)),
        );
        assert_eq!(plans.len(), 2);
        assert_eq!(plans[0].modes, VariantMode::Both.modes());
        assert_eq!(plans[1].modes, vec![MissionMode::Cooperative]);
        assert_eq!(plans[1].out, Path::new("/tmp/cmp/variant"));
        for mode in VariantMode::Both.modes() {
            let config = mission_config(&plans[0], 30, 3, 0.1, mode);
            assert_ne!(oracle(&config), Some(true), "base {}", mode.name());
        }
        let config = mission_config(&plans[1], 30, 3, 0.1, MissionMode::Cooperative);
        assert_eq!(oracle(&config), Some(true));
        assert_eq!(config.mission.mode, MissionMode::Cooperative);
        assert_eq!(config.run.out_dir, "/tmp/cmp/variant");
        // Everything the overlay does not name stays the base's.
        let mut rest = plans[1].config.clone();
        assert!(rest.sections.remove("mapper").is_some());
        assert_eq!(rest, base);
    }

    #[test]
    fn an_empty_overlay_gives_the_base_and_modes_follow_the_option() {
        let base = hopnav_config::load(Some("[run]\nframes = 77\n")).expect("base");
        let same = apply(&base, &overlay("").expect("empty")).expect("applies");
        assert_eq!(same, base);
        assert_eq!(VariantMode::RoverOnly.modes(), vec![MissionMode::RoverOnly]);
        assert_eq!(VariantMode::default(), VariantMode::Both);
    }

    #[test]
    fn a_bad_overlay_names_the_file_and_the_key() {
        let base = hopnav_config::load(None).expect("defaults");
        let unknown = overlay("[mapper]\noracle_prior_mapp = true\n").expect("parses");
        let error = apply(&base, &unknown).expect_err("unknown key").to_string();
        assert!(error.starts_with("variant overlay over.toml: "), "{error}");
        assert!(error.contains("mapper.oracle_prior_mapp"), "{error}");
        let wrong_type = overlay("[mapper]\noracle_prior_map = 3\n").expect("parses");
        let error = apply(&base, &wrong_type)
            .expect_err("wrong type")
            .to_string();
        assert!(error.contains("mapper.oracle_prior_map"), "{error}");
        let error = overlay("[mapper\n").expect_err("syntax").to_string();
        assert!(
            error.starts_with("variant overlay over.toml is not valid TOML"),
            "{error}"
        );
        let error = overlay("[mission]\nmode = \"rover-only\"\n")
            .expect_err("per run")
            .to_string();
        assert!(
            error.contains("key mission.mode is set by compare"),
            "{error}"
        );
        assert!(error.contains("--variant-mode"), "{error}");
        let error = read_overlay(Path::new("/nonexistent/over.toml"))
            .expect_err("missing")
            .to_string();
        assert!(error.starts_with("variant overlay /nonexistent/over.toml: cannot read"));
    }
}
