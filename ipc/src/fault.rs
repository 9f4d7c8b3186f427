//! Faults executed inside a process: dropped and corrupted samples on chosen topics, and a delay
//! before every step. The supervisor hands a child its faults in the `HOPNAV_FAULTS`
//! environment variable (`seed=S;incarnation=I;SPEC;SPEC…`, specs as in
//! [`hopnav_config::fault`]); kills and stalls are the supervisor's own and never reach here.
//!
//! A corrupted sample goes out with its header's sequence number garbled into a repeat of the
//! previous one: every subscriber's sequence check must reject and count it.
//!
//! Decisions come from a per-topic generator seeded by the seed, the topic and the
//! incarnation, so a run with the same faults and seed drops the same samples.

use std::sync::{Mutex, OnceLock};
use std::time::Duration;

use hopnav_config::fault::{FaultKind, FaultSpec};

/// Environment variable carrying a child's faults.
pub const FAULTS_ENV: &str = "HOPNAV_FAULTS";

/// What the transport does with one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PublishAction {
    /// Send it as it is.
    Send,
    /// Do not send it.
    Drop,
    /// Send it with a garbled header.
    Corrupt,
}

#[derive(Debug)]
struct TopicFault {
    /// Full topic name (`hopnav/camera/jumper`).
    topic: String,
    drop_percent: f64,
    corrupt_percent: f64,
    rng_state: u64,
    dropped: u64,
    corrupted: u64,
}

#[derive(Debug, Default)]
struct FaultPlan {
    topics: Vec<TopicFault>,
    step_delay: Option<Duration>,
}

static PLAN: OnceLock<Mutex<FaultPlan>> = OnceLock::new();

fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn hash_text(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Encodes `specs` for one child (only the in-process kinds are kept).
pub fn encode_env(seed: u64, incarnation: u32, specs: &[FaultSpec]) -> Option<String> {
    let kept: Vec<&str> = specs
        .iter()
        .filter(|spec| {
            matches!(
                spec.kind,
                FaultKind::Drop { .. } | FaultKind::Corrupt { .. } | FaultKind::Delay { .. }
            )
        })
        .map(|spec| spec.text.as_str())
        .collect();
    (!kept.is_empty()).then(|| format!("seed={seed};incarnation={incarnation};{}", kept.join(";")))
}

/// Why `HOPNAV_FAULTS` could not be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{FAULTS_ENV}: {0}")]
pub struct FaultEnvError(String);

fn parse_plan(text: &str) -> Result<FaultPlan, FaultEnvError> {
    let mut seed = 0u64;
    let mut incarnation = 0u64;
    let mut plan = FaultPlan::default();
    for part in text.split(';').filter(|part| !part.is_empty()) {
        if let Some(value) = part.strip_prefix("seed=") {
            seed = value
                .parse()
                .map_err(|_| FaultEnvError(format!("bad seed {value:?}")))?;
            continue;
        }
        if let Some(value) = part.strip_prefix("incarnation=") {
            incarnation = value
                .parse()
                .map_err(|_| FaultEnvError(format!("bad incarnation {value:?}")))?;
            continue;
        }
        let spec: FaultSpec =
            part.parse()
                .map_err(|error: hopnav_config::fault::FaultParseError| {
                    FaultEnvError(error.to_string())
                })?;
        if let FaultKind::Delay { delay_ms } = spec.kind {
            plan.step_delay = Some(Duration::from_millis(delay_ms));
            continue;
        }
        let Some(topic) = spec.topic.as_deref() else {
            continue;
        };
        let topic = format!("hopnav/{topic}");
        let index = match plan.topics.iter().position(|fault| fault.topic == topic) {
            Some(index) => index,
            None => {
                plan.topics.push(TopicFault {
                    rng_state: seed ^ hash_text(&topic) ^ incarnation.rotate_left(32),
                    topic,
                    drop_percent: 0.0,
                    corrupt_percent: 0.0,
                    dropped: 0,
                    corrupted: 0,
                });
                plan.topics.len() - 1
            }
        };
        match spec.kind {
            FaultKind::Drop { percent } => plan.topics[index].drop_percent = percent,
            FaultKind::Corrupt { percent } => plan.topics[index].corrupt_percent = percent,
            _ => {}
        }
    }
    Ok(plan)
}

/// Reads `HOPNAV_FAULTS` once per process (absent = no faults).
pub fn install_from_env() -> Result<(), FaultEnvError> {
    install(std::env::var(FAULTS_ENV).ok().as_deref())
}

/// Installs faults in the `HOPNAV_FAULTS` format (`None` = no faults); a warm standby gets
/// them on promotion, when its incarnation is known. The first call per process wins.
pub fn install(text: Option<&str>) -> Result<(), FaultEnvError> {
    let plan = match text {
        Some(text) => parse_plan(text)?,
        None => FaultPlan::default(),
    };
    let _ = PLAN.set(Mutex::new(plan));
    Ok(())
}

/// The decision for the next sample on `topic`.
pub fn on_publish(topic: &str) -> PublishAction {
    let Some(plan) = PLAN.get() else {
        return PublishAction::Send;
    };
    let Ok(mut plan) = plan.lock() else {
        return PublishAction::Send;
    };
    let Some(fault) = plan.topics.iter_mut().find(|fault| fault.topic == topic) else {
        return PublishAction::Send;
    };
    let draw = (splitmix(&mut fault.rng_state) >> 11) as f64 / (1u64 << 53) as f64 * 100.0;
    if draw < fault.drop_percent {
        fault.dropped += 1;
        PublishAction::Drop
    } else if draw < fault.drop_percent + fault.corrupt_percent {
        fault.corrupted += 1;
        PublishAction::Corrupt
    } else {
        PublishAction::Send
    }
}

/// The delay to apply before every step, if any.
pub fn step_delay() -> Option<Duration> {
    PLAN.get()
        .and_then(|plan| plan.lock().ok().and_then(|plan| plan.step_delay))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decisions_follow_the_rates_and_the_seed() {
        let mut plan = parse_plan("seed=7;incarnation=0;drop:camera/jumper@10%;corrupt:camera/jumper@5%;delay:camera@50ms").unwrap();
        assert_eq!(plan.step_delay, Some(Duration::from_millis(50)));
        let fault = &mut plan.topics[0];
        assert_eq!(fault.topic, "hopnav/camera/jumper");
        let mut state = fault.rng_state;
        let (mut drops, mut corrupts) = (0, 0);
        for _ in 0..10_000 {
            let draw = (splitmix(&mut state) >> 11) as f64 / (1u64 << 53) as f64 * 100.0;
            if draw < 10.0 {
                drops += 1;
            } else if draw < 15.0 {
                corrupts += 1;
            }
        }
        assert!((900..1100).contains(&drops), "{drops}");
        assert!((400..600).contains(&corrupts), "{corrupts}");
        assert!(parse_plan("seed=x").is_err());
        assert!(parse_plan("drop:camera@10%").is_err());
    }

    #[test]
    fn only_in_process_kinds_travel_to_the_child() {
        let specs: Vec<FaultSpec> = ["kill:camera@1s", "drop:camera/jumper@10%"]
            .iter()
            .map(|text| text.parse().unwrap())
            .collect();
        assert_eq!(
            encode_env(3, 1, &specs).as_deref(),
            Some("seed=3;incarnation=1;drop:camera/jumper@10%")
        );
        assert_eq!(encode_env(3, 1, &specs[..1]), None);
    }
}
