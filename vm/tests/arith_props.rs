//! Property tests: every integer and real arithmetic instruction against Rust's own
//! operations, per width. One program runs them all on inputs the test sets; each case
//! is one scan. Integer results wrap (two's complement); division by zero leaves OUT.

use std::sync::{Arc, OnceLock};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_vm::{Vm, VmConfig};
use proptest::prelude::*;

/// a in MW0/MD0, b in MW2/MD4 (reals in MD8/MD12); each result gets its own OUT that is
/// first loaded with the left operand, as S7-200 STL works (OUT := OUT op IN1).
const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n\
MOVW MW0, MW20\n+I MW2, MW20\nMOVW MW0, MW22\n-I MW2, MW22\nMOVW MW0, MW24\n*I MW2, MW24\nMOVW MW0, MW26\n/I MW2, MW26\n\
MOVD MD40, MD60\n+D MD44, MD60\nMOVD MD40, MD64\n-D MD44, MD64\nMOVD MD40, MD68\n*D MD44, MD68\nMOVD MD40, MD72\n/D MD44, MD72\n\
MOVR MD8, MD80\n+R MD12, MD80\nMOVR MD8, MD84\n-R MD12, MD84\nMOVR MD8, MD88\n*R MD12, MD88\nMOVR MD8, MD92\n/R MD12, MD92\n\
MOVW MW0, MW96\nINCW MW96\nMOVW MW0, MW98\nDECW MW98\nMOVB MB0, MB100\nINCB MB100\nMOVD MD40, MD104\nINCD MD104\n\
MOVW MW0, MW108\nANDW MW2, MW108\nMOVW MW0, MW110\nORW MW2, MW110\nMOVW MW0, MW112\nXORW MW2, MW112\nMOVW MW0, MW114\nINVW MW114\n\
MOVW 0, MW118\nMOVW MW2, MW116\nMUL MW0, MD116\nEND_ORGANIZATION_BLOCK\n";

fn vm() -> Vm {
    static IMAGE: OnceLock<gutta_format::VerifiedImage> = OnceLock::new();
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let image = IMAGE.get_or_init(|| {
        let explicit = ExplicitTarget {
            target: target.clone(),
            origin: "test".into(),
        };
        let c = compile(SourceFile::new("arith.lad", PROGRAM), Some(&explicit));
        let image = c
            .image
            .unwrap_or_else(|| panic!("{:?}", c.checked.diagnostics()));
        gutta_format::verify(&image, &target).expect("verifies")
    });
    Vm::new(image.clone(), Arc::clone(&target), VmConfig::default()).expect("loads")
}

fn at(vm: &Vm, v: &str) -> gutta_catalog::Address {
    vm.target().memory.parse_address(v).expect("address")
}
fn get(vm: &Vm, v: &str) -> u32 {
    vm.read(at(vm, v)).expect("read")
}
fn put(vm: &mut Vm, v: &str, x: u32) {
    let a = at(vm, v);
    vm.write(a, x).expect("write");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn word_arithmetic_matches_rust(a: i16, b: i16) {
        let mut vm = vm();
        put(&mut vm, "MW0", a as u16 as u32);
        put(&mut vm, "MW2", b as u16 as u32);
        vm.scan().expect("scan");
        let w = |v: &str| get(&vm, v) as u16 as i16;
        prop_assert_eq!(w("MW20"), a.wrapping_add(b));
        prop_assert_eq!(w("MW22"), a.wrapping_sub(b));
        prop_assert_eq!(w("MW24"), a.wrapping_mul(b));
        prop_assert_eq!(w("MW26"), if b == 0 { a } else { a.wrapping_div(b) });
        prop_assert_eq!(w("MW96"), a.wrapping_add(1));
        prop_assert_eq!(w("MW98"), a.wrapping_sub(1));
        prop_assert_eq!(get(&vm, "MB100") as u8, (a as u16 as u8).wrapping_add(1));
        prop_assert_eq!(w("MW108"), a & b);
        prop_assert_eq!(w("MW110"), a | b);
        prop_assert_eq!(w("MW112"), a ^ b);
        prop_assert_eq!(w("MW114"), !a);
        prop_assert_eq!(get(&vm, "MD116") as i32, a as i32 * b as i32, "MUL: 16 x 16 -> 32");
    }

    #[test]
    fn dword_arithmetic_matches_rust(a: i32, b: i32) {
        let mut vm = vm();
        put(&mut vm, "MD40", a as u32);
        put(&mut vm, "MD44", b as u32);
        vm.scan().expect("scan");
        let d = |v: &str| get(&vm, v) as i32;
        prop_assert_eq!(d("MD60"), a.wrapping_add(b));
        prop_assert_eq!(d("MD64"), a.wrapping_sub(b));
        prop_assert_eq!(d("MD68"), a.wrapping_mul(b));
        prop_assert_eq!(d("MD72"), if b == 0 { a } else { a.wrapping_div(b) });
        prop_assert_eq!(d("MD104"), a.wrapping_add(1));
    }

    #[test]
    fn real_arithmetic_matches_rust(a in -1.0e30f32..1.0e30, b in -1.0e30f32..1.0e30) {
        let mut vm = vm();
        put(&mut vm, "MD8", a.to_bits());
        put(&mut vm, "MD12", b.to_bits());
        vm.scan().expect("scan");
        let r = |v: &str| f32::from_bits(get(&vm, v));
        prop_assert_eq!(r("MD80").to_bits(), (a + b).to_bits());
        prop_assert_eq!(r("MD84").to_bits(), (a - b).to_bits());
        prop_assert_eq!(r("MD88").to_bits(), (a * b).to_bits());
        let q = if b == 0.0 { a } else { a / b };
        prop_assert_eq!(r("MD92").to_bits(), q.to_bits());
    }
}
