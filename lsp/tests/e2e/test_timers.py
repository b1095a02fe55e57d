"""A timer through the real server: hover on its preset and on the timer gives the
kind, the resolution and the preset as a duration; an inlay hint shows the duration
after the preset."""

from lsprotocol import types

from conftest import open_doc

# CPU-EC20 (the default): T4 counts 100 ms.
TIMER = """SYMBOLS
  Dwell : T4 // how long the lamp stays on
END_SYMBOLS
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     I0.0
TON    Dwell, 150
LDW>=  T4, 20
=      Q0.0
END_ORGANIZATION_BLOCK
"""

LINE = "**TON** (on-delay timer) `Dwell` (`T4`): counts 100 ms; preset 150 = 15.0 s"


async def test_a_timer_hover_and_hint_say_the_preset_as_a_duration(client, workdir):
    path = workdir / "timer.lad"
    path.write_text(TIMER)
    doc = open_doc(client, path)
    assert await doc.diagnostics() == []
    for needle, offset in [("150", 1), ("Dwell,", 1), ("T4, 20", 1)]:
        hover = await client.text_document_hover_async(
            types.HoverParams(text_document=doc.id(), position=doc.at(needle, 0, offset))
        )
        assert hover is not None, needle
        assert hover.contents.value.endswith(LINE), (needle, hover.contents.value)
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            text_document=doc.id(),
            range=types.Range(
                start=types.Position(line=0, character=0),
                end=types.Position(line=12, character=0),
            ),
        )
    )
    durations = [
        (h.position.line, h.position.character, h.label)
        for h in hints or []
        if isinstance(h.label, str) and h.label.endswith(" s")
    ]
    assert durations == [(7, 17, "15.0 s")], durations
