//! `hopnav_config::load` takes a file from the user: whatever it holds (any text, invalid UTF-8
//! read lossily, huge or non-finite numbers, deep nesting, wrong types), the answer is a
//! config or a `ConfigError`, never a panic. A config that loads satisfies every range check
//! and survives the round trip through the TOML that is written next to each run.

use hopnav_config::{HopnavConfig, load, to_toml};
use proptest::prelude::*;

/// Checks that hold for every config `load` accepts.
fn check_loaded(config: &HopnavConfig) -> Result<(), TestCaseError> {
    let run = &config.run;
    prop_assert!(run.frame_rate_hz.is_finite() && (0.1..=1000.0).contains(&run.frame_rate_hz));
    prop_assert!((1..=10_000_000).contains(&run.frames));
    prop_assert!(run.startup_timeout_s.is_finite() && run.shutdown_timeout_s.is_finite());
    prop_assert!(!run.out_dir.trim().is_empty());
    prop_assert!(config.restart.backoff_initial_ms <= config.restart.backoff_max_ms);
    prop_assert!(config.processes.values().any(|process| process.enabled));
    for (name, process) in &config.processes {
        prop_assert!(!name.is_empty() && name.len() <= 32);
        prop_assert!(process.stage <= 15 && process.budget_ms.is_finite());
    }
    prop_assert!((1..=8192).contains(&config.probe.width_px));
    let _ = run.frame_period_s();
    let _ = hopnav_config::check_section_names(config, &["world", "planner"]);
    let _ = hopnav_config::parse_section::<toml::Table>(config, "physics");
    let _ =
        hopnav_config::parse_section::<std::collections::BTreeMap<String, f64>>(config, "planner");
    // The config written next to a run must load back as itself (text-equal: NaN in a
    // process section would defeat `==`).
    let text = to_toml(config).map_err(|error| TestCaseError::fail(error.to_string()))?;
    let reloaded = load(Some(&text)).map_err(|error| TestCaseError::fail(error.to_string()))?;
    let again = to_toml(&reloaded).map_err(|error| TestCaseError::fail(error.to_string()))?;
    prop_assert_eq!(text, again);
    Ok(())
}

fn load_checked(text: &str) -> Result<(), TestCaseError> {
    match load(Some(text)) {
        Ok(config) => check_loaded(&config),
        Err(error) => {
            // Every error renders (and names something).
            prop_assert!(!error.to_string().is_empty());
            Ok(())
        }
    }
}

/// Keys the schema knows, with a plausible value for each so some inputs pass validation.
const KNOWN: &[(&str, &[&str])] = &[
    (
        "run",
        &[
            "frame_rate_hz",
            "frames",
            "lockstep",
            "startup_timeout_s",
            "shutdown_timeout_s",
            "out_dir",
        ],
    ),
    (
        "watchdog",
        &["heartbeat_timeout_frames", "stall_timeout_frames"],
    ),
    (
        "restart",
        &[
            "max_restarts",
            "window_s",
            "backoff_initial_ms",
            "backoff_max_ms",
            "warm_standby",
        ],
    ),
    ("probe", &["width_px", "height_px"]),
    ("recorder", &["dir", "mcap"]),
    ("mission", &["mode", "stop_on_goal"]),
    (
        "processes.physics",
        &["enabled", "stage", "budget_ms", "restart"],
    ),
    (
        "processes.recorder",
        &["enabled", "stage", "budget_ms", "restart"],
    ),
    ("planner", &["goal_tolerance_m", "lookahead_m"]),
    ("world.scenario", &["start_m", "goal_m"]),
];

/// A TOML key: bare when it can be, else a quoted string with escapes.
fn key_text(key: &str) -> String {
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        key.to_owned()
    } else {
        toml::Value::String(key.to_owned()).to_string()
    }
}

fn leaf_value() -> impl Strategy<Value = String> {
    prop_oneof![
        // Plausible values of every type the schema uses.
        (0_i64..40).prop_map(|n| n.to_string()),
        (0.0_f64..100.0).prop_map(|x| format!("{x:?}")),
        any::<bool>().prop_map(|b| b.to_string()),
        prop::sample::select(vec![
            "\"never\"",
            "\"on-failure\"",
            "\"always\"",
            "\"cooperative\"",
            "\"rover-only\"",
            "\"runs\"",
            "\"\"",
            "\"  \"",
            "\"sometimes\"",
        ])
        .prop_map(str::to_owned),
        // Edges: huge, negative, non-finite, overflowing, odd syntax.
        any::<i64>().prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|x| toml::Value::Float(x).to_string()),
        prop::sample::select(vec![
            "nan",
            "+nan",
            "-nan",
            "inf",
            "-inf",
            "1e999",
            "-1e999",
            "5e-324",
            "-0.0",
            "9223372036854775807",
            "-9223372036854775808",
            "9223372036854775808",
            "99999999999999999999999",
            "0x7fffffffffffffff",
            "0o777",
            "0b1",
            "1_000",
            "1979-05-27T07:32:00Z",
            "07:32:00",
            "1979-05-27",
            "'literal'",
            "\"\\u0000\"",
            "\"\\uD800\"",
            "\"\"\"multi\nline\"\"\"",
            "[]",
            "{}",
            "[1, \"mixed\", 2.0]",
        ])
        .prop_map(str::to_owned),
        any::<String>().prop_map(|s| toml::Value::String(s).to_string()),
    ]
}

/// A value: a leaf, or arrays and inline tables nested a few levels.
fn value() -> impl Strategy<Value = String> {
    leaf_value().prop_recursive(3, 16, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4)
                .prop_map(|items| format!("[{}]", items.join(", "))),
            prop::collection::vec(("[a-z_]{1,8}", inner), 0..4).prop_map(|entries| {
                let body: Vec<String> = entries
                    .into_iter()
                    .map(|(key, value)| format!("{key} = {value}"))
                    .collect();
                format!("{{{}}}", body.join(", "))
            }),
        ]
    })
}

/// A table header: known sections, new process names (valid or not), unknown tables.
fn section() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => prop::sample::select(KNOWN.iter().map(|(name, _)| *name).collect::<Vec<_>>())
            .prop_map(str::to_owned),
        1 => "[a-z0-9_]{1,40}".prop_map(|name| format!("processes.{name}")),
        1 => any::<String>().prop_map(|name| format!("processes.{}", key_text(&name))),
        1 => "[a-z]{1,10}(\\.[a-z]{1,10}){0,3}",
        1 => Just("processes".to_owned()),
    ]
}

/// A key for `section`: mostly one it knows, sometimes a typo or garbage.
fn entry(section: String) -> impl Strategy<Value = (String, String)> {
    let known: Vec<&'static str> = KNOWN
        .iter()
        .find(|(name, _)| *name == section)
        .map(|(_, keys)| keys.to_vec())
        .unwrap_or_else(|| vec!["enabled", "stage", "budget_ms", "restart"]);
    let key = prop_oneof![
        8 => prop::sample::select(known).prop_map(str::to_owned),
        1 => "[a-z_]{1,12}",
        1 => any::<String>().prop_map(|key| key_text(&key)),
    ];
    (key, value()).prop_map(|(key, value)| (key, value))
}

fn near_valid_toml() -> impl Strategy<Value = String> {
    let table = section()
        .prop_flat_map(|name| (Just(name.clone()), prop::collection::vec(entry(name), 0..5)));
    prop::collection::vec(table, 0..5).prop_map(|tables| {
        // One header per table and one line per key, as a redefinition is just a syntax error.
        let mut merged =
            std::collections::BTreeMap::<String, std::collections::BTreeMap<_, _>>::new();
        for (name, entries) in tables {
            merged.entry(name).or_default().extend(entries);
        }
        let mut text = String::new();
        for (name, entries) in merged {
            text.push_str(&format!("[{name}]\n"));
            for (key, value) in entries {
                text.push_str(&format!("{key} = {value}\n"));
            }
        }
        text
    })
}

proptest! {
    #[test]
    fn arbitrary_strings(text in any::<String>()) {
        load_checked(&text)?;
    }

    #[test]
    fn arbitrary_bytes_read_lossily(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        load_checked(&String::from_utf8_lossy(&bytes))?;
    }

    #[test]
    fn toml_alphabet(text in "[\\[\\]{}=.,\"'\\n a-z_0-9+\\-:#]{0,200}") {
        load_checked(&text)?;
    }

    #[test]
    fn near_valid_tables(text in near_valid_toml()) {
        load_checked(&text)?;
    }

    /// Valid inputs with one corrupted byte: errors point into real structure.
    #[test]
    fn mutated_defaults(
        position in any::<prop::sample::Index>(),
        byte in any::<u8>(),
        cut in any::<bool>(),
    ) {
        let mut bytes = hopnav_config::DEFAULT_TOML.as_bytes().to_vec();
        let index = position.index(bytes.len());
        if cut {
            bytes.truncate(index);
        } else {
            bytes[index] = byte;
        }
        load_checked(&String::from_utf8_lossy(&bytes))?;
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    for depth in [100, 10_000, 200_000] {
        let arrays = format!("a = {}{}", "[".repeat(depth), "]".repeat(depth));
        assert!(load(Some(&arrays)).is_err());
        let inline = format!("a = {}1{}", "{b = ".repeat(depth), "}".repeat(depth));
        assert!(load(Some(&inline)).is_err());
        let dotted = format!("[{}]\n", vec!["a"; depth].join("."));
        assert!(load(Some(&dotted)).is_err());
        let keys = format!("{} = 1\n", vec!["a"; depth].join("."));
        assert!(load(Some(&keys)).is_err());
    }
}

#[test]
fn huge_and_non_finite_numbers_are_rejected_with_the_key() {
    for (text, key) in [
        ("[run]\nframe_rate_hz = inf\n", "run.frame_rate_hz"),
        ("[run]\nframe_rate_hz = -nan\n", "run.frame_rate_hz"),
        ("[run]\nframes = -1\n", "run.frames"),
        (
            "[watchdog]\nheartbeat_timeout_frames = 9223372036854775807\n",
            "watchdog.heartbeat_timeout_frames",
        ),
        ("[restart]\nwindow_s = 1e308\n", "restart.window_s"),
        (
            "[processes.physics]\nbudget_ms = 5e-324\n",
            "processes.physics.budget_ms",
        ),
        (
            "[processes.physics]\nstage = 4294967296\n",
            "processes.physics.stage",
        ),
    ] {
        let error = load(Some(text)).expect_err(text).to_string();
        assert!(error.contains(key), "{text:?}: {error}");
    }
    assert!(load(Some("[run]\nframes = 99999999999999999999\n")).is_err());
}
