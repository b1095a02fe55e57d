//! The benchmark programs, generated as LAD text. Only text: what they mean is the
//! compiler's business (for the VM) and `transcribe`'s (for the native code).

/// (a): networks of LD/A/AN/O/= on I, Q and M bits; `count` instructions in all.
pub fn bit_logic(count: usize) -> String {
    let mut code = String::new();
    let mut n = 0;
    let mut net = 1;
    while n < count {
        code.push_str(&format!(
            "NETWORK {net}\nLD I0.{}\nA M{}.{}\nAN I1.{}\nO M{}.{}\n= M{}.{}\n",
            net % 8,
            net % 16,
            net % 8,
            (net + 3) % 8,
            (net + 5) % 16,
            net % 8,
            (net + 7) % 16,
            (net + 1) % 8
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
