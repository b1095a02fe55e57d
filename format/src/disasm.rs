//! The disassembler: an image's pages back to `.lad` text that compiles to the same
//! pages (docs/image-format.md, "Disassembly"), in one of two layouts ([`Format`]):
//! the toolchain's own STL, or a STEP 7-Micro/WIN STL export (`awl.rs`, docs/microwin.md).
//! It prints what the bytes say, by the target's names, and never panics on any bytes; it does not judge whether the image
//! is valid (that is the verifier's job), so the text of an image that fails
//! verification may not compile.
//!
//! **Errors.** Whatever cannot be printed faithfully (text that would compile to other
//! bytes, or to none) becomes a `// cannot decode ...` comment in the text and a
//! [`DisasmError`] naming the page and byte; everything else is still printed.
//! [`disassemble_with_errors`] returns the text with every error (for `gutta-cc dis`,
//! which prints the text and the errors); [`disassemble`] is the strict form: the text
//! only when there is no error, else the first one. Image-level problems (a missing
//! const page, a PLC type other than the target's) are errors with no page or with the
//! page that is missing; they do not stop the output either.

mod awl;
mod data;
mod operands;
mod units;

use std::collections::BTreeSet;
use std::fmt;

use gutta_catalog::{plural, AreaKind, Target};

use crate::{Image, PageId, PageKind};

/// Where and why part of an image cannot be printed as source text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisasmError {
    /// The page concerned; `None` for a problem of the image as a whole.
    pub page: Option<PageId>,
    /// Byte offset in the page (0 for a missing page or an image-level problem).
    pub offset: usize,
    pub reason: String,
}

impl fmt::Display for DisasmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.page {
            Some(p) => write!(
                f,
                "{} at byte {}: {}",
                p.file_name(),
                self.offset,
                self.reason
            ),
            None => write!(f, "image: {}", self.reason),
        }
    }
}

impl std::error::Error for DisasmError {}

/// The text of an image and everything in it that could not be printed faithfully.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Disassembly {
    /// `.lad` source; undecodable parts are `// cannot decode ...` comments.
    pub text: String,
    /// In the order of the text (the const page's coverage last); empty when every
    /// byte was printed faithfully.
    pub errors: Vec<DisasmError>,
}

/// The layout of the text: both compile back to the same pages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// The toolchain's own STL (`NETWORK n`, a `// step n` comment on every step, LF).
    #[default]
    Stl,
    /// A STEP 7-Micro/WIN STL export (`Network n`, `TITLE=`, `SBR_n:SBRn` block names,
    /// Micro/WIN's VAR lines, CRLF), data and system blocks after the program.
    Awl,
}

/// The image as `.lad` text, or the first thing that cannot be printed faithfully.
pub fn disassemble(image: &Image, target: &Target) -> Result<String, DisasmError> {
    let d = disassemble_with_errors(image, target);
    match d.errors.into_iter().next() {
        Some(e) => Err(e),
        None => Ok(d.text),
    }
}

/// The image as `.lad` text, with comments and errors for what does not decode.
pub fn disassemble_with_errors(image: &Image, target: &Target) -> Disassembly {
    disassemble_as(image, target, Format::Stl)
}

/// [`disassemble_with_errors`] in the chosen layout.
pub fn disassemble_as(image: &Image, target: &Target, format: Format) -> Disassembly {
    let mut d = Disassembler::new(image, target, format);
    d.run();
    Disassembly {
        text: d.out,
        errors: d.errors,
    }
}

/// Printing state: the output so far, the errors, and the const page's coverage.
struct Disassembler<'a> {
    image: &'a Image,
    target: &'a Target,
    format: Format,
    out: String,
    errors: Vec<DisasmError>,
    /// The const page (empty if missing).
    consts: &'a [u8],
    /// Which const page bytes a printed constant stands for.
    const_used: Vec<bool>,
}

/// Printable form of a text from the image (the PLC type) inside a `//` comment.
fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

impl<'a> Disassembler<'a> {
    fn new(image: &'a Image, target: &'a Target, format: Format) -> Disassembler<'a> {
        let consts = image.page(PageKind::Const, 0).unwrap_or(&[]);
        Disassembler {
            image,
            target,
            format,
            out: String::new(),
            errors: Vec::new(),
            consts,
            const_used: vec![false; consts.len()],
        }
    }

    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push_str(match self.format {
            Format::Stl => "\n",
            Format::Awl => "\r\n",
        });
    }

    fn error(&mut self, page: Option<PageId>, offset: usize, reason: impl Into<String>) {
        self.errors.push(DisasmError {
            page,
            offset,
            reason: reason.into(),
        });
    }

    /// A comment in place of what cannot be printed, and its error.
    fn cannot_decode(
        &mut self,
        indent: &str,
        what: &str,
        page: PageId,
        offset: usize,
        reason: &str,
    ) {
        self.line(&format!(
            "{indent}// cannot decode {what} ({} at byte {offset}): {}",
            page.file_name(),
            one_line(reason)
        ));
        self.error(Some(page), offset, reason);
    }

    fn run(&mut self) {
        let image = self.image;
        let name = self.target.name().to_string();
        let header = match self.format {
            Format::Stl => "gutta-cc dis",
            Format::Awl => "gutta-cc dis --format awl (STEP 7-Micro/WIN layout)",
        };
        self.line(&format!(
            "// Disassembly of an image for {}, produced by {header}",
            one_line(&image.plc_type)
        ));
        if !image.plc_type.eq_ignore_ascii_case(&name) {
            self.error(
                None,
                0,
                format!(
                    "the image is for PLC type `{}`, disassembled as {name}",
                    one_line(&image.plc_type)
                ),
            );
        }
        if self.format == Format::Awl {
            // compiler::source::GUTTA_BOXES: timer boxes as on GUTTA.
            self.line("// timer-boxes: gutta");
        }
        self.line(&format!("PLC_TYPE {name}"));
        if image.page(PageKind::Const, 0).is_none() {
            self.error(
                Some(PageId::new(PageKind::Const, 0)),
                0,
                "the image has no const page",
            );
        }
        let units: BTreeSet<u8> = image
            .pages
            .keys()
            .filter(|id| matches!(id.kind, PageKind::Argument | PageKind::Instruction))
            .map(|id| id.number)
            .collect();
        for number in units {
            if self.format == Format::Stl {
                self.line("");
            }
            self.unit(number);
        }
        let data: Vec<(PageId, &[u8])> = image
            .pages
            .iter()
            .filter(|(id, _)| matches!(id.kind, PageKind::Data | PageKind::System))
            .map(|(id, b)| (*id, b.as_slice()))
            .collect();
        if self.format == Format::Awl && !data.is_empty() {
            self.awl_data_note();
        }
        for (id, bytes) in data {
            self.line("");
            match id.kind {
                PageKind::Data => self.data_page(id, bytes),
                _ => self.system_page(id, bytes),
            }
        }
        self.const_coverage();
    }

    /// Every byte of the const page must be some printed constant's, or compiling the
    /// text gives a shorter or different const page.
    fn const_coverage(&mut self) {
        if let Some(first) = self.const_used.iter().position(|used| !used) {
            let k = self
                .target
                .memory
                .area_of_kind(AreaKind::Constant)
                .map(|a| a.name.clone())
                .unwrap_or_else(|| "K".to_string());
            let unused = self.const_used.iter().filter(|u| !**u).count();
            self.error(
                Some(PageId::new(PageKind::Const, 0)),
                first,
                format!(
                    "{} of the const page, the first {k}B{first}, {} no printed constant's value",
                    plural::count(unused, "byte"),
                    if unused == 1 { "is" } else { "are" }
                ),
            );
        }
    }
}
