"""Fixtures of the end-to-end suite: a pytest-lsp client talking to the real `gutta-lsp`
binary over stdio, and helpers that open documents and find positions by text. The
binary is $GUTTA_LSP (lsp/tests/pytest_e2e.rs passes CARGO_BIN_EXE_gutta-lsp), else
target/debug/gutta-lsp. This file holds no test."""

from __future__ import annotations

import asyncio
import concurrent.futures
import os
import pathlib
import shutil
import uuid

import pytest
import pytest_lsp
from lsprotocol import types
from pygls.protocol.json_rpc import JsonRPCRequestMessage
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

HERE = pathlib.Path(__file__).parent
DATA = HERE / "data"
REPO = HERE.parents[2]
SERVER = os.environ.get("GUTTA_LSP") or str(REPO / "target" / "debug" / "gutta-lsp")
TIMEOUT = 10.0


def position(text: str, needle: str, nth: int = 0, offset: int = 0) -> types.Position:
    """The LSP position (UTF-16 columns) of the `nth` occurrence of `needle` in `text`,
    moved `offset` characters right."""
    index = -1
    for _ in range(nth + 1):
        index = text.index(needle, index + 1)
    index += offset
    line = text.count("\n", 0, index)
    start = text.rfind("\n", 0, index) + 1
    return types.Position(line=line, character=len(text[start:index].encode("utf-16-le")) // 2)


def line_of(text: str, needle: str, nth: int = 0) -> int:
    return position(text, needle, nth).line


def apply_edits(text: str, edits: list[types.TextEdit]) -> str:
    """`text` with `edits` applied (non-overlapping, any order), positions in UTF-16."""
    lines = text.split("\n")

    def offset(p: types.Position) -> int:
        before = sum(len(line) + 1 for line in lines[: p.line])
        line = lines[p.line] if p.line < len(lines) else ""
        units = line.encode("utf-16-le")[: 2 * p.character]
        return before + len(units.decode("utf-16-le"))

    spans = sorted(
        ((offset(e.range.start), offset(e.range.end), e.new_text) for e in edits),
        reverse=True,
    )
    for start, end, new in spans:
        text = text[:start] + new + text[end:]
    return text


class Doc:
    """An open document: its URI, text and version."""

    def __init__(self, client: LanguageClient, path: pathlib.Path, text: str):
        self.client = client
        self.path = path
        self.uri = path.resolve().as_uri()
        self.text = text
        self.version = 1

    def id(self) -> types.TextDocumentIdentifier:
        return types.TextDocumentIdentifier(uri=self.uri)

    def at(self, needle: str, nth: int = 0, offset: int = 0) -> types.Position:
        return position(self.text, needle, nth, offset)

    def change(self, changes: list) -> None:
        """Send `changes` (full or incremental) and keep the text in step."""
        for change in changes:
            if isinstance(change, types.TextDocumentContentChangeWholeDocument):
                self.text = change.text
            else:
                self.text = apply_edits(
                    self.text, [types.TextEdit(range=change.range, new_text=change.text)]
                )
        self.version += 1
        self.client.diagnostics.pop(self.uri, None)
        self.client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(
                    uri=self.uri, version=self.version
                ),
                content_changes=changes,
            )
        )

    def replace(self, old: str, new: str, nth: int = 0) -> None:
        """An incremental change: the `nth` `old` becomes `new`."""
        start = self.at(old, nth)
        end = self.at(old, nth, len(old))
        self.change(
            [
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=start, end=end), text=new
                )
            ]
        )

    async def diagnostics(self) -> list[types.Diagnostic]:
        """The diagnostics published for this document since it was opened or last
        changed (waits for them)."""
        return await diagnostics_of(self.client, self.uri)


async def diagnostics_of(client: LanguageClient, uri: str) -> list[types.Diagnostic]:
    async def wait():
        while uri not in client.diagnostics:
            await asyncio.sleep(0.01)
        return list(client.diagnostics[uri])

    return await asyncio.wait_for(wait(), TIMEOUT)


def open_doc(
    client: LanguageClient, path: pathlib.Path, text: str | None = None
) -> Doc:
    doc = Doc(client, path, path.read_text() if text is None else text)
    client.diagnostics.pop(doc.uri, None)
    language = "csv" if path.suffix == ".csv" else "gutta-lad"
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri=doc.uri, language_id=language, version=doc.version, text=doc.text
            )
        )
    )
    return doc


@pytest.fixture
def workdir(tmp_path: pathlib.Path) -> pathlib.Path:
    """A copy of data/ in a fresh folder (tests may write files there)."""
    target = tmp_path / "data"
    shutil.copytree(DATA, target)
    return target


def capabilities() -> types.ClientCapabilities:
    """VS Code's capabilities as pytest-lsp records them (1.65), plus what later
    versions added and the server uses: inlay hints and inline values with refresh."""
    caps = client_capabilities("visual-studio-code")
    caps.text_document.inlay_hint = types.InlayHintClientCapabilities()
    caps.text_document.inline_value = types.InlineValueClientCapabilities()
    caps.workspace.inlay_hint = types.InlayHintWorkspaceClientCapabilities(refresh_support=True)
    caps.workspace.inline_value = types.InlineValueWorkspaceClientCapabilities(
        refresh_support=True
    )
    return caps


def initialize_params(root: pathlib.Path | None, options=None) -> types.InitializeParams:
    return types.InitializeParams(
        capabilities=capabilities(),
        root_uri=root.as_uri() if root else None,
        workspace_folders=(
            [types.WorkspaceFolder(uri=root.as_uri(), name=root.name)] if root else None
        ),
        initialization_options=options,
    )


def client_features(client: LanguageClient) -> None:
    """Answer the requests a server sends its client as VS Code does: refreshes
    (counted in `client.refreshes`) and capability registrations (kept in
    `client.registrations`, by id)."""
    client.refreshes = {"inlayHint": 0, "inlineValue": 0, "semanticTokens": 0}
    client.registrations = {}

    @client.feature(types.CLIENT_REGISTER_CAPABILITY)
    def register_capability(params: types.RegistrationParams):
        for registration in params.registrations:
            client.registrations[registration.id] = registration

    @client.feature(types.CLIENT_UNREGISTER_CAPABILITY)
    def unregister_capability(params: types.UnregistrationParams):
        for gone in params.unregisterations:
            client.registrations.pop(gone.id, None)

    @client.feature(types.WORKSPACE_INLAY_HINT_REFRESH)
    def inlay_hint_refresh(params):
        client.refreshes["inlayHint"] += 1

    @client.feature(types.WORKSPACE_INLINE_VALUE_REFRESH)
    def inline_value_refresh(params):
        client.refreshes["inlineValue"] += 1

    @client.feature(types.WORKSPACE_SEMANTIC_TOKENS_REFRESH)
    def semantic_tokens_refresh(params):
        client.refreshes["semanticTokens"] += 1


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[SERVER]))
async def client(lsp_client: LanguageClient, workdir: pathlib.Path):
    """A client initialised like VS Code with `workdir` as the workspace."""
    client_features(lsp_client)
    lsp_client.initialize_result = await lsp_client.initialize_session(
        initialize_params(workdir)
    )
    yield
    await lsp_client.shutdown_session()


@pytest.fixture
def main(client: LanguageClient, workdir: pathlib.Path) -> Doc:
    """data/main.lad, open."""
    return open_doc(client, workdir / "main.lad")


def edits_for(edit: types.WorkspaceEdit | None, uri: str) -> list[types.TextEdit]:
    """The text edits a workspace edit makes to `uri` (from `changes` or
    `documentChanges`)."""
    if edit is None:
        return []
    found: list[types.TextEdit] = []
    for changed, edits in (edit.changes or {}).items():
        if changed == uri:
            found.extend(edits)
    for change in edit.document_changes or []:
        if isinstance(change, types.TextDocumentEdit) and change.text_document.uri == uri:
            found.extend(e for e in change.edits if isinstance(e, types.TextEdit))
    return found


def edited_uris(edit: types.WorkspaceEdit | None) -> set[str]:
    if edit is None:
        return set()
    uris = set((edit.changes or {}).keys())
    for change in edit.document_changes or []:
        if isinstance(change, types.TextDocumentEdit):
            uris.add(change.text_document.uri)
    return uris


def raw_request(client: LanguageClient, method: str, params) -> asyncio.Future:
    """Send a request whose params are sent as given, not checked against the LSP
    types (pygls would refuse to send malformed ones); its answer or error."""
    protocol = client.protocol
    msg_id = str(uuid.uuid4())
    future: concurrent.futures.Future = concurrent.futures.Future()
    protocol._request_futures[msg_id] = future
    protocol._result_types[msg_id] = None
    protocol._send_data(
        JsonRPCRequestMessage(id=msg_id, method=method, params=params, jsonrpc="2.0")
    )
    return asyncio.wrap_future(future)
