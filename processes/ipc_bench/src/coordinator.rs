//! Starts the peer processes for every transport × size and collects their timings.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use hopnav_ipc::namespace::Namespace;

use crate::results::{BenchRow, BenchSummary};
use crate::transports::{SampleTiming, Transport};
use crate::{BenchError, PAYLOAD_SIZES_BYTES};

/// How to run the benchmark.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// The hopnav executable (peers are `hopnav bench ipc-peer …`).
    pub executable: PathBuf,
    /// Measured messages per transport and size.
    pub samples: usize,
    /// Unmeasured messages first.
    pub warmup: usize,
    /// Pause between messages.
    pub gap: Duration,
    /// Transports to run.
    pub transports: Vec<Transport>,
    /// Where the CSV, JSON and SVG go.
    pub out_dir: PathBuf,
}

fn peer_command(
    options: &BenchOptions,
    role: &str,
    transport: Transport,
    size_bytes: usize,
    id: &str,
    socket: &std::path::Path,
) -> Command {
    let mut command = Command::new(&options.executable);
    command
        .args(["bench", "ipc-peer", role, transport.name()])
        .arg(size_bytes.to_string())
        .arg("--samples")
        .arg(options.samples.to_string())
        .arg("--warmup")
        .arg(options.warmup.to_string())
        .arg("--id")
        .arg(id)
        .arg("--socket")
        .arg(socket)
        .arg("--gap-us")
        .arg(options.gap.as_micros().to_string())
        .stdin(Stdio::null())
        .stderr(Stdio::inherit());
    command
}

fn measure(
    options: &BenchOptions,
    transport: Transport,
    size_bytes: usize,
    id: &str,
) -> Result<Vec<SampleTiming>, BenchError> {
    let peer_error = |role: &'static str, message: String| BenchError::Peer {
        role,
        transport: transport.name(),
        size_bytes,
        message,
    };
    let socket = std::env::temp_dir().join(format!("{id}.sock"));
    let mut subscriber: Child = peer_command(options, "sub", transport, size_bytes, id, &socket)
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| peer_error("sub", e.to_string()))?;
    let stdout = subscriber
        .stdout
        .take()
        .ok_or_else(|| peer_error("sub", "no stdout".into()))?;
    let mut lines = BufReader::new(stdout).lines();
    match lines.next() {
        Some(Ok(line)) if line == "ready" => {}
        other => {
            let _ = subscriber.kill();
            let _ = subscriber.wait();
            return Err(peer_error(
                "sub",
                format!("did not report ready: {other:?}"),
            ));
        }
    }
    let publisher_status = peer_command(options, "pub", transport, size_bytes, id, &socket)
        .stdout(Stdio::null())
        .status()
        .map_err(|e| peer_error("pub", e.to_string()))?;
    let results = lines.next();
    let subscriber_status = subscriber
        .wait()
        .map_err(|e| peer_error("sub", e.to_string()))?;
    if !publisher_status.success() {
        return Err(peer_error("pub", format!("exited with {publisher_status}")));
    }
    if !subscriber_status.success() {
        return Err(peer_error(
            "sub",
            format!("exited with {subscriber_status}"),
        ));
    }
    let line = match results {
        Some(Ok(line)) => line,
        other => return Err(peer_error("sub", format!("no results: {other:?}"))),
    };
    serde_json::from_str(&line).map_err(|e| peer_error("sub", format!("bad results: {e}")))
}

/// Runs every transport at every payload size, prints progress, the table and the target
/// checks, and writes the files.
pub fn run_bench(options: &BenchOptions) -> Result<BenchSummary, BenchError> {
    let mut rows = Vec::new();
    let total = options.transports.len() * PAYLOAD_SIZES_BYTES.len();
    for transport in &options.transports {
        for size_bytes in PAYLOAD_SIZES_BYTES {
            let id = format!("bench-{}-{}", std::process::id(), rows.len());
            eprint!(
                "\r[{}/{total}] {} with {} B payloads …          ",
                rows.len() + 1,
                transport.name(),
                size_bytes
            );
            let _ = std::io::stderr().flush();
            let measured = measure(options, *transport, size_bytes, &id);
            if let Ok(namespace) = Namespace::new(&id) {
                namespace.remove_files_if_unused();
            }
            rows.push(BenchRow::new(*transport, size_bytes, &measured?));
        }
    }
    eprintln!();
    let summary = BenchSummary { rows };
    let mut stdout = std::io::stdout().lock();
    let _ = summary.print(&mut stdout);
    summary.write_files(&options.out_dir)?;
    let _ = writeln!(
        stdout,
        "\nwrote {}/ipc_latency.{{csv,json,svg,png}}",
        options.out_dir.display()
    );
    Ok(summary)
}
