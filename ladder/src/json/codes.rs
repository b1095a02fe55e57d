//! The registry of the ladder model's error codes (L codes, docs/ladder.md, "The model
//! as JSON"): one row per code with its summary and explanation; `gutta-cc explain`
//! reads it and a test keeps docs/ladder.md's table equal to it. Codes are never reused;
//! call sites name variants, never strings.

use std::fmt;

macro_rules! model_codes {
    ($($code:ident $variant:ident $summary:literal $explain:literal;)*) => {
        /// What is wrong with a ladder model read from JSON.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum ModelErrorCode { $($variant,)* }

        impl ModelErrorCode {
            /// Every code, in number order.
            pub const ALL: &'static [ModelErrorCode] = &[$(ModelErrorCode::$variant,)*];

            /// `L0001`, ...
            pub fn as_str(self) -> &'static str {
                match self { $(ModelErrorCode::$variant => stringify!($code),)* }
            }

            /// What the code means, in one line (docs/ladder.md's table).
            pub fn summary(self) -> &'static str {
                match self { $(ModelErrorCode::$variant => $summary,)* }
            }

            /// What the code means and how to fix it.
            pub fn explanation(self) -> &'static str {
                match self { $(ModelErrorCode::$variant => $explain,)* }
            }

            /// The code named `s` (any case).
            pub fn parse(s: &str) -> Option<ModelErrorCode> {
                ModelErrorCode::ALL.iter().copied().find(|c| c.as_str().eq_ignore_ascii_case(s))
            }
        }
    };
}

model_codes! {
    L0001 NotJson "the model is not valid JSON"
        "The file is not JSON text (RFC 8259): the message gives the line and column where reading stopped. A ladder model is one JSON object, `{\"format\": \"gutta-ladder\", \"version\": 1, ...}`.";
    L0002 Shape "a field is missing or has the wrong type"
        "A part of the model does not have the shape docs/ladder-model.schema.json describes: a required field is missing (`format`, `version`, `plc`, `blocks`; a block's `kind`, `name`, `id`, `networks`), a field has the wrong JSON type, an element is none of `series`, `parallel`, `contact`, `coil`, `box`, a block's `kind` is not `ORGANIZATION_BLOCK`, `SUBROUTINE_BLOCK` or `INTERRUPT_BLOCK`, or a field that becomes one line of the program (a name, a title, an operand, an `stl` line; not a network's `comment`) holds a line break. The path names the part.";
    L0003 UnknownFormat "the `format` is not `gutta-ladder`"
        "The object's `format` field says what it is; a ladder model says `\"format\": \"gutta-ladder\"`. Another value is another kind of file.";
    L0004 LaterVersion "the model's `version` is later than this tool reads"
        "The model was written for a later version of the format than this tool knows (it reads version 1). Update GUTTA, or write the model in version 1.";
    L0005 UnknownMnemonic "a mnemonic the PLC type does not have"
        "An element names an instruction that is not in the instruction set of the model's PLC type (ManagerFun.xml; see docs/instructions.md). Mnemonics are case-insensitive; compares are one word with their relation (`LDW>=`).";
    L0006 WrongElement "the mnemonic is not that kind of element"
        "A `contact` takes a contact in its load form (`LD`, `LDN`, `LDI`, `LDW>=`...) or `EU`, `ED`, `NOT`; a `coil` takes an output (`=`, `S`, `R`, `=I`...); a `box` takes a box instruction (`TON`, `MOVW`, `CALL`...). The message says what the mnemonic is: the help names the load form when an `A...` or `O...` form was written as a contact.";
    L0007 OperandCount "a wrong number of operands"
        "An element's `operands` are the instruction's operands in STL order, as many as the instruction has (`S` takes the bit and the count; `CALL` takes the subroutine and then its arguments), none of them empty. The message says how many the instruction takes, or which operand is empty.";
    L0008 OutputNotLast "an output in series before another element"
        "In a `series` only the last element may end the power path: a coil, a box without power output (`JMP`), or a `parallel` of outputs. A coil before a contact is not a rung; put the contact before the coil, or put the outputs in a `parallel`.";
    L0009 NoOutput "a rung or output branch without an output"
        "Every rung ends in an output (a coil or a box), and a `parallel` either joins paths of contacts (none of its branches ends) or splits into outputs (every branch ends in one). The path names the rung or the branch that has no output.";
    L0010 UnknownPlc "the model's `plc` is not a known PLC type"
        "The `plc` field names the PLC type whose instruction set the model uses (see `gutta-cc list-targets`), or `--plc`/`--target` chooses it.";
    L0011 WriterMissing "retired: writing STL from a model was not built yet"
        "No longer reported: `gutta-cc ladder MODEL.json -o OUT.lad` now writes the program's STL (issue 26). Earlier builds stopped a valid model with this code and wrote nothing. Codes are never reused, so the number stays retired.";
    L0012 BoxInputs "a box with the wrong number of power inputs"
        "A box's `inputs` are its power inputs after the first, as the instruction set names them (`PowerInputs` in ManagerFun.xml): none for `MOVW` or a timer, the reset `R` for `CTU`, `CD` and `R` for `CTUD`. The message names the inputs the box takes.";
    L0013 Unwritable "a rung the STL writer cannot say"
        "The rung has a shape that STL cannot write as one network meaning what the rung draws: a path from the left rail that starts with `NOT`, `EU` or `ED` (they only go in series after a contact), a coil or a box that needs power first on the left rail, a box that runs without power flow (`ENI`, `LBL`) inside a rung, a box (or `NOT`, `EU`, `ED`) inside a parallel of paths that comes after other elements in series (STL ANDs that path on after loading it from the rail, so the box would not take its power through what comes before), a box with no power path into it in the middle of a rung, a coil inside a power path, or an output branch that does not end in a coil, a box or outputs in parallel. The path names the rung or the part; start the path with a contact, move the box after the parallel, or write the network as `stl` lines.";
    L0014 NoSuchPath "an edit's path names nothing in the model"
        "An edit operation (docs/ladder.md, \"Editing the model\") names its element by the JSON path the L codes use (`blocks[0].networks[2].rung.series[1]`, `...rung.series[2].inputs[0]`) and its network by `blocks[0].networks[2]`. The path is not one of those, or the model has no block, network, rung or element there (a network shown as `stl` has no rung; a selection runs past the end of its series). Take the path from the model as it is now: an earlier edit may have moved the element.";
    L0015 WrongTarget "the edit does not apply to what its path names"
        "The element exists, but the operation does not apply to it: operands and mnemonics belong to contacts, coils and boxes, not to a `series` or a `parallel`; a selection of more than one element is a run of one `series`; a box's power input is a pin of the box, changed with the box's `set_mnemonic` (`inputs`) or edited inside, never deleted on its own. The message says which.";
    L0016 LastOutput "the edit would delete a rung's last output"
        "Every rung ends in an output, and so does every output branch. Deleting the last coil or box of a rung (or the whole rung) would leave a rung that is not a rung: insert another output first, or delete the network (`delete_network`).";
    L0017 OutOfRange "a network position past the block's networks"
        "A network edit names a block or a position that is not there: a network is inserted at a position from 0 to the number of networks (that number appends it), moved to a position from 0 to the last, and deleted, duplicated or moved only where one is (a title or comment edit, or an element path, naming a network that is not there is L0014).";
    L0018 NotAnEdit "the text is not an edit operation"
        "An edit sent as JSON is one object with `op` naming the operation (`insert_contact`, `insert_coil`, `insert_box`, `wrap_parallel`, `delete`, `set_operands`, `set_mnemonic`, `insert_network`, `delete_network`, `move_network`, `duplicate_network`, `set_network_title`, `set_network_comment`, `set_block_title`) and that operation's fields (docs/ladder.md, \"Editing the model\"). The message names what serde could not read.";
    L0019 NothingToUndo "nothing to undo, or nothing to redo"
        "The editor's history is empty in that direction: no edit was applied since the model was opened (or all were undone), or no edit was undone since the last new edit (a new edit clears what could be redone). The model is unchanged.";
    L0020 TextOutOfStep "the program text does not hold what the change names"
        "An edit's changes are applied to the program's `.lad` text in place (`edit::apply_to_text`, docs/ladder.md \"Editing the model\"), and the text has no block or network where the model has it: the text changed since the model was read from it, or it is another program. The message says what is missing. Nothing is written; read the model from the text again.";
}

impl fmt::Display for ModelErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A model that cannot be read: its code, the JSON path of the part at fault
/// (`blocks[0].networks[2].rung.series[1]`; empty for the whole document) and the
/// message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelError {
    pub code: ModelErrorCode,
    pub path: String,
    pub message: String,
}

impl ModelError {
    pub fn new(code: ModelErrorCode, path: &str, message: impl Into<String>) -> ModelError {
        ModelError {
            code,
            path: path.to_string(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ModelError {
    /// `L0005 at blocks[0].networks[2].rung.series[1]: ...`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.code, self.message)
        } else {
            write!(f, "{} at {}: {}", self.code, self.path, self.message)
        }
    }
}

impl std::error::Error for ModelError {}
