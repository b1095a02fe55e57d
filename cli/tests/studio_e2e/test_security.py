"""Who may talk to the studio, from raw requests and from the browser's side: no
token, a wrong token, a foreign Origin, a path that escapes the project: 403, and
nothing written (docs/studio.md, "The server")."""

import json
import urllib.error
import urllib.request

from conftest import wait_until


def request(studio, method, path, body=None, headers=None):
    """(status, JSON answer or None) of a raw request to the studio."""
    data = None if body is None else (body if isinstance(body, bytes) else json.dumps(body).encode())
    req = urllib.request.Request(studio.base + path, data=data, method=method,
                                 headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=10) as answer:
            raw = answer.read()
            status = answer.status
    except urllib.error.HTTPError as refused:
        raw = refused.read()
        status = refused.code
    try:
        return status, json.loads(raw)
    except ValueError:
        return status, None


def snapshot(project):
    """Every file under the project's parent folder with its bytes."""
    root = project.parent
    return {p: p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


EDIT = {"file": "src/main.lad",
        "edit": {"op": "set_operands", "at": "blocks[0].networks[1].rung.series[2]",
                 "operands": ["Q0.7"]}}


def test_raw_requests_without_the_right_token_or_origin_are_refused(studio, project):
    outside = project.parent / "outside.lad"
    outside.write_text("// outside\n")
    before = snapshot(project)
    good = {"X-Gutta-Token": studio.token}
    wrong = {"X-Gutta-Token": "0" * 32}
    foreign = {"X-Gutta-Token": studio.token, "Origin": "http://evil.example"}
    calls = [("GET", "/", None), ("GET", "/api/project", None),
             ("GET", "/api/file?file=src/main.lad", None),
             ("POST", "/api/edit", EDIT), ("POST", "/api/save", {"file": "src/main.lad"}),
             ("POST", "/api/undo", {"file": "src/main.lad"}),
             ("PUT", "/api/file?path=src/main.lad", b"// overwritten\n")]
    for method, path, body in calls:
        for headers, code in [({}, "token-missing"), (wrong, "token-wrong"),
                              (foreign, "origin-foreign")]:
            status, answer = request(studio, method, path, body, headers)
            assert status == 403, (method, path, headers)
            assert answer["code"] == code and answer["error"]["code"] == code
    # The token in the query is this run's only; a near miss is refused too.
    status, _ = request(studio, "GET", f"/api/project?token={studio.token[:-1]}x")
    assert status == 403
    # Paths out of the project: 403, whether read, written or named as a file.
    for escape in ["../outside.lad", "src/../../outside.lad", str(outside),
                   "%2E%2E/outside.lad"]:
        status, answer = request(studio, "PUT", f"/api/file?path={escape}",
                                 b"// written\n", good)
        assert (status, answer["code"]) == (403, "path-escape"), escape
        status, _ = request(studio, "GET", f"/api/file?path={escape}", None, good)
        assert status == 403, escape
        if "%" in escape:
            continue  # decoded in a query only; in JSON it is a plain (unknown) name
        status, answer = request(studio, "POST", "/api/edit", dict(EDIT, file=escape), good)
        assert (status, answer["code"]) == (403, "path-escape"), escape
        status, answer = request(studio, "POST", "/api/save", {"file": escape}, good)
        assert (status, answer["code"]) == (403, "path-escape"), escape
    assert snapshot(project) == before
    # The right token and no Origin: the same edit is taken (in the buffer only).
    status, answer = request(studio, "POST", "/api/edit", EDIT, good)
    assert status == 200 and answer["dirty"] is True
    assert snapshot(project) == before


def test_the_browser_side(browser, studio, project):
    before = snapshot(project)
    context = browser.new_context()
    page = context.new_page()
    # A page of another site that knows the studio's address, even its token.
    context.route("http://evil.test/**", lambda route: route.fulfill(
        status=200, content_type="text/html", body="<html><body>evil</body></html>"))
    page.goto("http://evil.test/")
    results = page.evaluate("""async ([base, token]) => {
        const out = [];
        for (const [method, path, body] of [
                ['POST', '/api/edit?token=' + token, JSON.stringify(%s)],
                ['POST', '/api/save?token=' + token, '{"file":"src/main.lad"}'],
                ['PUT', '/api/file?path=src/main.lad&token=' + token, '// evil\\n']]) {
            try {
                await fetch(base + path, {method, body, mode: 'no-cors',
                                          headers: {'Content-Type': 'text/plain'}});
                out.push('sent');
            } catch (e) { out.push('blocked'); }
        }
        return out;
    }""" % json.dumps(EDIT), [studio.base, studio.token])
    assert len(results) == 3
    # The studio's own page without the token is refused, and so are its requests.
    answer = page.goto(studio.base + "/")
    assert answer.status == 403
    assert "token-missing" in page.content()
    page.goto(studio.url)
    page.wait_for_selector(".status")
    statuses = page.evaluate("""async () => {
        const plain = await fetch('/api/project');
        const wrong = await fetch('/api/project', {headers: {'X-Gutta-Token': 'f'.repeat(32)}});
        const escape = await window.guttaStudio.api('/api/file?path=../outside.lad',
                                                     {method: 'PUT', body: 'x'});
        const good = await window.guttaStudio.api('/api/project');
        return [plain.status, wrong.status, escape.status, good.status];
    }""")
    assert statuses == [403, 403, 403, 200]
    context.close()
    # Nothing the foreign page sent was taken: no edit in the buffer, nothing on disk.
    status, answer = request(studio, "GET", "/api/project", None,
                             {"X-Gutta-Token": studio.token})
    assert answer["files"][0]["dirty"] is False
    wait_until(lambda: snapshot(project) == before, timeout=2, what="nothing written")
    assert not (project.parent / "outside.lad").exists()
