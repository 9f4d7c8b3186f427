//! `hopnav recording`: look into a recording (`hopnav launch --record FILE.mcap`) without
//! launching anything.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use hopnav_recorder::recording::inspect::{Depth, RecordingInfo, inspect_file};

use crate::text_table::align_columns;

#[derive(Debug, Subcommand)]
pub enum RecordingCommand {
    /// Check that a file is a complete hopnav recording this build reads, and summarise it:
    /// each channel with its schema, encodings and message count, the time span, the
    /// launch's run id and the build's commit. A file that is not one (truncated, corrupt,
    /// not MCAP, not hopnav's, another message version) is named as such, exit code 1.
    Info(InfoArgs),
}

#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The recording, as `hopnav launch --record FILE.mcap` wrote it.
    #[arg(value_name = "FILE.mcap")]
    file: PathBuf,
    /// Read only the summary section at the end of the file: instant on a large file, but a
    /// damaged chunk goes unnoticed. Default: read every message, checking each chunk's CRC
    /// and that the summary's counts match the data.
    #[arg(long)]
    summary_only: bool,
    /// Print the summary as JSON (sizes in bytes, times in nanoseconds of sim time) instead
    /// of a table.
    #[arg(long)]
    json: bool,
    /// Also print the launch's whole config as recorded (the TOML the processes ran with).
    #[arg(long)]
    config: bool,
}

pub fn run(command: RecordingCommand) -> ExitCode {
    match command {
        RecordingCommand::Info(args) => info(&args),
    }
}

fn info(args: &InfoArgs) -> ExitCode {
    let depth = if args.summary_only {
        Depth::Summary
    } else {
        Depth::EveryMessage
    };
    let info = match inspect_file(&args.file, depth) {
        Ok(info) => info,
        Err(error) => {
            eprintln!("error: {}: {error}", args.file.display());
            return ExitCode::FAILURE;
        }
    };
    if args.json {
        match serde_json::to_string_pretty(&info) {
            Ok(text) => println!("{text}"),
            Err(error) => {
                eprintln!("error: {error}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        print!("{}", describe(&args.file, &info));
    }
    if args.config
        && let Some(config) = info.metadata_entry("hopnav.launch", "config_toml")
    {
        println!("\n{config}");
    }
    ExitCode::SUCCESS
}

/// The summary as text: a few lines about the file, then one line per channel.
fn describe(file: &std::path::Path, info: &RecordingInfo) -> String {
    let unknown = "unknown";
    let mut text = format!(
        "file:      {}\nsize:      {:.1} MB ({} bytes)\nmessages:  {} in {} chunks{}\n",
        file.display(),
        info.size_bytes as f64 / 1e6,
        info.size_bytes,
        info.messages,
        info.chunks,
        if info.every_message_read {
            ", every one read (chunk CRCs checked)"
        } else {
            " (from the summary section)"
        }
    );
    if let Some((start_ns, end_ns)) = info.span_ns {
        text.push_str(&format!(
            "sim time:  {:.3} s to {:.3} s ({:.1} s)\n",
            start_ns as f64 * 1e-9,
            end_ns as f64 * 1e-9,
            info.duration_s()
        ));
    }
    text.push_str(&format!(
        "run id:    {}\ncommit:    {} (hopnav {})\n\n",
        info.metadata_entry("hopnav.launch", "run_id")
            .unwrap_or(unknown),
        info.metadata_entry("hopnav.build", "commit")
            .unwrap_or(unknown),
        info.metadata_entry("hopnav.build", "version")
            .unwrap_or(unknown),
    ));
    let mut lines = vec![[
        "channel".to_owned(),
        "messages".to_owned(),
        "schema".to_owned(),
        "encoding".to_owned(),
    ]];
    lines.extend(info.channels.iter().map(|channel| {
        [
            channel.topic.clone(),
            channel.messages.to_string(),
            channel.schema.clone(),
            channel.message_encoding.clone(),
        ]
    }));
    text.push_str(&align_columns(&lines, |column| column == 1));
    text
}
