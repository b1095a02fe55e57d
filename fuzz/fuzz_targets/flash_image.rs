//! The flash file's decoder (gutta-sim's `persist`, what `gutta-sim --flash DIR` reads
//! at power-on) on arbitrary bytes: it never panics, and whatever decodes encodes back
//! to the same bytes and decodes to the same flash.

#![no_main]

use gutta_sim::persist::FlashImage;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(flash) = FlashImage::decode(data) {
        let bytes = flash.encode().expect("a decoded flash encodes");
        assert_eq!(bytes, data, "decode then encode changed the bytes");
        assert_eq!(FlashImage::decode(&bytes), Ok(flash));
    }
});
