// The GUTTA extension: starts the `gutta-lsp` language server (docs/editors.md) for
// .lad files and a project's symbol tables, passes the `gutta.*` settings to it, and
// adds its commands. Everything the editor shows beyond colours comes from the
// server; this file holds no language knowledge. `GUTTA: Open Studio` runs
// `gutta-cc studio` for the workspace's project and shows it in a webview (src/studio.js);
// `GUTTA: Show as ladder` shows a .lad file drawn by `gutta-cc ladder` (src/ladder.js);
// the `gutta` task provider offers build, download and test (src/tasks.js).
'use strict';

const path = require('path');
const fs = require('fs');
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');
const { launchStudio, studioHtml } = require('./studio');
const { drawLadder, ladderWebviewHtml, ladderErrorHtml } = require('./ladder');
const { providedTasks, taskCommandLine, taskFolder, problemMatchersOf, TASK_COMMANDS } = require('./tasks');

/** @type {LanguageClient | undefined} */
let client;

function serverOptions() {
  const config = vscode.workspace.getConfiguration('gutta');
  const command = config.get('server.path') || 'gutta-lsp';
  const extraEnv = config.get('server.extraEnv') || {};
  return {
    command,
    args: [],
    transport: TransportKind.stdio,
    options: { env: { ...process.env, ...extraEnv } },
  };
}

function clientOptions() {
  const config = vscode.workspace.getConfiguration('gutta');
  const documentSelector = [{ scheme: 'file', language: 'gutta-lad' }];
  if (config.get('symbolTables')) {
    documentSelector.push({ scheme: 'file', pattern: '**/*.{csv,tsv}' });
  }
  return {
    documentSelector,
    // Sent in `initialize`; later changes arrive as workspace/didChangeConfiguration
    // with the whole `gutta` section: {"gutta": {"liveValues": true, ...}}.
    initializationOptions: {
      liveValues: config.get('liveValues') === true,
      inlayHints: {
        symbolAddresses: config.get('inlayHints.symbolAddresses') !== false,
        modbus: config.get('inlayHints.modbus') !== false,
        timerDurations: config.get('inlayHints.timerDurations') !== false,
      },
    },
    synchronize: { configurationSection: 'gutta' },
  };
}

async function start() {
  client = new LanguageClient('gutta-lsp', 'GUTTA language server', serverOptions(), clientOptions());
  try {
    await client.start();
  } catch (e) {
    const path = vscode.workspace.getConfiguration('gutta').get('server.path');
    vscode.window.showErrorMessage(
      `GUTTA: could not start \`${path}\` (${e && e.message ? e.message : e}). ` +
        'Install it with `cargo install --locked --path lsp` or set `gutta.server.path`.',
    );
  }
}

async function stop() {
  if (client) {
    const running = client;
    client = undefined;
    await running.stop();
  }
}

/** The project of one workspace folder: the folder itself when it holds a gutta.toml,
 * else the first folder right below it that does. */
function projectIn(folder) {
  if (fs.existsSync(path.join(folder, 'gutta.toml'))) return folder;
  let entries = [];
  try {
    entries = fs.readdirSync(folder, { withFileTypes: true });
  } catch (e) {
    return undefined;
  }
  for (const entry of entries) {
    const inner = path.join(folder, entry.name);
    if (entry.isDirectory() && fs.existsSync(path.join(inner, 'gutta.toml'))) return inner;
  }
  return undefined;
}

/** The first workspace folder holding a gutta.toml (itself, else one level down). */
function projectFolder() {
  const folders = (vscode.workspace.workspaceFolders || []).map((f) => f.uri.fsPath);
  for (const folder of folders) {
    if (fs.existsSync(path.join(folder, 'gutta.toml'))) return folder;
  }
  for (const folder of folders) {
    const inner = projectIn(folder);
    if (inner) return inner;
  }
  return undefined;
}

/** `GUTTA: Open Studio`: the studio of the workspace's project in a webview panel; the
 * gutta-cc process ends when the panel closes. */
async function openStudio() {
  const folder = projectFolder();
  if (!folder) {
    vscode.window.showErrorMessage('GUTTA: no gutta.toml in the workspace: open a project folder (`gutta-cc new`).');
    return;
  }
  const config = vscode.workspace.getConfiguration('gutta');
  const command = config.get('cc.path') || 'gutta-cc';
  let studio;
  try {
    studio = await launchStudio({ command, folder });
  } catch (e) {
    vscode.window.showErrorMessage(`GUTTA: ${e && e.message ? e.message : e}`);
    return;
  }
  const panel = vscode.window.createWebviewPanel(
    'guttaStudio',
    `GUTTA Studio: ${path.basename(folder)}`,
    vscode.ViewColumn.Active,
    { enableScripts: false, retainContextWhenHidden: true },
  );
  panel.webview.html = studioHtml(studio.url, studio.origin);
  panel.onDidDispose(() => {
    studio.stop();
  });
  studio.exited.then(({ code }) => {
    if (code !== 0 && code !== null) {
      vscode.window.showErrorMessage(`GUTTA: gutta-cc studio ended (exit ${code}).`);
    }
  });
  return studio;
}

/** The gutta-cc executable of the setting gutta.cc.path. */
function ccPath() {
  return vscode.workspace.getConfiguration('gutta').get('cc.path') || 'gutta-cc';
}

/** Ladder panels by file path: one panel per file, redrawn when it is saved. */
const ladderPanels = new Map();

/** Draws requested per panel: only the latest request's drawing is shown (saves in a
 * row may finish out of order). */
const ladderDraws = new WeakMap();

/** Draw `file` into `panel` (the reason instead, when gutta-cc cannot draw it). */
async function redrawLadder(panel, file) {
  const draw = (ladderDraws.get(panel) || 0) + 1;
  ladderDraws.set(panel, draw);
  let html;
  let enableScripts = false;
  try {
    const page = await drawLadder({ command: ccPath(), file });
    enableScripts = /<script[\s>]/i.test(page);
    html = ladderWebviewHtml(page);
  } catch (e) {
    html = ladderErrorHtml(file, e && e.message ? e.message : String(e));
  }
  if (ladderDraws.get(panel) !== draw || ladderPanels.get(file) !== panel) return undefined; // superseded or closed
  panel.webview.options = { enableScripts, localResourceRoots: [] };
  panel.webview.html = html;
  return html;
}

/** `GUTTA: Show as ladder`: the .lad file (the command's argument from a menu, else the
 * active editor's) drawn by `gutta-cc ladder` in a webview beside it. */
async function showLadder(uri) {
  const target = uri && uri.fsPath ? uri : vscode.window.activeTextEditor && vscode.window.activeTextEditor.document.uri;
  if (!target || target.scheme !== 'file' || path.extname(target.fsPath).toLowerCase() !== '.lad') {
    vscode.window.showErrorMessage('GUTTA: Show as ladder draws a .lad file: open one first.');
    return undefined;
  }
  const file = target.fsPath;
  let panel = ladderPanels.get(file);
  if (panel) {
    panel.reveal(vscode.ViewColumn.Beside, true);
  } else {
    panel = vscode.window.createWebviewPanel(
      'guttaLadder',
      `Ladder: ${path.basename(file)}`,
      { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
      { enableScripts: false, localResourceRoots: [] },
    );
    ladderPanels.set(file, panel);
    panel.onDidDispose(() => ladderPanels.delete(file));
  }
  return redrawLadder(panel, file);
}

/** A saved file redraws the ladder panels it may change: its own, and those of the files
 * in its folder and below (a project's other sources, its symbol tables, gutta.toml). */
function redrawOnSave(document) {
  const saved = document.uri.fsPath;
  if (!['.lad', '.csv', '.tsv', '.toml'].includes(path.extname(saved).toLowerCase())) return;
  const folder = path.dirname(saved) + path.sep;
  for (const [file, panel] of ladderPanels) {
    if (file === saved || file.startsWith(folder)) redrawLadder(panel, file);
  }
}

/** A vscode.Task from one of src/tasks.js's descriptions. */
function toTask(spec, scope) {
  const task = new vscode.Task(
    spec.definition,
    scope,
    spec.name,
    'gutta',
    new vscode.ProcessExecution(spec.command, spec.args, { cwd: spec.cwd }),
    spec.problemMatchers,
  );
  if (spec.group === 'build') task.group = vscode.TaskGroup.Build;
  if (spec.group === 'test') task.group = vscode.TaskGroup.Test;
  return task;
}

/** The `gutta` task provider: build, download and test for each project of the workspace. */
const taskProvider = {
  provideTasks() {
    const specs = [];
    for (const folder of vscode.workspace.workspaceFolders || []) {
      const project = projectIn(folder.uri.fsPath);
      if (!project) continue;
      for (const spec of providedTasks([{ folder: folder.uri.fsPath, project }], ccPath())) {
        specs.push(toTask(spec, folder));
      }
    }
    return specs;
  },
  resolveTask(task) {
    const definition = task.definition;
    if (!TASK_COMMANDS.some((t) => t.command === definition.command)) return undefined;
    const scope = task.scope && task.scope.uri ? task.scope : (vscode.workspace.workspaceFolders || [])[0];
    if (!scope) return undefined;
    const line = taskCommandLine(definition, ccPath());
    const spec = {
      definition,
      name: task.name,
      cwd: taskFolder(scope.uri.fsPath, definition),
      ...line,
      group: (TASK_COMMANDS.find((t) => t.command === definition.command) || {}).group,
      problemMatchers: problemMatchersOf(definition.command),
    };
    return toTask(spec, scope);
  },
};

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  context.subscriptions.push(
    vscode.commands.registerCommand('gutta.openStudio', openStudio),
    vscode.commands.registerCommand('gutta.showLadder', showLadder),
    vscode.workspace.onDidSaveTextDocument(redrawOnSave),
    vscode.tasks.registerTaskProvider('gutta', taskProvider),
    vscode.commands.registerCommand('gutta.restartServer', async () => {
      await stop();
      await start();
    }),
    vscode.commands.registerCommand('gutta.liveValues.toggle', async () => {
      const config = vscode.workspace.getConfiguration('gutta');
      const on = !(config.get('liveValues') === true);
      await config.update('liveValues', on, vscode.ConfigurationTarget.Workspace);
      vscode.window.setStatusBarMessage(`GUTTA live values ${on ? 'on' : 'off'}`, 3000);
    }),
    vscode.workspace.onDidChangeConfiguration(async (event) => {
      // The executable, its environment, the documents served and the inlay hints are
      // fixed when the server starts: restart for those. `gutta.liveValues` reaches the
      // running server (workspace/didChangeConfiguration).
      if (
        event.affectsConfiguration('gutta.server') ||
        event.affectsConfiguration('gutta.symbolTables') ||
        event.affectsConfiguration('gutta.inlayHints')
      ) {
        await stop();
        await start();
      }
    }),
  );
  await start();
}

async function deactivate() {
  await stop();
}

module.exports = { activate, deactivate, openStudio, showLadder, taskProvider };
