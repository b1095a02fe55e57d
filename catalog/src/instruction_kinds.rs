//! What an instruction is, as data of `ManagerFun.xml` (docs/instruction-schema.md,
//! "What an instruction is"): the timer or counter it is (`Kind`), the ladder element
//! it draws as (`Ladder`), how a `Combine` joins (`Logic`), a compare's relation
//! (`Compare`) and a FOR/NEXT's role (`Loop`). Typed keywords only: these enums are the
//! one place a keyword of the file becomes a value, so no consumer ever matches an
//! instruction's mnemonic to learn what it is.

use std::str::FromStr;

/// Parses a keyword through a `(keyword, value)` table, any case.
fn from_table<T: Copy>(table: &[(&str, T)], s: &str) -> Result<T, ()> {
    table
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(s.trim()))
        .map(|(_, v)| *v)
        .ok_or(())
}

/// The keyword of a value in its table.
fn keyword_of<T: Copy + PartialEq>(table: &[(&'static str, T)], value: T) -> &'static str {
    table
        .iter()
        .find(|(_, v)| *v == value)
        .map(|(n, _)| *n)
        .unwrap_or("?")
}

/// Implements `keyword()`, `ALL` and `FromStr` of a keyword enum from one table.
macro_rules! keyword_enum {
    ($ty:ty, $table:expr) => {
        impl $ty {
            const TABLE: &'static [(&'static str, $ty)] = $table;
            /// Every value, in the order the schema lists them.
            pub fn all() -> impl Iterator<Item = $ty> {
                Self::TABLE.iter().map(|(_, v)| *v)
            }
            /// The keyword `ManagerFun.xml` writes for it.
            pub fn keyword(self) -> &'static str {
                keyword_of(Self::TABLE, self)
            }
        }
        impl FromStr for $ty {
            type Err = ();
            fn from_str(s: &str) -> Result<Self, ()> {
                from_table(Self::TABLE, s)
            }
        }
    };
}

/// The timer or counter an instruction is (`Kind`): how it counts and when it is done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TimerCounterKind {
    /// `TON`: done once its input has stayed on for the preset.
    OnDelay,
    /// `TOF`: stays on for the preset after its input goes off.
    OffDelay,
    /// `TONR`: accumulates the time its input is on; done at the preset.
    RetentiveOnDelay,
    /// `CTU`: counts rising edges up; done at the preset.
    CountUp,
    /// `CTD`: counts rising edges down from the preset; done at 0.
    CountDown,
    /// `CTUD`: counts up and down; done at the preset.
    CountUpDown,
}

keyword_enum!(
    TimerCounterKind,
    &[
        ("TON", TimerCounterKind::OnDelay),
        ("TOF", TimerCounterKind::OffDelay),
        ("TONR", TimerCounterKind::RetentiveOnDelay),
        ("CTU", TimerCounterKind::CountUp),
        ("CTD", TimerCounterKind::CountDown),
        ("CTUD", TimerCounterKind::CountUpDown),
    ]
);

impl TimerCounterKind {
    /// A timer (its number counts time in the target's resolution), not a counter.
    pub fn is_timer(self) -> bool {
        matches!(
            self,
            TimerCounterKind::OnDelay
                | TimerCounterKind::OffDelay
                | TimerCounterKind::RetentiveOnDelay
        )
    }
}

/// The ladder element an instruction is drawn as (`Ladder`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LadderClass {
    /// A normally open bit contact (`LD`, `A`, `OI`).
    Contact,
    /// A normally closed bit contact (`LDN`, `AN`, `ONI`).
    ClosedContact,
    /// A compare contact (`LDW>=`, `AB=`); its relation is [`CompareOp`].
    Compare,
    /// `NOT`: inverts the power in series.
    Not,
    /// `EU`: passes power for one scan on a rising edge.
    RisingEdge,
    /// `ED`: passes power for one scan on a falling edge.
    FallingEdge,
    /// `=`: a coil.
    Coil,
    /// `S`: a set coil.
    SetCoil,
    /// `R`: a reset coil.
    ResetCoil,
    /// `ALD`: joins the two top paths in series.
    AndBlock,
    /// `OLD`: joins the two top paths in parallel.
    OrBlock,
    /// `LPS`: opens parallel outputs.
    Push,
    /// `LRD`: a further parallel output.
    Read,
    /// `LPP`: the last parallel output.
    Pop,
    /// `LDS n`: copies a lower level to the top.
    LoadStack,
    /// A box with pins (`MOVW`, `TON`, `CALL`, `JMP`, `LBL`).
    Box,
}

keyword_enum!(
    LadderClass,
    &[
        ("Contact", LadderClass::Contact),
        ("ClosedContact", LadderClass::ClosedContact),
        ("Compare", LadderClass::Compare),
        ("Not", LadderClass::Not),
        ("RisingEdge", LadderClass::RisingEdge),
        ("FallingEdge", LadderClass::FallingEdge),
        ("Coil", LadderClass::Coil),
        ("SetCoil", LadderClass::SetCoil),
        ("ResetCoil", LadderClass::ResetCoil),
        ("AndBlock", LadderClass::AndBlock),
        ("OrBlock", LadderClass::OrBlock),
        ("Push", LadderClass::Push),
        ("Read", LadderClass::Read),
        ("Pop", LadderClass::Pop),
        ("LoadStack", LadderClass::LoadStack),
        ("Box", LadderClass::Box),
    ]
);

impl LadderClass {
    /// A contact of a `Load` or `Combine` instruction.
    pub fn is_contact(self) -> bool {
        matches!(
            self,
            LadderClass::Contact | LadderClass::ClosedContact | LadderClass::Compare
        )
    }

    /// A coil of an `Output` instruction.
    pub fn is_coil(self) -> bool {
        matches!(
            self,
            LadderClass::Coil | LadderClass::SetCoil | LadderClass::ResetCoil
        )
    }

    /// An element of a `Stack` instruction (other than a timer or counter box).
    pub fn is_stack(self) -> bool {
        matches!(
            self,
            LadderClass::Not
                | LadderClass::RisingEdge
                | LadderClass::FallingEdge
                | LadderClass::AndBlock
                | LadderClass::OrBlock
                | LadderClass::Push
                | LadderClass::Read
                | LadderClass::Pop
                | LadderClass::LoadStack
        )
    }
}

/// How a `Combine` instruction joins its operand with the top of the logic stack
/// (`Logic`): in series (`A`, `AN`, `AW>=`) or in parallel (`O`, `ON`, `OW>=`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Logic {
    And,
    Or,
}

keyword_enum!(Logic, &[("And", Logic::And), ("Or", Logic::Or)]);

/// How a contact instruction starts or joins a path: the STL form of its mnemonic
/// (`LD`, `A`, `O`), from `Flow` and `Logic`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Join {
    /// `Flow="Load"`: a new path.
    Load,
    /// `Logic="And"`.
    And,
    /// `Logic="Or"`.
    Or,
}

/// A compare contact's relation (`Compare`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompareOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

keyword_enum!(
    CompareOp,
    &[
        ("Eq", CompareOp::Eq),
        ("Ne", CompareOp::Ne),
        ("Lt", CompareOp::Lt),
        ("Le", CompareOp::Le),
        ("Gt", CompareOp::Gt),
        ("Ge", CompareOp::Ge),
    ]
);

impl CompareOp {
    /// The relation as STL and ladder write it: `=`, `<>`, `<`, `<=`, `>`, `>=`.
    pub fn symbol(self) -> &'static str {
        match self {
            CompareOp::Eq => "=",
            CompareOp::Ne => "<>",
            CompareOp::Lt => "<",
            CompareOp::Le => "<=",
            CompareOp::Gt => ">",
            CompareOp::Ge => ">=",
        }
    }

    /// The relation written as STL and ladder write it (`>=`), the inverse of
    /// [`CompareOp::symbol`].
    pub fn from_symbol(symbol: &str) -> Option<CompareOp> {
        CompareOp::all().find(|op| op.symbol() == symbol)
    }

    /// The relation that holds exactly when this one does not (`>=` <-> `<`).
    pub fn negated(self) -> CompareOp {
        match self {
            CompareOp::Eq => CompareOp::Ne,
            CompareOp::Ne => CompareOp::Eq,
            CompareOp::Lt => CompareOp::Ge,
            CompareOp::Le => CompareOp::Gt,
            CompareOp::Gt => CompareOp::Le,
            CompareOp::Ge => CompareOp::Lt,
        }
    }

    /// Whether the relation holds for an ordering of left against right.
    pub fn holds(self, ordering: std::cmp::Ordering) -> bool {
        match self {
            CompareOp::Eq => ordering.is_eq(),
            CompareOp::Ne => ordering.is_ne(),
            CompareOp::Lt => ordering.is_lt(),
            CompareOp::Le => ordering.is_le(),
            CompareOp::Gt => ordering.is_gt(),
            CompareOp::Ge => ordering.is_ge(),
        }
    }
}

/// An instruction's part in a FOR/NEXT loop (`Loop`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LoopRole {
    /// `FOR`: opens a loop.
    Start,
    /// `NEXT`: closes the innermost loop.
    End,
}

keyword_enum!(
    LoopRole,
    &[("Start", LoopRole::Start), ("End", LoopRole::End)]
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keywords_round_trip_and_any_case_parses() {
        for kind in TimerCounterKind::all() {
            assert_eq!(kind.keyword().parse(), Ok(kind));
        }
        for class in LadderClass::all() {
            assert_eq!(class.keyword().to_ascii_lowercase().parse(), Ok(class));
        }
        for op in CompareOp::all() {
            assert_eq!(op.keyword().parse(), Ok(op));
            assert_eq!(op.negated().negated(), op);
            assert_eq!(CompareOp::from_symbol(op.symbol()), Some(op));
        }
        assert_eq!("TIMER".parse::<TimerCounterKind>(), Err(()));
        assert_eq!(TimerCounterKind::all().filter(|k| k.is_timer()).count(), 3);
    }
}
