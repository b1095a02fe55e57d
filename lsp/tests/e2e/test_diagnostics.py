"""Initialize, diagnostics after open and after full and incremental changes, with
code, severity, source, a link to the code's explanation and related locations."""

from lsprotocol import types

from conftest import Doc, line_of, open_doc

# Every capability the issue asks for, as lsprotocol names it.
FEATURES = [
    "hover_provider",
    "definition_provider",
    "references_provider",
    "document_highlight_provider",
    "document_symbol_provider",
    "workspace_symbol_provider",
    "completion_provider",
    "signature_help_provider",
    "rename_provider",
    "code_action_provider",
    "document_formatting_provider",
    "folding_range_provider",
    "semantic_tokens_provider",
    "inlay_hint_provider",
]


async def test_initialize_names_the_server_and_every_feature(client):
    result = client.initialize_result
    assert result.server_info.name == "gutta-lsp"
    caps = result.capabilities
    sync = caps.text_document_sync
    change = sync.change if isinstance(sync, types.TextDocumentSyncOptions) else sync
    assert change == types.TextDocumentSyncKind.Incremental
    missing = [name for name in FEATURES if getattr(caps, name) in (None, False)]
    assert missing == [], "not offered"


async def test_a_clean_file_publishes_an_empty_list(client, main: Doc):
    assert await main.diagnostics() == []


async def test_a_mistake_has_code_severity_source_and_a_link(client, workdir):
    text = (workdir / "main.lad").read_text().replace("LD     Start", "LD     Strat")
    doc = open_doc(client, workdir / "mistake.lad", text)
    diagnostics = await doc.diagnostics()
    assert [d.code for d in diagnostics] == ["E0202"]
    d = diagnostics[0]
    assert d.severity == types.DiagnosticSeverity.Error
    assert d.source == "gutta"
    assert "Strat" in d.message
    assert "Start" in d.message, "the did-you-mean help is part of the message"
    assert d.range.start == doc.at("Strat")
    assert d.range.end == doc.at("Strat", offset=len("Strat"))
    assert d.code_description is not None, "a link to the code's explanation"
    assert "e0202" in d.code_description.href.lower()


async def test_secondary_labels_are_related_information(client, workdir):
    text = (workdir / "main.lad").read_text().replace(
        "  Lamp    : Q0.0", "  Start   : Q0.1\n  Lamp    : Q0.0"
    )
    doc = open_doc(client, workdir / "twice.lad", text)
    diagnostics = await doc.diagnostics()
    assert [d.code for d in diagnostics] == ["E0203"]
    related = diagnostics[0].related_information
    assert related, "E0203 shows the first declaration"
    assert related[0].location.uri == doc.uri
    assert related[0].location.range.start.line == line_of(doc.text, "Start   : I0.0")
    assert diagnostics[0].range.start.line == line_of(doc.text, "Start   : Q0.1")


async def test_diagnostics_follow_incremental_changes(client, main: Doc):
    assert await main.diagnostics() == []
    main.replace("LD     SM0.5", "LDX    SM0.5")
    assert [d.code for d in await main.diagnostics()] == ["E0201"]
    main.replace("LDX", "LD ")
    assert await main.diagnostics() == []


async def test_diagnostics_follow_full_changes(client, main: Doc):
    assert await main.diagnostics() == []
    broken = main.text.replace("END_SUBROUTINE_BLOCK\n", "")
    main.change([types.TextDocumentContentChangeWholeDocument(text=broken)])
    codes = [d.code for d in await main.diagnostics()]
    assert "E0105" in codes, codes


async def test_incremental_changes_count_utf16_columns(client, workdir):
    text = (workdir / "main.lad").read_text().replace(
        "// push button", "// 按钮 🔘 push button"
    )
    doc = open_doc(client, workdir / "wide.lad", text)
    assert await doc.diagnostics() == []
    # After the emoji (two UTF-16 units) on the same line: `// x` stays a comment only if
    # the server counts columns in UTF-16.
    doc.replace("push button", "push-button")
    assert await doc.diagnostics() == []
    doc.replace("🔘 ", "🔘 Q ")
    assert await doc.diagnostics() == []
    assert "// 按钮 🔘 Q push-button" in doc.text
    doc.replace("  Lamp    : Q0.0", "  Lamp    : Q9.9")
    codes = [d.code for d in await doc.diagnostics()]
    assert codes and all(c.startswith("E") for c in codes), codes
