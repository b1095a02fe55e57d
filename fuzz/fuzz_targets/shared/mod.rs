//! What the image fuzz targets share: the default target, a valid image using every
//! operand kind (the format tests' full program), and byte edits of it.

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Target};
use gutta_format::{Image, PageId};

#[path = "../../../format/tests/common/mod.rs"]
mod common;

pub fn default_target() -> &'static Arc<Target> {
    static TARGET: OnceLock<Arc<Target>> = OnceLock::new();
    TARGET
        .get_or_init(|| stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"))
}

pub fn base_image() -> &'static Image {
    static IMAGE: OnceLock<Image> = OnceLock::new();
    IMAGE.get_or_init(|| common::full_program(default_target()).build())
}

/// Edit `image` by 4-byte commands `sel hi lo x`: page `sel` (modulo the pages), at
/// offset `hi lo`: xor `x` (sel >> 6 = 0 or 1), truncate (2), or insert `x` (3; only
/// when `insert` is allowed, else xor).
pub fn mutate(image: &mut Image, data: &[u8], insert: bool) {
    let ids: Vec<PageId> = image.pages.keys().copied().collect();
    for m in data.chunks(4) {
        let [sel, hi, lo, x] = [
            m[0],
            *m.get(1).unwrap_or(&0),
            *m.get(2).unwrap_or(&0),
            *m.get(3).unwrap_or(&0),
        ];
        let id = ids[usize::from(sel) % ids.len()];
        let Some(page) = image.pages.get_mut(&id) else {
            continue;
        };
        let at = usize::from(u16::from_be_bytes([hi, lo]));
        match sel >> 6 {
            2 => page.truncate(at % (page.len() + 1)),
            3 if insert => page.insert(at % (page.len() + 1), x),
            _ => {
                if let Some(len) = page.len().checked_sub(1) {
                    page[at % (len + 1)] ^= x;
                }
            }
        }
    }
}
