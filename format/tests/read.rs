//! `Image::read` through its callback and `Image::files`: round trip, and every way a
//! directory can be wrong (manifest, file names, duplicates, const page, read errors,
//! lengths, CRCs). Only canonical page file names ever reach the callback.

mod common;

use std::collections::BTreeMap;

use common::*;
use gutta_format::{Image, ImageError, PageId, PageKind, MANIFEST_FILE};

type Files = BTreeMap<String, Vec<u8>>;

fn files_of(image: &Image) -> Files {
    image.files().into_iter().collect()
}

fn read(files: &Files) -> Result<Image, ImageError> {
    let manifest = String::from_utf8_lossy(&files[MANIFEST_FILE]).into_owned();
    Image::read(&manifest, |name| {
        files
            .get(name)
            .cloned()
            .ok_or_else(|| format!("no such file {name}"))
    })
}

fn with_manifest(files: &Files, edit: impl Fn(String) -> String) -> Files {
    let mut files = files.clone();
    let text = String::from_utf8_lossy(&files[MANIFEST_FILE]).into_owned();
    files.insert(MANIFEST_FILE.to_string(), edit(text).into_bytes());
    files
}

#[test]
fn files_read_back_as_the_same_image() {
    let t = target();
    let image = full_program(&t).build();
    assert_eq!(read(&files_of(&image)), Ok(image));
}

#[test]
fn callback_is_asked_for_each_listed_page_once() {
    let t = target();
    let image = full_program(&t).build();
    let files = files_of(&image);
    let mut asked = Vec::new();
    let manifest = String::from_utf8_lossy(&files[MANIFEST_FILE]).into_owned();
    Image::read(&manifest, |name| {
        asked.push(name.to_string());
        Ok(files[name].clone())
    })
    .expect("reads");
    let expected: Vec<String> = image.pages.keys().map(|id| id.file_name()).collect();
    assert_eq!(asked, expected);
}

#[test]
fn bad_manifest() {
    let files = files_of(&full_program(&target()).build());
    let broken = with_manifest(&files, |m| m.replace("\"format\": 1", "\"format\": 2"));
    assert!(matches!(read(&broken), Err(ImageError::Manifest(_))));
    let broken = with_manifest(&files, |m| m[..m.len() / 2].to_string());
    assert!(matches!(read(&broken), Err(ImageError::Manifest(_))));
    let broken = with_manifest(&files, |m| m.replace("\"data\"", "\"dat\""));
    assert!(matches!(read(&broken), Err(ImageError::Manifest(_))));
}

#[test]
fn file_names_must_be_the_canonical_ones() {
    let files = files_of(&full_program(&target()).build());
    for bad in [
        "../const.bin",
        "/etc/passwd",
        "argument/8.bin",
        "argument/08.BIN",
        "argument\\\\08.bin",
        "./argument/08.bin",
        "instruction/08.bin",
    ] {
        let broken = with_manifest(&files, |m| {
            m.replace(
                "\"file\": \"argument/08.bin\"",
                &format!("\"file\": \"{bad}\""),
            )
        });
        let mut asked = Vec::new();
        let manifest = String::from_utf8_lossy(&broken[MANIFEST_FILE]).into_owned();
        let result = Image::read(&manifest, |name| {
            asked.push(name.to_string());
            Ok(Vec::new())
        });
        match result {
            Err(ImageError::FileName { page, expected, .. }) => {
                assert_eq!(page, PageId::new(PageKind::Argument, 8));
                assert_eq!(expected, "argument/08.bin");
            }
            other => panic!("{bad}: {other:?}"),
        }
        assert!(
            asked.is_empty(),
            "no file is read before the manifest checks"
        );
    }
}

#[test]
fn duplicate_pages_and_missing_const_page() {
    let files = files_of(&full_program(&target()).build());
    let twice = with_manifest(&files, |m| {
        let line = m
            .lines()
            .find(|l| l.contains("data/0.bin"))
            .expect("data line")
            .to_string();
        m.replace(&line, &format!("{line}\n{line}"))
    });
    assert_eq!(
        read(&twice),
        Err(ImageError::DuplicatePage {
            page: PageId::new(PageKind::Data, 0)
        })
    );
    let no_const = with_manifest(&files, |m| {
        m.lines()
            .filter(|l| !l.contains("const.bin"))
            .collect::<Vec<_>>()
            .join("\n")
    });
    assert_eq!(read(&no_const), Err(ImageError::MissingConstPage));
}

#[test]
fn read_errors_lengths_and_crcs() {
    let files = files_of(&full_program(&target()).build());
    let mut missing = files.clone();
    missing.remove("data/0.bin");
    assert!(matches!(read(&missing), Err(ImageError::Read { file, .. }) if file == "data/0.bin"));

    let mut longer = files.clone();
    longer.get_mut("system/0.bin").expect("system").push(0);
    assert!(matches!(
        read(&longer),
        Err(ImageError::Length {
            manifest: 26,
            actual: 27,
            ..
        })
    ));

    let mut flipped = files.clone();
    flipped.get_mut("instruction/00.bin").expect("MAIN")[5] ^= 0x80;
    let err = read(&flipped).expect_err("CRC differs");
    assert!(matches!(err, ImageError::Crc { ref file, .. } if file == "instruction/00.bin"));
    assert!(
        err.to_string().starts_with("instruction/00.bin: CRC 0x"),
        "{err}"
    );
}
