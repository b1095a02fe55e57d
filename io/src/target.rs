//! Loading the PLC type `gutta_catalog::choose_target` chose: a stdlib name from the
//! embedded stdlib, a folder from disk. Which one applies is the catalog's rule, not
//! decided here.

use std::sync::Arc;

use gutta_catalog::{stdlib, Target, TargetSpec};

use crate::{load_target_dir, ProjectTarget};

/// The target `spec` names, or the error's text (the catalog's, or the folder's read
/// error with its T code).
pub fn load_target(spec: &TargetSpec) -> Result<Arc<Target>, String> {
    match spec {
        TargetSpec::Stdlib(name) => stdlib::shared(name).map_err(|e| e.to_string()),
        TargetSpec::Folder(dir) => load_target_dir(dir).map(Arc::new),
    }
}

impl ProjectTarget {
    /// `[program] plc`/`target` as the resolver's project input; `None` for neither.
    pub fn spec(&self) -> Option<TargetSpec> {
        match self {
            ProjectTarget::Unspecified => None,
            ProjectTarget::Stdlib(name) => Some(TargetSpec::Stdlib(name.clone())),
            ProjectTarget::Folder(dir) => Some(TargetSpec::Folder(dir.clone())),
        }
    }
}
