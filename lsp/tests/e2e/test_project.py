"""A project (gutta.toml) of two .lad files and a CSV symbol table: one program across
the files, navigation into the other file and the table, diagnostics republished for a
file when another changes, diagnostics in the table."""

import asyncio
import pathlib

import pytest
from lsprotocol import types

from conftest import apply_edits, edited_uris, edits_for, line_of, open_doc


@pytest.fixture
def project(workdir) -> pathlib.Path:
    return workdir / "project"


async def test_a_file_of_a_project_sees_the_other_files_and_the_table(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    assert await a.diagnostics() == [], "Lamp and Level from symbols.csv, FILLUP from b.lad"


async def test_definition_reaches_the_other_file_and_the_table_row(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    await a.diagnostics()
    b_text = (project / "src" / "b.lad").read_text()

    result = await client.text_document_definition_async(
        types.DefinitionParams(text_document=a.id(), position=a.at("CALL   FILLUP", offset=8))
    )
    location = result[0] if isinstance(result, list) else result
    assert location.uri == (project / "src" / "b.lad").resolve().as_uri()
    assert location.range.start.line == line_of(b_text, "SUBROUTINE_BLOCK FILLUP")

    result = await client.text_document_definition_async(
        types.DefinitionParams(text_document=a.id(), position=a.at("=      Lamp", offset=8))
    )
    location = result[0] if isinstance(result, list) else result
    assert location.uri == (project / "symbols.csv").resolve().as_uri()
    assert location.range.start.line == 1, "the row of Lamp"


async def test_hover_on_a_table_symbol(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    await a.diagnostics()
    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=a.id(), position=a.at("FILLUP, Level", offset=9))
    )
    text = hover.contents.value if isinstance(hover.contents, types.MarkupContent) else str(hover.contents)
    assert "MW4" in text and "tank level" in text
    assert "symbols.csv" in text, "where it is declared"


async def test_a_change_in_one_file_republishes_the_others(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    assert await a.diagnostics() == []
    b = open_doc(client, project / "src" / "b.lad")
    assert await b.diagnostics() == []
    client.diagnostics.pop(a.uri, None)
    b.replace("FILLUP", "FILLIN")
    assert [d.code for d in await b.diagnostics()] == ["W0203"], "FILLIN is never called"
    codes = [d.code for d in await a.diagnostics()]
    assert codes == ["E0206"], "a.lad calls a block that is gone"
    client.diagnostics.pop(a.uri, None)
    b.replace("FILLIN", "FILLUP")
    assert await a.diagnostics() == []
    # What a.lad shows depends on b.lad: the server asks for its tokens and hints again.
    for _ in range(100):
        if client.refreshes["semanticTokens"] and client.refreshes["inlayHint"]:
            break
        await asyncio.sleep(0.02)
    assert client.refreshes["semanticTokens"] > 0, client.refreshes
    assert client.refreshes["inlayHint"] > 0, client.refreshes


async def test_open_text_wins_over_the_disk(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    await a.diagnostics()
    b = open_doc(client, project / "src" / "b.lad")
    await b.diagnostics()
    client.diagnostics.pop(a.uri, None)
    b.replace("+I     #level, MW30", "+I     #level, MW30\nLD     Lamp2")
    assert [d.code for d in await b.diagnostics()] == ["E0202"]
    assert (project / "src" / "b.lad").read_text().count("Lamp2") == 0


async def test_references_and_rename_reach_the_table(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    await a.diagnostics()
    position = a.at("FILLUP, Level", offset=9)
    csv_uri = (project / "symbols.csv").resolve().as_uri()
    refs = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=a.id(), position=position,
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    assert {r.uri for r in refs} == {a.uri, csv_uri}
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=a.id(), position=position, new_name="Height")
    )
    assert edited_uris(edit) == {a.uri, csv_uri}
    csv = (project / "symbols.csv").read_text()
    assert "Height,MW4,tank level" in apply_edits(csv, edits_for(edit, csv_uri))
    assert "CALL   FILLUP, Height" in apply_edits(a.text, edits_for(edit, a.uri))


async def test_a_symbol_table_gets_its_own_diagnostics(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    await a.diagnostics()
    table = open_doc(client, project / "symbols.csv")
    assert await table.diagnostics() == []
    table.replace("Level,MW4,tank level", "Level,MW4,tank level\nBad Name,MW6,x")
    codes = [d.code for d in await table.diagnostics()]
    assert codes == ["E0114"], codes


async def test_a_file_changed_on_disk_is_read_again(client, project):
    a = open_doc(client, project / "src" / "a.lad")
    assert await a.diagnostics() == []
    watchers = [
        r for r in client.registrations.values()
        if r.method == types.WORKSPACE_DID_CHANGE_WATCHED_FILES
    ]
    assert watchers, "the server asks to watch the project's files"
    b = project / "src" / "b.lad"
    b.write_text(b.read_text().replace("FILLUP", "FILLIN"))
    client.diagnostics.pop(a.uri, None)
    client.workspace_did_change_watched_files(
        types.DidChangeWatchedFilesParams(
            changes=[types.FileEvent(uri=b.resolve().as_uri(), type=types.FileChangeType.Changed)]
        )
    )
    assert [d.code for d in await a.diagnostics()] == ["E0206"], "a.lad calls a block gone from disk"
