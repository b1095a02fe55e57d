//! The benchmark programs, generated as LAD text. Only text: what they mean is the
//! compiler's business (for the VM) and `transcribe`'s (for the native code).

/// A fixed pseudo-random sequence (64-bit LCG, Knuth's MMIX constants): the programs
/// are the same on every run, and their operands do not repeat with a short period, so
/// the native transcription cannot fold repeated networks into one.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) % n
    }
}

/// (a): networks of LD/A/AN/O/= on I and M bits (inputs I0..I31, memory M0..M1023,
/// chosen pseudo-randomly); `count` instructions in all.
pub fn bit_logic(count: usize) -> String {
    let mut rng = Lcg(0x0067_7574_7461);
    let mut bit = |area: &str, bytes: u64| format!("{area}{}.{}", rng.below(bytes), rng.below(8));
    let mut code = String::new();
    let mut n = 0;
    let mut net = 1;
    while n < count {
        let (i1, m1, i2, m2, out) = (
            bit("I", 32),
            bit("M", 1024),
            bit("I", 32),
            bit("M", 1024),
            bit("M", 1024),
        );
        code.push_str(&format!(
            "NETWORK {net}\nLD {i1}\nA {m1}\nAN {i2}\nO {m2}\n= {out}\n"
        ));
        n += 5;
        net += 1;
    }
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n")
}

/// (b): moves, integer math, compares and a subroutine call per network.
pub fn mixed(count: usize) -> String {
    let mut code = String::new();
    let mut n = 0;
    let mut net = 1;
    while n < count {
        code.push_str(&format!(
            "NETWORK {net}\nLD SM0.0\nMOVW MW{a}, MW{b}\n+I 3, MW{b}\n*I 2, MW{b}\nLDW>= MW{b}, 100\nMOVD MD40, MD44\n+D 1, MD44\nCALL ADD1, MW{b}, MW{c}\n",
            a = (net * 2) % 32,
            b = 32 + (net * 2) % 32,
            c = 64 + (net * 2) % 32
        ));
        n += 8 + 3;
        net += 1;
    }
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n\
         SUBROUTINE_BLOCK ADD1:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW #a, #r\n+I 1, #r\nEND_SUBROUTINE_BLOCK\n"
    )
}
