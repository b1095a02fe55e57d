"""Formatting (Micro/WIN layout, idempotent, meaning kept), folding ranges, semantic
tokens and inlay hints."""

from lsprotocol import types

from conftest import Doc, apply_edits, line_of, open_doc

OPTIONS = types.FormattingOptions(tab_size=4, insert_spaces=True)


async def format_doc(client, doc: Doc) -> str:
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=doc.id(), options=OPTIONS)
    )
    return apply_edits(doc.text, edits or [])


async def test_formatting_lays_out_columns_and_is_idempotent(client, workdir):
    doc = open_doc(client, workdir / "unformatted.lad")
    assert await doc.diagnostics() == []
    formatted = await format_doc(client, doc)
    assert formatted != doc.text
    assert "LD     Start" in formatted, "mnemonics padded to 7 columns"
    assert "MOVW   16#0E01, MW20" in formatted
    assert "\t" not in formatted
    assert all(line == line.rstrip() for line in formatted.split("\n")), "no trailing blanks"
    lines = formatted.split("\n")
    network = lines[line_of(formatted, "LD     Start") : line_of(formatted, "=      M0.0") + 1]
    columns = {line.index("//") for line in network if "//" in line}
    assert len(columns) == 1, f"comments aligned within a network: {network}"
    symbols = lines[line_of(formatted, "Start") : line_of(formatted, "END_SYMBOLS")]
    assert len({line.index(":") for line in symbols}) == 1, f"colons aligned: {symbols}"

    doc.change([types.TextDocumentContentChangeWholeDocument(text=formatted)])
    assert await doc.diagnostics() == [], "formatting keeps the meaning"
    again = await format_doc(client, doc)
    assert again == formatted, "formatting a formatted file changes nothing"


async def test_formatting_main_twice_gives_the_same_text(client, main: Doc):
    await main.diagnostics()
    once = await format_doc(client, main)
    main.change([types.TextDocumentContentChangeWholeDocument(text=once)])
    await main.diagnostics()
    assert await format_doc(client, main) == once


async def test_folding_ranges_per_block_network_and_section(client, main: Doc):
    await main.diagnostics()
    ranges = await client.text_document_folding_range_async(
        types.FoldingRangeParams(text_document=main.id())
    )
    starts = {r.start_line: r for r in ranges}
    text = main.text
    for header in ["ORGANIZATION_BLOCK", "SUBROUTINE_BLOCK", "DATA_BLOCK", "SYSTEM_BLOCK", "SYMBOLS"]:
        assert line_of(text, header) in starts, f"{header} folds"
    block = starts[line_of(text, "ORGANIZATION_BLOCK")]
    assert block.end_line >= line_of(text, "END_ORGANIZATION_BLOCK") - 1
    for network in ["NETWORK 1 // latch", "NETWORK 2 // blink"]:
        assert line_of(text, network) in starts, f"{network} folds"
    first = starts[line_of(text, "NETWORK 1 // latch")]
    assert first.end_line < line_of(text, "NETWORK 2 // blink")


def decode(data: list[int]):
    line = column = 0
    for i in range(0, len(data), 5):
        delta_line, delta_start, length, kind, modifiers = data[i : i + 5]
        if delta_line:
            line += delta_line
            column = delta_start
        else:
            column += delta_start
        yield line, column, length, kind, modifiers


async def test_semantic_tokens_tell_the_kinds_apart(client, main: Doc):
    await main.diagnostics()
    provider = client.initialize_result.capabilities.semantic_tokens_provider
    legend = provider.legend
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=main.id())
    )
    assert tokens.data and len(tokens.data) % 5 == 0
    found = list(decode(tokens.data))

    def token(needle, offset=0, length=None):
        """The (type, modifiers) of the token that covers `needle`+`offset`."""
        p = main.at(needle, offset=offset)
        covering = [
            (got_length, kind, mods)
            for line, column, got_length, kind, mods in found
            if line == p.line and column <= p.character < column + got_length
        ]
        assert covering, f"no token covers `{needle}`+{offset}"
        got_length, kind, mods = covering[0]
        if length is not None:
            assert got_length == length, f"`{needle}`: length {got_length}"
        return legend.token_types[kind], mods

    mnemonic = token("MOVW   16#0E01", length=4)
    symbol = token("LD     Start", offset=7, length=5)
    local = token("MOVW   #a", offset=8)
    memory = token("16#0E01, MW20", offset=9, length=4)
    system = token("LD     SM0.5", offset=7, length=5)
    number = token("16#0E01", length=7)
    comment = token("// latch")
    assert len({mnemonic, symbol, local, memory, number, comment}) == 6, "distinct kinds"
    assert memory != system, "addresses differ by area"
    assert comment[0] == "comment"
    assert token("ORGANIZATION_BLOCK")[0] == "keyword"

    if getattr(provider, "range", None):
        ranged = await client.text_document_semantic_tokens_range_async(
            types.SemanticTokensRangeParams(
                text_document=main.id(),
                range=types.Range(
                    start=types.Position(line=line_of(main.text, "NETWORK 2"), character=0),
                    end=types.Position(line=line_of(main.text, "NETWORK 3"), character=0),
                ),
            )
        )
        lines = {line for line, *_ in decode(ranged.data)}
        assert lines and min(lines) >= line_of(main.text, "NETWORK 2")


async def test_inlay_hints_show_what_a_symbol_stands_for(client, main: Doc):
    await main.diagnostics()
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            text_document=main.id(),
            range=types.Range(
                start=types.Position(line=0, character=0),
                end=types.Position(line=len(main.text.split("\n")), character=0),
            ),
        )
    )
    assert hints

    def label(hint):
        return hint.label if isinstance(hint.label, str) else "".join(p.value for p in hint.label)

    after_start = main.at("LD     Start", offset=len("LD     Start"))
    at = [label(h) for h in hints if h.position == after_start]
    assert any("I0.0" in text for text in at), f"after `Start`: {at}"
