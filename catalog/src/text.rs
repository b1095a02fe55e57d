//! Decoding description files to text: UTF-8 (with or without BOM) and UTF-16 LE/BE
//! with BOM, as the vendor's real files are UTF-16.

use crate::{CatalogError, CatalogErrorCode};

/// Decode a description file's bytes into a `String`.
///
/// UTF-16 needs a BOM, or is recognised by the `<` of the XML declaration being
/// followed (LE) or preceded (BE) by a zero byte. The XML declaration's `encoding`
/// attribute is then dropped, as the text is no longer in that encoding.
pub fn decode_xml_text(bytes: &[u8], file: &str) -> Result<String, CatalogError> {
    let bad = |what: &str| {
        CatalogError::new(
            CatalogErrorCode::Encoding,
            file,
            format!("file is not valid {what}"),
        )
    };
    let text = match bytes {
        [0xEF, 0xBB, 0xBF, rest @ ..] => {
            String::from_utf8(rest.to_vec()).map_err(|_| bad("UTF-8"))?
        }
        [0xFF, 0xFE, rest @ ..] => {
            utf16(rest, u16::from_le_bytes).ok_or_else(|| bad("UTF-16LE"))?
        }
        [0xFE, 0xFF, rest @ ..] => {
            utf16(rest, u16::from_be_bytes).ok_or_else(|| bad("UTF-16BE"))?
        }
        [b'<', 0, ..] => utf16(bytes, u16::from_le_bytes).ok_or_else(|| bad("UTF-16LE"))?,
        [0, b'<', ..] => utf16(bytes, u16::from_be_bytes).ok_or_else(|| bad("UTF-16BE"))?,
        _ => String::from_utf8(bytes.to_vec()).map_err(|_| bad("UTF-8"))?,
    };
    Ok(strip_declared_encoding(text))
}

fn utf16(bytes: &[u8], read: fn([u8; 2]) -> u16) -> Option<String> {
    if !bytes.len().is_multiple_of(2) {
        return None;
    }
    let units = bytes.chunks_exact(2).map(|c| read([c[0], c[1]]));
    char::decode_utf16(units)
        .collect::<Result<String, _>>()
        .ok()
}

/// Remove `encoding="..."` from the XML declaration: the text is now UTF-8 in memory.
fn strip_declared_encoding(text: String) -> String {
    if !text.starts_with("<?xml") {
        return text;
    }
    let Some(end) = text.find("?>") else {
        return text;
    };
    let decl = &text[..end];
    let Some(at) = decl.find("encoding") else {
        return text;
    };
    let after = &decl[at..];
    let Some(q1) = after.find(['"', '\'']) else {
        return text;
    };
    let quote = after.as_bytes()[q1] as char;
    let Some(q2) = after[q1 + 1..].find(quote) else {
        return text;
    };
    let cut_end = at + q1 + 1 + q2 + 1;
    let mut out = String::with_capacity(text.len());
    out.push_str(text[..at].trim_end());
    out.push_str(&text[cut_end..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utf16le_bom(s: &str) -> Vec<u8> {
        let mut v = vec![0xFF, 0xFE];
        v.extend(s.encode_utf16().flat_map(|u| u.to_le_bytes()));
        v
    }

    #[test]
    fn utf16le_with_bom_and_declaration_decodes() {
        let src = "<?xml version=\"1.0\" encoding=\"utf-16\"?>\n<PlcType Name=\"X\"/>";
        let text = decode_xml_text(&utf16le_bom(src), "PlcType.xml").unwrap();
        assert_eq!(text, "<?xml version=\"1.0\"?>\n<PlcType Name=\"X\"/>");
    }

    #[test]
    fn utf16be_with_bom_decodes() {
        let mut v = vec![0xFE, 0xFF];
        v.extend("<a/>".encode_utf16().flat_map(|u| u.to_be_bytes()));
        assert_eq!(decode_xml_text(&v, "f").unwrap(), "<a/>");
    }

    #[test]
    fn odd_length_utf16_is_an_encoding_error() {
        let err = decode_xml_text(&[0xFF, 0xFE, b'<'], "f").unwrap_err();
        assert_eq!(err.code, CatalogErrorCode::Encoding);
    }

    #[test]
    fn utf8_bom_is_dropped() {
        assert_eq!(decode_xml_text(b"\xEF\xBB\xBF<a/>", "f").unwrap(), "<a/>");
    }
}
