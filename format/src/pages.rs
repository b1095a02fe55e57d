//! Encoders and decoders of the argument, instruction, data and system pages
//! (docs/image-format.md). Decoders check structure only (lengths, record shapes) and
//! return typed errors; whether opcodes and operands fit a target is the verifier's job.

use std::fmt;

use crate::PackedOperand;

/// Where and why a page does not decode.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    /// Byte offset in the page.
    pub offset: usize,
    pub reason: String,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at byte {}: {}", self.offset, self.reason)
    }
}

impl std::error::Error for DecodeError {}

fn err<T>(offset: usize, reason: impl Into<String>) -> Result<T, DecodeError> {
    Err(DecodeError {
        offset,
        reason: reason.into(),
    })
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes([*b.get(at)?, *b.get(at + 1)?]))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes([
        *b.get(at)?,
        *b.get(at + 1)?,
        *b.get(at + 2)?,
        *b.get(at + 3)?,
    ]))
}

// ---- argument pages --------------------------------------------------------------

/// Section of a local (argument page byte 8 + 8i).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LocalSection {
    Input = 0,
    InOut = 1,
    Output = 2,
    Temp = 3,
}

impl LocalSection {
    pub fn from_code(c: u8) -> Option<LocalSection> {
        Some(match c {
            0 => LocalSection::Input,
            1 => LocalSection::InOut,
            2 => LocalSection::Output,
            3 => LocalSection::Temp,
            _ => return None,
        })
    }
}

/// Data type codes of argument pages, in `gutta_catalog::DataType::ALL` order.
pub fn data_type_code(t: gutta_catalog::DataType) -> u8 {
    gutta_catalog::DataType::ALL
        .iter()
        .position(|x| *x == t)
        .unwrap_or(0) as u8
}

pub fn data_type_from_code(c: u8) -> Option<gutta_catalog::DataType> {
    gutta_catalog::DataType::ALL.get(c as usize).copied()
}

/// One local of a unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalEntry {
    pub operand: PackedOperand,
    pub section: LocalSection,
    pub data_type: gutta_catalog::DataType,
}

/// An argument page: the unit it describes and its locals.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArgumentPage {
    /// 0 interrupt routine, 1 subroutine.
    pub subroutine: bool,
    pub unit_number: u8,
    pub locals: Vec<LocalEntry>,
}

impl ArgumentPage {
    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(4 + 8 * self.locals.len());
        out.extend([
            u8::from(self.subroutine),
            self.unit_number,
            self.locals.len().min(255) as u8,
            0,
        ]);
        for l in self.locals.iter().take(255) {
            out.extend(l.operand.to_le_bytes());
            out.extend([l.section as u8, data_type_code(l.data_type), 0, 0]);
        }
        out
    }

    pub fn decode(b: &[u8]) -> Result<ArgumentPage, DecodeError> {
        if b.len() < 4 {
            return err(b.len(), "argument page shorter than its 4-byte header");
        }
        let subroutine = match b[0] {
            0 => false,
            1 => true,
            k => {
                return err(
                    0,
                    format!("unit kind {k} is neither 0 (interrupt) nor 1 (subroutine)"),
                )
            }
        };
        let count = b[2] as usize;
        if b.len() != 4 + 8 * count {
            return err(
                b.len().min(4 + 8 * count),
                format!(
                    "{count} locals need {} bytes, the page has {}",
                    4 + 8 * count,
                    b.len()
                ),
            );
        }
        let mut locals = Vec::with_capacity(count);
        for i in 0..count {
            let at = 4 + 8 * i;
            let operand = PackedOperand(u32_at(b, at).unwrap_or(0));
            let section = LocalSection::from_code(b[at + 4]).ok_or(DecodeError {
                offset: at + 4,
                reason: format!("local section {} is not 0..3", b[at + 4]),
            })?;
            let data_type = data_type_from_code(b[at + 5]).ok_or(DecodeError {
                offset: at + 5,
                reason: format!("data type code {} is not 0..10", b[at + 5]),
            })?;
            locals.push(LocalEntry {
                operand,
                section,
                data_type,
            });
        }
        Ok(ArgumentPage {
            subroutine,
            unit_number: b[1],
            locals,
        })
    }
}

// ---- instruction pages -----------------------------------------------------------

/// One record of an instruction page.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Record {
    /// Start of a network, with its number.
    Network(u16),
    Instruction {
        opcode: u16,
        operands: Vec<PackedOperand>,
    },
}

impl Record {
    pub fn encode_into(&self, out: &mut Vec<u8>) {
        match self {
            Record::Network(n) => {
                out.extend(0u16.to_le_bytes());
                out.extend(n.to_le_bytes());
            }
            Record::Instruction { opcode, operands } => {
                out.extend(opcode.to_le_bytes());
                out.push(operands.len().min(255) as u8);
                for op in operands.iter().take(255) {
                    out.extend(op.to_le_bytes());
                }
            }
        }
    }

    /// Encoded length in bytes.
    pub fn len(&self) -> usize {
        match self {
            Record::Network(_) => 4,
            Record::Instruction { operands, .. } => 3 + 4 * operands.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        false
    }
}

/// Encode a whole instruction page.
pub fn encode_instructions(records: &[Record]) -> Vec<u8> {
    let mut out = Vec::with_capacity(records.iter().map(Record::len).sum());
    for r in records {
        r.encode_into(&mut out);
    }
    out
}

/// Decode an instruction page into (byte offset, record) pairs.
pub fn decode_instructions(b: &[u8]) -> Result<Vec<(usize, Record)>, DecodeError> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut in_network = false;
    while at < b.len() {
        let Some(opcode) = u16_at(b, at) else {
            return err(at, "record cut off inside its opcode");
        };
        if opcode == 0 {
            let Some(n) = u16_at(b, at + 2) else {
                return err(at, "network record cut off");
            };
            out.push((at, Record::Network(n)));
            in_network = true;
            at += 4;
            continue;
        }
        if !in_network {
            return err(at, "instruction before the first network record");
        }
        let Some(&count) = b.get(at + 2) else {
            return err(at, "instruction record cut off before its operand count");
        };
        let end = at + 3 + 4 * count as usize;
        if end > b.len() {
            return err(
                at,
                format!(
                    "instruction with {count} operands needs {} bytes, {} are left",
                    3 + 4 * count as usize,
                    b.len() - at
                ),
            );
        }
        let operands = (0..count as usize)
            .map(|i| PackedOperand(u32_at(b, at + 3 + 4 * i).unwrap_or(0)))
            .collect();
        out.push((at, Record::Instruction { opcode, operands }));
        at = end;
    }
    Ok(out)
}

// ---- data pages ------------------------------------------------------------------

/// One 8-byte data item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataItem {
    pub operand: PackedOperand,
    /// Initial value, little-endian 32 bits (sign- or zero-extended; REAL bits).
    pub value: u32,
}

pub fn encode_data(items: &[DataItem]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 * items.len());
    for i in items {
        out.extend(i.operand.to_le_bytes());
        out.extend(i.value.to_le_bytes());
    }
    out
}

pub fn decode_data(b: &[u8]) -> Result<Vec<DataItem>, DecodeError> {
    if !b.len().is_multiple_of(8) {
        return err(
            b.len() - b.len() % 8,
            format!("data page length {} is not a multiple of 8", b.len()),
        );
    }
    Ok(b.chunks_exact(8)
        .map(|c| DataItem {
            operand: PackedOperand(u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            value: u32::from_le_bytes([c[4], c[5], c[6], c[7]]),
        })
        .collect())
}

// ---- system pages ----------------------------------------------------------------

/// The baud rates of the system block, by code.
pub const BAUD_RATES: [u32; 5] = [9600, 19200, 38400, 57600, 115200];

/// One serial port's settings (8 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortEntry {
    /// 0 = Modbus RTU.
    pub protocol: u8,
    pub address: u8,
    pub baud: u32,
    pub data_bits: u8,
    /// 0 none, 1 even, 2 odd.
    pub parity: u8,
    pub stop_bits: u8,
    pub timeout: u8,
    pub frame_gap: u8,
}

impl PortEntry {
    /// The serial line this port runs with.
    pub fn line(&self) -> LineSettings {
        LineSettings {
            baud: self.baud,
            data_bits: self.data_bits,
            parity: self.parity,
            stop_bits: self.stop_bits,
        }
    }
}

/// A serial line's parity: the one type of it (a system block's `PORTn.PARITY`,
/// gutta.toml's and the client's `parity`). In a system page, `PortEntry` and
/// `LineSettings` it is its code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parity {
    None,
    Even,
    Odd,
}

impl Parity {
    /// The code: 0 none, 1 even, 2 odd.
    pub fn code(self) -> u8 {
        match self {
            Parity::None => 0,
            Parity::Even => 1,
            Parity::Odd => 2,
        }
    }

    /// A code as a parity; `None` for a code other than 0..2.
    pub fn from_code(code: u8) -> Option<Parity> {
        match code {
            0 => Some(Parity::None),
            1 => Some(Parity::Even),
            2 => Some(Parity::Odd),
            _ => None,
        }
    }

    /// Every parity, in code order.
    pub const ALL: [Parity; 3] = [Parity::None, Parity::Even, Parity::Odd];

    /// A parity by its name (`none`, `even`, `odd`, as [`Parity::name`] gives it).
    pub fn from_name(name: &str) -> Option<Parity> {
        Parity::ALL.into_iter().find(|p| p.name() == name)
    }

    /// `none`, `even`, `odd`: as gutta.toml and the flags spell it.
    pub fn name(self) -> &'static str {
        match self {
            Parity::None => "none",
            Parity::Even => "even",
            Parity::Odd => "odd",
        }
    }
}

/// A serial line's settings: what a port of the system page says, or `DEFAULT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LineSettings {
    pub baud: u32,
    pub data_bits: u8,
    /// 0 none, 1 even, 2 odd (as in `PortEntry`).
    pub parity: u8,
    pub stop_bits: u8,
}

impl LineSettings {
    /// 19200 baud, 8 data bits, even parity, 1 stop bit: a port without a system page,
    /// and every port after PLC_CLEAR (UM4001).
    pub const DEFAULT: LineSettings = LineSettings {
        baud: 19200,
        data_bits: 8,
        parity: 1,
        stop_bits: 1,
    };
}

impl std::fmt::Display for LineSettings {
    /// `19200 8E1`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parity = match Parity::from_code(self.parity) {
            Some(Parity::None) => 'N',
            Some(Parity::Even) => 'E',
            Some(Parity::Odd) => 'O',
            None => '?',
        };
        write!(
            f,
            "{} {}{parity}{}",
            self.baud, self.data_bits, self.stop_bits
        )
    }
}

/// The system page: ports and password.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SystemPage {
    pub ports: Vec<PortEntry>,
    /// 16 bytes; 16 x 0xFF is the factory password (none set).
    pub password: [u8; 16],
}

pub const SYSTEM_LAYOUT_VERSION: u8 = 1;

/// The 16 password bytes of a text password: its bytes, zero-padded (longer text is cut
/// at 16 bytes); no password is the factory password, 16 x 0xFF. The compiler writes
/// the system block's password this way and the download client logs in with it.
pub fn password_bytes(text: Option<&str>) -> [u8; 16] {
    let Some(text) = text else {
        return [0xFF; 16];
    };
    let mut password = [0u8; 16];
    for (d, b) in password.iter_mut().zip(text.bytes()) {
        *d = b;
    }
    password
}

impl SystemPage {
    pub fn encode(&self) -> Vec<u8> {
        let mut out = vec![SYSTEM_LAYOUT_VERSION, self.ports.len().min(255) as u8];
        for p in self.ports.iter().take(255) {
            let baud = BAUD_RATES.iter().position(|b| *b == p.baud).unwrap_or(2) as u8;
            out.extend([
                p.protocol,
                p.address,
                baud,
                p.data_bits,
                p.parity,
                p.stop_bits,
                p.timeout,
                p.frame_gap,
            ]);
        }
        out.extend(self.password);
        out
    }

    pub fn decode(b: &[u8]) -> Result<SystemPage, DecodeError> {
        if b.len() < 2 {
            return err(b.len(), "system page shorter than its 2-byte header");
        }
        if b[0] != SYSTEM_LAYOUT_VERSION {
            return err(
                0,
                format!("system page layout {} is not {SYSTEM_LAYOUT_VERSION}", b[0]),
            );
        }
        let ports = b[1] as usize;
        let want = 2 + 8 * ports + 16;
        if b.len() != want {
            return err(
                b.len().min(want),
                format!("{ports} ports need {want} bytes, the page has {}", b.len()),
            );
        }
        let mut out = Vec::with_capacity(ports);
        for i in 0..ports {
            let p = &b[2 + 8 * i..10 + 8 * i];
            let baud = *BAUD_RATES.get(p[2] as usize).ok_or(DecodeError {
                offset: 4 + 8 * i,
                reason: format!("baud code {} is not 0..4", p[2]),
            })?;
            out.push(PortEntry {
                protocol: p[0],
                address: p[1],
                baud,
                data_bits: p[3],
                parity: p[4],
                stop_bits: p[5],
                timeout: p[6],
                frame_gap: p[7],
            });
        }
        let mut password = [0u8; 16];
        password.copy_from_slice(&b[2 + 8 * ports..]);
        Ok(SystemPage {
            ports: out,
            password,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_round_trip() {
        let recs = vec![
            Record::Network(1),
            Record::Instruction {
                opcode: 0x0101,
                operands: vec![PackedOperand(0x0000_0000)],
            },
            Record::Network(2),
        ];
        let bytes = encode_instructions(&recs);
        assert_eq!(bytes, [0, 0, 1, 0, 0x01, 0x01, 1, 0, 0, 0, 0, 0, 0, 2, 0]);
        let back: Vec<Record> = decode_instructions(&bytes)
            .unwrap()
            .into_iter()
            .map(|(_, r)| r)
            .collect();
        assert_eq!(back, recs);
        assert!(decode_instructions(&bytes[..6]).is_err());
        assert!(decode_instructions(&[1, 0, 0]).is_err());
        let sys = SystemPage {
            ports: vec![PortEntry {
                protocol: 0,
                address: 20,
                baud: 38400,
                data_bits: 8,
                parity: 1,
                stop_bits: 1,
                timeout: 10,
                frame_gap: 10,
            }],
            password: [0xFF; 16],
        };
        let b = sys.encode();
        assert_eq!(b.len(), 26);
        assert_eq!(SystemPage::decode(&b).unwrap(), sys);
        assert!(decode_data(&[0; 9]).is_err());
    }
}
