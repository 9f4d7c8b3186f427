//! Renders a few views of a world to PNG files for eyeballing:
//! `cargo run --release --example render_png [scenario.toml] [out_dir]`.

use std::io::Write;

use hopnav_world::camera::{CameraConfig, look_at};
use hopnav_world::raster::{RenderConfig, RenderScene, Renderer};
use hopnav_world::{World, WorldConfig};
use nalgebra::{Point3, Vector3};

fn crc32(data: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in data {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Grayscale PNG with stored (uncompressed) deflate blocks: no dependencies.
fn write_png(path: &str, w: usize, h: usize, px: &[u8]) -> std::io::Result<()> {
    let mut raw = Vec::with_capacity((w + 1) * h);
    for row in px.chunks(w).take(h) {
        raw.push(0);
        raw.extend_from_slice(row);
    }
    let mut z = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = raw.chunks(65535).collect();
    for (i, b) in blocks.iter().enumerate() {
        z.push(u8::from(i + 1 == blocks.len()));
        let n = b.len() as u16;
        z.extend_from_slice(&n.to_le_bytes());
        z.extend_from_slice(&(!n).to_le_bytes());
        z.extend_from_slice(b);
    }
    let (mut a, mut bsum) = (1u32, 0u32);
    for &v in &raw {
        a = (a + u32::from(v)) % 65521;
        bsum = (bsum + a) % 65521;
    }
    z.extend_from_slice(&((bsum << 16) | a).to_be_bytes());
    let mut f = std::fs::File::create(path)?;
    f.write_all(b"\x89PNG\r\n\x1a\n")?;
    let mut chunk = |ty: &[u8], data: &[u8]| -> std::io::Result<()> {
        f.write_all(&(data.len() as u32).to_be_bytes())?;
        let mut body = ty.to_vec();
        body.extend_from_slice(data);
        f.write_all(&body)?;
        f.write_all(&crc32(&body).to_be_bytes())
    };
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&(w as u32).to_be_bytes());
    ihdr.extend_from_slice(&(h as u32).to_be_bytes());
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
    chunk(b"IHDR", &ihdr)?;
    chunk(b"IDAT", &z)?;
    chunk(b"IEND", &[])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let cfg: WorldConfig = match args.get(1) {
        Some(p) if p.ends_with(".toml") => toml::from_str(&std::fs::read_to_string(p)?)?,
        _ => WorldConfig::default(),
    };
    let out_dir = args
        .get(2)
        .cloned()
        .unwrap_or_else(|| "/tmp/world-png".into());
    std::fs::create_dir_all(&out_dir)?;
    let world = World::generate(&cfg)?;
    let t = std::time::Instant::now();
    let scene = RenderScene::new(&world)?;
    println!(
        "{} rocks, scene built in {:?}",
        world.rocks().len(),
        t.elapsed()
    );
    let mut r = Renderer::new(&CameraConfig::default(), &RenderConfig::default())?;
    let views = [
        ("h0.5_p0.6", 0.5f64, 0.6f64),
        ("h1.5_p0.5", 1.5, 0.5),
        ("h5_p0.7", 5.0, 0.7),
        ("h10_p0.5", 10.0, 0.5),
        ("h15_p1.2", 15.0, 1.2),
        ("h0.8_p0.1", 0.8, 0.1),
        ("sun_h1.5_p0.5", -1.5, 0.5),
        ("h0.5_p1.3", 0.5, 1.3),
    ];
    let mut img = vec![0u8; 320 * 320];
    for (name, alt, pitch) in views {
        let (x, y) = (3.0, -2.0);
        // A negative height means: same height, looking towards the sun.
        let az = if alt < 0.0 {
            cfg.lighting.sun_azimuth_rad
        } else {
            0.3f64.atan()
        };
        let alt = alt.abs();
        let eye = Point3::new(x, y, world.ground_height_at(x, y) + alt);
        let dir = Vector3::new(
            pitch.cos() * az.cos(),
            pitch.cos() * az.sin(),
            -f64::sin(pitch),
        );
        let pose = look_at(&eye, &(eye + dir), &Vector3::z());
        let s = r.render(&scene, &pose, 0, &mut img, 320)?;
        write_png(&format!("{out_dir}/{name}.png"), 320, 320, &img)?;
        println!("{name}: {s:?}");
    }
    Ok(())
}
