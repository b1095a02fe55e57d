// Checks the `gutta` tasks (src/tasks.js) and the manifest's problem matchers against a
// real gutta-cc: `node test/tasks.js GUTTA_CC PROJECT`. It lists the tasks offered for
// the project (as the workspace folder, and as a folder right below one), runs each
// matcher over the lines gutta-cc prints for the project (`build` and `test` with
// `--message-format json`, in the project folder, as the task does), and reports what
// each matcher read from each line and the exit status. Prints JSON;
// lsp/tests/vscode_package.rs holds the assertions.
'use strict';

const { spawnSync } = require('child_process');
const path = require('path');
const { providedTasks, taskCommandLine, matchLine } = require(path.join(__dirname, '..', 'src', 'tasks.js'));
const manifest = require(path.join(__dirname, '..', 'package.json'));

const [cc, project] = process.argv.slice(2);
const matchers = Object.fromEntries(manifest.contributes.problemMatchers.map((m) => [`$${m.name}`, m]));
const report = {
  asFolder: providedTasks([{ folder: project, project }], 'gutta-cc'),
  below: providedTasks([{ folder: path.dirname(project), project }], '/opt/gutta/bin/gutta-cc').map((t) => ({
    name: t.name,
    definition: t.definition,
    cwd: t.cwd,
  })),
  runs: {},
};
try {
  taskCommandLine({ command: 'flash' }, 'gutta-cc');
} catch (e) {
  report.unknownCommand = e.message;
}
for (const task of report.asFolder) {
  if (task.definition.command === 'download') continue; // needs a PLC
  const run = spawnSync(cc, task.args, { cwd: task.cwd, encoding: 'utf8' });
  const lines = run.stdout.split('\n').filter((l) => l !== '');
  report.runs[task.definition.command] = {
    status: run.status,
    lines: lines.length,
    problems: lines.flatMap((line) =>
      task.problemMatchers.map((name) => matchLine(matchers[name], line)).filter((p) => p !== null),
    ),
  };
}
process.stdout.write(JSON.stringify(report) + '\n');
