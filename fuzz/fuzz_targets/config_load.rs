//! Any bytes, read as a config file is (lossily as UTF-8), give a config or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match hopnav_config::load(Some(&text)) {
        Ok(config) => {
            // What the launcher does next with a loaded config must not panic either.
            let _ = hopnav_config::check_section_names(&config, &["world", "planner"]);
            let _ = hopnav_config::parse_section::<toml::Table>(&config, "world");
            let text = hopnav_config::to_toml(&config).expect("a loaded config serializes");
            hopnav_config::load(Some(&text)).expect("a written config loads back");
        }
        Err(error) => {
            let _ = error.to_string();
        }
    }
});
