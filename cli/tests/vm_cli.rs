//! The `gutta-vm` command line: images compiled in the test (with the compiler library)
//! and written as gutta-cc writes them, then run by the binary: --read, --json, --set,
//! --force, --trace, --vcd, --break, --tier and --stats, and the exit status of verification errors and
//! faults.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{Image, PageId, PageKind};

fn compile_image(text: &str) -> Image {
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let explicit = ExplicitTarget {
        target,
        origin: "test".into(),
    };
    let c = compile(SourceFile::new("t.lad", text), Some(&explicit));
    c.image
        .unwrap_or_else(|| panic!("does not compile: {:?}", c.checked.diagnostics()))
}

/// A fresh directory under the target's temporary folder.
fn temp_dir(tag: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gutta-vm-cli-{}-{tag}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Write `image` as an image directory: pages, then manifest.json.
fn write_image(image: &Image, tag: &str) -> PathBuf {
    let dir = temp_dir(tag);
    for (id, bytes) in &image.pages {
        let path = dir.join(id.file_name());
        std::fs::create_dir_all(path.parent().expect("parent")).expect("page dir");
        std::fs::write(&path, bytes).expect("page");
    }
    std::fs::write(
        dir.join(gutta_format::MANIFEST_FILE),
        image.manifest().to_json(),
    )
    .expect("manifest");
    dir
}

fn image_dir(text: &str, tag: &str) -> PathBuf {
    write_image(&compile_image(text), tag)
}

fn main_block(code: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}\nEND_ORGANIZATION_BLOCK\n")
}

fn pointers() -> PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/in1001_pointers.lad"
    ))
    .expect("example");
    image_dir(&text, "pointers")
}

fn gutta_vm(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .arg(dir)
        .args(args)
        .output()
        .expect("runs gutta-vm")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(o)))
}

#[test]
fn reads_the_pointer_example() {
    let o = gutta_vm(&pointers(), &["--read", "MW24", "--read", "MW26"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "MW24 = 3585\nMW26 = 3586\n");
}

#[test]
fn json_report() {
    let o = gutta_vm(
        &pointers(),
        &["--read", "MW24", "--read", "md4", "--scans", "3", "--json"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v = json(&o);
    assert_eq!(v["scans"], 3);
    assert_eq!(v["values"]["MW24"], 3585);
    assert_eq!(
        v["values"]["MD4"], 0x0400_001A,
        "names are canonical: md4 is MD4"
    );
    assert_eq!(v["status"]["run"], true);
    assert_eq!(v["status"]["error"], false);
    assert!(v["error"].is_null());
}

const LATCH: &str = "NETWORK 1\nLD I0.0\nO Q0.0\nAN I0.1\n= Q0.0";

#[test]
fn set_drives_an_input_before_the_first_scan() {
    let dir = image_dir(&main_block(LATCH), "latch");
    let off = gutta_vm(&dir, &["--read", "Q0.0", "--scans", "3"]);
    assert_eq!(stdout(&off), "Q0.0 = 0\n");
    let on = gutta_vm(&dir, &["--set", "I0.0=1", "--read", "Q0.0", "--scans", "3"]);
    assert_eq!(on.status.code(), Some(0), "{}", stderr(&on));
    assert_eq!(stdout(&on), "Q0.0 = 1\n");
    // Set and reset both on: reset wins.
    let both = gutta_vm(
        &dir,
        &["--set", "I0.0=1", "--set", "I0.1=1", "--read", "Q0.0"],
    );
    assert_eq!(stdout(&both), "Q0.0 = 0\n");
    // Values in every notation, and words.
    let dir = image_dir(&main_block("NETWORK 1\nLD SM0.0\nMOVW AIW0, MW10"), "aiw");
    for value in ["100", "16#64", "2#1100100"] {
        let o = gutta_vm(&dir, &["--set", &format!("AIW0={value}"), "--read", "MW10"]);
        assert_eq!(stdout(&o), "MW10 = 100\n", "AIW0={value}");
    }
    // Words print signed (issue 11); `:uint` and `:hex` show the same bits otherwise.
    let o = gutta_vm(
        &dir,
        &[
            "--set",
            "AIW0=-1",
            "--read",
            "MW10",
            "--read",
            "MW10:uint",
            "--read",
            "MW10:hex",
        ],
    );
    assert_eq!(
        stdout(&o),
        "MW10 = -1\nMW10 = 65535\nMW10 = 16#FFFF\n",
        "negative values, printed signed"
    );
}

#[test]
fn bad_set_is_a_usage_error() {
    let dir = pointers();
    for (arg, says) in [
        ("XQ9=1", "XQ9"),
        ("I0.0=2", "does not fit"),
        ("MW0=70000", "does not fit"),
        ("MW0=abc", "not a number"),
        ("MW0", "VAR=VALUE"),
    ] {
        let o = gutta_vm(&dir, &["--set", arg]);
        assert_eq!(o.status.code(), Some(2), "--set {arg}");
        assert!(stderr(&o).contains(says), "--set {arg}: {}", stderr(&o));
    }
}

#[test]
fn force_holds_an_output_and_an_input() {
    let dir = image_dir(
        &main_block("NETWORK 1\nLD I0.0\n= Q0.0\nNETWORK 2\nLD SM0.0\nR Q0.1, 1"),
        "force",
    );
    let o = gutta_vm(
        &dir,
        &[
            "--force", "I0.0=1", "--force", "Q0.1=1", "--read", "Q0.0", "--read", "Q0.1",
            "--scans", "2",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "Q0.0 = 1\nQ0.1 = 1\n");
    let o = gutta_vm(&dir, &["--force", "MW0=1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot be forced"), "{}", stderr(&o));
}

/// Q0.0 toggles every scan.
const TOGGLE: &str = "NETWORK 1\nLD SM0.0\nAN M0.0\n= M0.1\nNETWORK 2\nLD M0.1\n= M0.0\n= Q0.0";

#[test]
fn trace_prints_what_changed_each_scan() {
    let dir = image_dir(&main_block(TOGGLE), "trace");
    let o = gutta_vm(
        &dir,
        &[
            "--trace", "--read", "Q0.0", "--read", "MW24", "--scans", "3",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        "scan 1: Q0.0 0 -> 1\nscan 2: Q0.0 1 -> 0\nscan 3: Q0.0 0 -> 1\nQ0.0 = 1\nMW24 = 0\n"
    );
    let o = gutta_vm(
        &dir,
        &["--trace", "--read", "Q0.0", "--scans", "2", "--json"],
    );
    let v = json(&o);
    assert_eq!(v["trace"][1]["scan"], 2);
    assert_eq!(v["trace"][1]["var"], "Q0.0");
    assert_eq!(v["trace"][1]["from"], 1);
    assert_eq!(v["trace"][1]["to"], 0);
}

#[test]
fn vcd_waveform() {
    let dir = image_dir(&main_block(TOGGLE), "vcd");
    let vcd = temp_dir("vcd-out").join("run.vcd");
    let vcd_arg = vcd.to_str().expect("utf-8 path");
    let o = gutta_vm(
        &dir,
        &[
            "--read",
            "Q0.0",
            "--read",
            "MW24",
            "--scans",
            "4",
            "--scan-ms",
            "5",
            "--vcd",
            vcd_arg,
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&vcd).expect("vcd written");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.contains(&"$timescale 1 ms $end"), "{text}");
    assert!(lines.contains(&"$var wire 1 ! Q0_0 $end"), "{text}");
    assert!(lines.contains(&"$var wire 16 \" MW24 $end"), "{text}");
    let defs = lines
        .iter()
        .position(|l| *l == "$enddefinitions $end")
        .expect("definitions end");
    // Every line after the header is a timestamp, a value change or $dumpvars/$end.
    let mut times = Vec::new();
    for l in &lines[defs + 1..] {
        if let Some(t) = l.strip_prefix('#') {
            times.push(t.parse::<u64>().expect("timestamp"));
        } else {
            assert!(
                matches!(*l, "$dumpvars" | "$end" | "0!" | "1!" | "b0 \""),
                "unexpected line {l:?} in\n{text}"
            );
        }
    }
    assert_eq!(times, [0, 5, 10, 15, 20], "{text}");
    // Vectors are written `bVALUE id`.
    let dir = pointers();
    let o = gutta_vm(&dir, &["--read", "MW24", "--vcd", vcd_arg]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = std::fs::read_to_string(&vcd).expect("vcd written");
    assert!(text.contains(&format!("#10\nb{:b} !\n", 0x0E01)), "{text}");
}

#[test]
fn trace_and_vcd_need_read() {
    let o = gutta_vm(&pointers(), &["--trace"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn break_pauses_before_the_instruction_and_reports_it() {
    // MAIN network 1 step 4 is the second `MOVW ..., *MD4`: MW24 is written, MW26 not.
    let o = gutta_vm(
        &pointers(),
        &["--break", "MAIN:1:4", "--read", "MW24", "--read", "MW26"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "MW24 = 3585\nMW26 = 0\n");
    assert!(
        stderr(&o).contains("paused at breakpoint MAIN (function 0) network 1 step 4 in scan 1"),
        "{}",
        stderr(&o)
    );
    let o = gutta_vm(
        &pointers(),
        &[
            "--break", "0:1:4", "--read", "MD4", "--scans", "5", "--json",
        ],
    );
    let v = json(&o);
    assert_eq!(v["break"]["function"], 0);
    assert_eq!(v["break"]["network"], 1);
    assert_eq!(v["break"]["step"], 4);
    assert_eq!(v["break"]["scan"], 1);
    assert_eq!(v["scans"], 0, "the first scan did not complete");
    assert_eq!(v["values"]["MD4"], 0x0400_001A);
    assert_eq!(v["status"]["paused"], true);
    // A breakpoint that is never reached: the run completes.
    let text =
        main_block("NETWORK 1\nLD I0.0\nJMP 1\nNETWORK 2\nLD SM0.0\nINCW MW0\nNETWORK 3\nLBL 1");
    let dir = image_dir(&text, "break-skip");
    let o = gutta_vm(
        &dir,
        &[
            "--break", "main:2:1", "--set", "I0.0=1", "--scans", "3", "--json",
        ],
    );
    let v = json(&o);
    assert!(v["break"].is_null());
    assert_eq!(v["scans"], 3);
}

#[test]
fn break_must_name_an_instruction() {
    for (arg, why) in [
        ("MAIN:1:9", "no instruction at function 0 network 1 step 9"),
        ("MAIN:1", "three parts"),
        ("FOO:1:0", "FUNCTION is MAIN, INTn, SBRn"),
        ("SBR0:x:0", "NETWORK is a network number"),
    ] {
        let o = gutta_vm(&pointers(), &["--break", arg, "--read", "MW24"]);
        assert_eq!(o.status.code(), Some(2), "{arg}");
        assert!(stderr(&o).contains(why), "{arg}: {}", stderr(&o));
        assert!(stdout(&o).is_empty());
    }
}

#[test]
fn an_image_that_does_not_verify_is_exit_2_with_its_v_code() {
    let mut image = compile_image(&main_block(LATCH));
    image
        .pages
        .remove(&PageId::new(PageKind::Instruction, 0))
        .expect("MAIN's instruction page");
    let dir = write_image(&image, "corrupt");
    let o = gutta_vm(&dir, &["--read", "Q0.0"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("V000"), "names the V code: {err}");
    assert!(stdout(&o).is_empty());
    // A page changed behind the manifest's back: the CRC check, also exit 2.
    let dir = image_dir(&main_block(LATCH), "crc");
    let page = dir.join(PageId::new(PageKind::Instruction, 0).file_name());
    let mut bytes = std::fs::read(&page).expect("page");
    bytes[0] ^= 0xFF;
    std::fs::write(&page, bytes).expect("page");
    assert_eq!(gutta_vm(&dir, &[]).status.code(), Some(2));
    // No image at all.
    let o = gutta_vm(&temp_dir("empty"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("manifest.json"), "{}", stderr(&o));
}

#[test]
fn a_watchdog_fault_is_exit_1() {
    let dir = image_dir(&main_block("NETWORK 1\nLBL 1\nLD SM0.0\nJMP 1"), "watchdog");
    let o = gutta_vm(
        &dir,
        &["--watchdog", "10000", "--scans", "5", "--read", "MW0"],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("watchdog"), "{}", stderr(&o));
    assert!(stderr(&o).contains("scan 1"), "{}", stderr(&o));
    let o = gutta_vm(&dir, &["--watchdog", "10000", "--scans", "5", "--json"]);
    assert_eq!(o.status.code(), Some(1));
    let v = json(&o);
    assert_eq!(v["scans"], 1, "the fault stops the run");
    assert_eq!(v["error"]["code"], 3);
    assert_eq!(v["error"]["kind"], "Watchdog");
    assert!(v["error"]["message"]
        .as_str()
        .is_some_and(|m| m.contains("watchdog")));
    assert_eq!(v["status"]["error"], true);
    assert_eq!(v["status"]["run"], false);
    // The default watchdog (10,000,000 instructions) catches it too.
    let o = gutta_vm(&dir, &[]);
    assert_eq!(o.status.code(), Some(1));
}

/// `stats: SCANS scans, INSTRUCTIONS instructions, SECONDS s, NS ns/scan, NS
/// ns/instruction, tier TIER`, parsed strictly: the numbers and the tier's name.
struct Stats {
    scans: u64,
    instructions: u64,
    seconds: f64,
    ns_per_scan: f64,
    ns_per_instruction: f64,
    tier: String,
}

fn parse_stats(stderr: &str) -> Stats {
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("stats: "))
        .collect();
    assert_eq!(lines.len(), 1, "one stats line in {stderr}");
    let rest = &lines[0]["stats: ".len()..];
    let fields: Vec<&str> = rest.split(", ").collect();
    assert_eq!(fields.len(), 6, "six fields in {rest}");
    let number = |field: &str, unit: &str| -> f64 {
        let value = field
            .strip_suffix(unit)
            .unwrap_or_else(|| panic!("{field:?} ends with {unit:?}"));
        value
            .parse()
            .unwrap_or_else(|e| panic!("{value:?} is a number: {e}"))
    };
    let whole = |field: &str, unit: &str| -> u64 {
        let value = field
            .strip_suffix(unit)
            .unwrap_or_else(|| panic!("{field:?} ends with {unit:?}"));
        value
            .parse()
            .unwrap_or_else(|e| panic!("{value:?} is a count: {e}"))
    };
    Stats {
        scans: whole(fields[0], " scans"),
        instructions: whole(fields[1], " instructions"),
        seconds: number(fields[2], " s"),
        ns_per_scan: number(fields[3], " ns/scan"),
        ns_per_instruction: number(fields[4], " ns/instruction"),
        tier: fields[5]
            .strip_prefix("tier ")
            .unwrap_or_else(|| panic!("{:?} starts with \"tier \"", fields[5]))
            .to_string(),
    }
}

/// Four instructions per scan (network records count none), all of them compilable.
/// Seven instructions a scan: enough to be worth a compiled region (6).
const COUNTER: &str =
    "NETWORK 1\nLD SM0.0\n+I 1, MW0\nNETWORK 2\nLD I0.0\n= Q0.0\nNETWORK 3\nLD I0.1\nA I0.2\n= Q0.1";

#[test]
fn stats_line_counts_the_scans_and_names_the_tier_asked() {
    let dir = image_dir(&main_block(COUNTER), "stats");
    for tier in ["interpreted", "compiled", "auto"] {
        let o = gutta_vm(
            &dir,
            &["--scans", "250", "--tier", tier, "--stats", "--read", "MW0"],
        );
        assert_eq!(o.status.code(), Some(0), "{tier}: {}", stderr(&o));
        // The same results on every tier (auto compiles after scan 100).
        assert_eq!(stdout(&o), "MW0 = 250\n", "{tier}");
        let s = parse_stats(&stderr(&o));
        assert_eq!(s.tier, tier);
        assert_eq!(s.scans, 250, "{tier}");
        assert_eq!(s.instructions, 1750, "{tier}");
        assert!(s.seconds > 0.0, "{tier}: {}", s.seconds);
        // The per-scan and per-instruction figures are the seconds divided (to the
        // rounding of the printed seconds, 1 us).
        let close = |printed: f64, n: f64| (printed - s.seconds * 1e9 / n).abs() <= 1e3 / n + 0.1;
        assert!(close(s.ns_per_scan, 250.0), "{tier}: {}", s.ns_per_scan);
        assert!(
            close(s.ns_per_instruction, 1750.0),
            "{tier}: {}",
            s.ns_per_instruction
        );
        assert!(
            !stderr(&o).contains("note:"),
            "{tier}: the program compiles: {}",
            stderr(&o)
        );
    }
    // Without --stats, no line.
    let o = gutta_vm(&dir, &["--scans", "3", "--tier", "compiled"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("stats:"), "{}", stderr(&o));
}

#[test]
fn stats_in_stop_count_only_the_scans_that_ran() {
    // STOP in the third scan: the scans after it run nothing.
    let code = "NETWORK 1\nLD SM0.0\n+I 1, MW0\nNETWORK 2\nLDW= MW0, 3\nSTOP";
    let dir = image_dir(&main_block(code), "stats-stop");
    let o = gutta_vm(&dir, &["--scans", "10", "--stats", "--tier", "interpreted"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = parse_stats(&stderr(&o));
    assert_eq!(s.scans, 3);
    // LD, +I, LDW= and STOP per scan (a box counts without power flow too).
    assert_eq!(s.instructions, 12);
}

#[test]
fn tier_compiled_says_when_nothing_compiles() {
    // A timer in a FOR loop: the tier takes the timer, but FOR and NEXT stay
    // interpreted, so MAIN does not compile whole, and the loop's body of two
    // instructions does not pay for entering native code (docs/vm-jit.md, "Regions").
    let dir = image_dir(
        &main_block(
            "NETWORK 1\nLD SM0.0\nFOR MW2, 1, 1\nNETWORK 2\nLD SM0.0\nTON T4, 100\nNETWORK 3\nNEXT",
        ),
        "stats-tier",
    );
    let o = gutta_vm(&dir, &["--scans", "5", "--tier", "compiled", "--stats"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = parse_stats(&stderr(&o));
    // LD, FOR, LD, TON, NEXT a scan.
    assert_eq!((s.tier.as_str(), s.instructions), ("compiled", 25));
    assert!(
        stderr(&o).contains(
            "gutta-vm: note: --tier compiled: nothing in the program is worth compiling (no unit compiles whole, no run of 6 instructions); every scan ran interpreted"
        ),
        "{}",
        stderr(&o)
    );
    let o = gutta_vm(&dir, &["--scans", "5", "--tier", "interpreted", "--stats"]);
    assert!(!stderr(&o).contains("note:"), "{}", stderr(&o));
}

#[test]
fn a_wrong_tier_is_a_usage_error() {
    let dir = image_dir(&main_block(COUNTER), "stats-bad-tier");
    let o = gutta_vm(&dir, &["--tier", "native", "--stats"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("--tier"), "{err}");
    assert!(
        err.contains("interpreted") && err.contains("compiled") && err.contains("auto"),
        "the possible values: {err}"
    );
    assert!(!err.contains("stats:"), "{err}");
}
