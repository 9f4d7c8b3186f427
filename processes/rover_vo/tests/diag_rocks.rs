//! Diagnostic (ignored): rock clearance of straight legs on the default world.
use hopnav_world::{World, WorldConfig};
#[test]
#[ignore]
fn scan_legs() {
    let world = World::generate(&WorldConfig::default()).unwrap();
    let clearance = |a: [f64; 2], b: [f64; 2]| {
        let mut m = f64::INFINITY;
        for k in 0..=400 {
            let s = k as f64 / 400.0;
            let (x, y) = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
            for r in world.rocks() {
                if r.height_m < 0.05 { continue; }
                m = f64::min(m, ((r.center_m[0] - x).powi(2) + (r.center_m[1] - y).powi(2)).sqrt() - 0.5 * r.diameter_m - 0.6);
            }
        }
        m
    };
    for y in -22..=22 {
        let y = y as f64;
        println!("east leg y {y:5.1}: {:.2}", clearance([-22.0, y], [18.0, y]));
    }
    for x in [14.0, 16.0, 18.0, 20.0, 22.0] {
        for y0 in [-20.0, -16.0, -12.0, -8.0] {
            println!("north leg x {x} from {y0}: {:.2}", clearance([x, y0], [x, y0 + 16.0]));
        }
    }
    println!("rocks {} max h {:.2}", world.rocks().len(), world.rocks().iter().map(|r| r.height_m).fold(0.0, f64::max));
}
