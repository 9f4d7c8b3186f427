//! Range checks; each failure names its key and the allowed range.

use crate::{ConfigError, HopnavConfig};

fn check<T: PartialOrd + std::fmt::Display>(
    key: &str,
    value: T,
    min: T,
    max: T,
) -> Result<(), ConfigError> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(ConfigError::OutOfRange {
            key: key.to_owned(),
            value: value.to_string(),
            allowed: format!("[{min}, {max}]"),
        })
    }
}

fn check_f64(key: &str, value: f64, min: f64, max: f64) -> Result<(), ConfigError> {
    if value.is_finite() {
        check(key, value, min, max)
    } else {
        Err(ConfigError::OutOfRange {
            key: key.to_owned(),
            value: value.to_string(),
            allowed: format!("a finite number in [{min}, {max}]"),
        })
    }
}

/// Checks every range of the configuration.
pub fn validate(config: &HopnavConfig) -> Result<(), ConfigError> {
    validate_run(config)?;
    validate_watchdog(config)?;
    config.faults.specs().map_err(|error| ConfigError::Schema {
        key: "faults.inject".into(),
        message: error.to_string(),
    })?;
    validate_restart(config)?;
    validate_processes(config)?;
    let recorder_enabled = config
        .processes
        .get("recorder")
        .is_some_and(|process| process.enabled);
    let recorder_has_output = [
        &config.recorder.dir,
        &config.recorder.mcap,
        &config.recorder.viewer,
    ]
    .iter()
    .any(|output| !output.trim().is_empty());
    if recorder_enabled && !recorder_has_output {
        return Err(ConfigError::OutOfRange {
            key: "recorder.dir".into(),
            value: "\"\"".into(),
            allowed: "a folder path (or recorder.mcap, a file, or recorder.viewer, an address) \
                      when processes.recorder.enabled (or use --export-dataset DIR, \
                      --record FILE.mcap, --viewer)"
                .into(),
        });
    }
    check("probe.width_px", config.probe.width_px, 1, 8192)?;
    check("probe.height_px", config.probe.height_px, 1, 8192)?;
    Ok(())
}

/// `[run]`: rate, length, timeouts and the output folder.
fn validate_run(config: &HopnavConfig) -> Result<(), ConfigError> {
    let run = &config.run;
    check_f64("run.frame_rate_hz", run.frame_rate_hz, 0.1, 1000.0)?;
    check("run.frames", run.frames, 1, 10_000_000)?;
    check_f64("run.startup_timeout_s", run.startup_timeout_s, 0.1, 600.0)?;
    check_f64("run.shutdown_timeout_s", run.shutdown_timeout_s, 0.1, 600.0)?;
    if run.out_dir.trim().is_empty() {
        return Err(ConfigError::OutOfRange {
            key: "run.out_dir".into(),
            value: format!("{:?}", run.out_dir),
            allowed: "a non-empty path".into(),
        });
    }
    Ok(())
}

/// `[watchdog]`: the heartbeat limit, and the stall limit below it.
fn validate_watchdog(config: &HopnavConfig) -> Result<(), ConfigError> {
    check(
        "watchdog.heartbeat_timeout_frames",
        config.watchdog.heartbeat_timeout_frames,
        2,
        100_000,
    )?;
    check_f64(
        "watchdog.stall_timeout_frames",
        config.watchdog.stall_timeout_frames,
        1.1,
        f64::from(config.watchdog.heartbeat_timeout_frames),
    )?;
    Ok(())
}

/// `[restart]`: intensity and back-off.
fn validate_restart(config: &HopnavConfig) -> Result<(), ConfigError> {
    let restart = &config.restart;
    check("restart.max_restarts", restart.max_restarts, 0, 1000)?;
    check_f64("restart.window_s", restart.window_s, 0.1, 86_400.0)?;
    check(
        "restart.backoff_initial_ms",
        restart.backoff_initial_ms,
        0,
        60_000,
    )?;
    check(
        "restart.backoff_max_ms",
        restart.backoff_max_ms,
        restart.backoff_initial_ms,
        600_000,
    )?;
    Ok(())
}

/// `[processes]`: at least one enabled, names, stages and budgets.
fn validate_processes(config: &HopnavConfig) -> Result<(), ConfigError> {
    if !config.processes.values().any(|process| process.enabled) {
        return Err(ConfigError::OutOfRange {
            key: "processes".into(),
            value: "no enabled process".into(),
            allowed: "at least one process with enabled = true".into(),
        });
    }
    for (name, process) in &config.processes {
        let valid_name = !name.is_empty()
            && name.len() <= 32
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if !valid_name {
            return Err(ConfigError::OutOfRange {
                key: format!("processes.{name}"),
                value: format!("{name:?}"),
                allowed: "a name of 1..=32 characters of [a-z0-9_]".into(),
            });
        }
        check(&format!("processes.{name}.stage"), process.stage, 0, 15)?;
        check_f64(
            &format!("processes.{name}.budget_ms"),
            process.budget_ms,
            0.01,
            60_000.0,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::load;

    fn error_of(text: &str) -> String {
        load(Some(text)).expect_err("must be rejected").to_string()
    }

    /// `text` is rejected with an error that names every one of `parts`.
    fn assert_rejected_naming(text: &str, parts: &[&str]) {
        let message = error_of(text);
        for part in parts {
            assert!(message.contains(part), "{part}: {message}");
        }
    }

    #[test]
    fn defaults_are_valid() {
        let config = load(None).expect("defaults");
        assert_eq!(config.run.frame_rate_hz, 10.0);
        assert!(config.processes.len() >= 2);
    }

    #[test]
    fn out_of_range_values_name_key_and_range() {
        assert_rejected_naming(
            "[run]\nframe_rate_hz = 0.0\n",
            &["run.frame_rate_hz", "[0.1, 1000]"],
        );
        assert_rejected_naming(
            "[processes.probe_sink]\nbudget_ms = -3.0\n",
            &["processes.probe_sink.budget_ms"],
        );
        assert_rejected_naming(
            "[restart]\nbackoff_initial_ms = 500\nbackoff_max_ms = 100\n",
            &["restart.backoff_max_ms"],
        );
        assert_rejected_naming("[run]\nframe_rate_hz = nan\n", &["finite"]);
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_the_key() {
        assert_rejected_naming("[run]\nframe_rat_hz = 5.0\n", &["run", "frame_rat_hz"]);
        assert_rejected_naming("[run]\nframes = \"many\"\n", &["run.frames"]);
        assert_rejected_naming(
            "[processes.probe_sink]\nrestart = \"sometimes\"\n",
            &["processes.probe_sink.restart"],
        );
    }

    #[test]
    fn sections_parse_with_full_key_paths_and_unknown_tables_are_named() {
        #[derive(serde::Deserialize, Debug, Default)]
        #[serde(deny_unknown_fields, default)]
        struct Jumper {
            launch_speed_mps: f64,
        }
        #[derive(serde::Deserialize, Debug, Default)]
        #[serde(deny_unknown_fields, default)]
        struct Physics {
            jumper: Jumper,
        }
        let config = load(Some("[physics.jumper]\nlaunch_speed_mps = 9.0\n")).expect("valid");
        let physics: Physics = crate::parse_section(&config, "physics").expect("parse");
        assert_eq!(physics.jumper.launch_speed_mps, 9.0);
        let absent: Physics = crate::parse_section(&config, "nothing").expect("defaults");
        assert_eq!(absent.jumper.launch_speed_mps, 0.0);
        let config = load(Some("[physics.jumper]\nlaunch_speed_mps = \"fast\"\n")).expect("loads");
        let error = crate::parse_section::<Physics>(&config, "physics").expect_err("type");
        assert!(
            error
                .to_string()
                .contains("physics.jumper.launch_speed_mps"),
            "{error}"
        );
        let config = load(Some("[phsyics]\nx = 1\n")).expect("loads");
        let known = ["physics", "world", "mapper", "planner"];
        let error = crate::check_section_names(&config, &known).expect_err("typo");
        assert!(error.to_string().contains("phsyics"), "{error}");
    }

    #[test]
    fn syntax_errors_are_reported_not_panicked() {
        let message = error_of("[run\nframes = 3");
        assert!(message.contains("not valid TOML"), "{message}");
    }

    #[test]
    fn config_round_trips_through_toml() {
        let config = load(Some("[run]\nframes = 7\nlockstep = true\n")).expect("valid");
        let text = crate::to_toml(&config).expect("serialize");
        assert_eq!(load(Some(&text)).expect("reload"), config);
    }

    #[test]
    fn arbitrary_text_never_panics() {
        let mut state = 0xdead_beef_u64;
        let alphabet = b"[]=.\"\n abcdefghijklmnoprstuvwxyz_0123456789-+e";
        for len in 0..400 {
            let text: String = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    alphabet[(state % alphabet.len() as u64) as usize] as char
                })
                .collect();
            let _ = load(Some(&text));
        }
    }
}
