//! The evaluator `hopnav launch` hands the supervisor: scores the mission, writes the Fig.-6
//! PNG and the VO pairs as TUM files into the run folder.

use std::path::Path;

use hopnav_config::HopnavConfig;
use hopnav_supervisor::mission_record::{Evaluation, MissionEvaluator, MissionRecord};
use hopnav_supervisor::mission_report::MissionReport;

use crate::figure::mission_figure;
use crate::mission::{MissionTruth, evaluate};

/// Scores missions against the world their config describes.
#[derive(Debug, Clone, Copy, Default)]
pub struct TruthEvaluator;

impl MissionEvaluator for TruthEvaluator {
    fn evaluate(
        &self,
        config: &HopnavConfig,
        report: &MissionReport,
        record: &MissionRecord,
        run_dir: &Path,
    ) -> Evaluation {
        let Some(truth) = MissionTruth::from_config(config) else {
            eprintln!("warning: the [world] section is invalid: the mission is not evaluated");
            return Evaluation::default();
        };
        let evaluation = evaluate(&truth, record);
        write_vo_tum(run_dir, record);
        let run_id = run_dir
            .file_name()
            .map_or_else(String::new, |name| name.to_string_lossy().into_owned());
        let title = format!("hopnav {} mission, run {run_id}", record.mode.name());
        let figure_path = mission_figure(&title, &truth, record).and_then(|figure| {
            let path = run_dir.join("mission_map.png");
            match hopnav_metrics::map_plot::write_map_png(&path, &figure) {
                Ok(()) => Some(path.display().to_string()),
                Err(error) => {
                    eprintln!("warning: {error}");
                    None
                }
            }
        });
        let mut summary = Vec::new();
        // Writing into a Vec cannot fail.
        let _ = evaluation.print(report, &mut summary);
        Evaluation {
            fields: evaluation.to_fields(),
            figure_path,
            summary_lines: String::from_utf8_lossy(&summary)
                .lines()
                .map(str::to_owned)
                .collect(),
        }
    }
}

/// `vo_<robot>_{estimate,truth}.tum`: the matched pairs, for evo.
fn write_vo_tum(run_dir: &Path, record: &MissionRecord) {
    for vo in &record.vo {
        let (estimate, truth) = vo.track.tum_poses();
        if estimate.is_empty() {
            continue;
        }
        for (kind, poses) in [("estimate", &estimate), ("truth", &truth)] {
            let path = run_dir.join(format!("vo_{}_{kind}.tum", vo.robot));
            if let Err(error) = hopnav_metrics::trajectory::tum::write_tum(&path, poses) {
                eprintln!("warning: {error}");
            }
        }
    }
}
