//! Fuzz target of plant files (`gutta-sim --plant`, gutta-io's `Plant::parse`):
//! arbitrary bytes (lossily decoded) parsed and validated. Panics are the bugs it looks
//! for; it also asserts what a valid plant promises (unique names, `device:NAME` ports
//! that lead to another device that is no fx, keys only of their kind) and that every
//! error carries its code and the file's place (`plant.toml:LINE:COLUMN: [P00..]`)
//! with a line of the text.
#![no_main]

use std::collections::BTreeSet;
use std::path::Path;

use gutta_io::{DeviceKind, Plant, PlcProgram, PortLead};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let file = Path::new("/plants/plant.toml");
    match Plant::parse(Path::new("/plants"), file, &text) {
        Err(e) => {
            let shown = e.to_string();
            assert!(shown.contains(&format!("[{}]", e.code.as_str())), "{shown}");
            if let Some(place) = shown.strip_prefix("/plants/plant.toml:") {
                let line: usize = place
                    .split(':')
                    .next()
                    .and_then(|l| l.parse().ok())
                    .unwrap_or_else(|| panic!("no line in {shown}"));
                assert!(
                    line >= 1 && line <= text.lines().count().max(1) + 1,
                    "{shown}"
                );
            } else {
                panic!("no place in {shown}");
            }
        }
        Ok(plant) => {
            assert!(!plant.devices.is_empty());
            let names: BTreeSet<&str> = plant.devices.iter().map(|d| d.name.as_str()).collect();
            assert_eq!(names.len(), plant.devices.len(), "names are unique");
            for d in &plant.devices {
                assert!((1..=60_000).contains(&d.scan_ms));
                if d.kind != DeviceKind::Plc {
                    assert!(d.rtu_tcp.is_empty() && d.program == PlcProgram::Empty);
                    assert!(d.ports.iter().all(Option::is_none) && d.flash.is_none());
                }
                for lead in d.ports.iter().flatten() {
                    if let PortLead::Device(other) = lead {
                        assert_ne!(other, &d.name);
                        let far = plant.devices.iter().find(|x| &x.name == other);
                        assert!(far.is_some_and(|x| x.kind != DeviceKind::Fx));
                    }
                }
            }
        }
    }
});
