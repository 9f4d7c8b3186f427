//! Summaries, the stdout table, the CSV and the plot.

use std::io::Write;
use std::path::Path;

use hopnav_ipc::latency::LatencySummary;
use hopnav_metrics::plot::{LinePlot, Scale, Series, write_png, write_svg};
use serde::Serialize;

use crate::BenchError;
use crate::transports::{SampleTiming, Transport};

/// One transport at one payload size.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    /// Transport name.
    pub transport: &'static str,
    /// Payload size.
    pub size_bytes: usize,
    /// Time to write the payload.
    pub fill: LatencySummary,
    /// Publish stamp to receipt.
    pub transport_latency: LatencySummary,
}

/// The whole benchmark.
#[derive(Debug, Clone, Serialize)]
pub struct BenchSummary {
    /// Every measurement.
    pub rows: Vec<BenchRow>,
}

impl BenchRow {
    pub(crate) fn new(transport: Transport, size_bytes: usize, timings: &[SampleTiming]) -> Self {
        let mut fill: Vec<u64> = timings.iter().map(|t| t.fill_ns).collect();
        let mut latency: Vec<u64> = timings.iter().map(|t| t.transport_ns).collect();
        Self {
            transport: transport.name(),
            size_bytes,
            fill: LatencySummary::from_ns(&mut fill),
            transport_latency: LatencySummary::from_ns(&mut latency),
        }
    }
}

fn human_size(bytes: usize) -> String {
    match bytes {
        b if b >= 1 << 20 => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 && b % 1024 == 0 => format!("{} KiB", b >> 10),
        b if b >= 1000 => format!("{:.0} KiB", b as f64 / 1024.0),
        b => format!("{b} B"),
    }
}

impl BenchSummary {
    fn p50_us(&self, transport: Transport, size_bytes: usize) -> Option<f64> {
        self.rows
            .iter()
            .find(|row| row.transport == transport.name() && row.size_bytes == size_bytes)
            .map(|row| row.transport_latency.p50_ms * 1e3)
    }

    /// Prints the table and the target checks.
    pub fn print(&self, out: &mut impl Write) -> std::io::Result<()> {
        writeln!(
            out,
            "\n{:<18} {:>9} {:>10} | {:>10} {:>10} {:>10} {:>10}   (one-way, µs)",
            "transport", "payload", "fill p50", "p50", "p99", "p99.9", "max"
        )?;
        for row in &self.rows {
            let t = &row.transport_latency;
            writeln!(
                out,
                "{:<18} {:>9} {:>10.1} | {:>10.1} {:>10.1} {:>10.1} {:>10.1}",
                row.transport,
                human_size(row.size_bytes),
                row.fill.p50_ms * 1e3,
                t.p50_ms * 1e3,
                t.p99_ms * 1e3,
                t.p999_ms * 1e3,
                t.max_ms * 1e3
            )?;
        }
        writeln!(out, "\ntargets (transport p50, fill excluded):")?;
        if let (Some(large), Some(small)) = (
            self.p50_us(Transport::Hopnav, 4 << 20),
            self.p50_us(Transport::Hopnav, 64),
        ) {
            let ratio = large / small;
            writeln!(
                out,
                "  hopnav 4 MiB / 64 B            = {ratio:5.2}x  (target <= 1.2x) {}",
                verdict(ratio <= 1.2)
            )?;
        }
        for size in crate::PAYLOAD_SIZES_BYTES {
            if let (Some(ours), Some(raw)) = (
                self.p50_us(Transport::Hopnav, size),
                self.p50_us(Transport::RawEvent, size),
            ) {
                let ratio = ours / raw;
                writeln!(
                    out,
                    "  hopnav / raw iceoryx2 event at {:>7} = {ratio:5.2}x  (target <= 2x) {}",
                    human_size(size),
                    verdict(ratio <= 2.0)
                )?;
            }
        }
        if let (Some(copying), Some(ours)) = (
            self.p50_us(Transport::UnixSocketBincode, 1 << 20),
            self.p50_us(Transport::Hopnav, 1 << 20),
        ) {
            let ratio = copying / ours;
            writeln!(
                out,
                "  copying / hopnav at 1 MiB      = {ratio:5.0}x  (target >= 100x) {}",
                verdict(ratio >= 100.0)
            )?;
        }
        Ok(())
    }

    /// Writes `ipc_latency.csv`, `.json`, `.svg` and `.png` into `dir`.
    pub fn write_files(&self, dir: &Path) -> Result<(), BenchError> {
        let output_error = |path: &Path, message: String| BenchError::Output {
            path: path.display().to_string(),
            message,
        };
        std::fs::create_dir_all(dir).map_err(|e| output_error(dir, e.to_string()))?;
        let csv_path = dir.join("ipc_latency.csv");
        let mut csv = String::from(
            "transport,payload_bytes,samples,fill_p50_us,transport_p50_us,transport_p99_us,transport_p999_us,transport_max_us,transport_mean_us\n",
        );
        for row in &self.rows {
            let t = &row.transport_latency;
            csv.push_str(&format!(
                "{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3}\n",
                row.transport,
                row.size_bytes,
                t.count,
                row.fill.p50_ms * 1e3,
                t.p50_ms * 1e3,
                t.p99_ms * 1e3,
                t.p999_ms * 1e3,
                t.max_ms * 1e3,
                t.mean_ms * 1e3
            ));
        }
        std::fs::write(&csv_path, csv).map_err(|e| output_error(&csv_path, e.to_string()))?;
        let json_path = dir.join("ipc_latency.json");
        let json = serde_json::to_string_pretty(self)
            .map_err(|e| output_error(&json_path, e.to_string()))?;
        std::fs::write(&json_path, json).map_err(|e| output_error(&json_path, e.to_string()))?;

        let series: Vec<Series> = Transport::ALL
            .iter()
            .map(|transport| Series {
                label: format!("{} p50", transport.name()),
                points: self
                    .rows
                    .iter()
                    .filter(|row| row.transport == transport.name())
                    .map(|row| (row.size_bytes as f64, row.transport_latency.p50_ms * 1e3))
                    .collect(),
            })
            .filter(|series| !series.points.is_empty())
            .collect();
        let plot = LinePlot {
            title: "one-way transport latency (p50), fill time excluded",
            x_label: "payload bytes",
            y_label: "latency µs",
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            series: &series,
        };
        let svg_path = dir.join("ipc_latency.svg");
        write_svg(&svg_path, &plot).map_err(|e| output_error(&svg_path, e.to_string()))?;
        let png_path = dir.join("ipc_latency.png");
        write_png(&png_path, &plot).map_err(|e| output_error(&png_path, e.to_string()))?;
        Ok(())
    }
}

fn verdict(met: bool) -> &'static str {
    if met { "met" } else { "NOT met" }
}
