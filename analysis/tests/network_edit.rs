//! Editing a network in place (`gutta_analysis::network_edit`) over every program of
//! the corpora: a network replaced by its own lines gives the file back byte for byte,
//! other lines change only that network's bytes, inserts and deletes leave every
//! other network as it was; CRLF and tab-indented files, comments between
//! instructions, renumbering after an insert, the refusals, a network's heading and a
//! block's title rewritten alone, and an edited program compiled against the same edit
//! made by hand.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

use std::path::{Path, PathBuf};

use gutta_analysis::network_edit::{
    apply, delete_network, insert_network_after, insert_network_first, parse, replace_heading,
    replace_network, set_block_title, BlockRef, EditError, NetworkRef, NewNetwork,
};
use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;
use gutta_compiler::syntax::ast::{Network, Program};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `.lad` and `.awl` files under a directory, recursively, sorted.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            sources(&p, out);
        } else if p
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("lad") || x.eq_ignore_ascii_case("awl"))
        {
            out.push(p);
        }
    }
}

/// Every corpus file as (path, decoded text, whether it is an `.awl` export).
fn corpus() -> Vec<(PathBuf, String, bool)> {
    let mut files = Vec::new();
    for dir in [
        "examples",
        "tests/data/check",
        "tests/data/run",
        "tests/data/microwin",
    ] {
        sources(&root().join(dir), &mut files);
    }
    assert!(files.len() > 100, "the corpora are there");
    files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).expect("read");
            let name = p.display().to_string();
            let (file, _) = SourceFile::from_program_file_bytes(name.as_str(), bytes, false)
                .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            let awl = p.extension().is_some_and(|x| x.eq_ignore_ascii_case("awl"));
            (p, file.text, awl)
        })
        .collect()
}

/// A network's instruction lines as written, trimmed (comment lines between them left out).
fn lines_of<'t>(text: &'t str, net: &Network) -> Vec<&'t str> {
    net.instructions
        .iter()
        .map(|i| {
            let start = text[..i.span.start as usize]
                .rfind('\n')
                .map_or(0, |n| n + 1);
            let end = text[start..].find('\n').map_or(text.len(), |n| start + n);
            text[start..end].trim()
        })
        .collect()
}

fn each_network(program: &Program) -> Vec<NetworkRef<'static>> {
    let mut all = Vec::new();
    for (b, unit) in program.units.iter().enumerate() {
        for n in 0..unit.networks.len() {
            all.push(NetworkRef {
                block: BlockRef::Index(b),
                network: n,
            });
        }
    }
    all
}

#[test]
fn a_network_replaced_by_its_own_lines_gives_the_file_back() {
    let mut networks = 0;
    for (path, text, awl) in corpus() {
        let program = parse(&text, awl);
        for at in each_network(&program) {
            let BlockRef::Index(b) = at.block else {
                unreachable!()
            };
            let own = lines_of(&text, &program.units[b].networks[at.network]);
            let edit = replace_network(&text, &program, at, &own).expect("edit");
            assert_eq!(
                apply(&text, &[edit]),
                text,
                "{} block {b} network {}",
                path.display(),
                at.network
            );
            networks += 1;
        }
    }
    assert!(networks > 500, "{networks} networks");
}

#[test]
fn other_lines_change_only_that_network() {
    let new = ["LDN    I0.7", "=      Q0.7"];
    for (path, text, awl) in corpus() {
        let program = parse(&text, awl);
        for at in each_network(&program) {
            let BlockRef::Index(b) = at.block else {
                unreachable!()
            };
            let unit = &program.units[b];
            let net = &unit.networks[at.network];
            let edit = replace_network(&text, &program, at, &new).expect("edit");
            let (start, end) = (edit.span.start as usize, edit.span.end as usize);
            // Inside the network: after its NETWORK line, before the next network.
            let floor = net.header.map_or(net.span.start, |h| h.end) as usize;
            let ceiling = unit
                .networks
                .get(at.network + 1)
                .map_or(text.len(), |n| n.span.start as usize);
            let place = format!("{} block {b} network {}", path.display(), at.network);
            assert!(floor <= start && end <= ceiling, "{place}");
            let edited = apply(&text, &[edit]);
            assert_eq!(edited[..start], text[..start], "{place}");
            assert_eq!(
                edited[edited.len() - (text.len() - end)..],
                text[end..],
                "{place}"
            );
            // The edited text has the new lines in that network, the rest as before.
            let again = parse(&edited, awl);
            let units = &again.units;
            assert_eq!(units.len(), program.units.len(), "{place}");
            assert_eq!(
                units[b].networks.len(),
                unit.networks.len(),
                "{place}:\n{edited}"
            );
            assert_eq!(
                lines_of(&edited, &units[b].networks[at.network]),
                new,
                "{place}"
            );
        }
    }
}

#[test]
fn inserts_and_deletes_leave_the_other_networks_as_they_were() {
    let new = NewNetwork {
        title: Some("added"),
        comment: &["why it is here"],
        lines: &["LD     I0.7", "=      Q0.7"],
    };
    for (path, text, awl) in corpus() {
        let program = parse(&text, awl);
        for at in each_network(&program) {
            let BlockRef::Index(b) = at.block else {
                unreachable!()
            };
            let place = format!("{} block {b} network {}", path.display(), at.network);
            let old = &program.units[b].networks;
            let stl = |p: &Program, t: &str| -> Vec<Vec<String>> {
                p.units[b]
                    .networks
                    .iter()
                    .map(|n| lines_of(t, n).into_iter().map(str::to_string).collect())
                    .collect()
            };
            let before = stl(&program, &text);

            let edits = insert_network_after(&text, &program, at, &new).expect("insert");
            let inserted = apply(&text, &edits);
            let again = parse(&inserted, awl);
            let mut expected = before.clone();
            expected.insert(
                at.network + 1,
                new.lines.iter().map(|s| s.to_string()).collect(),
            );
            assert_eq!(stl(&again, &inserted), expected, "{place}:\n{inserted}");
            let added = &again.units[b].networks[at.network + 1];
            let title = added.title.map(|t| inserted[t.range()].trim().to_string());
            assert_eq!(title.as_deref(), Some("added"), "{place}");
            // Numbers still increase where they did.
            let numbers = |p: &Program| {
                let mut last = None;
                p.units[b]
                    .networks
                    .iter()
                    .map(|n| {
                        let k = n.number_after(last);
                        if n.header.is_some() {
                            last = Some(k);
                        }
                        k
                    })
                    .collect::<Vec<u32>>()
            };
            if numbers(&program).windows(2).all(|w| w[0] < w[1]) {
                assert!(numbers(&again).windows(2).all(|w| w[0] < w[1]), "{place}");
            }

            let edit = delete_network(&text, &program, at).expect("delete");
            let deleted = apply(&text, &[edit]);
            let again = parse(&deleted, awl);
            let mut expected = before.clone();
            expected.remove(at.network);
            assert_eq!(again.units[b].networks.len(), old.len() - 1, "{place}");
            assert_eq!(stl(&again, &deleted), expected, "{place}");
        }
    }
}

const LATCH: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // start/stop latch
// a comment before the first instruction
LD     I0.0
O      M0.0
// between instructions
AN     I0.1
=      M0.0

NETWORK 2 // lamp
LD     M0.0
=      Q0.0
END_ORGANIZATION_BLOCK
";

fn main_net(network: usize) -> NetworkRef<'static> {
    NetworkRef {
        block: BlockRef::Name("MAIN"),
        network,
    }
}

#[test]
fn the_title_and_comments_stay_and_comments_between_instructions_move_by_position() {
    let program = parse(LATCH, false);
    // Fewer lines: the comment that stood before the third instruction follows the last.
    let edit = replace_network(
        LATCH,
        &program,
        main_net(0),
        &["LD     I0.0", "=      M0.0"],
    )
    .expect("edit");
    assert_eq!(
        apply(LATCH, &[edit]),
        LATCH.replace(
            "LD     I0.0\nO      M0.0\n// between instructions\nAN     I0.1\n=      M0.0\n",
            "LD     I0.0\n=      M0.0\n// between instructions\n"
        )
    );
    // As many lines: the comment stays before the third.
    let lines = ["LD     I0.2", "O      M0.0", "AN     I0.3", "=      M0.0"];
    let edit = replace_network(LATCH, &program, main_net(0), &lines).expect("edit");
    let edited = apply(LATCH, &[edit]);
    assert_eq!(
        edited,
        LATCH
            .replace("LD     I0.0\nO", "LD     I0.2\nO")
            .replace("AN     I0.1", "AN     I0.3")
    );
    // No lines: the network keeps its NETWORK line and comments, the lines go.
    let edit = replace_network(LATCH, &program, main_net(1), &[]).expect("edit");
    assert_eq!(
        apply(LATCH, &[edit]),
        LATCH.replace("LD     M0.0\n=      Q0.0\n", "")
    );
}

#[test]
fn a_heading_is_rewritten_alone() {
    let program = parse(LATCH, false);
    let heading = |at: usize, title: Option<&str>, comment: &[&str]| {
        let edits = replace_heading(LATCH, &program, main_net(at), title, comment).expect("edit");
        apply(LATCH, &edits)
    };
    // The same heading: no edit at all.
    let same = replace_heading(
        LATCH,
        &program,
        main_net(0),
        Some("start/stop latch"),
        &["a comment before the first instruction"],
    )
    .expect("edit");
    assert!(same.is_empty(), "{same:?}");
    // A new title: only the text after `//` on the NETWORK line.
    assert_eq!(
        heading(
            0,
            Some("latch"),
            &["a comment before the first instruction"]
        ),
        LATCH.replace("NETWORK 1 // start/stop latch", "NETWORK 1 // latch")
    );
    // No title: the `//` goes too; a title where there was none.
    assert_eq!(
        heading(1, None, &[]),
        LATCH.replace("NETWORK 2 // lamp", "NETWORK 2")
    );
    let untitled = LATCH.replace("NETWORK 2 // lamp", "NETWORK 2");
    let program2 = parse(&untitled, false);
    let edits =
        replace_heading(&untitled, &program2, main_net(1), Some("lamp"), &[]).expect("edit");
    assert_eq!(apply(&untitled, &edits), LATCH);
    // Comment lines replaced, added and removed; the instructions keep their bytes.
    assert_eq!(
        heading(0, Some("start/stop latch"), &["one", "two"]),
        LATCH.replace(
            "// a comment before the first instruction\n",
            "// one\n// two\n"
        )
    );
    assert_eq!(
        heading(1, Some("lamp"), &["the lamp"]),
        LATCH.replace("NETWORK 2 // lamp\n", "NETWORK 2 // lamp\n// the lamp\n")
    );
    assert_eq!(
        heading(0, Some("start/stop latch"), &[]),
        LATCH.replace("// a comment before the first instruction\n", "")
    );
    // CRLF and tabs: the file's line ending, the block's indentation.
    let text = LATCH.replace("\nLD ", "\n\tLD ").replace('\n', "\r\n");
    let program = parse(&text, false);
    let edits =
        replace_heading(&text, &program, main_net(1), Some("lamp"), &["lit"]).expect("edit");
    assert_eq!(
        apply(&text, &edits),
        text.replace("NETWORK 2 // lamp\r\n", "NETWORK 2 // lamp\r\n\t// lit\r\n")
    );
    // A line break in a title or comment is refused.
    assert!(matches!(
        replace_heading(LATCH, &parse(LATCH, false), main_net(0), Some("a\nb"), &[]),
        Err(EditError::LineBreak(_))
    ));
}

#[test]
fn a_block_title_is_rewritten_alone() {
    let program = parse(LATCH, false);
    let titled = LATCH.replace("MAIN:OB1\n", "MAIN:OB1\nTITLE=the machine\n");
    let edits =
        set_block_title(LATCH, &program, BlockRef::Index(0), Some("the machine")).expect("edit");
    assert_eq!(apply(LATCH, &edits), titled);
    let program = parse(&titled, false);
    let edits =
        set_block_title(&titled, &program, BlockRef::Index(0), Some("a machine")).expect("edit");
    assert_eq!(
        apply(&titled, &edits),
        titled.replace("the machine", "a machine")
    );
    let edits = set_block_title(&titled, &program, BlockRef::Index(0), None).expect("edit");
    assert_eq!(apply(&titled, &edits), LATCH);
    let same =
        set_block_title(&titled, &program, BlockRef::Index(0), Some("the machine")).expect("edit");
    assert!(same.is_empty());
}

#[test]
fn crlf_stays_crlf_and_tabs_stay_tabs() {
    let text = LATCH
        .replace("\nLD ", "\n\tLD ")
        .replace("\n=", "\n\t=")
        .replace('\n', "\r\n");
    let program = parse(&text, false);
    let edit = replace_network(
        &text,
        &program,
        main_net(1),
        &["LDN    M0.0", "=      Q0.0", "=      Q0.1"],
    )
    .expect("edit");
    assert_eq!(
        apply(&text, &[edit]),
        text.replace(
            "\tLD     M0.0\r\n\t=      Q0.0\r\n",
            "\tLDN    M0.0\r\n\t=      Q0.0\r\n\t=      Q0.1\r\n"
        )
    );
    let new = NewNetwork {
        title: Some("more"),
        comment: &["set by the studio"],
        lines: &["LD     I0.5", "=      Q0.5"],
    };
    let edits = insert_network_after(&text, &program, main_net(1), &new).expect("insert");
    assert_eq!(
        apply(&text, &edits),
        text.replace(
            "\t=      Q0.0\r\nEND_",
            "\t=      Q0.0\r\n\r\nNETWORK 3 // more\r\n\t// set by the studio\r\n\tLD     I0.5\r\n\t=      Q0.5\r\nEND_"
        )
    );
}

#[test]
fn an_insert_renumbers_only_the_digits_that_must_move() {
    let text = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     I0.0
=      Q0.0
NETWORK 2 // two
LD     I0.1
=      Q0.1
NETWORK   3   // three
LD     I0.2
=      Q0.2
NETWORK 10
LD     I0.3
=      Q0.3
END_ORGANIZATION_BLOCK
";
    let program = parse(text, false);
    let new = NewNetwork {
        lines: &["LD     I0.4", "=      Q0.4"],
        ..NewNetwork::default()
    };
    let edits = insert_network_after(text, &program, main_net(0), &new).expect("insert");
    assert_eq!(
        apply(text, &edits),
        text.replace(
            "NETWORK 2 // two",
            "NETWORK 2\nLD     I0.4\n=      Q0.4\nNETWORK 3 // two"
        )
        .replace("NETWORK   3   //", "NETWORK   4   //")
    );
    // A deleted network leaves the numbers as they are (they need only increase).
    let edit = delete_network(text, &program, main_net(1)).expect("delete");
    assert_eq!(
        apply(text, &[edit]),
        text.replace("NETWORK 2 // two\nLD     I0.1\n=      Q0.1\n", "")
    );
}

#[test]
fn refusals_are_typed() {
    let text = format!("{LATCH}\nDATA_BLOCK VALUES:DAT0\n  MW22 UINT 6\nEND_DATA_BLOCK\n");
    let program = parse(&text, false);
    let at = |block, network| NetworkRef { block, network };
    let lines = ["LD     I0.0"];
    assert_eq!(
        replace_network(&text, &program, at(BlockRef::Name("VALUES"), 0), &lines),
        Err(EditError::NotAProgramBlock("VALUES".to_string()))
    );
    assert_eq!(
        replace_network(&text, &program, at(BlockRef::Name("DAT0"), 0), &lines),
        Err(EditError::NotAProgramBlock("DAT0".to_string()))
    );
    assert_eq!(
        delete_network(&text, &program, at(BlockRef::Name("SBR3"), 0)),
        Err(EditError::BlockNotFound("SBR3".to_string()))
    );
    assert_eq!(
        delete_network(&text, &program, at(BlockRef::Index(1), 0)),
        Err(EditError::BlockNotFound("at index 1".to_string()))
    );
    let missing = replace_network(&text, &program, at(BlockRef::Name("main:ob1"), 2), &lines);
    assert_eq!(
        missing,
        Err(EditError::NetworkNotFound {
            block: "MAIN".to_string(),
            network: 2,
            networks: 2
        })
    );
    assert_eq!(
        missing.unwrap_err().to_string(),
        "MAIN has no network at index 2 (it has 2)"
    );
    assert!(matches!(
        replace_network(&text, &program, main_net(0), &["LD I0.0\n= Q0.0"]),
        Err(EditError::LineBreak(_))
    ));
}

#[test]
fn an_edited_program_compiles_as_the_same_edit_made_by_hand() {
    let path = root().join("examples/blink.lad");
    let text = std::fs::read_to_string(path).expect("read");
    let program = parse(&text, false);
    let at = main_net(0);
    let own = lines_of(&text, &program.units[0].networks[0]);
    assert_eq!(own[0], "LD     Start");
    let mut lines = own.clone();
    lines[0] = "LDN    Start";
    let edit = replace_network(&text, &program, at, &lines).expect("edit");
    let edited = apply(&text, &[edit]);
    let by_hand = text.replacen("LD     Start", "LDN    Start", 1);
    assert_eq!(edited, by_hand);
    let image = |t: &str| compile(SourceFile::new("blink.lad", t), None).image;
    let (ours, theirs, before) = (image(&edited), image(&by_hand), image(&text));
    assert!(ours.is_some());
    assert_eq!(ours, theirs);
    assert_ne!(ours, before);
}

#[test]
fn an_empty_network_gets_its_lines_after_its_comments() {
    let text = LATCH.replace("LD     M0.0\n=      Q0.0\n", "// nothing yet\n");
    let program = parse(&text, false);
    let edit = replace_network(
        &text,
        &program,
        main_net(1),
        &["LD     M0.0", "=      Q0.0"],
    )
    .expect("edit");
    assert_eq!(
        apply(&text, &[edit]),
        LATCH.replace("// lamp\n", "// lamp\n// nothing yet\n")
    );
}

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 32) % n.max(1) as u64) as usize
    }
}

#[test]
fn a_sequence_of_edits_keeps_every_network_as_the_edits_say() {
    let pool = [
        "LD     I0.0",
        "LDN    M1.1",
        "O      I0.2",
        "AN     M0.3",
        "=      Q0.4",
        "MOVW   16#0E01, MW10",
    ];
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for (path, text, awl) in corpus() {
        let mut text = text;
        let program = parse(&text, awl);
        let stl = |p: &Program, t: &str| -> Vec<Vec<Vec<String>>> {
            p.units
                .iter()
                .map(|u| {
                    u.networks
                        .iter()
                        .map(|n| lines_of(t, n).into_iter().map(str::to_string).collect())
                        .collect()
                })
                .collect()
        };
        let mut model = stl(&program, &text);
        for step in 0..12 {
            let program = parse(&text, awl);
            let blocks: Vec<usize> = (0..model.len()).filter(|b| !model[*b].is_empty()).collect();
            if blocks.is_empty() {
                break;
            }
            let b = blocks[rng.below(blocks.len())];
            let n = rng.below(model[b].len());
            let at = NetworkRef {
                block: BlockRef::Index(b),
                network: n,
            };
            let lines: Vec<&str> = (0..1 + rng.below(4))
                .map(|_| pool[rng.below(pool.len())])
                .collect();
            let owned: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            let edits = match rng.below(5) {
                4 => {
                    let new = NewNetwork {
                        title: None,
                        comment: &["first"],
                        lines: &lines,
                    };
                    match insert_network_first(&text, &program, at.block, &new) {
                        Ok(edits) => {
                            model[b].insert(0, owned);
                            edits
                        }
                        Err(EditError::NoNetworkLine(_)) => continue,
                        Err(e) => panic!("{}: {e}", path.display()),
                    }
                }
                0 if model[b].len() > 1 => {
                    model[b].remove(n);
                    vec![delete_network(&text, &program, at).expect("delete")]
                }
                1 => {
                    model[b].insert(n + 1, owned);
                    let new = NewNetwork {
                        title: Some("step"),
                        comment: &[],
                        lines: &lines,
                    };
                    insert_network_after(&text, &program, at, &new).expect("insert")
                }
                _ => {
                    model[b][n] = owned;
                    vec![replace_network(&text, &program, at, &lines).expect("replace")]
                }
            };
            text = apply(&text, &edits);
            let again = parse(&text, awl);
            assert_eq!(stl(&again, &text), model, "{} step {step}", path.display());
        }
    }
}

#[test]
fn a_network_inserted_first_takes_the_first_number() {
    let program = parse(LATCH, false);
    let new = NewNetwork {
        title: Some("first"),
        comment: &[],
        lines: &["LD     I0.5", "=      Q0.5"],
    };
    let edits = insert_network_first(LATCH, &program, BlockRef::Index(0), &new).expect("insert");
    assert_eq!(
        apply(LATCH, &edits),
        LATCH
            .replace("NETWORK 2 // lamp", "NETWORK 3 // lamp")
            .replace(
                "NETWORK 1 // start",
                "NETWORK 1 // first\nLD     I0.5\n=      Q0.5\n\nNETWORK 2 // start"
            )
    );
    // An empty block gets NETWORK 1 before its END line.
    let text = format!("{LATCH}SUBROUTINE_BLOCK S:SBR0\nBEGIN\nEND_SUBROUTINE_BLOCK\n");
    let program = parse(&text, false);
    let edits =
        insert_network_first(&text, &program, BlockRef::Name("SBR0"), &new).expect("insert");
    assert_eq!(
        apply(&text, &edits),
        text.replace(
            "BEGIN\nEND_SUB",
            "BEGIN\nNETWORK 1 // first\nLD     I0.5\n=      Q0.5\nEND_SUB"
        )
    );
    // Instructions before any NETWORK line would be taken into a network put before them.
    let text = LATCH.replace("NETWORK 1 // start/stop latch\n", "");
    let program = parse(&text, false);
    assert_eq!(
        insert_network_first(&text, &program, BlockRef::Index(0), &new),
        Err(EditError::NoNetworkLine("MAIN".to_string()))
    );
}
