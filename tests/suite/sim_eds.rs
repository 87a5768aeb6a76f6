//! The simulated devices' EDS files in eds/ are generated from the device models; this fails
//! when they are stale, and checks that reading them gives back the models.
//! Regenerate with: CANCTL_REGENERATE=1 cargo test --test suite sim_eds::

use canctl::od::eds;
use canctl::sim::profiles;
use std::path::Path;

#[test]
fn eds_files_are_fresh_and_agree_with_the_models() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("eds");
    let files = profiles::eds_files();
    if std::env::var_os("CANCTL_REGENERATE").is_some() {
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text) in &files {
            std::fs::write(dir.join(name), eds::to_latin1(text)).unwrap();
        }
    }
    let models = [
        profiles::drive(),
        profiles::position_sensor(profiles::SENSOR_SERIAL),
        profiles::io_module(),
        profiles::stepper(),
    ];
    for ((name, text), model) in files.iter().zip(models) {
        let committed = std::fs::read(dir.join(name)).unwrap_or_default();
        assert!(
            committed == eds::to_latin1(text),
            "eds/{name} is stale: CANCTL_REGENERATE=1 cargo test --test suite sim_eds::"
        );
        let parsed = eds::parse(&committed, name).unwrap();
        assert!(parsed.warnings.is_empty(), "{:?}", parsed.warnings);
        let mut count = 0;
        for e in model.dict.entries() {
            let p = parsed.dict.get(e.addr).unwrap_or_else(|| panic!("{name}: {} missing", e.addr));
            assert_eq!(
                (&p.name, p.dtype, p.access, p.range),
                (&e.name, e.dtype, e.access, e.range),
                "{name} {}",
                e.addr
            );
            // DOMAIN contents stay out of text files.
            if e.dtype != canctl::canopen::DataType::D {
                assert_eq!(p.default, e.default, "{name} {}", e.addr);
            }
            assert_eq!(parsed.dict.display_name(e.addr), model.dict.display_name(e.addr));
            count += 1;
        }
        assert_eq!(parsed.dict.entries().count(), count, "{name}: extra entries");
    }
}
