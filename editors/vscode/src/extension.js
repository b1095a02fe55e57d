// The GUTTA extension: starts the `gutta-lsp` language server (docs/editors.md) for
// .lad files and a project's symbol tables, passes the `gutta.*` settings to it, and
// adds two commands. Everything the editor shows beyond colours comes from the
// server; this file holds no language knowledge.
'use strict';

const vscode = require('vscode');
const { LanguageClient, TransportKind } = require('vscode-languageclient/node');

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

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  context.subscriptions.push(
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

module.exports = { activate, deactivate };
