//! The program and test files of the `gutta-cc test` benchmarks (issue 14's speed bar),
//! shared by `gtest/benches/gtest_run.rs` (the library) and
//! `cli/benches/test_command.rs` (the binary, through `#[path]`). Generates text only:
//! no I/O, no timing, no knowledge of the runner.
//!
//! The program is exactly [`INSTRUCTIONS`] instructions in MAIN, every one executed in
//! every scan (no jumps, no calls): a toggle bit, a scan counter, a counter (CTU), a
//! 10 ms timer (TON), input logic and word math the tests drive, then filler networks
//! of bit logic, word math, compares and latches with pseudo-random operands (a fixed
//! LCG, so no two fillers are alike but every run generates the same text). The
//! fillers write only MB40-MB79, MW80-MW126 and QB1-QB7, never what the tests check.
//!
//! What a fresh PLC shows after scan k of a test (k from 1, 10 ms scans):
//! `ScanCount` (MW10) = k; `Toggle` (M0.0) = k mod 2; C0 = (k + 1) / 2 (a rising edge
//! of M0.0 in every odd scan); T2 = k - 1 (started at 0 ms, scan k runs at
//! (k - 1) x 10 ms); `Lamp` (Q0.0) = `Start` AND `Enable`; `Result` (MW32) =
//! `Setpoint` (MW30) + 5.

/// Instructions of the generated program, by construction; the benches assert it again
/// from the compiled image.
pub const INSTRUCTIONS: usize = 200;

/// The program's file name, as the test files' `PROGRAM` line names it.
pub const PROGRAM_FILE: &str = "main.lad";

/// A fixed linear congruential generator (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

/// Networks every program has (18 instructions): what the tests check.
fn fixed_networks() -> Vec<(&'static str, Vec<String>)> {
    let lines = |l: &[&str]| l.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        (
            "Toggle is on in odd scans",
            lines(&["LD     Toggle", "NOT", "=      Toggle"]),
        ),
        ("count scans", lines(&["LD     SM0.0", "INCW   ScanCount"])),
        (
            "C0 counts the rising edges of Toggle",
            lines(&[
                "LD     Toggle",
                "LD     M0.1",
                "CTU    C0, 30000",
                "=      Q0.1",
            ]),
        ),
        (
            "T2 (10 ms) runs from the first scan",
            lines(&["LD     SM0.0", "TON    T2, 30000", "=      Q0.2"]),
        ),
        (
            "Lamp = Start AND Enable",
            lines(&["LD     Start", "A      Enable", "=      Lamp"]),
        ),
        (
            "Result = Setpoint + 5",
            lines(&[
                "LD     SM0.0",
                "MOVW   Setpoint, Result",
                "+I     5, Result",
            ]),
        ),
    ]
}

/// A filler network of 4 or 5 instructions, of kind `kind mod 5`.
fn filler(kind: usize, rng: &mut Lcg) -> (&'static str, Vec<String>) {
    let mut input = || format!("I{}.{}", rng.below(8), rng.below(8));
    let inputs = [input(), input()];
    let mut bit = || format!("M{}.{}", 40 + rng.below(40), rng.below(8));
    let bits = [bit(), bit(), bit()];
    let mut word = || format!("MW{}", 80 + 2 * rng.below(24));
    let words = [word(), word()];
    let byte = |rng: &mut Lcg| format!("MB{}", 40 + rng.below(40));
    let coil = format!("Q{}.{}", 1 + rng.below(7), rng.below(8));
    let [i1, i2] = &inputs;
    let [b1, b2, b3] = &bits;
    let [w1, w2] = &words;
    match kind % 5 {
        0 => (
            "bit logic",
            vec![
                format!("LD     {i1}"),
                format!("A      {b1}"),
                format!("O      {i2}"),
                format!("AN     {b2}"),
                format!("=      {b3}"),
            ],
        ),
        1 => (
            "word math",
            vec![
                "LD     SM0.0".into(),
                format!("MOVW   ScanCount, {w1}"),
                format!("+I     {w2}, {w1}"),
                format!("*I     3, {w1}"),
                format!("-I     7, {w1}"),
            ],
        ),
        2 => (
            "word compares",
            vec![
                "LDW>=  ScanCount, 100".into(),
                format!("AW<    {w1}, 900"),
                "OW=    Result, 5".into(),
                format!("=      {coil}"),
            ],
        ),
        3 => (
            "a latch",
            vec![
                format!("LD     {i1}"),
                format!("O      {b1}"),
                format!("AN     {i2}"),
                format!("=      {b1}"),
            ],
        ),
        _ => (
            "a byte compare and a move",
            vec![
                format!("LDB>   {}, 7", byte(rng)),
                "A      Toggle".into(),
                format!("MOVB   {}, {}", byte(rng), byte(rng)),
                format!("=      {b2}"),
            ],
        ),
    }
}

/// A short network to make the count exact: 2 or 3 instructions.
fn pad(size: usize, rng: &mut Lcg) -> (&'static str, Vec<String>) {
    let mut bit = || format!("M{}.{}", 40 + rng.below(40), rng.below(8));
    let (a, b, c) = (bit(), bit(), bit());
    if size == 2 {
        ("a copy", vec![format!("LD     {a}"), format!("=      {b}")])
    } else {
        (
            "an AND",
            vec![
                format!("LD     {a}"),
                format!("A      {b}"),
                format!("=      {c}"),
            ],
        )
    }
}

/// The program text: exactly [`INSTRUCTIONS`] instructions in MAIN.
pub fn program() -> String {
    let mut networks = fixed_networks();
    let mut count: usize = networks.iter().map(|(_, l)| l.len()).sum();
    let mut rng = Lcg(0x6775_7474_6120_7465);
    let mut kind = 0;
    while count < INSTRUCTIONS {
        let remaining = INSTRUCTIONS - count;
        // A filler leaves at least 2 (one pad); 2..=6 left are made of pads.
        let network = match remaining {
            7.. => {
                kind += 1;
                filler(kind - 1, &mut rng)
            }
            2 | 4 => pad(2, &mut rng),
            _ => pad(3, &mut rng),
        };
        count += network.1.len();
        networks.push(network);
    }
    assert_eq!(count, INSTRUCTIONS, "the generator counts exactly");
    let mut text = String::from(
        "// The gutta-cc test benchmark's program (gtest/benches/bench_program/mod.rs)\n\
         PLC_TYPE CPU-EC20\n\n\
         SYMBOLS\n\
         \x20 Start     : I0.0\n\
         \x20 Enable    : I0.1\n\
         \x20 Lamp      : Q0.0\n\
         \x20 Toggle    : M0.0\n\
         \x20 ScanCount : MW10\n\
         \x20 Setpoint  : MW30 : INT\n\
         \x20 Result    : MW32 : INT\n\
         END_SYMBOLS\n\n\
         ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n",
    );
    for (n, (title, lines)) in networks.iter().enumerate() {
        text.push_str(&format!("NETWORK {} // {title}\n", n + 1));
        for line in lines {
            text.push_str(line);
            text.push('\n');
        }
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    text
}

/// What the program's counters show after scan `k` of a fresh PLC (k >= 1), as the
/// comparisons of an EXPECT.
fn after_scans(k: u32) -> String {
    format!(
        "ScanCount = {k}, Toggle = {}, C0 = {}, T2 = {}",
        k % 2,
        k.div_ceil(2),
        k - 1
    )
}

/// One test of `scans` pairs `SCAN` + `EXPECT` (every EXPECT holds).
pub fn scans_test(scans: u32) -> String {
    let mut text = format!(
        "// {scans} scans of the {INSTRUCTIONS}-instruction program, an EXPECT after each\n\
         PROGRAM {PROGRAM_FILE}\nSCAN_TIME 10ms\n\nTEST scans_{scans}_expect_each\n"
    );
    for k in 1..=scans {
        text.push_str("  SCAN\n");
        text.push_str(&format!("  EXPECT {}\n", after_scans(k)));
    }
    text.push_str("END_TEST\n");
    text
}

/// A file of `tests` tests, each a few SET / SCAN / EXPECT (every one passes).
pub fn many_tests(tests: u32) -> String {
    let mut text = format!(
        "// {tests} tests of the {INSTRUCTIONS}-instruction program\n\
         PROGRAM {PROGRAM_FILE}\nSCAN_TIME 10ms\n"
    );
    for i in 0..tests {
        let enable = i % 2;
        let setpoint = i as i32 * 37 - 1800;
        let scans = 1 + i % 4;
        let later = -(i as i32) * 11;
        text.push_str(&format!(
            "\nTEST case_{i:03}\n\
             \x20 SET    Start = 1, Enable = {enable}, Setpoint = {setpoint}\n\
             \x20 SCAN   {scans}\n\
             \x20 EXPECT Lamp = {enable}, Result = {}, {}\n\
             \x20 SET    Enable = 0, Setpoint = {later}\n\
             \x20 SCAN   2\n\
             \x20 EXPECT Lamp = 0, Result = {}, {}\n\
             \x20 EXPECT Q0.1 = 0, Q0.2 = 0\n\
             END_TEST\n",
            setpoint + 5,
            after_scans(scans),
            later + 5,
            after_scans(scans + 2),
        ));
    }
    text
}
