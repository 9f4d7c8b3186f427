//! Runs the default Table-1 hop over several seeds with both scale methods and prints the
//! metrics. `cargo run --release --example eval_vo -- [seeds] [out_dir]`.
use hopnav_jumper_vo::config::{JumperVoConfig, ScaleMethod};
use hopnav_jumper_vo::eval::{evaluate, plot::write_fig5_png, run_hop, tum::write_tum};
use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seeds: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let out_dir = std::env::args()
        .nth(2)
        .unwrap_or_else(|| "/tmp/jvo-eval".into());
    let verbose = std::env::var("JVO_VERBOSE").is_ok();
    std::fs::create_dir_all(&out_dir)?;
    for method in [ScaleMethod::Ballistic, ScaleMethod::PaperEq4] {
        let mut ates = Vec::new();
        for seed in 1..=seeds {
            let mut sim_cfg = SimConfig {
                seed,
                ..SimConfig::default()
            };
            sim_cfg.world.seed = seed;
            let sim = simulate_hop(&sim_cfg)?;
            let mut cfg = JumperVoConfig {
                scale_method: method,
                ..JumperVoConfig::default()
            };
            if let Some(v) = std::env::var("JVO_KF_MAX_PARALLAX_DEG")
                .ok()
                .and_then(|s| s.parse().ok())
            {
                cfg.keyframe_max_parallax_deg = v;
            }
            if let Some(v) = std::env::var("JVO_KF_MIN_FRACTION")
                .ok()
                .and_then(|s| s.parse().ok())
            {
                cfg.keyframe_min_track_fraction = v;
            }
            let run = run_hop(&sim, &cfg)?;
            let report = evaluate(&run.outputs, &sim.truth_world_from_body).ok_or("no metrics")?;
            println!("{method:?} seed {seed}: {report}");
            if verbose {
                for (o, g) in run.outputs.iter().zip(&sim.truth_world_from_body) {
                    let e = o.world_from_body.translation.vector - g.translation.vector;
                    println!(
                        "  k {:2} {:?} kf {} tr {:4} inl {:4} model {:?} scale {:?} err [{:6.3} {:6.3} {:6.3}] rot {:.2}°",
                        o.frame_index,
                        o.status,
                        o.is_keyframe as u8,
                        o.tracked_features,
                        o.inliers,
                        o.model,
                        o.scale.map(|s| (s * 1000.0).round() / 1000.0),
                        e.x,
                        e.y,
                        e.z,
                        o.world_from_body
                            .rotation
                            .angle_to(&g.rotation)
                            .to_degrees()
                    );
                }
            }
            ates.push((report.ate_sim3_m, report.ate_se3_m, report.rmse_unaligned_m));
            if seed == 1 {
                let name = format!("{out_dir}/{method:?}");
                let est: Vec<_> = sim.t_s.iter().copied().zip(run.poses()).collect();
                let gt: Vec<_> = sim
                    .t_s
                    .iter()
                    .copied()
                    .zip(sim.truth_world_from_body.iter().copied())
                    .collect();
                write_tum(format!("{name}_estimate.tum").as_ref(), &est)?;
                write_tum(format!("{name}_truth.tum").as_ref(), &gt)?;
                write_fig5_png(
                    format!("{name}_fig5.png").as_ref(),
                    &sim.t_s,
                    &sim.truth_world_from_body,
                    &run.poses(),
                )?;
            }
        }
        let n = ates.len() as f64;
        let mean = |f: fn(&(f64, f64, f64)) -> f64| ates.iter().map(f).sum::<f64>() / n;
        let worst = |f: fn(&(f64, f64, f64)) -> f64| ates.iter().map(f).fold(0.0, f64::max);
        println!(
            "{method:?}: ATE sim3 mean {:.3} worst {:.3} | se3 mean {:.3} worst {:.3} | unaligned mean {:.3} worst {:.3}",
            mean(|a| a.0),
            worst(|a| a.0),
            mean(|a| a.1),
            worst(|a| a.1),
            mean(|a| a.2),
            worst(|a| a.2)
        );
    }
    Ok(())
}
