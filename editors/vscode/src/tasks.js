// The `gutta` tasks (docs/editors.md, "Tasks"): build, download and test a project with
// gutta-cc, their diagnostics read into the Problems panel by the problem matchers the
// manifest contributes ($gutta, $gutta-test). gutta-cc prints one JSON object per line
// with `--message-format json`, so the matchers read one line each: a diagnostic
// (`{"code":"E0202","severity":"error","message":...,"file":...,"line":...,"column":...,
// "end_line":...,"end_column":...}`) or a failed test (`{...,"failure":{"kind":...,
// "line":...,"message":...},"file":...,"status":"failed",...}`). Plain Node: no `vscode`
// module here, so test/tasks.js checks the command lines and the matchers on the real
// gutta-cc's output; src/extension.js turns these into vscode.Task objects.
'use strict';

const path = require('path');

/** The commands a `gutta` task runs, in the order the provider offers them, with the
 * task group each belongs to. */
const TASK_COMMANDS = [
  { command: 'build', group: 'build' },
  { command: 'download', group: undefined },
  { command: 'test', group: 'test' },
];

/** The problem matchers of each command (names as tasks.json writes them). */
function problemMatchersOf(command) {
  return command === 'test' ? ['$gutta', '$gutta-test'] : ['$gutta'];
}

/**
 * The command line of a task definition `{type: "gutta", command, project?, args?}`.
 * @param {{command: string, args?: string[]}} definition
 * @param {string} cc the gutta-cc executable (setting gutta.cc.path)
 * @returns {{command: string, args: string[]}}
 */
function taskCommandLine(definition, cc) {
  if (!TASK_COMMANDS.some((t) => t.command === definition.command)) {
    throw new Error(
      `a gutta task's "command" is one of ${TASK_COMMANDS.map((t) => t.command).join(', ')}, ` +
        `not ${JSON.stringify(definition.command)}`,
    );
  }
  return { command: cc, args: [definition.command, '--message-format', 'json', ...(definition.args || [])] };
}

/**
 * The folder a task runs in: the workspace folder, or its subfolder `project`.
 * @param {string} workspaceFolder
 * @param {{project?: string}} definition
 */
function taskFolder(workspaceFolder, definition) {
  return definition.project ? path.resolve(workspaceFolder, definition.project) : workspaceFolder;
}

/**
 * The tasks offered for a workspace: each command for each project.
 * @param {{folder: string, project: string}[]} projects workspace folder and project
 *   folder (the same, or one right below it)
 * @param {string} cc
 */
function providedTasks(projects, cc) {
  const tasks = [];
  for (const { folder, project } of projects) {
    const relative = path.relative(folder, project);
    for (const { command, group } of TASK_COMMANDS) {
      const definition = { type: 'gutta', command };
      if (relative) definition.project = relative.split(path.sep).join('/');
      tasks.push({
        definition,
        name: relative ? `${command} ${definition.project}` : command,
        cwd: project,
        ...taskCommandLine(definition, cc),
        group,
        problemMatchers: problemMatchersOf(command),
      });
    }
  }
  return tasks;
}

/**
 * What a manifest problem matcher reads from one line, as VS Code's matcher would:
 * its regexp and the groups it names. Used by test/tasks.js on real output.
 * @param {{pattern: object, severity?: string}} matcher the manifest's entry
 * @param {string} line
 */
function matchLine(matcher, line) {
  const pattern = matcher.pattern;
  const m = new RegExp(pattern.regexp).exec(line);
  if (!m) return null;
  const out = {};
  for (const key of ['file', 'line', 'column', 'endLine', 'endColumn', 'severity', 'code', 'message']) {
    if (pattern[key] !== undefined) out[key] = m[pattern[key]];
  }
  if (out.severity === undefined && matcher.severity) out.severity = matcher.severity;
  return out;
}

module.exports = { TASK_COMMANDS, problemMatchersOf, taskCommandLine, taskFolder, providedTasks, matchLine };
