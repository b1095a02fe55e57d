//! Advice that fits (issue 29): E0306 names the area's size and valid range; E0408 for
//! files that hold single blocks of an export written one block per file, and E0206 for
//! a CALL or ATCH of a block of another such file, say to pass the export's files
//! together with the command; MicroWIN SMART's default I/O names resolve in the dialect
//! (W0206 only for a symbol at another address, E0221 past the target's I or Q); the
//! S7-200 SM names say what they are and that the target has no such register.

use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, check_source, ProgramSources};

fn diagnostics(name: &str, text: &str) -> Vec<Diagnostic> {
    check_source(SourceFile::new(name, text), None)
        .diagnostics()
        .to_vec()
}

fn main_with(body: &str) -> String {
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\n{body}\nEND_ORGANIZATION_BLOCK\n"
    )
}

fn only(diags: &[Diagnostic], code: Code) -> &Diagnostic {
    assert_eq!(diags.len(), 1, "{diags:#?}");
    assert_eq!(diags[0].code, code, "{diags:#?}");
    &diags[0]
}

#[test]
fn e0306_names_the_area_size_and_the_valid_range() {
    let cases = [
        (
            "MOVB 1, MB200",
            "`MB200` is outside area M of CPU-EC20: M has 128 bytes, MB0..MB127",
        ),
        (
            "MOVW 1, MW127",
            "`MW127` is outside area M of CPU-EC20: M has 128 bytes, MW0..MW126",
        ),
        (
            "= Q8.0",
            "`Q8.0` is outside area Q of CPU-EC20: Q has 8 bytes, Q0.0..Q7.7",
        ),
        (
            "MOVW 1, T16",
            "`T16` is outside area T of CPU-EC20: T has 16 numbers, T0..T15",
        ),
    ];
    for (line, message) in cases {
        let diags = diagnostics("range.lad", &main_with(line));
        let d = only(&diags, Code::AddressOutOfTarget);
        assert_eq!(d.message, message, "{line}");
    }
}

const SBR_FILE: &str = "SUBROUTINE_BLOCK SBR_0:SBR0\nTITLE=\nBEGIN\nNetwork 1\nLD Always_On\nINCW MW0\nEND_SUBROUTINE_BLOCK\n";
const INT_FILE: &str = "INTERRUPT_BLOCK INT_0:INT0\nTITLE=\nBEGIN\nNetwork 1\nLD Always_On\nINCW MW2\nEND_INTERRUPT_BLOCK\n";

fn program(files: &[(&str, &str)]) -> Vec<Diagnostic> {
    let sources = ProgramSources {
        sources: files
            .iter()
            .map(|(name, text)| SourceFile::new(*name, *text))
            .collect(),
        ..ProgramSources::default()
    };
    check_program(sources, None).diagnostics().to_vec()
}

#[test]
fn e0408_for_single_blocks_says_to_pass_the_export_together() {
    let diags = program(&[("SBR_0.awl", SBR_FILE), ("INT_0.awl", INT_FILE)]);
    let d = diags
        .iter()
        .find(|d| d.code == Code::MissingMain)
        .expect("E0408");
    let help = d.help.as_deref().unwrap_or("");
    assert!(
        help.contains("`gutta-cc MAIN.awl SBR_0.awl INT_0.awl ...`"),
        "{help}"
    );
    assert!(help.contains("one block per file"), "{help}");
    // A whole export of several blocks in one file without OB1: the old help.
    let both = format!("{SBR_FILE}{INT_FILE}");
    let diags = program(&[("project.awl", &both)]);
    let d = diags
        .iter()
        .find(|d| d.code == Code::MissingMain)
        .expect("E0408");
    let help = d.help.as_deref().unwrap_or("");
    assert!(!help.contains("gutta-cc"), "{help}");
    assert!(help.contains("INT(n+1)"), "{help}");
}

#[test]
fn e0206_for_a_block_of_another_file_says_to_pass_it_along() {
    let main =
        main_with("CALL SBR_1\nCALL 子程序_2\nCALL Motor:SBR3\nATCH INT_0:INT0, 10\nCALL Pump");
    let diags = program(&[("MAIN.awl", &main)]);
    let undefined: Vec<&Diagnostic> = diags
        .iter()
        .filter(|d| d.code == Code::UndefinedBlock)
        .collect();
    assert_eq!(undefined.len(), 5, "{diags:#?}");
    for (d, file) in undefined
        .iter()
        .zip(["SBR_1", "子程序_2", "Motor", "INT_0"])
    {
        let help = d.help.as_deref().unwrap_or("");
        assert!(
            help.contains(&format!("`gutta-cc MAIN.awl {file}.awl ...`")),
            "{help}"
        );
        assert!(help.contains("one block per file"), "{help}");
        assert!(d.fixes.is_empty(), "no did-you-mean: {:?}", d.fixes);
    }
    // `Pump` is no default block name: no advice.
    let help = undefined[4].help.as_deref().unwrap_or("");
    assert!(!help.contains("gutta-cc"), "{help}");
    // Outside the dialect a CALL of SBR_1 is an ordinary undefined block.
    let diags = diagnostics("main.lad", &main_with("CALL SBR_1"));
    let d = only(&diags, Code::UndefinedBlock);
    assert!(!d.help.as_deref().unwrap_or("").contains("gutta-cc"));
}

#[test]
fn smart_io_names_resolve_and_warn_only_for_another_address() {
    let text = "SYMBOLS\nCPU_Input1 : I0.1\nCPU_Output2 : M0.0\nEND_SYMBOLS\n".to_string()
        + &main_with("LD CPU_Input1\n= CPU_Output2\nLD CPU_输入8\n= CPU_输出3");
    let diags = diagnostics("smart.awl", &text);
    let d = only(&diags, Code::SystemNameShadowed);
    assert_eq!(
        d.message,
        "symbol `CPU_Output2` hides MicroWIN SMART's default symbol for Q0.2"
    );
    // Outside the dialect: E0221 with the bit and how to declare it.
    let diags = diagnostics("smart.lad", &main_with("LD CPU_Input9\n= Q0.0"));
    let d = only(&diags, Code::S7200Area);
    assert_eq!(
        d.message,
        "`CPU_Input9` is MicroWIN SMART's default symbol for input 9 (I1.1); CPU-EC20 has no such name"
    );
    assert!(d
        .help
        .as_deref()
        .unwrap_or("")
        .contains("`CPU_Input9 : I1.1`"));
}

#[test]
fn a_smart_io_name_past_the_area_is_e0221_with_the_address_and_the_size() {
    let diags = diagnostics("smart.awl", &main_with("LD CPU_Input64\n= CPU_Output70"));
    assert_eq!(diags.len(), 2, "{diags:#?}");
    assert!(diags.iter().all(|d| d.code == Code::S7200Area));
    assert_eq!(
        diags[0].message,
        "`CPU_Input64` is MicroWIN SMART's default symbol for input 64, I8.0; CPU-EC20's area I has 8 bytes, I0.0..I7.7 (inputs 0..63)"
    );
    assert_eq!(
        diags[1].message,
        "`CPU_Output70` is MicroWIN SMART's default symbol for output 70, Q8.6; CPU-EC20's area Q has 8 bytes, Q0.0..Q7.7 (outputs 0..63)"
    );
    // A target with 32 bytes of I has input 64.
    let text = format!(
        "PLC_TYPE EC30-EKSTM32\n{}",
        main_with("LD CPU_Input64\n= Q0.0")
    );
    assert!(diagnostics("smart.awl", &text).is_empty());
}

#[test]
fn sm_names_say_what_they_are_and_that_the_register_is_missing() {
    let diags = diagnostics("ports.awl", &main_with("MOVB 16#B0, P0_Ctrl_Rcv"));
    let d = only(&diags, Code::S7200Area);
    assert_eq!(
        d.message,
        "`P0_Ctrl_Rcv` is Micro/WIN's system symbol for the S7-200's SMB87 (port 0's receive message control); CPU-EC20 has no such register"
    );
}

/// An SM name the target keeps under another Micro/WIN name (the scan times: the target
/// names SMW4 `Last_Scan_Time`) says where the same value is and how to declare it.
#[test]
fn an_sm_name_with_the_same_value_elsewhere_says_how_to_declare_it() {
    let diags = diagnostics("scan.awl", &main_with("MOVW Scan_Time, MW0"));
    let d = only(&diags, Code::S7200Area);
    assert!(
        d.message.ends_with("CPU-EC20 has no such name"),
        "{}",
        d.message
    );
    assert_eq!(
        d.help.as_deref(),
        Some("declare it in SYMBOLS (`Scan_Time : SMW4`): CPU-EC20 keeps the same value there")
    );
}
