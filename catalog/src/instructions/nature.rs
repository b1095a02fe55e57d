//! What an instruction is (docs/instruction-schema.md, "What an instruction is"): the
//! `Kind`, `Ladder`, `Immediate`, `Logic`, `Compare`, `PowerInputs`, `PowerOutput` and
//! `Loop` attributes of one `<Instruction>`, parsed into typed values and checked
//! against its flow. Every refusal is a catalog error naming the instruction.

use std::str::FromStr;

use super::{err, Flow, RawInstruction, FILE};
use crate::instruction_kinds::{CompareOp, LadderClass, Logic, LoopRole, TimerCounterKind};
use crate::xml_util::attr_bool;
use crate::{CatalogError, CatalogErrorCode};

/// What an instruction is, parsed from its `Kind`, `Ladder`, `Immediate`, `Logic`,
/// `Compare`, `PowerInputs`, `PowerOutput` and `Loop` attributes and checked against
/// its flow (docs/instruction-schema.md, "What an instruction is").
pub(super) struct Nature {
    pub(super) kind: Option<TimerCounterKind>,
    pub(super) ladder: LadderClass,
    pub(super) immediate: bool,
    pub(super) logic: Option<Logic>,
    pub(super) compare: Option<CompareOp>,
    pub(super) power_inputs: Vec<String>,
    pub(super) power_output: Option<String>,
    pub(super) loop_role: Option<LoopRole>,
    pub(super) defines_label: bool,
}

/// An optional keyword attribute: `None` when absent, T0003 naming the keywords the
/// schema allows when unknown.
fn keyword<T: FromStr>(
    m: &str,
    attr: &str,
    value: Option<&str>,
    allowed: impl Iterator<Item = &'static str>,
) -> Result<Option<T>, CatalogError> {
    let Some(text) = value else {
        return Ok(None);
    };
    text.trim().parse::<T>().map(Some).map_err(|_| {
        let allowed: Vec<&str> = allowed.collect();
        err(
            CatalogErrorCode::Value,
            format!(
                "unknown {attr} `{text}` of {m}; expected one of {}",
                allowed.join(", ")
            ),
        )
    })
}

/// T0002: an attribute given where it has no meaning, or missing where it is needed.
fn shape(m: &str, text: String) -> CatalogError {
    err(CatalogErrorCode::Syntax, format!("{m}: {text}"))
}

pub(super) fn parse(
    m: &str,
    flow: Flow,
    stack_needs: u8,
    raw: &RawInstruction,
) -> Result<Nature, CatalogError> {
    let kind: Option<TimerCounterKind> = keyword(
        m,
        "Kind",
        raw.kind.as_deref(),
        TimerCounterKind::all().map(TimerCounterKind::keyword),
    )?;
    if kind.is_some() && flow != Flow::Stack {
        return Err(shape(m, "Kind goes with Flow=\"Stack\"".into()));
    }
    let given: Option<LadderClass> = keyword(
        m,
        "Ladder",
        raw.ladder.as_deref(),
        LadderClass::all().map(LadderClass::keyword),
    )?;
    let is_box = kind.is_some() || matches!(flow, Flow::Box | Flow::Always);
    let ladder = match given {
        Some(class) => class,
        None if is_box => LadderClass::Box,
        None => {
            return Err(shape(
                m,
                format!("Flow=\"{}\" needs a Ladder attribute", flow.keyword()),
            ))
        }
    };
    let fits = match flow {
        Flow::Load | Flow::Combine => ladder.is_contact(),
        Flow::Output => ladder.is_coil(),
        Flow::Box | Flow::Always => ladder == LadderClass::Box,
        Flow::Stack if kind.is_some() => ladder == LadderClass::Box,
        Flow::Stack => ladder.is_stack(),
    };
    if !fits {
        return Err(err(
            CatalogErrorCode::Value,
            format!(
                "Ladder=\"{}\" of {m} does not fit Flow=\"{}\"",
                ladder.keyword(),
                flow.keyword()
            ),
        ));
    }
    let immediate = attr_bool(
        FILE,
        &format!("Immediate of {m}"),
        raw.immediate.as_deref(),
        false,
    )?;
    let bit =
        matches!(ladder, LadderClass::Contact | LadderClass::ClosedContact) || ladder.is_coil();
    if immediate && !bit {
        return Err(shape(
            m,
            "Immediate goes with bit contacts and coils only".into(),
        ));
    }
    let logic: Option<Logic> = keyword(
        m,
        "Logic",
        raw.logic.as_deref(),
        Logic::all().map(Logic::keyword),
    )?;
    if logic.is_some() != (flow == Flow::Combine) {
        return Err(shape(
            m,
            "Logic goes with Flow=\"Combine\" and only there".into(),
        ));
    }
    let compare: Option<CompareOp> = keyword(
        m,
        "Compare",
        raw.compare.as_deref(),
        CompareOp::all().map(CompareOp::keyword),
    )?;
    if compare.is_some() != (ladder == LadderClass::Compare) {
        return Err(shape(
            m,
            "Compare goes with Ladder=\"Compare\" and only there".into(),
        ));
    }
    let words = |text: &str| -> Vec<String> {
        text.split_whitespace()
            .map(str::to_ascii_uppercase)
            .collect()
    };
    let power_inputs = match raw.power_inputs.as_deref() {
        Some(text) => words(text),
        None if matches!(flow, Flow::Box | Flow::Always) => vec!["EN".to_string()],
        None => Vec::new(),
    };
    let power_output = match raw.power_output.as_deref().map(str::trim) {
        Some("") => None,
        Some(text) => Some(text.to_ascii_uppercase()),
        None if flow == Flow::Box => Some("ENO".to_string()),
        None => None,
    };
    if !is_box && (raw.power_inputs.is_some() || raw.power_output.is_some()) {
        return Err(shape(
            m,
            "PowerInputs and PowerOutput go with boxes only".into(),
        ));
    }
    if power_output
        .as_deref()
        .is_some_and(|o| o.contains(char::is_whitespace))
    {
        return Err(err(
            CatalogErrorCode::Value,
            format!("PowerOutput of {m} must be one name"),
        ));
    }
    if kind.is_some() {
        if power_inputs.len() != usize::from(stack_needs) || power_output.is_none() {
            return Err(err(
                CatalogErrorCode::Value,
                format!(
                    "{m} is a timer or counter: it needs one name in PowerInputs per level \
                     it reads ({stack_needs}) and a PowerOutput"
                ),
            ));
        }
    } else if is_box && power_inputs.len() != 1 {
        return Err(err(
            CatalogErrorCode::Value,
            format!("PowerInputs of {m} must be one name"),
        ));
    }
    let loop_role: Option<LoopRole> = keyword(
        m,
        "Loop",
        raw.loop_role.as_deref(),
        LoopRole::all().map(LoopRole::keyword),
    )?;
    let defines_label = attr_bool(
        FILE,
        &format!("DefinesLabel of {m}"),
        raw.defines_label.as_deref(),
        false,
    )?;
    Ok(Nature {
        kind,
        ladder,
        immediate,
        logic,
        compare,
        power_inputs,
        power_output,
        loop_role,
        defines_label,
    })
}
