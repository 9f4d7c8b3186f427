//! Diagnostic (ignored): prints the error along the default traverse.
use hopnav_rover_vo::config::RoverVoConfig;
use hopnav_rover_vo::run::run_traverse;
use hopnav_rover_vo::simulate::{TraverseConfig, simulate_traverse};

#[test]
#[ignore]
fn error_along_traverse() {
    let mut cfg = TraverseConfig::default();
    if let Ok(n) = std::env::var("FRAMES") {
        cfg.max_frames = n.parse().ok();
    }
    if let Ok(p) = std::env::var("WAYPOINTS") {
        cfg.waypoints_xy_m = p
            .split(';')
            .map(|p| {
                let v: Vec<f64> = p.split(',').filter_map(|x| x.trim().parse().ok()).collect();
                [v[0], v[1]]
            })
            .collect();
    }
    let sim = simulate_traverse(&cfg).unwrap();
    println!("min rock clearance {:.2} m", sim.min_rock_clearance_m);
    let run = run_traverse(&sim, &RoverVoConfig::default()).unwrap();
    for (k, o) in run.outputs.iter().enumerate() {
        if k % 40 == 0 || o.status != hopnav_rover_vo::pipeline::VoStatus::Tracking && k > 0 {
            let t = sim.truth_world_from_body[k];
            let e = o.world_from_body;
            let d = e.translation.vector - t.translation.vector;
            let (r, p, y) = (t.inverse() * e).rotation.euler_angles();
            println!(
                "{k:5} truth ({:7.2},{:7.2},{:6.2}) err ({:6.3},{:6.3},{:6.3}) rot err ({:.2},{:.2},{:.2})° trk {} inl {} kf {} {:?} {:?} t {:.1}ms",
                t.translation.x,
                t.translation.y,
                t.translation.z,
                d.x,
                d.y,
                d.z,
                r.to_degrees(),
                p.to_degrees(),
                y.to_degrees(),
                o.tracked_features,
                o.inliers,
                o.is_keyframe,
                o.status,
                o.rejection,
                run.frame_time_us[k] / 1e3
            );
        }
    }
}
