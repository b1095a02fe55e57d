"""Malformed and unknown requests get LSP errors and the server lives on; requests
about unknown documents or impossible positions do not kill it either."""

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException

from conftest import Doc, raw_request


async def alive(client, doc: Doc):
    """The server still answers: a hover request gets a response (any), and a change
    gets its diagnostics."""
    try:
        await client.text_document_hover_async(
            types.HoverParams(text_document=doc.id(), position=doc.at("LD     Start", offset=8))
        )
    except JsonRpcException:
        pass  # an error is an answer too
    doc.replace("LD     Start", "LD     Strat")
    assert [d.code for d in await doc.diagnostics()] == ["E0202"]


async def test_malformed_params_get_invalid_params(client, main: Doc):
    await main.diagnostics()
    with pytest.raises(JsonRpcException) as error:
        await raw_request(client, "textDocument/hover", {"textDocument": 5, "position": "nowhere"})
    assert error.value.code == -32602, error.value  # InvalidParams
    await alive(client, main)


async def test_unknown_methods_get_method_not_found(client, main: Doc):
    await main.diagnostics()
    with pytest.raises(JsonRpcException) as error:
        await raw_request(client, "gutta/noSuchThing", {})
    assert error.value.code == -32601, error.value  # MethodNotFound
    client.protocol.notify("gutta/noSuchNotification", {"x": 1})
    await alive(client, main)


async def test_requests_about_unopened_documents_and_far_positions(client, main: Doc):
    await main.diagnostics()
    nowhere = types.TextDocumentIdentifier(uri=main.uri.replace("main.lad", "absent.lad"))
    for document, position in [
        (nowhere, types.Position(line=0, character=0)),
        (main.id(), types.Position(line=100000, character=3)),
        (main.id(), types.Position(line=3, character=100000)),
    ]:
        try:
            await client.text_document_hover_async(
                types.HoverParams(text_document=document, position=position)
            )
            await client.text_document_definition_async(
                types.DefinitionParams(text_document=document, position=position)
            )
        except JsonRpcException:
            pass  # an error answer is fine: the point is that an answer comes
    await alive(client, main)


async def test_a_change_out_of_range_does_not_kill_the_server(client, main: Doc):
    await main.diagnostics()
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=main.uri, version=99),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(
                        start=types.Position(line=5000, character=0),
                        end=types.Position(line=5001, character=0),
                    ),
                    text="junk",
                )
            ],
        )
    )
    # Whatever the server made of it, it still answers and reports on a fresh document.
    fresh = main.text
    main.change([types.TextDocumentContentChangeWholeDocument(text=fresh)])
    assert await main.diagnostics() == []
    await alive(client, main)
