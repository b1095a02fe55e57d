//! `gutta-cc studio`'s server and its security (docs/studio.md, "The server"), driving
//! the real binary: the first line's exact form on loopback, 403 without the token, with
//! a wrong one or a foreign Origin, the page and /api/project, files read and written
//! only inside the project (`../x.lad`, an absolute path and a symlink out refused,
//! nothing written), Ctrl-C (SIGINT) exits 0, and `--no-open` never starts a browser.
//! HTTP/1.1 is written by hand over a std TcpStream.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// A running studio, killed when dropped (a test that ends it itself waits for it).
struct Studio {
    child: Child,
    /// `127.0.0.1:PORT`.
    address: String,
    token: String,
    first_line: String,
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `gutta-cc studio ARGS --no-open` in `dir`, with `path` first on PATH (a fake
/// `xdg-open` tests put there), until its first line.
fn start(dir: &Path, args: &[&str], path_first: Option<&Path>) -> Studio {
    let mut command = Command::new(env!("CARGO_BIN_EXE_gutta-cc"));
    command
        .arg("studio")
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null());
    if let Some(first) = path_first {
        let path = format!(
            "{}:{}",
            first.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        command.env("PATH", path);
    }
    let mut child = command.spawn().expect("gutta-cc studio starts");
    let mut first_line = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut first_line)
        .expect("reads the first line");
    let first_line = first_line.trim_end().to_string();
    let rest = first_line
        .strip_prefix("gutta-cc studio: http://")
        .unwrap_or_else(|| panic!("first line: {first_line:?}"));
    let (address, token) = rest
        .split_once("/?token=")
        .unwrap_or_else(|| panic!("first line: {first_line:?}"));
    Studio {
        address: address.to_string(),
        token: token.to_string(),
        first_line,
        child,
    }
}

/// A project made by `gutta-cc new`, and a file beside it (outside the project).
fn project(tag: &str) -> (PathBuf, PathBuf) {
    let scratch = common::scratch(&format!("studio-{tag}"));
    let out = common::cc_in(&scratch, &["new", "demo"]);
    assert!(out.status.success(), "{}", common::text(&out));
    std::fs::write(scratch.join("outside.lad"), "// outside\n").expect("writes");
    (scratch.join("demo"), scratch.join("outside.lad"))
}

/// An answer: status code, headers (lower-case names), body.
struct Answer {
    status: u16,
    headers: String,
    body: String,
}

/// One request with `headers` (each `Name: value`), `Connection: close`.
fn request(studio: &Studio, method: &str, target: &str, headers: &[&str], body: &str) -> Answer {
    let mut stream = TcpStream::connect(&studio.address).expect("connects");
    stream
        .set_read_timeout(Some(Duration::from_secs(30)))
        .expect("timeout");
    let mut text = format!(
        "{method} {target} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: {}\r\n",
        studio.address,
        body.len()
    );
    for h in headers {
        text.push_str(h);
        text.push_str("\r\n");
    }
    text.push_str("\r\n");
    text.push_str(body);
    stream.write_all(text.as_bytes()).expect("sends");
    let mut answer = Vec::new();
    stream.read_to_end(&mut answer).expect("reads the answer");
    let answer = String::from_utf8_lossy(&answer).into_owned();
    let (head, body) = answer.split_once("\r\n\r\n").expect("a head and a body");
    let status = head
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("status line: {head}"));
    assert!(
        !head
            .to_ascii_lowercase()
            .contains("transfer-encoding: chunked"),
        "{head}"
    );
    Answer {
        status,
        headers: head.to_ascii_lowercase(),
        body: body.to_string(),
    }
}

fn with_token(studio: &Studio, path: &str) -> String {
    let join = if path.contains('?') { '&' } else { '?' };
    format!("{path}{join}token={}", studio.token)
}

fn error_code(answer: &Answer) -> String {
    let json: serde_json::Value =
        serde_json::from_str(&answer.body).unwrap_or_else(|e| panic!("{e}: {}", answer.body));
    json["error"]["code"]
        .as_str()
        .unwrap_or_default()
        .to_string()
}

#[test]
fn the_first_line_gives_the_loopback_address_and_a_token() {
    let (demo, _) = project("first-line");
    let studio = start(&demo, &["--no-open"], None);
    let (host, port) = studio.address.rsplit_once(':').expect("HOST:PORT");
    assert_eq!(host, "127.0.0.1", "{}", studio.first_line);
    assert!(
        port.parse::<u16>().is_ok_and(|p| p != 0),
        "{}",
        studio.first_line
    );
    assert!(studio.token.len() >= 32, "{}", studio.first_line);
    assert!(studio.token.bytes().all(|b| b.is_ascii_hexdigit()));
    assert_eq!(
        studio.first_line,
        format!(
            "gutta-cc studio: http://{}/?token={}",
            studio.address, studio.token
        )
    );
    // A second run has another token.
    let again = start(&demo, &["--no-open"], None);
    assert_ne!(again.token, studio.token);
}

#[test]
fn requests_without_the_token_or_from_another_origin_are_refused() {
    let (demo, _) = project("refused");
    let studio = start(&demo, &["--no-open"], None);
    for target in [
        "/",
        "/api/project",
        "/api/file?path=src/main.lad",
        "/nothing",
    ] {
        let answer = request(&studio, "GET", target, &[], "");
        assert_eq!(answer.status, 403, "{target}: {}", answer.body);
        assert_eq!(error_code(&answer), "token-missing");
    }
    let wrong = format!("/?token={}", "0".repeat(studio.token.len()));
    let answer = request(&studio, "GET", &wrong, &[], "");
    assert_eq!(
        (answer.status, error_code(&answer).as_str()),
        (403, "token-wrong")
    );
    let header = format!("X-Gutta-Token: {}x", studio.token);
    let answer = request(&studio, "GET", "/api/project", &[&header], "");
    assert_eq!(
        (answer.status, error_code(&answer).as_str()),
        (403, "token-wrong")
    );
    // The right token from a foreign page.
    let good = with_token(&studio, "/api/project");
    for origin in [
        "Origin: http://evil.example",
        "Origin: null",
        "Origin: http://127.0.0.1:1",
    ] {
        let answer = request(&studio, "GET", &good, &[origin], "");
        assert_eq!(answer.status, 403, "{origin}");
        assert_eq!(error_code(&answer), "origin-foreign");
    }
    // The studio's own origin, and the token in either header, pass.
    let own = format!("Origin: http://{}", studio.address);
    assert_eq!(request(&studio, "GET", &good, &[&own], "").status, 200);
    let header = format!("X-Gutta-Token: {}", studio.token);
    assert_eq!(
        request(&studio, "GET", "/api/project", &[&header], "").status,
        200
    );
    let bearer = format!("Authorization: Bearer {}", studio.token);
    assert_eq!(
        request(&studio, "GET", "/api/project", &[&bearer], "").status,
        200
    );
    // A PUT without the token writes nothing.
    let main = demo.join("src/main.lad");
    let before = std::fs::read(&main).expect("reads");
    let answer = request(
        &studio,
        "PUT",
        "/api/file?path=src/main.lad",
        &[],
        "// gone\n",
    );
    assert_eq!(answer.status, 403);
    assert_eq!(std::fs::read(&main).expect("reads"), before);
}

#[test]
fn the_page_draws_the_project_in_edit_mode() {
    let (demo, _) = project("page");
    let studio = start(&demo, &["--no-open"], None);
    let page = request(&studio, "GET", &with_token(&studio, "/"), &[], "");
    assert_eq!(page.status, 200, "{}", page.body);
    assert!(
        page.headers.contains("content-type: text/html"),
        "{}",
        page.headers
    );
    assert!(
        page.headers.contains("referrer-policy: no-referrer"),
        "{}",
        page.headers
    );
    // Framed only by itself and VS Code's webview: a foreign page cannot frame it.
    assert!(
        page.headers
            .contains("frame-ancestors 'self' vscode-webview:"),
        "{}",
        page.headers
    );
    assert!(page.body.contains("class=\"network\""));
    let networks = page.body.matches("<g class=\"network").count();
    assert_eq!(networks, 3, "the template's three networks:\n{}", page.body);
    for drawn in [
        "class=\"contact",
        "class=\"coil",
        "data-operand=\"M0.0\"",
        "data-network=\"3\"",
    ] {
        assert!(page.body.contains(drawn), "{drawn} missing");
    }
    assert!(
        page.body
            .contains("<div class=\"status\" data-mode=\"EDIT\"><span class=\"mode\">EDIT</span>"),
        "no status bar in EDIT"
    );
    assert!(page
        .body
        .contains(&format!("const GUTTA_TOKEN = \"{}\";", studio.token)));
    // Nothing is fetched but the page: the one link is the empty icon (a favicon
    // request would carry no token).
    assert!(!page.body.contains("<script src"));
    assert_eq!(
        page.body
            .replace("<link rel=\"icon\" href=\"data:,\">", "")
            .matches("<link")
            .count(),
        0
    );

    let answer = request(
        &studio,
        "GET",
        &with_token(&studio, "/api/project"),
        &[],
        "",
    );
    assert_eq!(answer.status, 200, "{}", answer.body);
    let project: serde_json::Value = serde_json::from_str(&answer.body).expect("JSON");
    assert_eq!(project["name"], "demo");
    let files: Vec<&str> = project["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f["path"].as_str().expect("path"))
        .collect();
    assert_eq!(files, ["src/main.lad", "symbols.csv"]);
    assert_eq!(project["blocks"][0]["name"], "MAIN");
    assert_eq!(project["blocks"][0]["networks"], 3);
    let symbols: Vec<&str> = project["symbols"]
        .as_array()
        .expect("symbols")
        .iter()
        .map(|s| s["name"].as_str().expect("name"))
        .collect();
    for name in ["Running", "Blinks", "Start", "Stop", "Lamp"] {
        assert!(symbols.contains(&name), "{name} in {symbols:?}");
    }
    assert_eq!(project["diagnostics"]["errors"], 0);

    let text = request(
        &studio,
        "GET",
        &with_token(&studio, "/api/file?path=src%2Fmain.lad"),
        &[],
        "",
    );
    assert_eq!(text.status, 200);
    assert_eq!(
        text.body,
        std::fs::read_to_string(demo.join("src/main.lad")).expect("reads")
    );
    let missing = request(
        &studio,
        "GET",
        &with_token(&studio, "/api/file?path=nope.lad"),
        &[],
        "",
    );
    assert_eq!(
        (missing.status, error_code(&missing).as_str()),
        (404, "not-found")
    );
}

#[test]
fn a_put_writes_a_lad_file_of_the_project_and_nothing_outside() {
    let (demo, outside) = project("put");
    #[cfg(unix)]
    std::os::unix::fs::symlink(&outside, demo.join("src/link.lad")).expect("symlink");
    let studio = start(&demo, &["--no-open"], None);
    let outside_before = std::fs::read(&outside).expect("reads");
    let absolute = outside.display().to_string().replace('/', "%2F");
    let mut escapes = vec![
        "../outside.lad".to_string(),
        "src/../../outside.lad".to_string(),
        absolute,
        "%2E%2E/outside.lad".to_string(),
    ];
    if cfg!(unix) {
        escapes.push("src/link.lad".to_string());
    }
    for escape in &escapes {
        let target = with_token(&studio, &format!("/api/file?path={escape}"));
        let answer = request(&studio, "PUT", &target, &[], "// written\n");
        assert_eq!(answer.status, 403, "{escape}: {}", answer.body);
        assert_eq!(error_code(&answer), "path-escape", "{escape}");
        let read = request(&studio, "GET", &target, &[], "");
        assert_eq!(read.status, 403, "{escape}");
    }
    assert_eq!(std::fs::read(&outside).expect("reads"), outside_before);
    assert!(!demo.parent().expect("scratch").join("x.lad").exists());

    let not_lad = with_token(&studio, "/api/file?path=gutta.toml");
    let answer = request(&studio, "PUT", &not_lad, &[], "[program]\n");
    assert_eq!(
        (answer.status, error_code(&answer).as_str()),
        (400, "path-not-lad")
    );

    let main = demo.join("src/main.lad");
    let text = std::fs::read_to_string(&main).expect("reads").replace(
        "Network 2 // blink while running",
        "Network 2 // blink, from the studio",
    );
    let answer = request(
        &studio,
        "PUT",
        &with_token(&studio, "/api/file?path=src/main.lad"),
        &[],
        &text,
    );
    assert_eq!(answer.status, 200, "{}", answer.body);
    assert_eq!(std::fs::read_to_string(&main).expect("reads"), text);
    let leftovers: Vec<_> = std::fs::read_dir(demo.join("src"))
        .expect("lists")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // What the page draws is the file now on disk.
    let page = request(&studio, "GET", &with_token(&studio, "/"), &[], "");
    assert!(page.body.contains("blink, from the studio"));
    // A new file in a folder of the project.
    let new = with_token(&studio, "/api/file?path=src/extra.lad");
    assert_eq!(request(&studio, "PUT", &new, &[], "// extra\n").status, 200);
    assert_eq!(
        std::fs::read_to_string(demo.join("src/extra.lad")).expect("reads"),
        "// extra\n"
    );
}

#[test]
fn files_beside_the_given_sources_are_the_project() {
    let (demo, _) = project("files");
    let src = demo.join("src");
    let studio = start(&src, &["main.lad", "--no-open"], None);
    let answer = request(
        &studio,
        "GET",
        &with_token(&studio, "/api/project"),
        &[],
        "",
    );
    let project: serde_json::Value = serde_json::from_str(&answer.body).expect("JSON");
    assert_eq!(project["files"][0]["path"], "main.lad");
    let up = with_token(&studio, "/api/file?path=../gutta.toml");
    assert_eq!(request(&studio, "GET", &up, &[], "").status, 403);
    // A project folder given relative to the current directory, and files with a
    // symbol table given from elsewhere.
    let scratch = demo.parent().expect("scratch");
    for args in [
        &["demo", "--no-open"][..],
        &[
            "demo/src/main.lad",
            "--symbols",
            "demo/symbols.csv",
            "--no-open",
        ][..],
    ] {
        let studio = start(scratch, args, None);
        let answer = request(
            &studio,
            "GET",
            &with_token(&studio, "/api/project"),
            &[],
            "",
        );
        assert_eq!(answer.status, 200, "{args:?}: {}", answer.body);
        let project: serde_json::Value = serde_json::from_str(&answer.body).expect("JSON");
        assert_eq!(project["diagnostics"]["errors"], 0, "{args:?}");
        let names = project["symbols"].to_string();
        assert!(
            names.contains("\"Lamp\"") && names.contains("\"Running\""),
            "{names}"
        );
    }
}

#[cfg(unix)]
#[test]
fn ctrl_c_exits_0() {
    let (demo, _) = project("sigint");
    let mut studio = start(&demo, &["--no-open"], None);
    let page = request(&studio, "GET", &with_token(&studio, "/"), &[], "");
    assert_eq!(page.status, 200);
    let pid = studio.child.id().to_string();
    let kill = Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    let status = studio.child.wait().expect("waits");
    assert_eq!(status.code(), Some(0), "{status:?}");
}

/// A fake `xdg-open` first on PATH that leaves a marker when started.
#[cfg(unix)]
fn fake_opener(dir: &Path) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).expect("mkdir");
    let marker = dir.join("opened");
    let script = bin.join("xdg-open");
    std::fs::write(
        &script,
        format!("#!/bin/sh\necho \"$1\" > '{}'\n", marker.display()),
    )
    .expect("writes");
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    bin
}

#[cfg(target_os = "linux")]
#[test]
fn no_open_never_starts_a_browser_and_without_it_the_opener_gets_the_address() {
    let (demo, _) = project("open");
    let scratch = demo.parent().expect("scratch").to_path_buf();
    let bin = fake_opener(&scratch);
    let marker = scratch.join("opened");
    let studio = start(&demo, &["--no-open"], Some(&bin));
    // The page is served, so the studio has long passed the point of opening.
    assert_eq!(
        request(&studio, "GET", &with_token(&studio, "/"), &[], "").status,
        200
    );
    std::thread::sleep(Duration::from_millis(300));
    assert!(!marker.exists(), "--no-open started the opener");
    drop(studio);
    let studio = start(&demo, &[], Some(&bin));
    let url = studio
        .first_line
        .trim_start_matches("gutta-cc studio: ")
        .to_string();
    let mut opened = String::new();
    for _ in 0..100 {
        if let Ok(text) = std::fs::read_to_string(&marker) {
            opened = text;
            if opened.ends_with('\n') {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    assert_eq!(opened.trim_end(), url);
}

#[test]
fn edits_over_http_change_the_buffer_until_saved() {
    let (demo, _) = project("edit");
    let main = demo.join("src/main.lad");
    let on_disk = std::fs::read_to_string(&main).expect("reads");
    let studio = start(&demo, &["--no-open"], None);
    let token = format!("X-Gutta-Token: {}", studio.token);
    let post = |path: &str, body: &str| {
        let answer = request(
            &studio,
            "POST",
            path,
            &[&token, "Content-Type: application/json"],
            body,
        );
        let json: serde_json::Value = serde_json::from_str(&answer.body).expect("JSON");
        (answer.status, json)
    };
    let get = |path: &str| {
        let answer = request(&studio, "GET", path, &[&token], "");
        (answer.status, answer.body)
    };
    let edit = r#"{"file": "src/main.lad", "edit": {"op": "set_operands",
        "at": "blocks[0].networks[1].rung.series[2]", "operands": ["Q9.9"]}}"#;
    let (status, update) = post("/api/edit", edit);
    assert_eq!(status, 200, "{update}");
    assert_eq!(update["dirty"], true);
    assert_eq!(update["can_undo"], true);
    assert_eq!(update["networks"].as_array().expect("networks").len(), 1);
    let html = update["networks"][0]["html"].as_str().expect("html");
    assert!(html.starts_with("<svg") && html.contains("data-network=\"2\""));
    assert!(html.contains("data-path=\"blocks[0].networks[1].rung.series[2]\""));
    let bad = &update["diagnostics"][0];
    assert_eq!(bad["path"], "blocks[0].networks[1].rung.series[2]");
    assert!(bad["code"].as_str().expect("code").starts_with('E'));
    assert_eq!(update["errors"], 1);
    // The buffer has it, the disk not; the page and the drawing are the buffer's.
    let (_, buffer) = get("/api/file?file=src/main.lad");
    assert!(buffer.contains("Q9.9"));
    assert_eq!(std::fs::read_to_string(&main).expect("reads"), on_disk);
    let (_, page) = get("/");
    assert!(page.contains(">Q9.9<"));
    let (_, drawing) = get("/api/drawing?file=src/main.lad");
    assert!(drawing.contains("Q9.9"));
    // Undo gives the exact text back, redo the edited one.
    let (status, _) = post("/api/undo", r#"{"file": "src/main.lad"}"#);
    assert_eq!(status, 200);
    assert_eq!(get("/api/file?file=src/main.lad").1, on_disk);
    let (status, update) = post("/api/redo", r#"{"file": "src/main.lad"}"#);
    assert_eq!((status, &update["dirty"]), (200, &serde_json::json!(true)));
    assert_eq!(get("/api/file?file=src/main.lad").1, buffer);
    // An edit that leaves the diagnostics as they were answers without them (the page
    // keeps its list); the error count still comes.
    let retitle = r#"{"file": "src/main.lad", "edit": {"op": "set_network_title",
        "at": "blocks[0].networks[0]", "title": "latch"}}"#;
    let (status, update) = post("/api/edit", retitle);
    assert_eq!(status, 200, "{update}");
    assert!(update.get("diagnostics").is_none(), "{update}");
    assert_eq!(update["errors"], 1);
    let (status, update) = post("/api/undo", r#"{"file": "src/main.lad"}"#);
    assert_eq!(status, 200);
    assert!(update.get("diagnostics").is_none(), "{update}");
    // A refused edit is its L code and path, and nothing changes.
    let refused = r#"{"file": "src/main.lad", "edit": {"op": "delete",
        "at": "blocks[0].networks[9].rung"}}"#;
    let (status, answer) = post("/api/edit", refused);
    assert_eq!((status, answer["code"].as_str()), (422, Some("L0014")));
    assert_eq!(get("/api/file?file=src/main.lad").1, buffer);
    let (status, answer) = post("/api/edit", "not json");
    assert_eq!(
        (status, answer["code"].as_str()),
        (400, Some("bad-request"))
    );
    // Save writes the buffer.
    let (status, answer) = post("/api/save", r#"{"file": "src/main.lad"}"#);
    assert_eq!((status, &answer["dirty"]), (200, &serde_json::json!(false)));
    assert_eq!(std::fs::read_to_string(&main).expect("reads"), buffer);
    // A block's STL, and completion from the editor analysis.
    let (status, stl) = get("/api/stl?file=src/main.lad&block=0");
    assert_eq!(status, 200);
    assert!(stl.contains("ORGANIZATION_BLOCK MAIN:OB1") && stl.contains("Q9.9"));
    let (_, items) = get("/api/complete?file=src/main.lad&kind=mnemonic&element=box&prefix=TO");
    for mnemonic in ["\"TON\"", "\"TOF\"", "\"operands\":[\"T\",\"PT\"]"] {
        assert!(items.contains(mnemonic), "{mnemonic}: {items}");
    }
    let (_, items) = get("/api/complete?file=src/main.lad&kind=operand&element=contact&prefix=St");
    assert!(
        items.contains("\"Start\"") && items.contains("\"Stop\""),
        "{items}"
    );
    let (status, _) = get("/api/complete?file=src/main.lad&kind=nonsense");
    assert_eq!(status, 400);
}
