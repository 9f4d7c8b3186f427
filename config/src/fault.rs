//! Fault specifications: `kind:target[@when][+duration]`, from `[faults] inject` and from
//! `hopnav launch --fault`. The supervisor executes kills and stalls; drops, corruption and
//! delays are executed inside the target process by its transport and loop.
//!
//! ```
//! use hopnav_config::fault::{FaultKind, FaultSpec, FaultTime};
//! let kill: FaultSpec = "kill:jumper_vo@3s".parse()?;
//! assert_eq!(kill.process, "jumper_vo");
//! assert_eq!(kill.at, Some(FaultTime::Seconds(3.0)));
//! let stall: FaultSpec = "stall:mapper@5s+800ms".parse()?;
//! assert_eq!(stall.kind, FaultKind::Stall { duration_ms: 800 });
//! let drop: FaultSpec = "drop:camera/jumper@10%".parse()?;
//! assert_eq!(drop.kind, FaultKind::Drop { percent: 10.0 });
//! assert_eq!(drop.topic.as_deref(), Some("camera/jumper"));
//! # Ok::<(), hopnav_config::fault::FaultParseError>(())
//! ```

use serde::{Deserialize, Serialize};

/// What a fault does.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum FaultKind {
    /// SIGKILL the process once.
    Kill,
    /// SIGSTOP the process, SIGCONT it after `duration_ms` (a hang if longer than the
    /// watchdog's timeout).
    Stall {
        /// Stop time, milliseconds.
        duration_ms: u64,
    },
    /// Drop this share of the process's samples on one topic.
    Drop {
        /// Percent of samples, 0..=100.
        percent: f64,
    },
    /// Corrupt this share of the samples on one topic (consumers must reject them).
    Corrupt {
        /// Percent of samples, 0..=100.
        percent: f64,
    },
    /// Delay every step of the process by this long.
    Delay {
        /// Delay, milliseconds.
        delay_ms: u64,
    },
}

/// When a one-shot fault fires.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum FaultTime {
    /// Simulated seconds after the start (frame = seconds × frame rate).
    Seconds(f64),
    /// At the start of this frame.
    Frame(u64),
}

impl FaultTime {
    /// The frame at which the fault fires, at `frame_rate_hz`.
    pub fn frame(&self, frame_rate_hz: f64) -> u64 {
        match *self {
            FaultTime::Seconds(seconds) => (seconds * frame_rate_hz).round().max(0.0) as u64,
            FaultTime::Frame(frame) => frame,
        }
    }
}

/// One fault.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaultSpec {
    /// What it does.
    pub kind: FaultKind,
    /// The process it targets.
    pub process: String,
    /// For drop and corrupt: the topic below `hopnav/` (e.g. `camera/jumper`); its first
    /// part names the publishing process.
    pub topic: Option<String>,
    /// When kill and stall fire.
    pub at: Option<FaultTime>,
    /// The text it was parsed from.
    pub text: String,
}

/// Why a fault specification is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "fault {text:?}: {reason} (syntax: kill:PROC@3s | stall:PROC@5s+800ms | drop:PROC/TOPIC@10% | corrupt:PROC/TOPIC@5% | delay:PROC@50ms; times as 3s, 250ms or f30 for frame 30)"
)]
pub struct FaultParseError {
    /// The specification.
    pub text: String,
    /// What is wrong.
    pub reason: String,
}

fn error(text: &str, reason: impl Into<String>) -> FaultParseError {
    FaultParseError {
        text: text.to_owned(),
        reason: reason.into(),
    }
}

/// `3s`, `2.5s`, `250ms` → milliseconds.
fn parse_duration_ms(text: &str, value: &str) -> Result<u64, FaultParseError> {
    let (number, scale) = if let Some(ms) = value.strip_suffix("ms") {
        (ms, 1.0)
    } else if let Some(s) = value.strip_suffix('s') {
        (s, 1000.0)
    } else {
        return Err(error(
            text,
            format!("duration {value:?} needs a unit (ms or s)"),
        ));
    };
    let parsed: f64 = number
        .parse()
        .map_err(|_| error(text, format!("{number:?} is not a number")))?;
    let ms = parsed * scale;
    if !(ms.is_finite() && (0.0..=3_600_000.0).contains(&ms)) {
        return Err(error(
            text,
            format!("duration {value:?} is outside 0..=1 h"),
        ));
    }
    Ok(ms.round() as u64)
}

fn parse_time(text: &str, value: &str) -> Result<FaultTime, FaultParseError> {
    if let Some(frame) = value.strip_prefix('f') {
        return frame
            .parse()
            .map(FaultTime::Frame)
            .map_err(|_| error(text, format!("frame {frame:?} is not a whole number")));
    }
    Ok(FaultTime::Seconds(
        parse_duration_ms(text, value)? as f64 / 1000.0,
    ))
}

fn parse_percent(text: &str, value: &str) -> Result<f64, FaultParseError> {
    let number = value
        .strip_suffix('%')
        .ok_or_else(|| error(text, format!("rate {value:?} must end in %")))?;
    let percent: f64 = number
        .parse()
        .map_err(|_| error(text, format!("{number:?} is not a number")))?;
    if !(percent.is_finite() && (0.0..=100.0).contains(&percent)) {
        return Err(error(text, format!("rate {percent}% is outside 0..=100")));
    }
    Ok(percent)
}

fn check_name(text: &str, what: &str, name: &str) -> Result<(), FaultParseError> {
    let valid = !name.is_empty()
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/');
    if valid {
        Ok(())
    } else {
        Err(error(
            text,
            format!("{what} {name:?} must be 1..=64 of [A-Za-z0-9_/]"),
        ))
    }
}

impl std::str::FromStr for FaultSpec {
    type Err = FaultParseError;

    fn from_str(text: &str) -> Result<Self, FaultParseError> {
        let (kind, rest) = text
            .split_once(':')
            .ok_or_else(|| error(text, "missing ':' after the fault kind"))?;
        let (target, when) = rest
            .split_once('@')
            .ok_or_else(|| error(text, "missing '@' (when, rate or delay)"))?;
        check_name(text, "target", target)?;
        let (process, topic) = match target.split_once('/') {
            Some((process, _)) => (process.to_owned(), Some(target.to_owned())),
            None => (target.to_owned(), None),
        };
        let needs_topic = matches!(kind, "drop" | "corrupt");
        if needs_topic != topic.is_some() {
            return Err(error(
                text,
                if needs_topic {
                    "drop and corrupt need PROCESS/TOPIC (e.g. camera/jumper)"
                } else {
                    "only drop and corrupt take a topic"
                },
            ));
        }
        let (kind, at) = match kind {
            "kill" => (FaultKind::Kill, Some(parse_time(text, when)?)),
            "stall" => {
                let (at, duration) = when
                    .split_once('+')
                    .ok_or_else(|| error(text, "stall needs @TIME+DURATION"))?;
                let duration_ms = parse_duration_ms(text, duration)?;
                (
                    FaultKind::Stall { duration_ms },
                    Some(parse_time(text, at)?),
                )
            }
            "drop" => (
                FaultKind::Drop {
                    percent: parse_percent(text, when)?,
                },
                None,
            ),
            "corrupt" => (
                FaultKind::Corrupt {
                    percent: parse_percent(text, when)?,
                },
                None,
            ),
            "delay" => (
                FaultKind::Delay {
                    delay_ms: parse_duration_ms(text, when)?,
                },
                None,
            ),
            other => {
                return Err(error(
                    text,
                    format!("unknown kind {other:?} (kill, stall, drop, corrupt, delay)"),
                ));
            }
        };
        Ok(FaultSpec {
            kind,
            process,
            topic,
            at,
            text: text.to_owned(),
        })
    }
}

/// `[faults]`: faults every launch of this config injects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultsConfig {
    /// Specifications, same syntax as `--fault`.
    pub inject: Vec<String>,
    /// Seed of the random drop/corrupt decisions (reproducible runs).
    pub seed: u64,
}

impl Default for FaultsConfig {
    fn default() -> Self {
        Self {
            inject: Vec::new(),
            seed: 1,
        }
    }
}

impl FaultsConfig {
    /// Parses every specification.
    pub fn specs(&self) -> Result<Vec<FaultSpec>, FaultParseError> {
        self.inject.iter().map(|text| text.parse()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_kind() {
        let spec: FaultSpec = "corrupt:rover_vo/cloud@5%".parse().unwrap();
        assert_eq!(spec.kind, FaultKind::Corrupt { percent: 5.0 });
        assert_eq!(spec.process, "rover_vo");
        let spec: FaultSpec = "delay:camera@50ms".parse().unwrap();
        assert_eq!(spec.kind, FaultKind::Delay { delay_ms: 50 });
        let spec: FaultSpec = "kill:planner@f12".parse().unwrap();
        assert_eq!(spec.at, Some(FaultTime::Frame(12)));
        assert_eq!(spec.at.unwrap().frame(10.0), 12);
        assert_eq!(FaultTime::Seconds(3.0).frame(10.0), 30);
    }

    #[test]
    fn errors_name_the_problem() {
        for (text, needle) in [
            ("kill", "missing ':'"),
            ("kill:physics", "missing '@'"),
            ("explode:physics@1s", "unknown kind"),
            ("kill:physics@3", "needs a unit"),
            ("drop:camera@10%", "need PROCESS/TOPIC"),
            ("kill:camera/jumper@1s", "only drop and corrupt"),
            ("drop:camera/jumper@150%", "outside 0..=100"),
            ("stall:mapper@5s", "stall needs"),
            ("kill:bad name@1s", "must be 1..=64"),
            ("delay:camera@NaNms", "outside 0..=1 h"),
        ] {
            let error = text.parse::<FaultSpec>().unwrap_err().to_string();
            assert!(error.contains(needle), "{text}: {error}");
        }
    }
}
