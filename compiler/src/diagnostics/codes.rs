//! The registry of diagnostic codes: every code the compiler can emit, with its
//! severity, a title and an explanation. docs/diagnostics.md is generated from this
//! table (a test keeps it in sync). Codes are never reused; call sites name variants,
//! never strings.

use crate::diagnostics::Severity;

macro_rules! codes {
    ($($code:ident $variant:ident $sev:ident $title:literal $explain:literal;)*) => {
        /// A diagnostic code.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum Code { $($variant,)* }

        impl Code {
            pub const ALL: &'static [Code] = &[$(Code::$variant,)*];

            /// `E0101`, `W0204`, ...
            pub fn as_str(self) -> &'static str {
                match self { $(Code::$variant => stringify!($code),)* }
            }

            pub fn severity(self) -> Severity {
                match self { $(Code::$variant => Severity::$sev,)* }
            }

            /// Short title for the docs index.
            pub fn title(self) -> &'static str {
                match self { $(Code::$variant => $title,)* }
            }

            /// What the code means and how to fix it.
            pub fn explanation(self) -> &'static str {
                match self { $(Code::$variant => $explain,)* }
            }

            pub fn parse(s: &str) -> Option<Code> {
                Code::ALL.iter().copied().find(|c| c.as_str().eq_ignore_ascii_case(s))
            }
        }
    };
}

codes! {
    // ---- E01xx: lexical and block structure --------------------------------------
    E0101 InvalidCharacter Error "invalid character"
        "A character that starts no token of the language, such as `?` or `$`. Remove it; comments start with `//`.";
    E0102 Syntax Error "syntax error"
        "The line does not have the shape its context expects: an instruction is `MNEMONIC operand, operand`, a symbol `Name : ADDRESS`, a local `name : TYPE;`, a data row `ADDRESS TYPE VALUE`, a system entry `KEY = VALUE`. The message says what was expected.";
    E0103 UnterminatedString Error "unterminated string"
        "A string has no closing `\"` on its line. Strings cannot span lines.";
    E0104 MalformedNumber Error "malformed number"
        "A number with a digit its base does not have (`2#102`), no digits after `#`, an unsupported base (bases are 2, 8, 10 and 16), or a value too large for 64 bits.";
    E0105 UnterminatedBlock Error "unterminated block"
        "A block (`ORGANIZATION_BLOCK`, `SUBROUTINE_BLOCK`, `INTERRUPT_BLOCK`, `DATA_BLOCK`, `SYSTEM_BLOCK`, `SYMBOLS`, a `VAR` section) was not closed by its `END_...` line before the next block or the end of the file. The block is still checked as far as it goes.";
    E0106 MismatchedEnd Error "mismatched END"
        "An `END_...` line does not match the open block, e.g. `END_SUBROUTINE_BLOCK` closing an `ORGANIZATION_BLOCK`, or there is no open block at all.";
    E0107 OutsideBlock Error "text outside any block"
        "Only `PLC_TYPE`, `SYMBOLS`, program blocks, data blocks and the system block may stand at the top level. Instructions belong between `BEGIN` and the block's `END_...` line, inside a `NETWORK`.";
    E0108 NoNetwork Error "instruction before the first NETWORK"
        "Code in a program block is divided into networks; each starts with `NETWORK n` (an optional `// title` follows). Breakpoints and the debugger name instructions by network and step, so an instruction outside a network cannot be placed.";
    E0109 MisplacedSection Error "misplaced section"
        "A block's parts come in order: header, `TITLE=`, `VAR_INPUT`/`VAR_IN_OUT`/`VAR_OUTPUT`/`VAR` sections, `BEGIN`, networks, `END_...`. A `VAR` section after `BEGIN`, a second `BEGIN`, a `TITLE=` inside code, or a VAR section in a data block is reported here.";
    E0110 BadBlockHeader Error "malformed block header"
        "A block header is `KEYWORD NAME:NUMBERED` (`SUBROUTINE_BLOCK ADD3:SBR0`), `KEYWORD NUMBERED` (`SUBROUTINE_BLOCK SBR0`) or `KEYWORD NAME` (numbered automatically). The numbered name's prefix must fit the block: OB1 or INT0 for MAIN, INTn for interrupt routines, SBRn for subroutines, DATn for data blocks.";
    E0111 BadPlcType Error "bad PLC_TYPE line"
        "`PLC_TYPE NAME` may appear once per file, before the file's blocks, and must name a known PLC type (see `gutta-cc list-targets`) unless `--plc` or `--target` chooses the target.";
    E0112 PlcTypeConflict Error "files name different PLC types"
        "A program in several files names its PLC type in more than one file, and the names differ (the label shows the first). Name one type in every file that has a `PLC_TYPE` line, or in one file only, or choose the target with `--plc`/`--target`.";
    E0113 BadSymbolTable Error "malformed symbol table"
        "A CSV symbol table starts with the header row `Symbol,Address,Comment` (any case; the format STEP 7-Micro/WIN SMART exports). Tab-separated tables (Micro/WIN's pasted rows, `Symbol<TAB>Address<TAB>Comment`) may omit the header. A file is read as tab-separated when its first non-empty line holds a tab.";
    E0114 BadSymbolTableRow Error "malformed symbol table row"
        "A symbol table row is `Symbol,Address,Comment` (CSV) or the same separated by tabs: a name that is one word (letters, digits, `_`), a direct address optionally followed by `:TYPE` (`MD8:REAL`), and an optional comment. The message says what is wrong: a missing name or address, extra fields, a quote that is not closed, or text after a closing quote.";
    E0115 MisplacedMend Error "MEND not at the end of the main program"
        "In a STEP 7-Micro/WIN export (docs/microwin.md) `MEND`, S7-200's unconditional end of the main program, is accepted as the last instruction of the `ORGANIZATION_BLOCK`, where GUTTA's main program (MAIN, INT0) ends anyway, and compiles to nothing. In a subroutine or interrupt routine, or with code after it in the main program (which S7-200 would never run), it is this error: remove it, or end a subroutine with `RET` and an interrupt routine with `RETI`.";
    E0116 MisspeltEnd Error "misspelt END keyword"
        "A line starts with a word that looks like an `END_...` keyword but is none, such as `END_ORGANISATION_BLOCK` for `END_ORGANIZATION_BLOCK`. The help names the keyword meant: the one the open block or `VAR` section ends with when the word is close to it, else the closest `END_` keyword. The line closes what that keyword would close, so the block is not also reported as unterminated; the fix replaces the word.";

    // ---- E02xx: names --------------------------------------------------------------
    E0201 UnknownMnemonic Error "unknown mnemonic"
        "The instruction is not in the target's ManagerFun.xml. The help line suggests the closest known mnemonic. Mnemonics are case-insensitive; compares are written as one word with their operator (`LDW>=`, `AB=`).";
    E0202 UndefinedSymbol Error "undefined symbol"
        "A name that is neither a direct address of the target, a symbol of the SYMBOLS section, nor a block name. Declare it in SYMBOLS (`Start : I0.0`) or fix the spelling; the help line suggests the closest symbol. A name is reported once, at its first use; the message counts the other uses and labels point at the first few of them.";
    E0203 DuplicateSymbol Error "duplicate symbol"
        "A symbol is declared twice (names are case-insensitive) with a different address or type: in one SYMBOLS block, in two blocks or files of the program, or in a symbol table as well (two declarations that agree are W0208). The label shows the first declaration, also when it is in another file.";
    E0204 UndefinedLocal Error "undefined local variable"
        "`#name` refers to a local that the enclosing block does not declare in its VAR sections.";
    E0205 DuplicateLocal Error "duplicate local variable"
        "A local variable name appears twice in a block's VAR sections (names are case-insensitive).";
    E0206 UndefinedBlock Error "undefined block"
        "`CALL`, `ATCH` or a data reference names a block that does not exist. Blocks are named by their symbolic name (`ADD3`) or numbered name (`SBR0`). In a Micro/WIN export a name that looks like a block of another file (`SBR_1`, `INT_0`, `子程序_2`, `SBR3`, a `NAME:SBRn` operand) is most likely in a file of the same export that was not passed: MicroWIN SMART exports one block per file, and the help shows the command that compiles them together (docs/microwin.md, \"One block per file\").";
    E0207 DuplicateBlock Error "duplicate block"
        "Two blocks share a symbolic name or a numbered name (`SBR0`, `INT1`, `DAT0`), or MAIN is defined twice. GUTTA's MAIN is interrupt routine INT0 (`ORGANIZATION_BLOCK MAIN:OB1` and `INTERRUPT_BLOCK MAIN:INT0` are the same block), so an S7-200 program's own interrupt routine INT0 collides with MAIN: renumber it (INT1 and up). The label points at the numbered name that collides.";
    E0208 UndefinedLabel Error "undefined label"
        "`JMP n` has no `LBL n` in the same block.";
    E0209 DuplicateLabel Error "duplicate label"
        "`LBL n` appears twice in one block; jump targets must be unique within a block.";
    E0210 JumpAcrossBlocks Error "jump across blocks"
        "`JMP n` names a label defined in another block. Jumps stay inside their block; use CALL for a subroutine.";
    E0211 LocalOutsideBlock Error "local variable outside its block"
        "`#name` is declared in another block. Locals live in L and belong to their block; pass the value as a CALL argument instead.";
    E0212 BadSymbolName Error "symbol name not allowed"
        "A symbol name has the shape of a direct address (`M0`, `VB100`) or is a reserved word, so uses of it would be ambiguous.";
    E0213 UnknownDataType Error "unknown data type"
        "Data types are BOOL, BYTE, WORD, DWORD, SINT, INT, DINT, USINT, UINT, UDINT and REAL.";
    E0214 SymbolTypeWidth Error "symbol type does not fit its address"
        "A typed symbol (`Temp : MD8 : REAL`, or `MD8:REAL` in a table) names a type whose width differs from the address's: REAL, DINT, DWORD and UDINT need a double word (`MD8`), INT, WORD and UINT a word (`MW4`), BYTE, SINT and USINT a byte (`MB2`), BOOL a bit (`M0.0`).";

    E0220 S7200Instruction Error "S7-200 instruction the target does not have"
        "The mnemonic is an instruction of the Siemens S7-200 (STEP 7-Micro/WIN, MicroWIN SMART) that GUTTA targets do not have: sequence control relays (`LSCR`, `SCRT`, `SCRE`, `CSCRE`), freeport and network communication (`XMT`, `RCV`, `NETR`, `NETW`, `GET`, `PUT`), strings (`SLEN`, `SCPY`, `SCAT`, `SFND`, `ITS`, `STI`, ...), the real-time clock (`TODR`, `TODW`, ...), high-speed counter and pulse output set-up (`HDEF`, `HSC`, `PLS`), `PID` and a few others. The help line names what to use instead where GUTTA has an equivalent (step bits with `S`/`R` for SCR steps, `EXCH` for Modbus master exchanges, `ITA` for `ITS`, ...); otherwise the part must be rewritten. docs/microwin.md lists them all.";
    E0221 S7200Area Error "S7-200 area or system name the target does not have"
        "The operand names memory that exists on an S7-200 but not on GUTTA targets: the S area of sequence control relays (`S0.0`, `SB0`; keep step bits in M instead), the accumulators `AC0`..`AC3` (use M, V or local words), or a name of Micro/WIN's system symbol table (`Always_On`, `Time_0_Intrvl`, `HSC0_Ctrl`). For a system symbol GUTTA has an equivalent of, the help line gives the SM address to declare it with (`Always_On : SM0.0`); S7-200 SM control bytes without one (high-speed counters, pulse outputs, freeport) have no counterpart.";

    E0222 S7200TimerBit Error "S7-200 timer or counter bit without one meaning"
        "In a STEP 7-Micro/WIN export, `LD T37`, `A C0`, `ON T37` and `R T37, 1` use a timer's or counter's bit as the S7-200 does (docs/microwin.md, \"Timer and counter bits\"). GUTTA's T and C areas hold only current values, so the compiler reads the bit as a comparison of the current value with the preset of the instruction that drives that number (`LD T37` after `TON T37, 100` is `LDW>= T37, 100`). That needs exactly one meaning: some TON, TONR, TOF (or CTU, CTUD, CTD) drives the number, all its instructions are of one kind and share one preset. Otherwise this error names what is missing or which instructions disagree. `S T37, 1` (setting a timer bit) has no counterpart on GUTTA.";
    E0223 S7200Event Error "S7-200 interrupt event the target does not have"
        "In a STEP 7-Micro/WIN export, the event operand of `ATCH`, `DTCH` and `CEVNT` is an S7-200 interrupt event number (0 = I0.0 rising edge, 10 = timed interrupt 0, 12 = HSC0 CV=PV, ...), translated to the GUTTA event that means the same as the target's ManagerVar.xml says (`<Event MicroWin=...>`; docs/microwin.md, \"Interrupt events\"). This S7-200 event has no counterpart on the target: GUTTA targets raise no events for high-speed counters, pulse outputs, freeport communication or the 1 ms timers T32/T96. The help line lists the S7-200 events the target has; rewrite the part (poll the condition in the main program, or use a timed interrupt). Numbers past 33 are no S7-200 event at all (E0307).";
    E0224 S7200Sequence Error "sequence control relay that cannot be compiled"
        "In a STEP 7-Micro/WIN export, `LSCR`, `SCRT`, `SCRE`, `CSCRE` and the S area (`S0.1`, `SB2`) compile onto ordinary code (docs/microwin.md, \"Sequence control relays\"): the S bytes live in a byte range of the target (`[microwin] s_area` in gutta.toml, `--s-area`, else the last 32 bytes of M) and each segment from `LSCR` to `SCRE` runs only while its S bit is set. This error names what does not fit that: `SCRT`, `CSCRE` or `SCRE` outside a segment, `LSCR` inside one (S7-200 segments do not nest), a segment without `SCRE` before the end of its block, a `JMP` into or out of a segment, `END` inside one, `FOR`/`NEXT` crossing a segment's border, an operand of `LSCR`/`SCRT` that is no S bit, an S address past S31.7, an S area that does not fit where it was placed, or a program that uses the bytes the S area went to itself (both uses are labelled; move the S area to a free range).";
    E0225 S7200Aeno Error "AENO whose ENO GUTTA cannot know"
        "In a STEP 7-Micro/WIN export, `AENO` (which Micro/WIN writes after a box when it turns chained LAD boxes into STL) ANDs the top of the logic stack with the previous box's ENO: 0 when the box ran into an error on an S7-200. The compiler translates it into `AN` of the flags the GUTTA box sets on that error (`AN SM1.1` after `+I`, `AN SM1.1` and `AN SM1.3` after `/I`, `AN SM1.6` after `BCDI`), or into nothing after a box that cannot fail (docs/microwin.md, \"AENO\"; the table is `catalog/src/s7200_eno.rs`). This error says where that ENO cannot be known: `AENO` at the start of a network, after a line that is no box with an ENO (a contact, a coil, a timer, a jump), after an S7-200 box GUTTA lacks, or after a box whose S7-200 error GUTTA sets no flag for. Read the flag the box sets yourself (`AN SM1.1`), or end the chain before the box.";
    E0226 S7200LTemporaries Error "Micro/WIN's LAD temporaries L60-L63 do not fit"
        "In a STEP 7-Micro/WIN export, L60.0-L63.7 (LB60-LB63, LW60-LW62, LD60) are the temporaries Micro/WIN uses when it converts LAD networks to STL (`= L60.0` ... `LD L60.0`). GUTTA's L area is smaller (32 bytes on the stdlib targets), so the compiler places these four bytes in the last four bytes of the target's L (LB28-LB31 on 32 bytes) in each block that uses them (docs/microwin.md, \"LAD temporaries L60-L63\"). This error says that in this block those bytes are taken: by its locals (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, VAR) or by a direct L operand of its own. Declare fewer or smaller locals, or move the block's own use of those L bytes to M or V. Any other L address past the target's L stays E0306.";
    E0227 S7200DataBlock Error "malformed line of a Micro/WIN data block export"
        "A STEP 7-Micro/WIN data block export (a file whose first line is `DATA_BLOCK_TAB name`; docs/microwin.md, \"Data block exports\") holds rows of a V address and its values separated by commas (`VB40 1, 2, 3 // comment`), lines of values alone that continue the row above, comments and blank lines, between an optional `BEGIN` and `END_DATA_BLOCK_TAB`. This line is none of these: values without an address before them, an address without a value, two values without a comma between them, an empty value between commas, a quote that is not closed, a character that is not printable ASCII in quotes, text after `END_DATA_BLOCK_TAB`, or a row whose address is a bit (`V0.0`): the rows of a data block are bytes, words and double words (VB, VW, VD). A malformed number is E0104, a value that does not fit its address E0501, overlapping rows E0504, V on a target without V E0306.";

    // ---- E03xx: operands -----------------------------------------------------------
    E0301 OperandCount Error "wrong number of operands"
        "The instruction takes a fixed number of operands (see docs/instructions.md); the message lists them.";
    E0302 WidthMismatch Error "operand width not allowed"
        "The operand's width does not fit the instruction: `MOVW` moves words, so `MOVW MB0, MW2` is wrong (use `MOVB` for bytes, or `MW0`). Widths: B = 8 bits, W = 16, D = 32. For a direct address whose area has the wanted width, the diagnostic carries a fix (editors' quick fix, `fixes` in JSON): the address of that width at the same byte (`MB0` -> `MW0`), where it exists; a symbol or a bit gets none, since what was meant is not known.";
    E0303 TypeMismatch Error "data type not allowed"
        "A typed operand (a local variable or argument declared with a type) has a type the instruction does not accept, e.g. an INT local in `+R`.";
    E0304 AreaNotAllowed Error "area not allowed"
        "The memory area cannot be used this way: a bit of an area without bit access (`AI0.0`, `LD T4` where T holds only words: read a timer with a compare such as `LDW>= T4, 20`), or an area the operand excludes (EXCH tables live in M; TON takes a timer T).";
    E0305 UseNotAllowed Error "address-of or pointer not allowed"
        "`&` takes the address of a BYTE variable in an area that allows it (M, V, SM, L): `&MB24`, not `&MW24`. `*` reads through a pointer held in a DWORD of M, V or L: `*MD4`, not `*MW4`. Only some operands accept them: `&` only where an address is expected (`MOVD &MB24, MD4`).";
    E0306 AddressOutOfTarget Error "address outside the target"
        "The address does not exist on the selected PLC type: the area is too small (`MB200` on CPU-EC20, which has MB0..MB127) or the area is missing (`VB100` exists only on EC30-EKSTM32-XC). The message names the area's size and its valid range (`M has 128 bytes, MB0..MB127`; for timers and counters the numbers, `T has 16 numbers, T0..T15`), the help the stdlib types where the address exists; `--plc` selects another type.";
    E0307 ConstantOutOfRange Error "constant out of range"
        "A constant does not fit the width or type of its operand: `MOVB 300, MB1` (a byte holds 0..255, or -128..127), `+I 40000, MW0` (INT holds -32768..32767), or a literal outside the operand's documented range.";
    E0308 WriteToReadOnly Error "write to a constant or read-only area"
        "The operand is written by the instruction but is a constant, or lies in an area programs cannot write: K (constants), I and AI (inputs are refreshed from the terminals each scan).";
    E0309 ConstantNotAllowed Error "constant not allowed"
        "A constant stands where the instruction needs a variable (bit logic operands, outputs, EXCH tables), or a variable stands where only a literal number is allowed (`LDS n`, the port of EXCH, interrupt event numbers).";
    E0310 WrongOperandKind Error "wrong kind of operand"
        "The operand is of the wrong kind: a label number is expected (`JMP 3`), a subroutine (`CALL ADD3`), an interrupt routine (`ATCH TICK, 10`), or a variable where a block name was written.";
    E0311 MalformedAddress Error "malformed address"
        "An address has the wrong shape for its area: an area with several widths needs a width letter or a bit (`MB3`, `M3.0`), an area with one width takes none (`T5`, not `TW5`), bits are numbered 0..7.";
    E0312 RealNotAllowed Error "REAL constant not allowed"
        "A constant with a fraction or exponent (`1.5`) stands where an integer is expected. REAL constants go to REAL instructions (`MOVR`, `+R`, ...).";

    // ---- E04xx: program structure and limits ---------------------------------------
    E0401 ArgumentCount Error "wrong number of CALL arguments"
        "`CALL` passes one argument for every VAR_INPUT, VAR_IN_OUT and VAR_OUTPUT of the subroutine, in that order.";
    E0402 ArgumentMismatch Error "CALL argument does not fit its parameter"
        "An argument's width or type differs from the parameter's, a constant is passed to a VAR_IN_OUT or VAR_OUTPUT parameter, or an output argument is not writable.";
    E0403 TooManyInterrupts Error "too many interrupt routines"
        "The PLC type allows `ProgramBlockPageIntSize` interrupt routines, MAIN (INT0) included, numbered INT0..INTn-1.";
    E0404 TooManySubroutines Error "too many subroutines"
        "The PLC type allows `ProgramBlockPageSbrSize` subroutines, numbered SBR0..SBRn-1.";
    E0405 TooManyArguments Error "too many local variables"
        "A subroutine may declare `ProgramBlockPageArgSbrSize` locals (arguments and temporaries) and an interrupt routine `ProgramBlockPageArgIntSize`.";
    E0406 LocalsTooLarge Error "locals do not fit in L"
        "A block's locals are laid out in the L area (BOOLs packed in bytes, other types byte-aligned, in the order VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, VAR); together they must fit the target's L size.";
    E0407 InterruptArguments Error "interrupt routine with parameters"
        "Nothing calls an interrupt routine with arguments, so it may declare only temporaries (`VAR`), not VAR_INPUT, VAR_IN_OUT or VAR_OUTPUT.";
    E0408 MissingMain Error "no MAIN"
        "A program needs its main routine: `ORGANIZATION_BLOCK MAIN:OB1` (or `INTERRUPT_BLOCK MAIN:INT0`). In a Micro/WIN export whose files hold one subroutine or interrupt routine each (MicroWIN SMART exports a project one block per file), the help says to pass the export's files together, the one with OB1 among them, with the command (`gutta-cc MAIN.awl SBR_0.awl ...`).";
    E0409 CallCycle Error "recursive call or call too deep"
        "Subroutines may not call themselves, directly or through others (the PLC has no stack for it), and calls nest at most as deep as the target's CallDepth (8).";
    E0410 StackUnderflow Error "no power flow for this instruction"
        "The instruction needs values on the logic stack that are not there: a network must start with a load (`LD`, `LDN`, a compare such as `LDW>=`); `A`, `O`, `=`, and box instructions such as `MOVW` use the top of the stack; `ALD`/`OLD` need two levels. Start the network with `LD SM0.0` for an unconditional box.";
    E0411 StackOverflow Error "logic stack too deep"
        "More loads are pending than the logic stack holds (LogicStackDepth, 9 levels). Combine earlier branches with `ALD`/`OLD` first.";
    E0412 ForNext Error "FOR without NEXT, or NEXT without FOR"
        "Every `FOR` needs a `NEXT` later in the same block, and loops nest at most ForDepth (8) deep.";
    E0413 BlockNumberRange Error "block number out of range"
        "A numbered name exceeds what the PLC type allows: INT0..INTn-1 (ProgramBlockPageIntSize), SBR0..SBRn-1 (ProgramBlockPageSbrSize), DAT0..DATn-1 (DataBlockPageSize).";
    E0414 NetworkOrder Error "network numbers out of order"
        "Network numbers within a block must increase; a number used twice would make breakpoints ambiguous.";
    E0416 WrongUnitKind Error "instruction not allowed in this block"
        "Some instructions belong to one kind of block (the `Units` attribute in ManagerFun.xml): `RET` and `CRET` return from subroutines, `RETI` and `CRETI` from interrupt routines, and `END` ends the scan in MAIN.";

    // ---- E05xx: data blocks --------------------------------------------------------
    E0501 DataValueRange Error "data value does not fit its type"
        "A data block row's initial value is outside its data type's range (`MB30 USINT 300`).";
    E0502 DataTypeWidth Error "data type does not fit the address"
        "A data row's type must have the width of its address: `MW22 UINT 6` (16 bits), `MB30 USINT 1` (8), `MD40 DINT -70000` (32), `M0.0 BOOL 1`.";
    E0503 DataArea Error "area cannot be initialised"
        "Data blocks initialise memory that persists across scans: M, V, Q, AQ, T and C. K is filled by the compiler, inputs come from the terminals, L exists only during a call.";
    E0504 DataOverlap Error "overlapping data rows"
        "Two rows initialise the same byte; the second would silently win on the PLC.";
    E0505 DataBlockTooLarge Error "data block too large"
        "A data block (one data page) holds at most `DataBlockPageItemSize` rows of 8 bytes. (Data block numbers beyond `DataBlockPageSize` are E0413.)";

    // ---- E06xx: system block -------------------------------------------------------
    E0601 UnknownSystemKey Error "unknown system block key"
        "Keys are `PORTn.PROTOCOL`, `PORTn.ADDRESS`, `PORTn.BAUD`, `PORTn.DATA_BITS`, `PORTn.PARITY`, `PORTn.STOP_BITS`, `PORTn.TIMEOUT`, `PORTn.FRAME_GAP` and `PASSWORD`. The help line suggests the closest key.";
    E0602 SystemValue Error "system block value not allowed"
        "PROTOCOL is MODBUS; ADDRESS 0..255; BAUD 9600, 19200, 38400, 57600 or 115200; DATA_BITS 8 (RTU); PARITY NONE, EVEN or ODD; STOP_BITS 1 or 2; TIMEOUT 1..255 (x 100 ms); FRAME_GAP 1..255 (x 1 ms); PASSWORD a string of at most 16 ASCII characters.";
    E0603 DuplicateSystemKey Error "system block key set twice"
        "Each key may be set once; the second value would silently win.";
    E0604 NoSuchPort Error "serial port not on this PLC type"
        "The PLC type has fewer serial ports (CPU-EC20 has PORT0 only).";
    E0605 DuplicateSystemBlock Error "more than one SYSTEM_BLOCK"
        "A program has one system block; merge the entries.";

    // ---- E07xx: image limits ---------------------------------------------------------
    E0701 ConstPageTooLarge Error "constants do not fit the const page"
        "All distinct constants of the program, packed as tightly as the format allows, must fit `ProgramBlockConstBinarySize` and the K area. Use fewer distinct constants, e.g. keep tables in a data block instead of immediates.";
    E0702 InstructionsTooLarge Error "program too large"
        "The instruction pages of all blocks together must fit `ProgramBlockInstructionBinarySize`. Each instruction takes 3 bytes plus 4 per operand, each network 4 bytes (docs/image-format.md).";
    E0703 SystemPageTooLarge Error "system block too large"
        "The system page (18 bytes + 8 per serial port) must fit `SystemBlockBinarySize`.";

    // ---- E08xx: test files (.gtest, docs/testing-programs.md) -----------------------
    E0801 TestSyntax Error "malformed test statement"
        "A line of a `.gtest` file does not have its statement's shape: `SET VAR = VALUE, ...`, `SCAN [n]`, `ADVANCE 2s`, `EXPECT VAR = VALUE, ...` (comparisons `=`, `<>`, `<`, `<=`, `>`, `>=`), `UNTIL VAR = VALUE WITHIN n SCANS`, `FORCE VAR = VALUE`, `UNFORCE VAR` or `UNFORCE ALL`, `EXPECT FAULT code`, `EXPECT RUN`/`EXPECT STOP`, `RESET`, `RUN`, `STOP`; a header `PROGRAM path`, `SCAN_TIME 10ms`, `PLC_TYPE name`, `OPTION name`, `WATCHDOG n`. The message says what was expected where.";
    E0802 UnknownStatement Error "unknown test statement"
        "The first word of a line of a `.gtest` file is no statement keyword (keywords are case-insensitive). The help names the closest keyword; docs/testing-programs.md lists them all.";
    E0803 TestStructure Error "statement outside its place in a test file"
        "A test file is a header (`PROGRAM`, `SCAN_TIME`, `PLC_TYPE`, `OPTION`, `WATCHDOG`, each at most once, before the first test), then tests, each from `TEST name` to `END_TEST`. A statement outside a test, a header line inside one, a `TEST` before the previous `END_TEST`, an `END_TEST` without its `TEST`, or a test not closed at the end of the file is this error.";
    E0804 DuplicateTest Error "test name used twice"
        "Each test of a file needs its own name: `--filter`, the report and JUnit XML name tests by it. Rename one.";
    E0805 UnknownTestVariable Error "unknown variable in a test"
        "A variable of a test is neither a symbol of the program under test (its SYMBOLS blocks and symbol tables) nor a direct address of its PLC type. The help names the closest symbol.";
    E0806 TestValueMismatch Error "value does not fit the variable"
        "A test value must fit its variable's type: 0/1 or TRUE/FALSE for a bit, an integer that fits the width signed or unsigned for a byte, word or double word, a REAL (`1.5`) only for a variable declared REAL, a text (`\"12\"`) only for a byte (consecutive bytes), and only `=` or `<>` for a text. A FORCE needs a variable of a forcing area (I, Q).";
    E0807 TestProgramMissing Error "program under test not found"
        "`PROGRAM path` names a file that cannot be read (the path is relative to the test file), or a test file has no `PROGRAM` line and is not inside a project (gutta.toml), whose program it would test.";
    E0808 TestProgramErrors Error "program under test does not compile"
        "The program a test file names has errors; they are shown after this one. No test of the file runs until the program compiles.";
    E0809 TestHeaderValue Error "bad test file header value"
        "A header value is wrong: a `SCAN_TIME` of 0 or not whole milliseconds, an unknown `PLC_TYPE` or `OPTION`, a `WATCHDOG` of 0, or a header line given twice.";

    // ---- W02xx: warnings -------------------------------------------------------------
    W0201 DoubleCoil Warning "output written by more than one `=`"
        "The same bit is the target of `=` in two places; the last one in the scan wins, which is rarely intended. Use S/R, or combine the conditions.";
    W0202 TimerReused Warning "timer or counter used by two instructions"
        "Two timer (or counter) instructions drive the same T (or C) number; they overwrite each other's current value.";
    W0203 UnusedSubroutine Warning "subroutine never called"
        "No CALL reaches this subroutine; it is still downloaded.";
    W0204 PlcTypeOverridden Warning "PLC_TYPE overridden"
        "The file names one PLC type and the command line (`--plc` or `--target`) another; the command line wins.";
    W0205 EmptyNetwork Warning "empty network"
        "A network without instructions. It is kept (so numbering stays), but does nothing.";
    W0206 SystemNameShadowed Warning "user symbol hides a Micro/WIN system symbol"
        "In a STEP 7-Micro/WIN export (docs/microwin.md) Micro/WIN's system symbols (`Always_On`, `Clock_1s`, ...) name the target's SM bits that mean the same (the `MicroWin` attribute of its `SystemBit` rows, docs/targets.md). A user symbol of the same name wins, as in Micro/WIN; this warning says so, in case the program meant the system bit. MicroWIN SMART's default I/O names (`CPU_输入0`, `CPU_Output3`) are system symbols too: a user symbol named so at another address gets this warning, one at the same bit (a copy of SMART's I/O symbol table) none.";
    W0207 TimerResolution Warning "S7-200 timer resolution differs from the target's"
        "On an S7-200 a timer's number fixes its resolution (CPU 22x: TON/TOF T32 and T96 count 1 ms, T33-T36 and T97-T100 10 ms, the rest 100 ms; TONR T0 and T64 1 ms, T1-T4 and T65-T68 10 ms, the rest 100 ms). Where the target's resolution for that number (its `<Timers>` rows, docs/targets.md) differs, the same preset lasts a different time: the warning, once per timer, gives both resolutions and what the preset means on each. `gutta-cc --scale-timer-presets` (or `scale-timer-presets = true` in gutta.toml's [build]) scales constant presets to keep the S7-200 timing, rounded to the nearest unit; it warns only where rounding changes the time or a preset in memory cannot be scaled.";
    W0208 SymbolRepeated Warning "symbol declared twice with the same address"
        "Two declarations of one symbol (in two symbol tables, a table and a SYMBOLS block, or one block) agree: the same address and the same type (or none). Micro/WIN projects often carry the same table twice; the symbol means one thing, so this is a warning where a different address or type is E0203. Remove one of them.";
    W0801 TestChecksNothing Warning "test checks nothing"
        "A test without `EXPECT` or `UNTIL` passes whatever the program does (only a fault fails it). Add the expectation the test is about.";
    W0802 NoTests Warning "test file without tests"
        "A `.gtest` file has no `TEST` block; it runs nothing.";
    W0803 ComparisonAlwaysTrue Warning "comparison that is always true"
        "An `EXPECT` or `UNTIL` comparison holds whatever the variable's value, because of the variable's type: `Lamp >= 0` or `Lamp <= 1` on a bit, `>= 0` on an unsigned BYTE, WORD or DWORD, `<= 255` on a BYTE, `>= -32768` or `<= 32767` on an INT. It checks nothing; compare with the value the test is about (`Lamp = 1`, `MB4 > 0`).";
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn codes_are_unique_well_formed_and_explained() {
        let mut seen = BTreeSet::new();
        for c in Code::ALL {
            assert!(seen.insert(c.as_str()), "{} twice", c.as_str());
            let s = c.as_str();
            assert_eq!(s.len(), 5);
            let want = if s.starts_with('W') {
                Severity::Warning
            } else {
                Severity::Error
            };
            assert_eq!(c.severity(), want);
            assert!(c.explanation().len() > 40, "{s} needs an explanation");
            assert_eq!(Code::parse(s), Some(*c));
        }
    }
}
