// The GUTTA extension: starts the `gutta-lsp` language server (docs/editors.md) for
// .lad files and a project's symbol tables, passes the `gutta.*` settings to it, and
// adds two commands. Everything the editor shows beyond colours comes from the
// server; this file holds no language knowledge. `GUTTA: Open Studio` runs
// `gutta-cc studio` for the workspace's project and shows it in a webview (src/studio.js).
'use strict';

const path = require('path');
const fs = require('fs');
const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');
const { launchStudio, studioHtml } = require('./studio');

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

/** The first workspace folder holding a gutta.toml (itself, else one level down). */
function projectFolder() {
  const folders = (vscode.workspace.workspaceFolders || []).map((f) => f.uri.fsPath);
  for (const folder of folders) {
    if (fs.existsSync(path.join(folder, 'gutta.toml'))) return folder;
  }
  for (const folder of folders) {
    let entries = [];
    try {
      entries = fs.readdirSync(folder, { withFileTypes: true });
    } catch (e) {
      continue;
    }
    for (const entry of entries) {
      const inner = path.join(folder, entry.name);
      if (entry.isDirectory() && fs.existsSync(path.join(inner, 'gutta.toml'))) return inner;
    }
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

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  context.subscriptions.push(
    vscode.commands.registerCommand('gutta.openStudio', openStudio),
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

module.exports = { activate, deactivate, openStudio };
