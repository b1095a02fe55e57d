//! `gutta-cc explain CODE`: every code the tools print, read from its registry: E and W
//! (the compiler's `Code`), V (`gutta_format::VerifyCode`, with its longer meaning from
//! docs/image-format.md's table row), T (`CatalogErrorCode`, the registry
//! docs/diagnostics.md's table is generated from), L (`gutta_ladder::json::ModelErrorCode`,
//! a ladder model read from JSON), P (`gutta_io::PlantErrorCode`, a plant file of
//! `gutta-sim --plant`). It keeps no list of codes or texts of its own.

use gutta_catalog::CatalogErrorCode;
use gutta_compiler::diagnostics::Code;
use gutta_compiler::suggest::closest;
use gutta_format::VerifyCode;
use gutta_io::PlantErrorCode;
use gutta_ladder::json::ModelErrorCode;

/// docs/image-format.md: its Verification table has one row per V code.
const IMAGE_FORMAT_DOC: &str = include_str!("../../../../docs/image-format.md");

/// The text `explain` prints for `code` (any case), or why there is none.
pub(crate) fn explanation(code: &str) -> Result<String, String> {
    let wanted = code.trim();
    if let Some(c) = Code::parse(wanted) {
        return Ok(format!(
            "{} ({}): {}\n\n{}",
            c.as_str(),
            c.severity().as_str(),
            c.title(),
            c.explanation()
        ));
    }
    let same = |name: &str| name.eq_ignore_ascii_case(wanted);
    if let Some(v) = VerifyCode::ALL.iter().find(|v| same(v.as_str())) {
        return Ok(with_doc_row(
            format!(
                "{v} (image verification: the image is refused): {}",
                v.summary()
            ),
            IMAGE_FORMAT_DOC,
            v.as_str(),
            "docs/image-format.md, Verification",
        ));
    }
    if let Some(t) = CatalogErrorCode::ALL.iter().find(|t| same(t.as_str())) {
        return Ok(format!(
            "{} (target description files: exit status 2): {}",
            t.as_str(),
            t.summary()
        ));
    }
    if let Some(p) = PlantErrorCode::ALL.iter().find(|p| same(p.as_str())) {
        return Ok(format!(
            "{} (plant files of gutta-sim --plant: exit status 2): {}",
            p.as_str(),
            p.summary()
        ));
    }
    if let Some(l) = ModelErrorCode::parse(wanted) {
        return Ok(format!(
            "{} (ladder model: exit status 2): {}\n\n{}",
            l.as_str(),
            l.summary(),
            l.explanation()
        ));
    }
    Err(unknown(wanted))
}

/// `headline`, then the doc's table row for `code` (`| V0040 | meaning |`) when it has one.
fn with_doc_row(headline: String, doc: &str, code: &str, place: &str) -> String {
    let row_start = format!("| {code} | ");
    let meaning = doc.lines().find_map(|line| {
        line.strip_prefix(&row_start)
            .map(|rest| rest.trim_end().trim_end_matches('|').trim_end())
    });
    match meaning {
        Some(m) => format!("{headline}\n\n{m}\n\n(from {place})"),
        None => headline,
    }
}

/// Every code of every registry.
fn all_codes() -> impl Iterator<Item = &'static str> {
    Code::ALL
        .iter()
        .map(|c| c.as_str())
        .chain(VerifyCode::ALL.iter().map(|v| v.as_str()))
        .chain(CatalogErrorCode::ALL.iter().map(|t| t.as_str()))
        .chain(ModelErrorCode::ALL.iter().map(|l| l.as_str()))
        .chain(PlantErrorCode::ALL.iter().map(|p| p.as_str()))
}

/// The message for a code no registry has, with the nearest one if there is one.
fn unknown(wanted: &str) -> String {
    // `v40` is V0040 written short; otherwise the closest by edit distance.
    let padded = wanted
        .split_at_checked(1)
        .filter(|(letter, digits)| {
            letter.chars().all(|c| c.is_ascii_alphabetic())
                && !digits.is_empty()
                && digits.len() < 4
                && digits.chars().all(|c| c.is_ascii_digit())
        })
        .map(|(letter, digits)| format!("{}{digits:0>4}", letter.to_ascii_uppercase()));
    let suggestion = all_codes()
        .find(|c| padded.as_deref() == Some(*c))
        .or_else(|| closest(wanted, all_codes()));
    let known =
        "codes are E and W (compiler), V (image verification), T (target files), L (ladder models), P (plant files)";
    match suggestion {
        Some(s) => format!("no code `{wanted}` ({known}); did you mean {s}?"),
        None => format!("no code `{wanted}` ({known})"),
    }
}

/// `explain CODE`: the registry's text; an unknown code is a usage error (exit 2).
pub(crate) fn run(code: &str) -> Result<std::process::ExitCode, gutta_cli::fatal::Fatal> {
    let text = explanation(code).map_err(gutta_cli::fatal::Fatal::usage)?;
    println!("{text}");
    Ok(std::process::ExitCode::SUCCESS)
}
