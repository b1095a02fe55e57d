//! The source map `compile` returns beside the image: exact for a two-network
//! program, and the same bytes for the same source.

use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;

const TWO_NETWORKS: &str = "\
PLC_TYPE CPU-EC20

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // start
LD     I0.0
=      Q0.0   // lamp

NETWORK 2
LD     SM0.0
MOVW   MW10, MW20
END_ORGANIZATION_BLOCK
";

fn map_json(text: &str) -> String {
    let compiled = compile(SourceFile::new("main.lad", text), None);
    assert!(
        compiled.image.is_some(),
        "{:?}",
        compiled.checked.diagnostics()
    );
    compiled
        .source_map()
        .expect("a map beside the image")
        .to_json()
}

#[test]
fn two_networks_map_exactly() {
    let expected = r#"{"format":2,"file":"main.lad","files":["main.lad"],"manifest_crc":15653,"symbols":[],"instructions":[
{"page":0,"byte":4,"network":1,"step":0,"line":6,"column":1,"text":"LD     I0.0"},
{"page":0,"byte":11,"network":1,"step":1,"line":7,"column":1,"text":"=      Q0.0"},
{"page":0,"byte":22,"network":2,"step":0,"line":10,"column":1,"text":"LD     SM0.0"},
{"page":0,"byte":29,"network":2,"step":1,"line":11,"column":1,"text":"MOVW   MW10, MW20"}
]}
"#;
    assert_eq!(map_json(TWO_NETWORKS), expected);
}

#[test]
fn bytes_are_the_instruction_records_of_the_page() {
    let compiled = compile(SourceFile::new("main.lad", TWO_NETWORKS), None);
    let image = compiled.image.clone().expect("compiles");
    let page = image
        .page(gutta_format::PageKind::Instruction, 0)
        .expect("MAIN's page");
    let records: Vec<u32> = gutta_format::decode_instructions(page)
        .expect("decodes")
        .into_iter()
        .filter(|(_, r)| matches!(r, gutta_format::Record::Instruction { .. }))
        .map(|(at, _)| at as u32)
        .collect();
    let mapped: Vec<u32> = compiled
        .source_map()
        .expect("a map")
        .instructions
        .iter()
        .map(|i| i.byte)
        .collect();
    assert_eq!(mapped, records);
    let compiled = compile(SourceFile::new("main.lad", TWO_NETWORKS), None);
    let map = compiled.source_map().expect("a map");
    let image = compiled.image.expect("an image");
    assert!(map.describes(&image.manifest()));
}

#[test]
fn same_source_same_map() {
    assert_eq!(map_json(TWO_NETWORKS), map_json(TWO_NETWORKS));
}

#[test]
fn no_image_no_map() {
    let compiled = compile(
        SourceFile::new(
            "bad.lad",
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Z9.9\n",
        ),
        None,
    );
    assert!(compiled.image.is_none());
    assert!(compiled.source_map().is_none());
}
