//! Loading: a verified image for the VM's target becomes an engine, reset and ready to
//! scan. The VM refuses an image verified for another PLC type or one that uses an
//! instruction it has no semantics for (only possible with a vendor's ManagerFun.xml).

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::{UnitRecord, VerifiedImage};

use crate::clock::Clock;
use crate::engine::{Engine, Phase};
use crate::exch::Exch;
use crate::interrupts::Interrupts;
use crate::machine::Machine;
use crate::ops::{self, Handler};
use crate::program::{Program, VmConfig};
use crate::terminals::Terminals;

/// Why an image cannot be loaded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoadError {
    /// The image was verified against another PLC type.
    WrongTarget { image: String, target: String },
    /// The image uses instructions the VM has no semantics for.
    MissingSemantics(Vec<String>),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::WrongTarget { image, target } => {
                write!(f, "image for {image}, VM target {target}")
            }
            LoadError::MissingSemantics(m) => write!(f, "no semantics for: {}", m.join(", ")),
        }
    }
}

impl std::error::Error for LoadError {}

/// Load a verified image: an engine after its power-on reset.
pub(crate) fn load(
    image: VerifiedImage,
    target: Arc<Target>,
    config: VmConfig,
) -> Result<Engine, LoadError> {
    if image.target_name() != target.name() {
        return Err(LoadError::WrongTarget {
            image: image.target_name().to_string(),
            target: target.name().to_string(),
        });
    }
    let handlers: Vec<Option<Handler>> = target
        .instructions
        .instructions
        .iter()
        .map(ops::semantics)
        .collect();
    let mut missing: Vec<String> = Vec::new();
    for unit in image.units().values() {
        for r in &unit.records {
            if let UnitRecord::Instruction { id, .. } = r {
                if handlers.get(id.0 as usize).copied().flatten().is_none() {
                    missing.push(target.instructions.get(*id).mnemonic.clone());
                }
            }
        }
    }
    missing.sort();
    missing.dedup();
    if !missing.is_empty() {
        return Err(LoadError::MissingSemantics(missing));
    }
    let mut machine = Machine::new(&target);
    let terminals = Terminals::new(&target, &machine.memory);
    let program = Program::new(image, target, config, &mut machine.memory);
    let mut engine = Engine {
        program,
        handlers,
        machine,
        terminals,
        interrupts: Interrupts::default(),
        exch: Exch::default(),
        clock: Clock::default(),
        phase: Phase::Idle,
        events: Default::default(),
        paused: false,
        stopped: false,
        reset_requested: false,
        fault: None,
        fault_at: None,
        #[cfg(feature = "jit")]
        native: None,
        tier: Default::default(),
        native_hold: false,
        native_executed: 0,
    };
    engine.reset();
    // `native_after: Some(0)`: compiled at load.
    engine.tier_up();
    Ok(engine)
}
