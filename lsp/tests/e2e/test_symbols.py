"""Document symbols (blocks with their networks, SYMBOLS, data and system blocks) and
workspace symbols."""

from lsprotocol import types

from conftest import Doc, line_of


def flatten(symbols, depth=0):
    for s in symbols or []:
        yield depth, s
        yield from flatten(getattr(s, "children", None), depth + 1)


async def test_document_symbols_show_blocks_networks_and_sections(client, main: Doc):
    await main.diagnostics()
    result = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=main.id())
    )
    assert result and isinstance(result[0], types.DocumentSymbol), "hierarchical symbols"
    top = {s.name: s for s in result}
    assert any("MAIN" in name for name in top), list(top)
    assert any("ADD3" in name for name in top), list(top)
    assert any("TABLE1" in name for name in top), list(top)
    main_block = next(s for name, s in top.items() if "MAIN" in name)
    assert main_block.range.start.line == line_of(main.text, "ORGANIZATION_BLOCK")
    assert main_block.range.end.line >= line_of(main.text, "END_ORGANIZATION_BLOCK") - 1
    networks = [c.name + " " + (c.detail or "") for c in main_block.children or []]
    assert len([n for n in networks if "1" in n or "2" in n or "3" in n]) >= 3, networks
    assert any("latch" in n for n in networks), "a network shows its title"
    names = [s.name for _, s in flatten(result)]
    assert any("Start" in n for n in names), "the SYMBOLS section's symbols"
    assert any("SYSTEM" in n.upper() for n in names), "the system block"


async def test_workspace_symbols_find_blocks_and_symbols_fuzzily(client, main: Doc):
    await main.diagnostics()
    result = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="add"))
    names = [s.name for s in result]
    assert any("ADD3" in n for n in names), names
    hit = next(s for s in result if "ADD3" in s.name)
    assert hit.location.uri == main.uri
    result = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="lmp"))
    assert any("Lamp" in s.name for s in result), "fuzzy: l-m-p finds Lamp"
