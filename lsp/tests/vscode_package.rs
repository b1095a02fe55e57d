//! The VS Code extension (editors/vscode/): its manifest, language configuration and
//! TextMate grammar hang together (always); with node, its activation (test/activate.js,
//! with stand-ins for VS Code's modules) starts gutta-lsp with the settings passed on,
//! and the Open Studio launcher (test/studio.js) runs the real gutta-cc studio and stops it;
//! with npm, the extension packages into a .vsix holding the grammar, and the grammar,
//! run by vscode-textmate over oniguruma as VS Code runs it, colours examples/blink.lad
//! and every mnemonic of the stdlib's instruction set. Without node or npm those tests fail saying how to install them,
//! unless GUTTA_SKIP_EXTERNAL=1.

mod external;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn extension_dir() -> PathBuf {
    external::repo_root().join("editors/vscode")
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `name` and `include` of a grammar rule tree.
fn walk_rules(value: &Value, names: &mut Vec<String>, includes: &mut BTreeSet<String>) {
    match value {
        Value::Object(map) => {
            for (key, v) in map {
                match (key.as_str(), v) {
                    ("name", Value::String(s)) => names.push(s.clone()),
                    ("include", Value::String(s)) => {
                        includes.insert(s.clone());
                    }
                    _ => walk_rules(v, names, includes),
                }
            }
        }
        Value::Array(items) => items.iter().for_each(|v| walk_rules(v, names, includes)),
        _ => {}
    }
}

#[test]
fn manifest_language_configuration_and_grammar_hang_together() {
    let dir = extension_dir();
    let manifest = read_json(&dir.join("package.json"));
    let language = &manifest["contributes"]["languages"][0];
    assert_eq!(language["id"], "gutta-lad");
    assert_eq!(language["extensions"], serde_json::json!([".lad"]));
    let config = read_json(&dir.join(language["configuration"].as_str().expect("path")));
    assert_eq!(config["comments"]["lineComment"], "//");
    assert!(config["folding"]["markers"]["start"].is_string());
    let grammar_entry = &manifest["contributes"]["grammars"][0];
    assert_eq!(grammar_entry["language"], "gutta-lad");
    let grammar = read_json(&dir.join(grammar_entry["path"].as_str().expect("path")));
    assert_eq!(grammar["scopeName"], grammar_entry["scopeName"]);
    assert_eq!(grammar["scopeName"], "source.gutta-lad");
    assert!(dir.join(manifest["main"].as_str().expect("main")).is_file());

    let mut names = Vec::new();
    let mut includes = BTreeSet::new();
    walk_rules(&grammar["patterns"], &mut names, &mut includes);
    walk_rules(&grammar["repository"], &mut names, &mut includes);
    let repository = grammar["repository"].as_object().expect("repository");
    for include in &includes {
        let key = include
            .strip_prefix('#')
            .unwrap_or_else(|| panic!("include `{include}` reaches outside the grammar"));
        assert!(
            repository.contains_key(key),
            "include `{include}` names no rule"
        );
    }
    for key in repository.keys() {
        assert!(
            includes.contains(&format!("#{key}")),
            "rule `{key}` is never included"
        );
    }
    for name in &names {
        assert!(
            name.ends_with(".gutta-lad"),
            "scope `{name}` lacks the language suffix"
        );
    }
    // docs/editors.md and the extension's README name every setting.
    let docs = std::fs::read_to_string(external::repo_root().join("docs/editors.md"))
        .expect("reads the docs");
    let readme = std::fs::read_to_string(dir.join("README.md")).expect("reads the README");
    let settings = manifest["contributes"]["configuration"]["properties"]
        .as_object()
        .expect("settings");
    for key in settings.keys() {
        let shown = format!("`{key}`");
        assert!(docs.contains(&shown), "docs/editors.md lacks {key}");
        assert!(
            readme.contains(&shown),
            "editors/vscode/README.md lacks {key}"
        );
    }
    // The commands the manifest shows are the ones the extension registers.
    let source = std::fs::read_to_string(dir.join("src/extension.js")).expect("reads");
    for command in manifest["contributes"]["commands"]
        .as_array()
        .expect("commands")
    {
        let id = command["command"].as_str().expect("id");
        assert!(
            source.contains(&format!("registerCommand('{id}'")),
            "{id} is not registered"
        );
    }
}

/// The workspace's `gutta-cc` (another package's binary, so no CARGO_BIN_EXE; the
/// workspace's `cargo test` builds it).
fn cc_binary() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| external::repo_root().join("target"));
    let path = target.join("debug/gutta-cc");
    assert!(
        path.exists(),
        "{} is missing: build it first with `cargo build -p gutta-cli --bin gutta-cc`",
        path.display()
    );
    path
}

/// A project as `gutta-cc new` makes it, in `parent/name`: gutta.toml, src/main.lad,
/// symbols.csv, tests/main.gtest. Its folder.
fn new_project(parent: &Path, name: &str) -> PathBuf {
    let project = parent.join(name);
    std::fs::create_dir_all(project.join("src")).expect("src");
    std::fs::create_dir_all(project.join("tests")).expect("tests");
    let templates = external::repo_root().join("cli/templates");
    let manifest = std::fs::read_to_string(templates.join("gutta.toml"))
        .expect("template")
        .replace("{name}", name)
        .replace("{plc}", "CPU-EC20");
    std::fs::write(project.join("gutta.toml"), manifest).expect("gutta.toml");
    std::fs::copy(templates.join("main.lad"), project.join("src/main.lad")).expect("copies");
    std::fs::copy(templates.join("symbols.csv"), project.join("symbols.csv")).expect("copies");
    std::fs::copy(
        templates.join("main.gtest"),
        project.join("tests/main.gtest"),
    )
    .expect("copies");
    project
}

/// Replace `from` by `to` in a file (the test's own edits of a project).
fn edit(file: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(file).expect("reads");
    assert!(text.contains(from), "{} lacks `{from}`", file.display());
    std::fs::write(file, text.replacen(from, to, 1)).expect("writes");
}

#[test]
fn open_studio_is_contributed_and_its_launcher_runs_the_real_studio() {
    let dir = extension_dir();
    let manifest = read_json(&dir.join("package.json"));
    let commands = manifest["contributes"]["commands"]
        .as_array()
        .expect("commands");
    let open = commands
        .iter()
        .find(|c| c["command"] == "gutta.openStudio")
        .expect("gutta.openStudio is contributed");
    assert_eq!(
        (&open["title"], &open["category"]),
        (&"Open Studio".into(), &"GUTTA".into())
    );
    assert_eq!(
        manifest["contributes"]["configuration"]["properties"]["gutta.cc.path"]["default"],
        "gutta-cc"
    );
    if !external::have("node") {
        return;
    }
    let work = external::scratch("studio");
    let project = new_project(&work, "blinky");
    let out = external::run(
        Command::new("node")
            .arg("test/studio.js")
            .arg(cc_binary())
            .arg(&project)
            .current_dir(&dir),
        "node test/studio.js",
    );
    let seen: Value = serde_json::from_str(&out).expect("studio.js JSON");
    assert_eq!(
        seen["parsed"],
        serde_json::json!({"url": "http://127.0.0.1:4711/?token=abc_DEF-1", "origin": "http://127.0.0.1:4711", "host": "127.0.0.1:4711", "token": "abc_DEF-1"})
    );
    assert_eq!(seen["notParsed"], serde_json::json!([null, null]));
    let origin = seen["origin"].as_str().expect("origin");
    assert!(origin.starts_with("http://127.0.0.1:"), "{origin}");
    assert!(seen["url"]
        .as_str()
        .expect("url")
        .starts_with(&format!("{origin}/?token=")));
    assert_eq!(
        seen["page"],
        serde_json::json!({"status": 200, "hasStatusBar": true})
    );
    assert_eq!(
        seen["ownOrigin"], 200,
        "the frame's requests carry the studio's origin"
    );
    assert_eq!(seen["foreignOrigin"], 403);
    let html = seen["html"].as_str().expect("html");
    assert!(html.contains(&format!("frame-src {origin};")), "{html}");
    assert!(
        html.contains(&format!(
            "<iframe src=\"{}\"",
            seen["url"].as_str().expect("url")
        )),
        "{html}"
    );
    // Ctrl-C: the studio ends with 0, and nothing answers at its address any more.
    assert_eq!(seen["exit"], serde_json::json!({"code": 0, "signal": null}));
    assert!(
        seen["afterStop"]["error"].is_string(),
        "{}",
        seen["afterStop"]
    );
    let pid = seen["pid"].as_u64().expect("pid");
    assert!(
        !Path::new(&format!("/proc/{pid}")).exists(),
        "gutta-cc {pid} still runs"
    );
    let missing = seen["missing"]
        .as_str()
        .expect("a missing gutta-cc is refused");
    assert!(missing.contains("gutta.cc.path"), "{missing}");
    assert!(seen["notAProject"].is_string(), "{}", seen["notAProject"]);
    let _ = std::fs::remove_dir_all(&work);
}

/// What `node test/activate.js SETTINGS [WORKSPACE]` saw the extension do.
fn activate_in(settings: Value, workspace: Option<Value>) -> Value {
    let mut node = Command::new("node");
    node.arg("test/activate.js")
        .arg(settings.to_string())
        .current_dir(extension_dir());
    if let Some(workspace) = workspace {
        node.arg(workspace.to_string());
    }
    let out = external::run(&mut node, "node test/activate.js");
    serde_json::from_str(&out).expect("activate.js JSON")
}

/// What `node test/activate.js SETTINGS` saw the extension do.
fn activate(settings: Value) -> Value {
    activate_in(settings, None)
}

#[test]
fn activation_starts_gutta_lsp_with_the_settings() {
    if !external::have("node") {
        return;
    }
    let defaults = activate(serde_json::json!({}));
    assert_eq!(
        defaults["commands"],
        serde_json::json!([
            "gutta.openStudio",
            "gutta.showLadder",
            "gutta.restartServer",
            "gutta.liveValues.toggle"
        ])
    );
    assert_eq!(defaults["taskTypes"], serde_json::json!(["gutta"]));
    let client = &defaults["clients"][0];
    assert_eq!(client["serverOptions"]["command"], "gutta-lsp");
    assert_eq!(
        client["clientOptions"]["documentSelector"],
        serde_json::json!([
            {"scheme": "file", "language": "gutta-lad"},
            {"scheme": "file", "pattern": "**/*.{csv,tsv}"}
        ])
    );
    assert_eq!(
        client["clientOptions"]["initializationOptions"],
        serde_json::json!({"liveValues": false, "inlayHints": {"symbolAddresses": true, "modbus": true, "timerDurations": true}})
    );
    assert_eq!(
        client["clientOptions"]["synchronize"]["configurationSection"],
        "gutta"
    );
    assert_eq!(
        defaults["liveValuesAfterToggle"], true,
        "the toggle flips the setting"
    );
    assert_eq!(defaults["stopped"], 1, "deactivate stops the client");

    let set = activate(serde_json::json!({
        "gutta.server.path": "/opt/gutta/bin/gutta-lsp",
        "gutta.liveValues": true,
        "gutta.inlayHints.modbus": false,
        "gutta.symbolTables": false,
    }));
    let client = &set["clients"][0];
    assert_eq!(
        client["serverOptions"]["command"],
        "/opt/gutta/bin/gutta-lsp"
    );
    assert_eq!(
        client["clientOptions"]["documentSelector"],
        serde_json::json!([{"scheme": "file", "language": "gutta-lad"}])
    );
    assert_eq!(
        client["clientOptions"]["initializationOptions"],
        serde_json::json!({"liveValues": true, "inlayHints": {"symbolAddresses": true, "modbus": false, "timerDurations": true}})
    );
    assert_eq!(set["liveValuesAfterToggle"], false);
}

/// The tasks and problem matchers the manifest contributes: a `gutta` task type whose
/// `command` is build, download or test, and the matchers $gutta and $gutta-test.
fn contributed_task_parts(manifest: &Value) -> (Value, Value) {
    let definitions = manifest["contributes"]["taskDefinitions"]
        .as_array()
        .expect("taskDefinitions");
    assert_eq!(definitions.len(), 1);
    let names: Vec<&str> = manifest["contributes"]["problemMatchers"]
        .as_array()
        .expect("problemMatchers")
        .iter()
        .map(|m| m["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["gutta", "gutta-test"]);
    (
        definitions[0].clone(),
        manifest["contributes"]["problemMatchers"].clone(),
    )
}

#[test]
fn tasks_build_download_and_test_and_their_problems_are_matched() {
    let dir = extension_dir();
    let manifest = read_json(&dir.join("package.json"));
    let (definition, matchers) = contributed_task_parts(&manifest);
    assert_eq!(definition["type"], "gutta");
    assert_eq!(definition["required"], serde_json::json!(["command"]));
    assert_eq!(
        definition["properties"]["command"]["enum"],
        serde_json::json!(["build", "download", "test"])
    );
    for matcher in matchers.as_array().expect("matchers") {
        assert_eq!(
            matcher["fileLocation"],
            serde_json::json!(["relative", "${workspaceFolder}"])
        );
    }
    if !external::have("node") {
        return;
    }
    let work = external::scratch("vscode-tasks");
    // `good` builds and one of its tests fails; `bad` has an error and a warning.
    let good = new_project(&work, "good");
    edit(
        &good.join("tests/main.gtest"),
        "EXPECT Running = 0, Lamp = 0",
        "EXPECT Running = 1  // wrong on purpose",
    );
    let bad = new_project(&work, "bad");
    edit(
        &bad.join("src/main.lad"),
        "END_ORGANIZATION_BLOCK",
        "Network 4 // mistakes\nLD     Strat\n=      Lamp\nEND_ORGANIZATION_BLOCK",
    );
    let run = |project: &Path| -> Value {
        let out = external::run(
            Command::new("node")
                .arg("test/tasks.js")
                .arg(cc_binary())
                .arg(project)
                .current_dir(&dir),
            "node test/tasks.js",
        );
        serde_json::from_str(&out).expect("tasks.js JSON")
    };

    let seen = run(&bad);
    let tasks = seen["asFolder"].as_array().expect("tasks");
    let offered: Vec<Value> = tasks
        .iter()
        .map(|t| serde_json::json!([t["name"], t["args"], t["group"], t["problemMatchers"]]))
        .collect();
    assert_eq!(
        offered,
        [
            serde_json::json!([
                "build",
                ["build", "--message-format", "json"],
                "build",
                ["$gutta"]
            ]),
            serde_json::json!([
                "download",
                ["download", "--message-format", "json"],
                null,
                ["$gutta"]
            ]),
            serde_json::json!([
                "test",
                ["test", "--message-format", "json"],
                "test",
                ["$gutta", "$gutta-test"]
            ]),
        ]
    );
    for task in tasks {
        assert_eq!(task["command"], "gutta-cc");
        assert_eq!(task["cwd"], bad.to_str().expect("utf-8"));
        assert_eq!(task["definition"]["project"], Value::Null, "{task}");
    }
    // A project right below the workspace folder: named, and run in its folder.
    assert_eq!(seen["below"][2]["name"], "test bad");
    assert_eq!(
        seen["below"][2]["definition"],
        serde_json::json!({"type": "gutta", "command": "test", "project": "bad"})
    );
    assert_eq!(seen["below"][2]["cwd"], bad.to_str().expect("utf-8"));
    assert!(
        seen["unknownCommand"]
            .as_str()
            .is_some_and(|m| m.contains("build, download, test")),
        "{seen}"
    );
    // The matchers on gutta-cc's own lines: every field of the error and the warning.
    assert_eq!(seen["runs"]["build"]["status"], 1, "{seen}");
    assert_eq!(
        seen["runs"]["build"]["problems"],
        serde_json::json!([
            {"file": "src/main.lad", "line": "27", "column": "8", "endLine": "27", "endColumn": "13",
             "severity": "error", "code": "E0202", "message": "undefined symbol `Strat`"},
            {"file": "src/main.lad", "line": "28", "column": "8", "endLine": "28", "endColumn": "12",
             "severity": "warning", "code": "W0201", "message": "`Lamp` is also assigned with `=` elsewhere"}
        ]),
        "{seen}"
    );
    let problems = seen["runs"]["test"]["problems"]
        .as_array()
        .expect("problems");
    assert!(
        problems
            .iter()
            .any(|p| p["code"] == "E0202" && p["file"] == "src/main.lad" && p["line"] == "27"),
        "{seen}"
    );

    let seen = run(&good);
    assert_eq!(
        seen["runs"]["build"],
        serde_json::json!({"status": 0, "lines": 0, "problems": []})
    );
    assert_eq!(seen["runs"]["test"]["status"], 1, "{seen}");
    assert_eq!(
        seen["runs"]["test"]["problems"],
        serde_json::json!([{"file": "tests/main.gtest", "line": "15", "severity": "error",
            "message": "EXPECT failed after scan 7 (70 ms): Running (M0.0) = 1 expected, is 0"}]),
        "{seen}"
    );

    // Through the extension: the provider of the `gutta` task type, for a workspace folder
    // holding the project one level down, and a task of tasks.json resolved.
    let seen = activate_in(
        serde_json::json!({"gutta.cc.path": "/opt/gutta/bin/gutta-cc"}),
        Some(serde_json::json!({"folder": work.join("ws-parent")})),
    );
    assert_eq!(seen["tasks"], serde_json::json!([]), "no project, no tasks");
    std::fs::create_dir_all(work.join("ws")).expect("ws");
    let inner = new_project(&work.join("ws"), "blinky");
    let seen = activate_in(
        serde_json::json!({"gutta.cc.path": "/opt/gutta/bin/gutta-cc"}),
        Some(serde_json::json!({"folder": work.join("ws")})),
    );
    let tasks = seen["tasks"].as_array().expect("tasks");
    assert_eq!(tasks.len(), 3, "{seen}");
    for (task, command) in tasks.iter().zip(["build", "download", "test"]) {
        assert_eq!(task["name"], format!("{command} blinky"));
        assert_eq!(task["source"], "gutta");
        assert_eq!(task["process"], "/opt/gutta/bin/gutta-cc");
        assert_eq!(
            task["args"],
            serde_json::json!([command, "--message-format", "json"])
        );
        assert_eq!(task["cwd"], inner.to_str().expect("utf-8"));
        assert_eq!(task["scope"], work.join("ws").to_str().expect("utf-8"));
    }
    assert_eq!(
        seen["resolved"],
        serde_json::json!({"name": "my tests",
            "args": ["test", "--message-format", "json", "--filter", "lamp"],
            "cwd": work.join("ws").to_str().expect("utf-8"),
            "problemMatchers": ["$gutta", "$gutta-test"]})
    );
    let _ = std::fs::remove_dir_all(&work);
}

/// `class="network-view"` elements of a page: one per network drawn.
fn networks_in(html: &str) -> usize {
    html.matches("class=\"network-view\"").count()
}

/// Chromium's console about `file`: the Content-Security-Policy violations it reports.
fn csp_violations(file: &Path, profile: &Path) -> Vec<String> {
    let out = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-logging=stderr",
            "--v=0",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", file.display()))
        .output()
        .expect("chromium starts");
    assert!(out.status.success(), "chromium: {}", out.status);
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("network-view"),
        "chromium loaded {}",
        file.display()
    );
    String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.contains("Content Security Policy"))
        .map(str::to_string)
        .collect()
}

#[test]
fn show_as_ladder_draws_a_lad_file_in_a_webview_and_redraws_it_on_save() {
    let dir = extension_dir();
    let manifest = read_json(&dir.join("package.json"));
    let menus = &manifest["contributes"]["menus"];
    for place in [
        "editor/title",
        "editor/context",
        "explorer/context",
        "commandPalette",
    ] {
        let entry = &menus[place][0];
        assert_eq!(entry["command"], "gutta.showLadder", "{place}");
        assert_eq!(entry["when"], "resourceExtname == .lad", "{place}");
    }
    if !external::have("node") || !external::have("chromium") {
        return;
    }
    let work = external::scratch("vscode-ladder");
    let project = new_project(&work, "blinky");
    let lone = work.join("lone");
    std::fs::create_dir_all(&lone).expect("lone");
    std::fs::copy(
        external::repo_root().join("examples/blink.lad"),
        lone.join("blink.lad"),
    )
    .expect("copies");
    std::fs::write(
        lone.join("bad.lad"),
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     Strat\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("writes");
    let out = work.join("out");
    std::fs::create_dir_all(&out).expect("out");
    let seen: Value = serde_json::from_str(&external::run(
        Command::new("node")
            .arg("test/ladder.js")
            .arg(cc_binary())
            .arg(project.join("src/main.lad"))
            .arg(lone.join("blink.lad"))
            .arg(lone.join("bad.lad"))
            .arg(&out)
            .current_dir(&dir),
        "node test/ladder.js",
    ))
    .expect("ladder.js JSON");
    // A project's source draws the project (its symbol table included), a lone file itself.
    assert_eq!(
        seen["project"]["input"],
        serde_json::json!({"input": project, "cwd": project, "project": true})
    );
    assert_eq!(
        seen["lone"]["input"],
        serde_json::json!({"input": lone.join("blink.lad"), "cwd": lone, "project": false})
    );
    for (name, networks, operand) in [("project", 3, "I0.0"), ("lone", 6, "SM0.5")] {
        let html = std::fs::read_to_string(out.join(format!("{name}.html"))).expect("reads");
        assert_eq!(networks_in(&html), networks, "{name}: {html}");
        assert!(
            html.contains(&format!("data-operand=\"{operand}\"")),
            "{name}: {html}"
        );
        assert_eq!(seen[name]["pageInHtml"], true);
        assert_eq!(seen[name]["white"], true, "black on white in any theme");
        let policy = seen[name]["policy"].as_str().expect("policy");
        assert!(
            policy.starts_with("default-src 'none'; style-src 'sha256-")
                && policy.ends_with("; script-src 'none'")
                && !policy.contains("unsafe"),
            "{policy}"
        );
        assert!(html.contains(&format!("content=\"{policy}\"")), "{html}");
    }
    // Two styles in the webview (the page's, the white background), one in the page.
    let both = seen["project"]["policy"].as_str().expect("policy");
    let page_only = seen["policyOfPage"].as_str().expect("policy");
    assert_eq!(both.matches("'sha256-").count(), 2, "{both}");
    assert_eq!(page_only.matches("'sha256-").count(), 1, "{page_only}");
    // Chromium applies the page's styles under that policy and refuses anything else.
    let page = out.join("project.html");
    let profile = work.join("chromium");
    assert_eq!(csp_violations(&page, &profile), Vec::<String>::new());
    let html = std::fs::read_to_string(&page).expect("reads");
    let tampered = out.join("tampered.html");
    std::fs::write(
        &tampered,
        html.replace(
            "</body>",
            "<style>h1{color:red}</style><script>document.title='x'</script>\
             <p style=\"color:red\">x</p></body>",
        ),
    )
    .expect("writes");
    let refused = csp_violations(&tampered, &profile);
    assert_eq!(refused.len(), 3, "{refused:?}");
    // A style attribute the page carries is allowed by its hash ('unsafe-hashes').
    let styled = seen["styledPolicy"].as_str().expect("policy");
    assert!(styled.contains("'unsafe-hashes' 'sha256-"), "{styled}");
    assert_eq!(
        csp_violations(&out.join("styled.html"), &profile),
        Vec::<String>::new()
    );
    let bad = seen["bad"]
        .as_str()
        .expect("a program with errors is refused");
    assert!(bad.contains("E0202") && bad.contains("Strat"), "{bad}");
    assert!(seen["badHtml"]
        .as_str()
        .expect("html")
        .contains("undefined symbol `Strat`"));
    assert!(
        seen["missing"]
            .as_str()
            .is_some_and(|m| m.contains("gutta.cc.path")),
        "{seen}"
    );

    // The command itself, through the extension: a panel beside the file, redrawn when the
    // file is saved; the same file again reuses the panel; not a .lad file is refused.
    let main = project.join("src/main.lad");
    let seen = activate_in(
        serde_json::json!({"gutta.cc.path": cc_binary()}),
        Some(serde_json::json!({"folder": work, "ladder": main})),
    );
    let ladder = &seen["ladder"];
    assert_eq!(ladder["title"], "Ladder: main.lad");
    assert_eq!(
        ladder["options"],
        serde_json::json!({"enableScripts": false, "localResourceRoots": []})
    );
    let first = ladder["html"].as_str().expect("html");
    assert_eq!(networks_in(first), 3, "{first}");
    assert!(first.contains("Content-Security-Policy"), "{first}");
    let after = ladder["afterSave"].as_str().expect("html");
    assert_eq!(networks_in(after), 4, "{after}");
    assert!(after.contains("data-operand=\"Q0.7\""), "{after}");
    assert_eq!(ladder["panels"], 1);
    let errors: Vec<&Value> = seen["clients"]
        .as_array()
        .expect("clients")
        .iter()
        .filter(|c| c["error"].is_string())
        .collect();
    assert_eq!(errors.len(), 1, "{seen}");
    assert!(errors[0]["error"]
        .as_str()
        .expect("message")
        .contains(".lad"));
    let _ = std::fs::remove_dir_all(&work);
}

/// One token of the tokenizer's answer.
struct Token {
    text: String,
    scopes: Vec<String>,
}

fn tokens_of(answer: &Value, file: &Path) -> Vec<Vec<Token>> {
    let lines = answer[file.to_str().expect("utf-8 path")]
        .as_array()
        .unwrap_or_else(|| panic!("no tokens for {}", file.display()));
    lines
        .iter()
        .map(|line| {
            line.as_array()
                .expect("tokens")
                .iter()
                .map(|t| Token {
                    text: t["text"].as_str().expect("text").to_string(),
                    scopes: t["scopes"]
                        .as_array()
                        .expect("scopes")
                        .iter()
                        .map(|s| s.as_str().expect("scope").to_string())
                        .collect(),
                })
                .collect()
        })
        .collect()
}

/// The innermost scope of the token `text` on 1-based `line`.
fn scope_of(lines: &[Vec<Token>], line: usize, text: &str) -> String {
    lines[line - 1]
        .iter()
        .find(|t| t.text == text)
        .unwrap_or_else(|| panic!("no token `{text}` on line {line}"))
        .scopes
        .last()
        .cloned()
        .unwrap_or_default()
}

/// A program naming every mnemonic and alias of the stdlib's instruction set once in
/// upper and once in lower case; the mnemonics in line order.
fn every_mnemonic() -> (String, Vec<String>) {
    let mut mnemonics = BTreeSet::new();
    for plc in gutta_catalog::stdlib::names() {
        let target = gutta_catalog::stdlib::shared(plc).expect("stdlib target");
        for (name, _) in target.instructions.names() {
            mnemonics.insert(name.to_string());
        }
    }
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n");
    let mut order = Vec::new();
    for m in &mnemonics {
        for written in [m.clone(), m.to_lowercase()] {
            text.push_str(&format!("{written:<7} MW0, 1 // x\n"));
            order.push(written);
        }
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    (text, order)
}

#[test]
fn package_builds_and_the_grammar_colours_every_construct() {
    if !external::have("npm") || !external::have("node") {
        return;
    }
    let work = external::scratch("vscode");
    let copy = work.join("vscode");
    external::copy_tree(&extension_dir(), &copy, &["node_modules"]);
    let _ = std::fs::remove_file(copy.join("gutta-lad.vsix"));
    external::run(
        Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund"])
            .current_dir(&copy),
        "npm ci",
    );
    external::run(
        Command::new("npm")
            .args(["run", "package"])
            .current_dir(&copy),
        "npm run package",
    );
    let vsix =
        std::fs::read(copy.join("gutta-lad.vsix")).expect("npm run package writes gutta-lad.vsix");
    for inside in [
        "extension/syntaxes/gutta-lad.tmLanguage.json",
        "extension/language-configuration.json",
        "extension/src/extension.js",
        "extension/src/studio.js",
        "extension/src/ladder.js",
        "extension/src/tasks.js",
        "extension/node_modules/vscode-languageclient/package.json",
    ] {
        assert!(
            vsix.windows(inside.len()).any(|w| w == inside.as_bytes()),
            "the .vsix lacks {inside}"
        );
    }

    let blink = external::repo_root().join("examples/blink.lad");
    let (program, mnemonics) = every_mnemonic();
    let all = work.join("mnemonics.lad");
    std::fs::write(&all, program).expect("writes");
    let answer = external::run(
        Command::new("node")
            .arg("test/tokenize.js")
            .arg(&blink)
            .arg(&all)
            .current_dir(&copy),
        "node test/tokenize.js",
    );
    let answer: Value = serde_json::from_str(&answer).expect("tokenizer JSON");

    let lines = tokens_of(&answer, &blink);
    let expect = [
        (1, "//", "punctuation.definition.comment.gutta-lad"),
        (3, "PLC_TYPE", "keyword.control.directive.gutta-lad"),
        (3, "CPU-EC20", "support.constant.plc-type.gutta-lad"),
        (5, "SYMBOLS", "keyword.control.block.gutta-lad"),
        (6, "Start", "entity.name.variable.symbol.gutta-lad"),
        (6, "I0.0", "variable.language.address.input.gutta-lad"),
        (10, "ORGANIZATION_BLOCK", "keyword.control.block.gutta-lad"),
        (10, "MAIN", "entity.name.function.block.gutta-lad"),
        (10, "OB1", "entity.name.function.block.number.gutta-lad"),
        (11, "TITLE=", "keyword.control.title.gutta-lad"),
        (13, "Network", "keyword.control.network.gutta-lad"),
        (14, "LD", "keyword.other.mnemonic.bit.gutta-lad"),
        (14, "Start", "variable.other.symbol.gutta-lad"),
        (17, "=", "keyword.other.mnemonic.bit.gutta-lad"),
        (19, "SM0.1", "variable.language.address.system.gutta-lad"),
        (20, "&", "keyword.operator.address-of.gutta-lad"),
        (20, "MB24", "variable.language.address.memory.gutta-lad"),
        (21, "16#0E01", "constant.numeric.based.gutta-lad"),
        (21, "*", "keyword.operator.pointer.gutta-lad"),
        (22, "+D", "keyword.other.mnemonic.math.gutta-lad"),
        (26, "CALL", "keyword.other.mnemonic.control.gutta-lad"),
        (26, "ADD3", "entity.name.function.block.gutta-lad"),
        (26, "+5", "constant.numeric.integer.gutta-lad"),
        (35, "a", "variable.parameter.declaration.gutta-lad"),
        (35, "INT", "storage.type.gutta-lad"),
        (47, "a", "variable.parameter.local.gutta-lad"),
        (64, "-70000", "constant.numeric.integer.gutta-lad"),
        (
            68,
            "PORT0.PROTOCOL",
            "variable.other.property.key.gutta-lad",
        ),
        (68, "MODBUS", "constant.language.gutta-lad"),
        (75, "1234", "string.quoted.double.gutta-lad"),
        (76, "END_SYSTEM_BLOCK", "keyword.control.block.gutta-lad"),
    ];
    for (line, text, scope) in expect {
        assert_eq!(
            scope_of(&lines, line, text),
            scope,
            "`{text}` on line {line}"
        );
    }
    assert!(
        lines[12].iter().any(|t| t.text.starts_with("latch")
            && t.scopes.iter().any(|s| s.starts_with("comment.line"))),
        "a network's title is a comment"
    );
    assert!(
        lines
            .iter()
            .flatten()
            .all(|t| !t.scopes.iter().any(|s| s.starts_with("invalid"))),
        "blink.lad is valid, so nothing in it is coloured invalid"
    );

    let lines = tokens_of(&answer, &all);
    for (i, mnemonic) in mnemonics.iter().enumerate() {
        let scope = scope_of(&lines, i + 4, mnemonic);
        assert!(
            scope.starts_with("keyword.other.mnemonic."),
            "mnemonic `{mnemonic}` is coloured {scope}"
        );
        if ["CALL", "ATCH", "DTCH"].contains(&mnemonic.to_uppercase().as_str()) {
            continue; // their first operand is a block's name
        }
        assert_eq!(
            scope_of(&lines, i + 4, "MW0"),
            "variable.language.address.memory.gutta-lad",
            "the operand after `{mnemonic}`"
        );
    }
    let _ = std::fs::remove_dir_all(&work);
}
