//! Fuzz target of the image reader and verifier: arbitrary bytes become an image
//! directory (three ways, chosen by the first byte) that goes through `Image::read` and
//! `verify` on the default target; every page decoder also runs on every page's bytes.
//! Panics are the bugs it looks for. Mode 0: raw manifest text and page files. Mode 1:
//! pages of any kind and number with a manifest that matches them (so the verifier is
//! reached). Mode 2: byte mutations of a valid image using every operand kind.
#![no_main]

use std::collections::BTreeMap;

use gutta_catalog::stdlib;
use gutta_format::{
    decode_data, decode_instructions, verify, ArgumentPage, Image, Manifest, PageId, PageKind,
    SystemPage, MANIFEST_FILE,
};
use libfuzzer_sys::fuzz_target;

mod shared;

use shared::{base_image, default_target, mutate};

/// Every decoder on raw bytes: they return errors, never panic.
fn decode_all(bytes: &[u8]) {
    let _ = ArgumentPage::decode(bytes);
    let _ = decode_instructions(bytes);
    let _ = decode_data(bytes);
    let _ = SystemPage::decode(bytes);
}

/// Read the files through the callback interface, then verify; a verified image must
/// still have MAIN and read back identically from its own files.
fn read_and_verify(files: &BTreeMap<String, Vec<u8>>) {
    let Some(manifest) = files.get(MANIFEST_FILE) else {
        return;
    };
    let manifest = String::from_utf8_lossy(manifest);
    let _ = Manifest::parse(&manifest);
    let read = Image::read(&manifest, |name| {
        files
            .get(name)
            .cloned()
            .ok_or_else(|| format!("no file {name}"))
    });
    let Ok(image) = read else {
        return;
    };
    for bytes in image.pages.values() {
        decode_all(bytes);
    }
    if let Ok(verified) = verify(&image, default_target()) {
        assert!(verified.main().is_some(), "a verified image has MAIN");
    }
    let again: BTreeMap<String, Vec<u8>> = image.files().into_iter().collect();
    let manifest = String::from_utf8_lossy(&again[MANIFEST_FILE]).into_owned();
    let back = Image::read(&manifest, |name| {
        again
            .get(name)
            .cloned()
            .ok_or_else(|| format!("no file {name}"))
    });
    assert_eq!(
        back.as_ref(),
        Ok(&image),
        "files() reads back as the same image"
    );
}

/// One length-prefixed chunk (a length byte, then up to that many bytes) and the rest.
fn take_chunk(data: &[u8]) -> Option<(&[u8], &[u8])> {
    let (&len, rest) = data.split_first()?;
    Some(rest.split_at(usize::from(len).min(rest.len())))
}

fn raw_manifest(data: &[u8]) {
    let Some((&len, rest)) = data.split_first() else {
        return;
    };
    let cut = (usize::from(len) * 4).min(rest.len());
    let (manifest, pages) = rest.split_at(cut);
    let mut files = BTreeMap::new();
    files.insert(MANIFEST_FILE.to_string(), manifest.to_vec());
    let names = [
        "const.bin",
        "argument/00.bin",
        "instruction/00.bin",
        "argument/08.bin",
        "instruction/08.bin",
        "data/0.bin",
        "system/0.bin",
    ];
    let mut pages = pages;
    for name in names {
        let Some((bytes, rest)) = take_chunk(pages) else {
            break;
        };
        decode_all(bytes);
        files.insert(name.to_string(), bytes.to_vec());
        pages = rest;
    }
    read_and_verify(&files);
}

fn structured_pages(data: &[u8]) {
    let mut pages = BTreeMap::new();
    let mut rest = data;
    while let [k, n, body @ ..] = rest {
        let kind = PageKind::ALL[usize::from(k % 5)];
        let number = n & kind.max_number();
        let Some((bytes, after)) = take_chunk(body) else {
            break;
        };
        decode_all(bytes);
        pages.insert(PageId::new(kind, number), bytes.to_vec());
        rest = after;
    }
    let image = Image {
        plc_type: stdlib::DEFAULT.to_string(),
        pages,
    };
    let _ = verify(&image, default_target());
    read_and_verify(&image.files().into_iter().collect());
}

fn mutated_base(data: &[u8]) {
    let mut image = base_image().clone();
    mutate(&mut image, data, true);
    let _ = verify(&image, default_target());
    read_and_verify(&image.files().into_iter().collect());
}

fuzz_target!(|data: &[u8]| {
    decode_all(data);
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    match mode % 3 {
        0 => raw_manifest(rest),
        1 => structured_pages(rest),
        _ => mutated_base(rest),
    }
});
