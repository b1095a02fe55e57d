"""Completion, signature help, rename (and its refusals) and code actions."""

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException

from conftest import Doc, apply_edits, edits_for, line_of


def labels(result) -> list[str]:
    items = result.items if isinstance(result, types.CompletionList) else result or []
    return [i.label for i in items]


def items(result) -> list[types.CompletionItem]:
    return result.items if isinstance(result, types.CompletionList) else result or []


async def complete_after(client, doc: Doc, anchor: str, line: str):
    """Add `line` after the line holding `anchor`; complete at its end."""
    await doc.diagnostics()
    doc.replace(anchor + "\n", anchor + "\n" + line + "\n")
    position = doc.at(anchor + "\n" + line + "\n", offset=len(anchor) + 1 + len(line))
    return await client.text_document_completion_async(
        types.CompletionParams(text_document=doc.id(), position=position)
    )


async def test_completion_of_mnemonics_fits_the_block(client, main: Doc):
    in_main = labels(await complete_after(client, main, "LBL    1", ""))
    assert "MOVW" in in_main and "LD" in in_main and "END" in in_main
    assert "RET" not in in_main, "RET belongs to subroutines"
    movw = next(i for i in items(await complete_after(client, main, "LBL    1", "MO")) if i.label == "MOVW")
    assert movw.detail, "a mnemonic shows its operand signature"


async def test_completion_of_mnemonics_in_a_subroutine(client, main: Doc):
    in_sbr = labels(await complete_after(client, main, "+I     #b, #r", ""))
    assert "RET" in in_sbr
    assert "END" not in in_sbr, "END belongs to MAIN"


async def test_completion_of_operands_offers_symbols_and_addresses(client, main: Doc):
    found = labels(await complete_after(client, main, "LBL    1", "LD     "))
    assert "Start" in found and "Lamp" in found
    assert any(label.upper().startswith(("I", "M", "Q")) for label in found if label not in ("Lamp",)), found


async def test_completion_after_call_offers_blocks(client, main: Doc):
    found = labels(await complete_after(client, main, "LBL    1", "CALL   "))
    assert any("ADD3" in label for label in found), found


async def test_completion_of_locals_in_their_block(client, main: Doc):
    found = labels(await complete_after(client, main, "+I     #b, #r", "MOVW   #"))
    assert any(label.lstrip("#") == "a" for label in found), found


async def test_completion_of_labels_after_jmp(client, main: Doc):
    found = labels(await complete_after(client, main, "LBL    1", "JMP    "))
    assert "1" in found, found


async def test_completion_of_system_block_keys_and_values(client, main: Doc):
    keys = labels(await complete_after(client, main, "  PORT0.BAUD      = 38400", "  "))
    assert any("PARITY" in k for k in keys), keys
    values = labels(
        await complete_after(client, main, "  PORT0.BAUD      = 38400", "  PORT0.PARITY = ")
    )
    assert "EVEN" in values, values


async def test_signature_help_names_the_active_operand(client, main: Doc):
    await main.diagnostics()
    help_ = await client.text_document_signature_help_async(
        types.SignatureHelpParams(
            text_document=main.id(), position=main.at("MOVW   #a, #r", offset=len("MOVW   #a, #"))
        )
    )
    assert help_ is not None and help_.signatures
    signature = help_.signatures[help_.active_signature or 0]
    assert "MOVW" in signature.label
    assert len(signature.parameters) == 2
    active = signature.active_parameter if signature.active_parameter is not None else help_.active_parameter
    assert active == 1
    second = signature.parameters[1]
    label = second.label if isinstance(second.label, str) else signature.label[second.label[0] : second.label[1]]
    documentation = second.documentation
    text = label + " " + (documentation if isinstance(documentation, str) else documentation.value if documentation else "")
    assert "OUT" in text.upper(), text


async def test_rename_a_symbol_edits_every_use(client, main: Doc):
    await main.diagnostics()
    position = main.at("LD     Start", offset=8)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=main.id(), position=position)
    )
    assert prepared is not None
    range_ = prepared if isinstance(prepared, types.Range) else prepared.range
    assert range_.start == main.at("LD     Start", offset=7)
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=main.id(), position=position, new_name="Button")
    )
    renamed = apply_edits(main.text, edits_for(edit, main.uri))
    assert "Button   : I0.0" in renamed and "LD     Button" in renamed
    assert "Start" not in renamed
    main.change([types.TextDocumentContentChangeWholeDocument(text=renamed)])
    assert await main.diagnostics() == []


async def test_rename_a_block_and_a_local(client, main: Doc):
    await main.diagnostics()
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=main.id(), position=main.at("CALL   ADD3", offset=8), new_name="SUM3")
    )
    renamed = apply_edits(main.text, edits_for(edit, main.uri))
    assert "SUBROUTINE_BLOCK SUM3:SBR0" in renamed and "CALL   SUM3" in renamed
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=main.id(), position=main.at("MOVW   #a", offset=8), new_name="first")
    )
    renamed = apply_edits(main.text, edits_for(edit, main.uri))
    assert "  first : INT;" in renamed and "MOVW   #first, #r" in renamed


@pytest.mark.parametrize(
    "new_name, why",
    [("Lamp", "taken"), ("MW10", "an address"), ("END_VAR", "a reserved word"), ("9lives", "not a name")],
)
async def test_rename_is_refused_with_a_reason(client, main: Doc, new_name, why):
    await main.diagnostics()
    with pytest.raises(JsonRpcException) as refused:
        await client.text_document_rename_async(
            types.RenameParams(
                text_document=main.id(), position=main.at("LD     Start", offset=8), new_name=new_name
            )
        )
    error = refused.value
    assert getattr(error, "code", None) != -32601, "rename is served"
    assert str(error).strip(), f"the refusal ({why}) says why"
    if why == "taken":
        assert "Lamp" in str(error), f"the refusal names the taken name: {error}"


async def actions_for(client, doc: Doc, diagnostic: types.Diagnostic):
    return await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc.id(),
            range=diagnostic.range,
            context=types.CodeActionContext(diagnostics=[diagnostic]),
        )
    )


async def test_code_action_replaces_a_misspelt_name(client, main: Doc):
    await main.diagnostics()
    main.replace("LD     Start", "LD     Strat")
    [diagnostic] = await main.diagnostics()
    actions = [a for a in await actions_for(client, main, diagnostic) if isinstance(a, types.CodeAction)]
    fix = next(a for a in actions if "Start" in a.title)
    assert fix.kind == types.CodeActionKind.QuickFix
    fixed = apply_edits(main.text, edits_for(fix.edit, main.uri))
    assert "LD     Start" in fixed
    main.change([types.TextDocumentContentChangeWholeDocument(text=fixed)])
    assert await main.diagnostics() == []


async def test_code_action_declares_an_undefined_symbol(client, main: Doc):
    await main.diagnostics()
    main.replace("LD     Start", "LD     Pump")
    [diagnostic] = await main.diagnostics()
    actions = [a for a in await actions_for(client, main, diagnostic) if isinstance(a, types.CodeAction)]
    declare = next(a for a in actions if "Pump" in a.title and "eclare" in a.title)
    declared = apply_edits(main.text, edits_for(declare.edit, main.uri))
    lines = declared.split("\n")
    inside = lines[line_of(declared, "SYMBOLS") + 1 : line_of(declared, "END_SYMBOLS")]
    assert any(line.strip().startswith("Pump") for line in inside), inside


async def test_code_action_adds_a_missing_end(client, main: Doc):
    await main.diagnostics()
    main.replace("END_SUBROUTINE_BLOCK\n", "")
    diagnostics = await main.diagnostics()
    missing = next(d for d in diagnostics if d.code == "E0105")
    actions = [a for a in await actions_for(client, main, missing) if isinstance(a, types.CodeAction)]
    add = next(a for a in actions if "END_SUBROUTINE_BLOCK" in a.title)
    fixed = apply_edits(main.text, edits_for(add.edit, main.uri))
    main.change([types.TextDocumentContentChangeWholeDocument(text=fixed)])
    assert await main.diagnostics() == []
