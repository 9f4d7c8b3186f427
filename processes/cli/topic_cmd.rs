//! `hopnav topic`: look at the topics of a running launch from outside the graph.
//!
//! The tools find the launch by themselves when one runs (`--run ID` picks one of several),
//! open only topics that exist, take no history and never a subscriber slot the graph needs.

use std::process::ExitCode;

use clap::{Args, Subcommand};
use hopnav_ipc::live::{self, KnownTopic, LiveError, RunSelectError, TopicRow};
use hopnav_ipc::namespace::Namespace;
use hopnav_ipc::transport::OpenError;

use crate::text_table::align_columns;
use crate::topic_bw::{self, BwArgs};
use crate::topic_echo::{self, EchoArgs};
use crate::topic_hz::{self, HzArgs};

#[derive(Debug, Subcommand)]
pub enum TopicCommand {
    /// One line per topic of the running launch: name, message type, publishing and
    /// subscribing processes (as iceoryx2 records them), subscriber slots in use, bytes per
    /// sample.
    List(ListArgs),
    /// Receive rate of one topic, printed every second (mean rate over the window, min and
    /// max period, spread), as an extra subscriber that never holds the launch back.
    Hz(HzArgs),
    /// Bandwidth of one topic, printed every second: bytes per second over the window, mean,
    /// smallest and largest sample (the bytes a sample occupies in shared memory, which a
    /// bridge or a recorder of the topic would have to carry).
    Bw(BwArgs),
    /// Print the samples of one topic as they arrive: every field of small messages (poses,
    /// commands), the header and size of images, clouds and maps.
    Echo(EchoArgs),
}

/// Which launch to look at.
#[derive(Debug, Args)]
pub struct RunChoice {
    /// Run id of the launch (needed only when several launches run).
    #[arg(long = "run", value_name = "ID")]
    run_id: Option<String>,
}

#[derive(Debug, Args)]
pub struct ListArgs {
    #[command(flatten)]
    run: RunChoice,
}

pub fn run(command: TopicCommand) -> ExitCode {
    match command {
        TopicCommand::List(args) => list(&args),
        TopicCommand::Hz(args) => topic_hz::run(&args),
        TopicCommand::Bw(args) => topic_bw::run(&args),
        TopicCommand::Echo(args) => topic_echo::run(&args),
    }
}

impl RunChoice {
    /// The launch's namespace, or the exit code after saying why there is none.
    pub fn namespace(&self) -> Result<Namespace, ExitCode> {
        live::find_launch(self.run_id.as_deref()).map_err(|error| {
            eprintln!("error: {error}");
            ExitCode::from(match error {
                RunSelectError::NoLaunch => 1,
                RunSelectError::Ambiguous(_) | RunSelectError::NotRunning { .. } => {
                    crate::EXIT_CONFIG
                }
            })
        })
    }

    /// The launch's namespace and its topic named `name`, or the exit code after saying why
    /// there is no such launch or topic.
    pub fn topic(&self, name: &str) -> Result<(Namespace, KnownTopic), ExitCode> {
        let namespace = self.namespace()?;
        let topic = find_topic(&namespace, name)?;
        Ok((namespace, topic))
    }
}

/// The topic named `name` (the `hopnav/` prefix may be left out), or the exit code after an
/// error that lists the launch's topics.
fn find_topic(namespace: &Namespace, name: &str) -> Result<KnownTopic, ExitCode> {
    let full_name = if name.starts_with("hopnav/") {
        name.to_owned()
    } else {
        format!("hopnav/{name}")
    };
    live::known_topic(&full_name).ok_or_else(|| unknown_topic(namespace, name))
}

/// Says that `name` is no topic of the launch, listing those it has.
fn unknown_topic(namespace: &Namespace, name: &str) -> ExitCode {
    let known = match live::topic_census(namespace) {
        Ok(rows) => rows
            .into_iter()
            .map(|row| row.name)
            .collect::<Vec<_>>()
            .join("\n  "),
        Err(error) => format!("(cannot list them: {error})"),
    };
    eprintln!(
        "error: launch {} has no topic {name:?}; its topics:\n  {known}",
        namespace.run_id()
    );
    ExitCode::from(crate::EXIT_CONFIG)
}

/// Prints the error of a watch and gives its exit code (a topic the launch lacks is a usage
/// error, and lists the topics it has).
pub fn watch_failed(namespace: &Namespace, name: &str, error: LiveError) -> ExitCode {
    match error {
        LiveError::Open(OpenError::NoSuchTopic(_)) => unknown_topic(namespace, name),
        error => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

fn list(args: &ListArgs) -> ExitCode {
    let namespace = match args.run.namespace() {
        Ok(namespace) => namespace,
        Err(code) => return code,
    };
    match live::topic_census(&namespace) {
        Ok(rows) => {
            println!("launch {}: {} topics", namespace.run_id(), rows.len());
            print!("{}", list_table(&rows));
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

/// The table `topic list` prints, columns aligned.
fn list_table(rows: &[TopicRow]) -> String {
    let header = [
        "TOPIC",
        "TYPE",
        "PUBLISHER",
        "SUBSCRIBERS",
        "SLOTS",
        "BYTES",
    ]
    .map(str::to_owned);
    let mut lines = vec![header];
    for row in rows {
        let ports = |ports: &[(String, usize)]| {
            if !row.ports_known {
                return "?".to_owned();
            }
            if ports.is_empty() {
                return "-".to_owned();
            }
            let names: Vec<String> = ports
                .iter()
                .map(|(name, count)| match count {
                    1 => name.clone(),
                    count => format!("{name}×{count}"),
                })
                .collect();
            names.join(",")
        };
        let used: usize = row.subscribers.iter().map(|(_, count)| count).sum();
        lines.push([
            row.name.clone(),
            row.message_type.clone(),
            ports(&row.publishers),
            ports(&row.subscribers),
            if row.ports_known {
                format!("{used}/{}", row.max_subscribers)
            } else {
                format!("?/{}", row.max_subscribers)
            },
            row.sample_bytes
                .map_or_else(|| "?".to_owned(), |bytes| bytes.to_string()),
        ]);
    }
    align_columns(&lines, |column| column == 5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_table_aligns_columns_and_counts_ports() {
        let rows = [
            TopicRow {
                name: "hopnav/jumper_vo/pose".to_owned(),
                message_type: "PoseEstimate".to_owned(),
                publishers: vec![("jumper_vo".to_owned(), 1)],
                subscribers: vec![("planner".to_owned(), 1), ("supervisor".to_owned(), 2)],
                max_subscribers: 8,
                sample_bytes: Some(128),
                ports_known: true,
            },
            TopicRow {
                name: "hopnav/x".to_owned(),
                message_type: "Y + [u8]".to_owned(),
                publishers: Vec::new(),
                subscribers: Vec::new(),
                max_subscribers: 4,
                sample_bytes: None,
                ports_known: false,
            },
        ];
        let table = list_table(&rows);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[1].contains("planner,supervisor×2"), "{table}");
        assert!(lines[1].contains("3/8"), "{table}");
        assert!(lines[1].ends_with("128"), "{table}");
        assert!(lines[2].contains("?/4"), "{table}");
        let type_column = lines[0].find("TYPE").unwrap();
        assert_eq!(lines[1].find("PoseEstimate"), Some(type_column));
    }
}
