//! The stdlib target descriptions, embedded at build time so the compiler needs no
//! files at run time; no file I/O. `stdlib/targets/<Name>/` holds PlcType.xml and
//! ManagerVar.xml of every PLC type (the default, CPU-EC20, among them), all sharing
//! `stdlib/ManagerFun.xml`. Each file exists once.

use std::sync::{Arc, OnceLock};

use crate::{CatalogError, CatalogErrorCode, Target, TargetSources};

/// Name of the default PLC type.
pub const DEFAULT: &str = "CPU-EC20";

/// The shared instruction set.
pub const MANAGER_FUN: &[u8] = include_bytes!("../../stdlib/ManagerFun.xml");

/// Embeds `stdlib/targets/<name>/PlcType.xml` and `ManagerVar.xml` as one `TARGETS` row.
macro_rules! target {
    ($name:literal) => {
        (
            $name,
            include_bytes!(concat!("../../stdlib/targets/", $name, "/PlcType.xml")),
            include_bytes!(concat!("../../stdlib/targets/", $name, "/ManagerVar.xml")),
        )
    };
}

/// (name, PlcType.xml, ManagerVar.xml) of every stdlib target, default first. The six
/// PLC types of IN1001; docs/targets.md describes each.
pub const TARGETS: &[(&str, &[u8], &[u8])] = &[
    target!("CPU-EC20"),
    target!("CPU-EC20-AVR"),
    target!("CPU-EC20-M3"),
    target!("EC30-EK51"),
    target!("EC30-EKSTM32"),
    target!("EC30-EKSTM32-XC"),
];

/// Names of all stdlib targets, default first.
pub fn names() -> impl Iterator<Item = &'static str> {
    TARGETS.iter().map(|(n, _, _)| *n)
}

/// Load a stdlib target by name (case-insensitive).
pub fn load(name: &str) -> Result<Target, CatalogError> {
    let (_, plc, var) = TARGETS
        .iter()
        .find(|(n, _, _)| n.eq_ignore_ascii_case(name))
        .ok_or_else(|| {
            let known: Vec<&str> = names().collect();
            let mut message = format!("no stdlib PLC type `{name}` (known: {})", known.join(", "));
            if let Some(near) = nearest(name) {
                message.push_str(&format!("; did you mean `{near}`?"));
            }
            CatalogError::new(CatalogErrorCode::NotFound, name, message)
        })?;
    Target::load(TargetSources {
        plc_type: plc,
        manager_var: var,
        manager_fun: MANAGER_FUN,
    })
}

/// The stdlib name closest to a mistyped one (case folded), if it is close: at most
/// two edits, and fewer than half the name's length.
fn nearest(name: &str) -> Option<&'static str> {
    let wanted = name.to_ascii_uppercase();
    names()
        .map(|n| (crate::edit_distance(&wanted, &n.to_ascii_uppercase()), n))
        .filter(|(d, _)| *d <= 2 && *d * 2 < wanted.len().max(1))
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

/// Load the default target.
pub fn default_target() -> Result<Target, CatalogError> {
    load(DEFAULT)
}

/// A stdlib target, loaded once per process and shared: checking a file costs no XML
/// parsing and no copy of the tables.
pub fn shared(name: &str) -> Result<Arc<Target>, CatalogError> {
    type Cache = Vec<(&'static str, Result<Arc<Target>, CatalogError>)>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| names().map(|n| (n, load(n).map(Arc::new))).collect());
    match cache.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)) {
        Some((_, result)) => result.clone(),
        None => load(name).map(Arc::new),
    }
}

#[cfg(test)]
mod tests {
    use super::load;

    #[test]
    fn a_mistyped_name_gets_the_nearest_stdlib_type() {
        let e = load("cpu-ec2").expect_err("not a stdlib type");
        assert!(e.to_string().contains("did you mean `CPU-EC20`?"), "{e}");
        let e = load("S7-200").expect_err("not a stdlib type");
        assert!(!e.to_string().contains("did you mean"), "{e}");
    }
}
