// Runs the extension's activate() in plain Node with stand-ins for the `vscode` and
// `vscode-languageclient/node` modules, and prints what it did as JSON: the commands it
// registered and, for each language client it started, the server command, the
// documents it serves and the initializationOptions. The settings come from argv[2]
// (JSON, `{"gutta.server.path": ...}`), else the manifest's defaults; the toggle command
// is run once. lsp/tests/vscode_package.rs holds the assertions.
'use strict';

const Module = require('module');
const path = require('path');

const settings = JSON.parse(process.argv[2] || '{}');
const report = { commands: [], clients: [], stopped: 0 };
const handlers = {};

const vscode = {
  workspace: {
    getConfiguration: (section) => ({
      get: (key) => {
        const manifest = require('../package.json');
        const full = `${section}.${key}`;
        if (full in settings) return settings[full];
        const declared = manifest.contributes.configuration.properties[full];
        return declared ? declared.default : undefined;
      },
      update: async (key, value) => {
        settings[`${section}.${key}`] = value;
      },
    }),
    onDidChangeConfiguration: () => ({ dispose() {} }),
  },
  window: {
    showErrorMessage: (message) => report.clients.push({ error: message }),
    setStatusBarMessage: () => ({ dispose() {} }),
  },
  commands: {
    registerCommand: (id, run) => {
      report.commands.push(id);
      handlers[id] = run;
      return { dispose() {} };
    },
  },
  ConfigurationTarget: { Workspace: 2 },
};

class LanguageClient {
  constructor(id, name, serverOptions, clientOptions) {
    this.entry = { id, name, serverOptions, clientOptions };
    report.clients.push(this.entry);
  }
  async start() {}
  async stop() {
    report.stopped += 1;
  }
}
const languageClient = { LanguageClient, TransportKind: { stdio: 0 } };

const resolve = Module._resolveFilename;
Module._resolveFilename = function (request, ...rest) {
  if (request === 'vscode' || request === 'vscode-languageclient/node') return request;
  return resolve.call(this, request, ...rest);
};
require.cache.vscode = { id: 'vscode', filename: 'vscode', loaded: true, exports: vscode };
require.cache['vscode-languageclient/node'] = {
  id: 'vscode-languageclient/node',
  filename: 'vscode-languageclient/node',
  loaded: true,
  exports: languageClient,
};

const extension = require(path.join(__dirname, '..', 'src', 'extension.js'));

(async () => {
  const context = { subscriptions: [] };
  await extension.activate(context);
  await handlers['gutta.liveValues.toggle']();
  report.liveValuesAfterToggle = settings['gutta.liveValues'];
  await extension.deactivate();
  for (const c of report.clients) {
    if (c.serverOptions) delete c.serverOptions.options; // the whole environment
  }
  process.stdout.write(JSON.stringify(report) + '\n');
})().catch((e) => {
  process.stderr.write(`activate: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
