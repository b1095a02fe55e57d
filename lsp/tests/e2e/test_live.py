"""Live values (opt-in): with `liveValues` on, a project with a `[connection]` shows the
PLC's values after the operands, in inlay hints and inline values, refreshed while the
document is open; against a real `gutta-sim` whose program blinks Lamp, and against a
PLC that does not answer (one warning, `?` for every value). The setting, the
workspace/didChangeConfiguration section and the `gutta.toggleLiveValues` command turn
it on and off.

The simulator is $GUTTA_SIM running the image $GUTTA_E2E_IMAGE (data/live/main.lad
compiled); lsp/tests/pytest_e2e.rs sets both."""

import asyncio
import os
import pathlib
import socket
import subprocess

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

from conftest import SERVER, Doc, client_features, initialize_params, open_doc


def write_project(folder: pathlib.Path, address: str) -> None:
    (folder / "gutta.toml").write_text(
        '[program]\nplc = "CPU-EC20"\nsources = ["main.lad"]\n\n'
        f'[connection]\ntcp = "{address}"\ntimeout = 300\nretries = 0\n'
    )


def closed_port() -> str:
    """A loopback address where nothing listens."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    return f"127.0.0.1:{port}"


@pytest.fixture
def sim():
    """`gutta-sim IMAGE --tcp 127.0.0.1:0` running data/live/main.lad; its address."""
    binary, image = os.environ.get("GUTTA_SIM"), os.environ.get("GUTTA_E2E_IMAGE")
    assert binary and image, "run through `cargo test -p gutta-lsp --test pytest_e2e`"
    process = subprocess.Popen(
        [binary, image, "--plc", "CPU-EC20", "--tcp", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        line = process.stdout.readline()
        assert "modbus-tcp on" in line, line
        yield line.split()[-1]
    finally:
        process.kill()
        process.wait()


@pytest.fixture
def live_dir(workdir) -> pathlib.Path:
    return workdir / "live"


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[SERVER]))
async def live_client(lsp_client: LanguageClient, live_dir: pathlib.Path):
    """A client that asks for live values at `initialize`."""
    client_features(lsp_client)
    lsp_client.initialize_result = await lsp_client.initialize_session(
        initialize_params(live_dir, options={"liveValues": True})
    )
    yield
    await lsp_client.shutdown_session()


def whole(doc: Doc) -> types.Range:
    return types.Range(
        start=types.Position(line=0, character=0),
        end=types.Position(line=len(doc.text.split("\n")), character=0),
    )


async def live_hints(client, doc: Doc) -> dict[str, list[str]]:
    """The inlay hints that carry a live value (` = ...`), by the operand before them."""
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(text_document=doc.id(), range=whole(doc))
    )
    lines = doc.text.split("\n")
    found: dict[str, list[str]] = {}
    for hint in hints or []:
        label = hint.label if isinstance(hint.label, str) else "".join(p.value for p in hint.label)
        if " = " not in label and not label.startswith("="):
            continue
        before = lines[hint.position.line][: hint.position.character]
        operand = before.replace(",", " ").split()[-1]
        found.setdefault(operand, []).append(label.strip())
    return found


async def inline_values(client, doc: Doc) -> list[str]:
    values = await client.text_document_inline_value_async(
        types.InlineValueParams(
            text_document=doc.id(),
            range=whole(doc),
            context=types.InlineValueContext(
                frame_id=0,
                stopped_location=types.Range(
                    start=types.Position(line=0, character=0),
                    end=types.Position(line=0, character=0),
                ),
            ),
        )
    )
    return [v.text for v in values or [] if isinstance(v, types.InlineValueText)]


async def until(condition, seconds: float = 10.0, step: float = 0.1):
    """Poll the coroutine function `condition` until it returns a true value."""
    async def loop():
        while not (result := await condition()):
            await asyncio.sleep(step)
        return result

    return await asyncio.wait_for(loop(), seconds)


async def test_live_values_follow_a_blinking_lamp(live_client, live_dir, sim):
    write_project(live_dir, sim)
    doc = open_doc(live_client, live_dir / "main.lad")
    assert await doc.diagnostics() == []
    seen: set[str] = set()

    async def both_states():
        hints = await live_hints(live_client, doc)
        seen.update(hints.get("Lamp", []))
        return any(s.endswith("= 0") for s in seen) and any(s.endswith("= 1") for s in seen)

    await until(both_states, seconds=15)
    speed = (await live_hints(live_client, doc)).get("Speed", [])
    assert any("258" in s or "16#0102" in s for s in speed), speed
    values = await until(lambda: _with_values(live_client, doc))
    assert any(v.startswith("Lamp = ") for v in values), values
    assert live_client.refreshes["inlayHint"] > 0, "the server asks for new hints as values change"


async def _with_values(client, doc):
    values = await inline_values(client, doc)
    return values if values and not all(v.endswith("?") for v in values) else None


async def test_a_silent_plc_warns_once_and_shows_question_marks(live_client, live_dir):
    address = closed_port()
    write_project(live_dir, address)
    doc = open_doc(live_client, live_dir / "main.lad")
    assert await doc.diagnostics() == []
    hints = await live_hints(live_client, doc)
    assert hints.get("Lamp") and all(s.endswith("?") for s in hints["Lamp"]), hints

    async def warned():
        await live_hints(live_client, doc)
        return [m for m in live_client.messages if m.type == types.MessageType.Warning]

    warnings = await until(warned)
    assert address in warnings[0].message, warnings[0].message
    await asyncio.sleep(1.5)
    await live_hints(live_client, doc)
    warnings = [m for m in live_client.messages if m.type == types.MessageType.Warning]
    assert len(warnings) == 1, "one warning per outage"


async def test_live_values_are_opt_in_and_toggled(client, workdir):
    live_dir = workdir / "live"
    write_project(live_dir, closed_port())
    doc = open_doc(client, live_dir / "main.lad")
    assert await doc.diagnostics() == []
    assert await live_hints(client, doc) == {}, "off unless asked for"
    assert await inline_values(client, doc) == []

    client.workspace_did_change_configuration(
        types.DidChangeConfigurationParams(settings={"gutta": {"liveValues": True}})
    )
    assert "Lamp" in await live_hints(client, doc), "the setting turns it on"

    commands = client.initialize_result.capabilities.execute_command_provider
    assert commands and "gutta.toggleLiveValues" in commands.commands
    await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="gutta.toggleLiveValues")
    )
    assert await live_hints(client, doc) == {}, "the command turns it off"
    await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="gutta.toggleLiveValues")
    )
    assert "Lamp" in await live_hints(client, doc), "and on again"
