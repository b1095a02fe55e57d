//! The packed 32-bit operand, OFFSET<<16 | BIT_OFFSET<<12 | WIDTH<<8 | SLOT<<4 | USE, and
//! what it names: variables, pointer values, labels, literals and program units with
//! their page numbers. The only code in the toolchain that shifts or masks an operand
//! word, a pointer value or computes a unit's page; everything else calls it.

use std::fmt;

use gutta_catalog::{Address, BlockKind, PlcType, Width};

/// How an operand is used (the USE field).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Use {
    /// The variable's value (constants are variables in K).
    Value = 0,
    /// `&MB24`: the pointer value of that byte.
    AddressOf = 1,
    /// `*MD4`: the variable the pointer in MD4 points to.
    Pointer = 2,
    /// A label number (OFFSET).
    Label = 3,
    /// A program unit: SLOT 0 interrupt, 1 subroutine; OFFSET its number.
    Unit = 4,
    /// A literal number (OFFSET).
    Literal = 5,
}

impl Use {
    /// Its name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Use::Value => "value",
            Use::AddressOf => "address-of",
            Use::Pointer => "pointer",
            Use::Label => "label",
            Use::Unit => "unit",
            Use::Literal => "literal",
        }
    }

    pub fn from_code(code: u8) -> Option<Use> {
        Some(match code {
            0 => Use::Value,
            1 => Use::AddressOf,
            2 => Use::Pointer,
            3 => Use::Label,
            4 => Use::Unit,
            5 => Use::Literal,
            _ => return None,
        })
    }
}

/// The USE code of a force-release address word (`PackedOperand::force_release`).
pub const RELEASE_USE: u8 = 0xF;

/// One packed operand, as stored (little-endian) in pages.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PackedOperand(pub u32);

impl PackedOperand {
    /// A memory operand.
    pub fn memory(address: Address, use_: Use, width: Width) -> PackedOperand {
        let bit = if width == Width::Bit {
            address.bit as u32 & 7
        } else {
            0
        };
        PackedOperand(
            ((address.offset & 0xFFFF) << 16)
                | (bit << 12)
                | ((width as u32) << 8)
                | ((address.slot as u32 & 0xF) << 4)
                | use_ as u32,
        )
    }

    /// A label, unit or literal operand.
    pub fn special(use_: Use, slot: u8, value: u16) -> PackedOperand {
        PackedOperand(((value as u32) << 16) | ((slot as u32 & 0xF) << 4) | use_ as u32)
    }

    pub fn offset(self) -> u16 {
        (self.0 >> 16) as u16
    }

    pub fn bit(self) -> u8 {
        ((self.0 >> 12) & 0xF) as u8
    }

    pub fn width_code(self) -> u8 {
        ((self.0 >> 8) & 0xF) as u8
    }

    pub fn width(self) -> Option<Width> {
        Width::from_code(self.width_code())
    }

    pub fn slot(self) -> u8 {
        ((self.0 >> 4) & 0xF) as u8
    }

    pub fn use_code(self) -> u8 {
        (self.0 & 0xF) as u8
    }

    pub fn use_(self) -> Option<Use> {
        Use::from_code(self.use_code())
    }

    /// The address this operand names (memory uses only; for `Pointer`, where the pointer is).
    pub fn address(self) -> Option<Address> {
        let width = match self.use_()? {
            Use::Value => self.width()?,
            Use::AddressOf => gutta_catalog::Width::Byte,
            Use::Pointer => Width::Dword,
            _ => return None,
        };
        Some(Address {
            slot: self.slot(),
            width,
            offset: self.offset() as u32,
            bit: if width == Width::Bit { self.bit() } else { 0 },
        })
    }

    pub fn to_le_bytes(self) -> [u8; 4] {
        self.0.to_le_bytes()
    }

    pub fn from_le_bytes(b: [u8; 4]) -> PackedOperand {
        PackedOperand(u32::from_le_bytes(b))
    }
}

impl fmt::Debug for PackedOperand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "PackedOperand(0x{:08X}: use {} slot {} width {} bit {} offset {})",
            self.0,
            self.use_code(),
            self.slot(),
            self.width_code(),
            self.bit(),
            self.offset()
        )
    }
}

/// A packed operand word, decoded: the only place that knows its fields' meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Operand {
    /// USE 0: the variable at `Address` (its width is the access width).
    Value(Address),
    /// USE 1: `&byte`, read as a `width` value (DWORD, as the compiler writes it): its
    /// value is `Pointer::to(byte).0`. `byte.width` is Byte.
    AddressOf { byte: Address, width: Width },
    /// USE 2: `*holder`: the variable of `width` that the pointer held in the DWORD at
    /// `holder` points to.
    Pointer { holder: Address, width: Width },
    /// USE 3: a label number.
    Label(u16),
    /// USE 4: a program unit.
    Unit(UnitRef),
    /// USE 5: a literal number.
    Literal(u16),
}

/// What is wrong with an operand word that does not decode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OperandError {
    /// USE is not 0..5.
    Use(u8),
    /// WIDTH is not a width code (0 bit, 1 byte, 2 word, 3 dword).
    Width(u8),
    /// BIT_OFFSET is above 7 on a bit, or not 0 where there is no bit.
    Bit { bit: u8 },
    /// A label, unit or literal operand with WIDTH, BIT_OFFSET or SLOT bits it must not have.
    NotZero { use_: Use },
    /// The SLOT of a unit operand is not 0 (interrupt) or 1 (subroutine).
    UnitSlot(u8),
}

impl fmt::Display for OperandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OperandError::Use(code) => write!(f, "USE {code} is not 0..5"),
            OperandError::Width(code) => write!(f, "WIDTH {code} is not a width code (0..3)"),
            OperandError::Bit { bit } => write!(
                f,
                "BIT_OFFSET {bit}: a bit operand has 0..7, any other operand 0"
            ),
            OperandError::NotZero { use_ } => write!(
                f,
                "a {} operand has WIDTH 0 and BIT_OFFSET 0{}",
                use_.name(),
                if *use_ == Use::Unit {
                    ""
                } else {
                    " and SLOT 0"
                }
            ),
            OperandError::UnitSlot(slot) => write!(
                f,
                "SLOT {slot}: the SLOT of a unit operand is 0 (interrupt) or 1 (subroutine)"
            ),
        }
    }
}

impl std::error::Error for OperandError {}

impl PackedOperand {
    /// The operand word, decoded. Strict: only the forms `encode` writes decode, so
    /// `PackedOperand::encode(w.decode()?) == w`.
    pub fn decode(self) -> Result<Operand, OperandError> {
        let use_ = self.use_().ok_or(OperandError::Use(self.use_code()))?;
        match use_ {
            Use::Value | Use::AddressOf | Use::Pointer => {
                let width = self.width().ok_or(OperandError::Width(self.width_code()))?;
                let bit = self.bit();
                let bit_ok = if use_ == Use::Value && width == Width::Bit {
                    bit < 8
                } else {
                    bit == 0
                };
                if !bit_ok {
                    return Err(OperandError::Bit { bit });
                }
                let at = |width: Width| Address {
                    slot: self.slot(),
                    width,
                    offset: u32::from(self.offset()),
                    bit,
                };
                Ok(match use_ {
                    Use::Value => Operand::Value(at(width)),
                    Use::AddressOf => Operand::AddressOf {
                        byte: at(Width::Byte),
                        width,
                    },
                    _ => Operand::Pointer {
                        holder: at(Width::Dword),
                        width,
                    },
                })
            }
            Use::Label | Use::Literal | Use::Unit => {
                let slot_free = use_ == Use::Unit || self.slot() == 0;
                if self.width_code() != 0 || self.bit() != 0 || !slot_free {
                    return Err(OperandError::NotZero { use_ });
                }
                let value = self.offset();
                Ok(match use_ {
                    Use::Label => Operand::Label(value),
                    Use::Literal => Operand::Literal(value),
                    _ => Operand::Unit(UnitRef {
                        kind: match self.slot() {
                            0 => BlockKind::Interrupt,
                            1 => BlockKind::Subroutine,
                            slot => return Err(OperandError::UnitSlot(slot)),
                        },
                        number: value,
                    }),
                })
            }
        }
    }

    /// The operand word of a decoded operand. A `Value` keeps its bit only when its
    /// width is `Bit`.
    pub fn encode(operand: Operand) -> PackedOperand {
        match operand {
            Operand::Value(a) => PackedOperand::memory(a, Use::Value, a.width),
            Operand::AddressOf { byte, width } => {
                PackedOperand::memory(byte, Use::AddressOf, width)
            }
            Operand::Pointer { holder, width } => {
                PackedOperand::memory(holder, Use::Pointer, width)
            }
            Operand::Label(n) => PackedOperand::special(Use::Label, 0, n),
            Operand::Literal(n) => PackedOperand::special(Use::Literal, 0, n),
            Operand::Unit(unit) => PackedOperand::special(
                Use::Unit,
                match unit.kind {
                    BlockKind::Interrupt => 0,
                    BlockKind::Subroutine => 1,
                },
                unit.number,
            ),
        }
    }

    /// The address word that releases the force of a variable: USE 15, our extension of
    /// STATUS_VAR_FORCE_WRITE (UM4001 has no unforce; docs/simulator.md). A PLC that
    /// ignores USE forces the value sent instead.
    pub fn force_release(variable: Address) -> PackedOperand {
        let word = PackedOperand::encode(Operand::Value(variable)).0;
        PackedOperand((word & !0xF) | u32::from(RELEASE_USE))
    }

    /// The variable an address word of STATUS_VAR_* / STATUS_FORCE_* names: USE is
    /// ignored, as the PLC reads these words, and only the low three bits of BIT_OFFSET
    /// count on a bit. Fails only on a bad WIDTH.
    pub fn variable(self) -> Result<Address, OperandError> {
        let width = self.width().ok_or(OperandError::Width(self.width_code()))?;
        Ok(Address {
            slot: self.slot(),
            width,
            offset: u32::from(self.offset()),
            bit: if width == Width::Bit {
                self.bit() & 7
            } else {
                0
            },
        })
    }
}

/// A pointer value, as `&` makes it and `*` follows it: SLOT in bits 31..24, the byte
/// offset in bits 23..0 (`&MB24` with M in slot 4 is 0x0400_0018).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Pointer(pub u32);

impl Pointer {
    /// The pointer to an address's first byte.
    pub fn to(address: Address) -> Pointer {
        Pointer((u32::from(address.slot) << 24) | (address.offset & 0x00FF_FFFF))
    }

    pub fn slot(self) -> u8 {
        (self.0 >> 24) as u8
    }

    pub fn offset(self) -> u32 {
        self.0 & 0x00FF_FFFF
    }

    /// The variable of `width` it points to (a pointer names bytes, so bit 0).
    pub fn target(self, width: Width) -> Address {
        Address {
            slot: self.slot(),
            width,
            offset: self.offset(),
            bit: 0,
        }
    }
}

/// A program unit: an interrupt routine (MAIN is INT0) or a subroutine, by number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct UnitRef {
    pub kind: BlockKind,
    pub number: u16,
}

impl UnitRef {
    /// The main program, INT0.
    pub const MAIN: UnitRef = UnitRef {
        kind: BlockKind::Interrupt,
        number: 0,
    };

    pub fn interrupt(number: u16) -> UnitRef {
        UnitRef {
            kind: BlockKind::Interrupt,
            number,
        }
    }

    pub fn subroutine(number: u16) -> UnitRef {
        UnitRef {
            kind: BlockKind::Subroutine,
            number,
        }
    }

    /// The unit's page number (its function index) on a target: INTn is page n, SBRn
    /// page ProgramBlockPageIntSize + n (docs/image-format.md). None when the target
    /// cannot have the unit.
    pub fn page(self, plc: &PlcType) -> Option<u8> {
        let number = u32::from(self.number);
        let page = match self.kind {
            BlockKind::Interrupt => (number < plc.program_block_page_int_size).then_some(number)?,
            BlockKind::Subroutine => (number < plc.program_block_page_sbr_size)
                .then(|| plc.program_block_page_int_size.checked_add(number))??,
        };
        u8::try_from(page).ok()
    }

    /// The unit a page number stands for on a target; None past IntSize + SbrSize.
    pub fn from_page(page: u8, plc: &PlcType) -> Option<UnitRef> {
        let (page, int_size) = (u32::from(page), plc.program_block_page_int_size);
        let unit = if page < int_size {
            UnitRef::interrupt(u16::try_from(page).ok()?)
        } else {
            UnitRef::subroutine(u16::try_from(page - int_size).ok()?)
        };
        unit.page(plc).is_some().then_some(unit)
    }
}

impl fmt::Display for UnitRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            BlockKind::Interrupt if self.number == 0 => f.write_str("MAIN"),
            BlockKind::Interrupt => write!(f, "INT{}", self.number),
            BlockKind::Subroutine => write!(f, "SBR{}", self.number),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_examples() {
        let mw20 = Address {
            slot: 4,
            width: Width::Word,
            offset: 20,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(mw20, Use::Value, Width::Word).0,
            0x0014_0240
        );
        assert_eq!(
            PackedOperand::memory(mw20, Use::Value, Width::Word).to_le_bytes(),
            [0x40, 0x02, 0x14, 0x00]
        );
        let m03 = Address {
            slot: 4,
            width: Width::Bit,
            offset: 0,
            bit: 3,
        };
        assert_eq!(
            PackedOperand::memory(m03, Use::Value, Width::Bit).0,
            0x0000_3040
        );
        let md4 = Address {
            slot: 4,
            width: Width::Dword,
            offset: 4,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(md4, Use::Pointer, Width::Word).0,
            0x0004_0242
        );
        let mb24 = Address {
            slot: 4,
            width: Width::Byte,
            offset: 24,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(mb24, Use::AddressOf, Width::Dword).0,
            0x0018_0341
        );
        assert_eq!(Pointer::to(mb24).0, 0x0400_0018);
    }
}

#[cfg(test)]
mod decode_tests {
    use super::*;

    /// Every combination of the four small fields, at three offsets: whatever decodes
    /// encodes back to the same word, and the decoded form means what the fields say.
    #[test]
    fn decode_is_the_inverse_of_encode() {
        let mut decoded = 0;
        for low in 0..=0xFFFFu32 {
            for offset in [0u32, 1, 0xFFFF] {
                let word = PackedOperand((offset << 16) | low);
                let Ok(op) = word.decode() else { continue };
                decoded += 1;
                assert_eq!(PackedOperand::encode(op), word, "{word:?} -> {op:?}");
                match op {
                    Operand::Value(a) => {
                        assert_eq!((a.slot, a.offset), (word.slot(), offset));
                        assert_eq!(Some(a.width), word.width());
                    }
                    Operand::Pointer { holder, width } => {
                        assert_eq!(holder.width, Width::Dword);
                        assert_eq!(Some(width), word.width());
                    }
                    Operand::AddressOf { byte, width } => {
                        assert_eq!(byte.width, Width::Byte);
                        assert_eq!(Some(width), word.width());
                    }
                    Operand::Label(n) | Operand::Literal(n) => assert_eq!(u32::from(n), offset),
                    Operand::Unit(u) => assert_eq!(u32::from(u.number), offset),
                }
            }
        }
        // USE 0..2 x 16 slots x 4 widths (bits 0..7 on a bit, else 0), label and
        // literal with slot 0, unit with slot 0 or 1; three offsets each.
        let memory = 16 * (8 + 3) + 2 * 16 * 4;
        assert_eq!(decoded, 3 * (memory + 2 + 2));
    }

    #[test]
    fn bad_words_say_what_is_wrong() {
        assert_eq!(PackedOperand(0x6).decode(), Err(OperandError::Use(6)));
        assert_eq!(PackedOperand(0x0440).decode(), Err(OperandError::Width(4)));
        assert_eq!(
            PackedOperand(0x8040).decode(),
            Err(OperandError::Bit { bit: 8 })
        );
        assert_eq!(
            PackedOperand(0x1140).decode(),
            Err(OperandError::Bit { bit: 1 })
        );
        assert_eq!(PackedOperand(0x24).decode(), Err(OperandError::UnitSlot(2)));
        assert_eq!(
            PackedOperand(0x15).decode(),
            Err(OperandError::NotZero { use_: Use::Literal })
        );
        // A STATUS_VAR address word ignores USE and the high bit-offset bit.
        let a = PackedOperand(0x0002_B047).variable().expect("a bit");
        assert_eq!((a.slot, a.offset, a.width, a.bit), (4, 2, Width::Bit, 3));
        // The force-release word names the same variable with USE 15.
        let release = PackedOperand::force_release(a);
        assert_eq!(release.0, 0x0002_304F);
        assert_eq!(release.variable(), Ok(a));
    }

    #[test]
    fn unit_pages_and_back() {
        let plc = gutta_catalog::stdlib::default_target()
            .expect("the default target loads")
            .plc;
        // CPU-EC20: 8 interrupt routines, 8 subroutines.
        assert_eq!(UnitRef::MAIN.page(&plc), Some(0));
        assert_eq!(UnitRef::interrupt(7).page(&plc), Some(7));
        assert_eq!(UnitRef::interrupt(8).page(&plc), None);
        assert_eq!(UnitRef::subroutine(0).page(&plc), Some(8));
        assert_eq!(UnitRef::subroutine(8).page(&plc), None);
        for page in 0..=255u8 {
            match UnitRef::from_page(page, &plc) {
                Some(unit) => assert_eq!(unit.page(&plc), Some(page)),
                None => assert!(page >= 16),
            }
        }
        assert_eq!(
            UnitRef::from_page(9, &plc).map(|u| u.to_string()),
            Some("SBR1".into())
        );
        assert_eq!(UnitRef::MAIN.to_string(), "MAIN");
        assert_eq!(UnitRef::interrupt(3).to_string(), "INT3");
    }
}
