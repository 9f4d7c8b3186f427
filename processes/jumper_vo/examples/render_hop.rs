//! Renders the default hop and writes every frame as PGM to the directory given as argument.
use hopnav_jumper_vo::simulate::{SimConfig, simulate_hop};
use std::io::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "/tmp/jvo-frames".into());
    std::fs::create_dir_all(&dir)?;
    let hop = simulate_hop(&SimConfig::default())?;
    for (k, img) in hop.images.iter().enumerate() {
        let mut f = std::fs::File::create(format!("{dir}/frame_{k:03}.pgm"))?;
        write!(f, "P5\n{} {}\n255\n", hop.width_px, hop.height_px)?;
        f.write_all(img)?;
    }
    println!("{} frames to {dir}", hop.images.len());
    Ok(())
}
