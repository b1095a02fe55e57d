// Runs the extension's activate() in plain Node with stand-ins for the `vscode` and
// `vscode-languageclient/node` modules, and prints what it did as JSON: the commands it
// registered and, for each language client it started, the server command, the
// documents it serves and the initializationOptions. The settings come from argv[2]
// (JSON, `{"gutta.server.path": ...}`), else the manifest's defaults; the toggle command
// is run once. With argv[3] (JSON, `{"folder": WORKSPACE_FOLDER, "ladder": FILE.lad}`) it
// also reports the tasks the `gutta` task provider offers for that workspace folder, and
// runs "Show as ladder" on the file (gutta.cc.path from the settings) in a stand-in
// webview panel, then appends a network to the file, "saves" it and reports the redrawn
// panel. lsp/tests/vscode_package.rs holds the assertions.
'use strict';

const Module = require('module');
const path = require('path');

const fs = require('fs');

const settings = JSON.parse(process.argv[2] || '{}');
const workspace = JSON.parse(process.argv[3] || '{}');
const report = { commands: [], clients: [], stopped: 0 };
const handlers = {};
const saveHandlers = [];
const taskProviders = {};
const panels = [];

class Task {
  constructor(definition, scope, name, source, execution, problemMatchers) {
    Object.assign(this, { definition, scope, name, source, execution, problemMatchers });
  }
}
class ProcessExecution {
  constructor(process, args, options) {
    Object.assign(this, { process, args, options });
  }
}

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
    onDidSaveTextDocument: (handler) => {
      saveHandlers.push(handler);
      return { dispose() {} };
    },
    workspaceFolders: workspace.folder
      ? [{ uri: { fsPath: workspace.folder, scheme: 'file' }, name: path.basename(workspace.folder), index: 0 }]
      : undefined,
  },
  window: {
    showErrorMessage: (message) => report.clients.push({ error: message }),
    setStatusBarMessage: () => ({ dispose() {} }),
    createWebviewPanel: (viewType, title, showOptions, options) => {
      const panel = {
        viewType,
        title,
        createdWith: options,
        webview: { html: '', options },
        reveal() {},
        onDidDispose: () => ({ dispose() {} }),
      };
      panels.push(panel);
      return panel;
    },
  },
  tasks: {
    registerTaskProvider: (type, provider) => {
      taskProviders[type] = provider;
      return { dispose() {} };
    },
  },
  Task,
  ProcessExecution,
  TaskGroup: { Build: 'build', Test: 'test' },
  ViewColumn: { Active: -1, Beside: -2 },
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
  report.taskTypes = Object.keys(taskProviders);
  if (workspace.folder) {
    report.tasks = taskProviders.gutta.provideTasks().map((t) => ({
      name: t.name,
      source: t.source,
      definition: t.definition,
      group: t.group,
      scope: t.scope.uri.fsPath,
      process: t.execution.process,
      args: t.execution.args,
      cwd: t.execution.options.cwd,
      problemMatchers: t.problemMatchers,
    }));
    // A task of tasks.json: `{"type": "gutta", "command": "test", "args": [...]}`.
    const definition = { type: 'gutta', command: 'test', args: ['--filter', 'lamp'] };
    const resolved = taskProviders.gutta.resolveTask(
      new Task(definition, vscode.workspace.workspaceFolders[0], 'my tests', 'Workspace'),
    );
    report.resolved = resolved && { name: resolved.name, args: resolved.execution.args, cwd: resolved.execution.options.cwd, problemMatchers: resolved.problemMatchers };
  }
  if (workspace.ladder) {
    const uri = { fsPath: workspace.ladder, scheme: 'file' };
    await handlers['gutta.showLadder'](uri);
    const panel = panels.find((p) => p.viewType === 'guttaLadder');
    const first = panel.webview.html;
    report.ladder = { title: panel.title, options: panel.webview.options, html: first };
    const source = fs.readFileSync(workspace.ladder, 'utf8');
    fs.writeFileSync(
      workspace.ladder,
      source.replace(/END_ORGANIZATION_BLOCK/, 'Network 99 // added by the test\nLD     SM0.0\n=      Q0.7\nEND_ORGANIZATION_BLOCK'),
    );
    for (const handler of saveHandlers) handler({ uri });
    const started = Date.now();
    while (panel.webview.html === first && Date.now() - started < 20000) {
      await new Promise((r) => setTimeout(r, 50));
    }
    report.ladder.afterSave = panel.webview.html;
    await handlers['gutta.showLadder'](uri);
    report.ladder.panels = panels.filter((p) => p.viewType === 'guttaLadder').length;
    await handlers['gutta.showLadder']({ fsPath: path.join(workspace.folder || '/', 'notes.txt'), scheme: 'file' });
  }
  await extension.deactivate();
  for (const c of report.clients) {
    if (c.serverOptions) delete c.serverOptions.options; // the whole environment
  }
  process.stdout.write(JSON.stringify(report) + '\n');
})().catch((e) => {
  process.stderr.write(`activate: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
