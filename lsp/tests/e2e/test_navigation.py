"""Hover, go to definition, references and document highlight on one file."""

from lsprotocol import types

from conftest import Doc, line_of


def text_of(hover: types.Hover | None) -> str:
    assert hover is not None, "no hover"
    contents = hover.contents
    if isinstance(contents, types.MarkupContent):
        return contents.value
    if isinstance(contents, str):
        return contents
    if isinstance(contents, list):
        return "\n".join(c if isinstance(c, str) else c.value for c in contents)
    return contents.value


async def hover(client, doc: Doc, needle: str, nth: int = 0, offset: int = 0) -> types.Hover:
    await doc.diagnostics()
    return await client.text_document_hover_async(
        types.HoverParams(text_document=doc.id(), position=doc.at(needle, nth, offset))
    )


async def test_hover_on_a_mnemonic_gives_its_signature_and_summary(client, main: Doc):
    h = await hover(client, main, "MOVW   16#0E01", offset=1)
    text = text_of(h)
    assert "MOVW" in text
    assert "IN" in text and "OUT" in text, "the operands with their roles"
    assert "WORD" in text.upper() or "INT" in text.upper(), "the operands' types"
    assert h.range is None or h.range.start == main.at("MOVW   16#0E01")


async def test_hover_on_an_address_gives_area_width_and_modbus(client, main: Doc):
    text = text_of(await hover(client, main, "MW20", offset=1))
    assert "MW20" in text
    assert "Modbus" in text or "modbus" in text


async def test_hover_on_an_address_names_the_symbol_for_it(client, main: Doc):
    main.replace("=      M0.0", "=      Q0.0")
    text = text_of(await hover(client, main, "=      Q0.0", offset=8))
    assert "Lamp" in text, "Q0.0 is named Lamp in SYMBOLS"


async def test_hover_on_a_symbol_gives_address_type_and_comment(client, main: Doc):
    text = text_of(await hover(client, main, "CALL   ADD3, Count", offset=len("CALL   ADD3, ")))
    assert "MW10" in text
    assert "INT" in text
    assert "flashes" in text


async def test_hover_on_a_block_gives_its_interface(client, main: Doc):
    text = text_of(await hover(client, main, "CALL   ADD3", offset=8))
    assert "SBR0" in text
    for part in ["a", "b", "r", "INT"]:
        assert part in text
    assert "VAR_INPUT" in text or "input" in text.lower()


async def test_hover_on_a_local(client, main: Doc):
    text = text_of(await hover(client, main, "MOVW   #a", offset=8))
    assert "INT" in text


async def definition(client, doc: Doc, needle: str, nth: int = 0, offset: int = 0):
    await doc.diagnostics()
    result = await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc.id(), position=doc.at(needle, nth, offset))
    )
    assert result, f"no definition for {needle}"
    first = result[0] if isinstance(result, list) else result
    if isinstance(first, types.LocationLink):
        return first.target_uri, first.target_selection_range
    return first.uri, first.range


async def test_definition_of_a_symbol(client, main: Doc):
    uri, range_ = await definition(client, main, "LD     Start", offset=8)
    assert uri == main.uri
    assert range_.start.line == line_of(main.text, "Start   : I0.0")


async def test_definition_of_a_block(client, main: Doc):
    uri, range_ = await definition(client, main, "CALL   ADD3", offset=8)
    assert uri == main.uri
    assert range_.start.line == line_of(main.text, "SUBROUTINE_BLOCK ADD3")


async def test_definition_of_a_local(client, main: Doc):
    _, range_ = await definition(client, main, "+I     #b", offset=8)
    assert range_.start.line == line_of(main.text, "  b : INT;")


async def test_definition_of_a_label(client, main: Doc):
    _, range_ = await definition(client, main, "JMP    1", offset=7)
    assert range_.start.line == line_of(main.text, "LBL    1")


async def test_references_of_a_symbol(client, main: Doc):
    await main.diagnostics()
    result = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=main.id(),
            position=main.at("LD     Start", offset=8),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    lines = sorted(loc.range.start.line for loc in result)
    assert lines == [line_of(main.text, "Start   : I0.0"), line_of(main.text, "LD     Start")]
    assert all(loc.uri == main.uri for loc in result)


async def test_references_of_a_local(client, main: Doc):
    await main.diagnostics()
    result = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=main.id(),
            position=main.at("  r : INT;", offset=2),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    lines = sorted(loc.range.start.line for loc in result)
    assert lines == [
        line_of(main.text, "  r : INT;"),
        line_of(main.text, "MOVW   #a, #r"),
        line_of(main.text, "+I     #b, #r"),
    ]


async def test_document_highlight(client, main: Doc):
    await main.diagnostics()
    result = await client.text_document_document_highlight_async(
        types.DocumentHighlightParams(
            text_document=main.id(), position=main.at("=      Lamp", offset=8)
        )
    )
    starts = sorted((h.range.start.line, h.range.start.character) for h in result)
    assert starts == [
        (line_of(main.text, "Lamp    : Q0.0"), 2),
        (line_of(main.text, "=      Lamp"), 7),
    ]


async def test_nothing_to_find_is_an_empty_answer(client, main: Doc):
    await main.diagnostics()
    position = main.at("// main.lad", offset=5)  # inside a comment
    h = await client.text_document_hover_async(
        types.HoverParams(text_document=main.id(), position=position)
    )
    assert h is None
    d = await client.text_document_definition_async(
        types.DefinitionParams(text_document=main.id(), position=position)
    )
    assert not d
