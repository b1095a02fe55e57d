//! Conversions (BTI, ITB, ITD, DTI, DTR, ROUND, TRUNC, BCDI, IBCD, SEG, DECO, ENCO) and real functions (SIN, COS, TAN, LN, EXP).

use super::Handler;

pub fn lookup(_mnemonic: &str) -> Option<Handler> {
    None
}
