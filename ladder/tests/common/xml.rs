//! A small strict XML reader for the drawing's tests (SVG and the HTML page): every
//! element in document order with its attributes, its text content and the indexes of
//! the elements around it. Panics on anything not well-formed: a mismatched or unclosed
//! tag, a bad attribute, an entity other than XML's five.

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

#[derive(Debug, Clone)]
pub struct Element {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    /// The text inside the element (its children's too), entities resolved.
    pub text: String,
    /// Indexes of the enclosing elements, outermost first.
    pub parents: Vec<usize>,
}

impl Element {
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    pub fn has_class(&self, class: &str) -> bool {
        self.attr("class")
            .is_some_and(|c| c.split(' ').any(|part| part == class))
    }

    /// A numeric attribute (`x`, `y`); panics when it is missing or not a number.
    pub fn num(&self, key: &str) -> i32 {
        self.attr(key)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{} without a numeric {key}", self.name))
    }
}

/// Parse `text` as XML: the elements in document order, and the whole text content with
/// entities resolved.
pub fn parse(text: &str) -> (Vec<Element>, String) {
    let mut reader = Reader::from_str(text);
    let mut elements: Vec<Element> = Vec::new();
    let mut content = String::new();
    let mut open: Vec<usize> = Vec::new();
    let element = |e: &BytesStart<'_>, parents: &[usize]| Element {
        name: String::from_utf8(e.name().as_ref().to_vec()).expect("a UTF-8 name"),
        attrs: e
            .attributes()
            .map(|a| {
                let a = a.expect("well-formed attribute");
                (
                    String::from_utf8(a.key.as_ref().to_vec()).expect("a UTF-8 key"),
                    a.unescape_value().expect("attribute escapes").into_owned(),
                )
            })
            .collect(),
        text: String::new(),
        parents: parents.to_vec(),
    };
    let mut add_text = |elements: &mut Vec<Element>, open: &[usize], t: &str| {
        content.push_str(t);
        for &i in open {
            elements[i].text.push_str(t);
        }
    };
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Start(e)) => {
                elements.push(element(&e, &open));
                open.push(elements.len() - 1);
            }
            Ok(Event::Empty(e)) => elements.push(element(&e, &open)),
            Ok(Event::End(e)) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).expect("a UTF-8 name");
                let opened = open.pop().map(|i| elements[i].name.as_str());
                assert_eq!(opened, Some(name.as_str()), "end tag");
            }
            Ok(Event::Text(t)) => {
                let t = t.decode().expect("text decodes").into_owned();
                add_text(&mut elements, &open, &t);
            }
            Ok(Event::GeneralRef(r)) => {
                let name = r.decode().expect("entity decodes");
                let c = match name.as_ref() {
                    "amp" => "&",
                    "lt" => "<",
                    "gt" => ">",
                    "quot" => "\"",
                    "apos" => "'",
                    other => panic!("entity &{other}; is not XML's"),
                };
                add_text(&mut elements, &open, c);
            }
            Ok(_) => {}
            Err(e) => panic!("not well-formed at {}: {e}", reader.buffer_position()),
        }
    }
    assert!(open.is_empty(), "unclosed elements");
    (elements, content)
}
