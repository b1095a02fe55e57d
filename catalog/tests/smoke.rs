//! The default stdlib target loads and parses the document's addresses.

use gutta_catalog::{stdlib, AddressError, Width};

#[test]
fn default_target_loads_and_parses_addresses() {
    let t = stdlib::default_target().expect("default target loads");
    assert_eq!(t.name(), "CPU-EC20");
    let m = &t.memory;
    let a = m.parse_address("T5").unwrap();
    assert_eq!((a.width, a.offset), (Width::Word, 10));
    let a = m.parse_address("smb0").unwrap();
    assert_eq!(m.format_address(&a), "SMB0");
    assert_eq!(m.parse_address("MD4").unwrap().width, Width::Dword);
    assert!(matches!(
        m.parse_address("MB200"),
        Err(AddressError::OutOfRange { .. })
    ));
    assert!(
        matches!(m.parse_address("VB100"), Err(AddressError::UnknownArea { prefix }) if prefix == "V")
    );
    assert!(matches!(
        m.parse_address("AI0.0"),
        Err(AddressError::WidthNotAllowed { .. })
    ));
    assert!(matches!(
        m.parse_address("TW5"),
        Err(AddressError::LetterNotAllowed { .. })
    ));
    assert!(t.instructions.lookup("ldw>=").is_some());
}
