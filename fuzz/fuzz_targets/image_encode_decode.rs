//! Fuzz target of the page encoders: structured values built from the input with
//! `arbitrary::Unstructured` (records, argument pages, data items, system pages,
//! packed operands, manifests, whole images) are encoded and decoded again, and must
//! come back equal. A mismatch or a panic is the bug it looks for.
#![no_main]

use std::collections::BTreeMap;

use gutta_catalog::{Address, DataType, Width};
use gutta_format::{
    decode_data, decode_instructions, encode_data, encode_instructions, ArgumentPage, DataItem,
    Image, LocalEntry, LocalSection, Manifest, ManifestPage, PackedOperand, PageId, PageKind,
    PortEntry, Record, SystemPage, Use, BAUD_RATES, FORMAT_VERSION,
};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

fn operand(u: &mut Unstructured<'_>) -> Result<PackedOperand> {
    Ok(PackedOperand(u.arbitrary()?))
}

fn records(u: &mut Unstructured<'_>) -> Result<Vec<Record>> {
    let mut out = vec![Record::Network(u.arbitrary()?)];
    for _ in 0..u.int_in_range(0..=64)? {
        if u.ratio(1, 4)? {
            out.push(Record::Network(u.arbitrary()?));
        } else {
            let opcode = u.int_in_range(1..=u16::MAX)?;
            let n = u.int_in_range(0..=255u16)?;
            let operands = (0..n).map(|_| operand(u)).collect::<Result<Vec<_>>>()?;
            out.push(Record::Instruction { opcode, operands });
        }
    }
    Ok(out)
}

fn argument_page(u: &mut Unstructured<'_>) -> Result<ArgumentPage> {
    let n = u.int_in_range(0..=255u16)?;
    let mut locals = Vec::new();
    for _ in 0..n {
        locals.push(LocalEntry {
            operand: operand(u)?,
            section: *u.choose(&[
                LocalSection::Input,
                LocalSection::InOut,
                LocalSection::Output,
                LocalSection::Temp,
            ])?,
            data_type: *u.choose(&DataType::ALL)?,
        });
    }
    Ok(ArgumentPage {
        subroutine: u.arbitrary()?,
        unit_number: u.arbitrary()?,
        locals,
    })
}

fn system_page(u: &mut Unstructured<'_>) -> Result<SystemPage> {
    let n = u.int_in_range(0..=255u16)?;
    let mut ports = Vec::new();
    for _ in 0..n {
        ports.push(PortEntry {
            protocol: u.arbitrary()?,
            address: u.arbitrary()?,
            baud: *u.choose(&BAUD_RATES)?,
            data_bits: u.arbitrary()?,
            parity: u.arbitrary()?,
            stop_bits: u.arbitrary()?,
            timeout: u.arbitrary()?,
            frame_gap: u.arbitrary()?,
        });
    }
    Ok(SystemPage {
        ports,
        password: u.arbitrary()?,
    })
}

fn page_id(u: &mut Unstructured<'_>) -> Result<PageId> {
    let kind = *u.choose(&PageKind::ALL)?;
    let number = u.int_in_range(0..=kind.max_number())?;
    Ok(PageId::new(kind, number))
}

fn text(u: &mut Unstructured<'_>) -> Result<String> {
    u.arbitrary()
}

fn check(u: &mut Unstructured<'_>) -> Result<()> {
    let recs = records(u)?;
    let bytes = encode_instructions(&recs);
    let back = decode_instructions(&bytes).expect("encoded records decode");
    let mut offset = 0;
    for ((at, got), want) in back.iter().zip(&recs) {
        assert_eq!((*at, got), (offset, want));
        offset += want.len();
    }
    assert_eq!(back.len(), recs.len());
    assert_eq!(offset, bytes.len());

    let args = argument_page(u)?;
    assert_eq!(ArgumentPage::decode(&args.encode()), Ok(args));

    let items = (0..u.int_in_range(0..=64)?)
        .map(|_| {
            Ok(DataItem {
                operand: operand(u)?,
                value: u.arbitrary()?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    assert_eq!(decode_data(&encode_data(&items)), Ok(items));

    let sys = system_page(u)?;
    assert_eq!(SystemPage::decode(&sys.encode()), Ok(sys));

    let width = *u.choose(&Width::ALL)?;
    let use_ = *u.choose(&[Use::Value, Use::AddressOf, Use::Pointer])?;
    let address = Address {
        slot: u.int_in_range(0..=15)?,
        width,
        offset: u.arbitrary::<u16>()?.into(),
        bit: u.int_in_range(0..=7)?,
    };
    let op = PackedOperand::memory(address, use_, width);
    assert_eq!(PackedOperand::from_le_bytes(op.to_le_bytes()), op);
    assert_eq!(
        (op.use_(), op.slot(), op.width(), op.offset() as u32),
        (Some(use_), address.slot, Some(width), address.offset)
    );
    assert_eq!(op.bit(), if width == Width::Bit { address.bit } else { 0 });

    let manifest = Manifest {
        format: FORMAT_VERSION,
        plc_type: text(u)?,
        pages: (0..u.int_in_range(0..=8)?)
            .map(|_| {
                let id = page_id(u)?;
                Ok(ManifestPage {
                    kind: id.kind,
                    number: id.number,
                    file: text(u)?,
                    length: u.arbitrary()?,
                    crc: u.arbitrary()?,
                })
            })
            .collect::<Result<Vec<_>>>()?,
    };
    assert_eq!(Manifest::parse(&manifest.to_json()), Ok(manifest));

    let mut pages = BTreeMap::new();
    for _ in 0..u.int_in_range(0..=8)? {
        pages.insert(page_id(u)?, u.arbitrary::<Vec<u8>>()?);
    }
    pages.insert(PageId::new(PageKind::Const, 0), u.arbitrary::<Vec<u8>>()?);
    let image = Image {
        plc_type: text(u)?,
        pages,
    };
    let files: BTreeMap<String, Vec<u8>> = image.files().into_iter().collect();
    let manifest = String::from_utf8(files["manifest.json"].clone()).expect("UTF-8 manifest");
    let back = Image::read(&manifest, |name| {
        files.get(name).cloned().ok_or_else(|| name.to_string())
    });
    assert_eq!(back, Ok(image));
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = check(&mut Unstructured::new(data));
});
