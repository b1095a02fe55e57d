// Runs the extension's studio launcher (src/studio.js) against a real gutta-cc:
// `node test/studio.js GUTTA_CC PROJECT_FOLDER`. It parses the first line, starts the
// studio, asks it for its page and its project as the webview's frame does (the
// studio's own Origin) and as a foreign page would, builds the webview's HTML, stops
// the process and asks again; a missing executable and a folder that is no project
// are refused with a message. Prints what it saw as JSON; lsp/tests/vscode_package.rs
// holds the assertions.
'use strict';

const fs = require('fs');
const os = require('os');
const path = require('path');
const { launchStudio, parseStudioLine, studioHtml } = require(path.join(__dirname, '..', 'src', 'studio.js'));

const [command, folder] = process.argv.slice(2);
const report = {};

async function status(url, headers) {
  try {
    const answer = await fetch(url, { headers });
    return { status: answer.status, text: await answer.text() };
  } catch (e) {
    return { error: String(e && e.cause ? e.cause.code || e.cause : e) };
  }
}

async function refusal(options) {
  try {
    const s = await launchStudio(options);
    await s.stop();
    return null;
  } catch (e) {
    return e.message;
  }
}

(async () => {
  report.parsed = parseStudioLine('gutta-cc studio: http://127.0.0.1:4711/?token=abc_DEF-1');
  report.notParsed = [
    parseStudioLine('gutta-cc studio: http://127.0.0.1:4711/'),
    parseStudioLine('listening on http://127.0.0.1:4711/?token=abc'),
  ];
  const studio = await launchStudio({ command, folder });
  report.url = studio.url;
  report.origin = studio.origin;
  report.pid = studio.process.pid;
  const page = await status(studio.url, {});
  report.page = { status: page.status, hasStatusBar: /class="status"/.test(page.text || '') };
  report.ownOrigin = (
    await status(`${studio.origin}/api/project`, { Origin: studio.origin, 'X-Gutta-Token': studio.token })
  ).status;
  report.foreignOrigin = (
    await status(`${studio.origin}/api/project`, { Origin: 'http://example.com', 'X-Gutta-Token': studio.token })
  ).status;
  report.html = studioHtml(studio.url, studio.origin);
  report.exit = await studio.stop();
  report.afterStop = await status(studio.url, {});
  report.missing = await refusal({ command: path.join(folder, 'no-such-gutta-cc'), folder });
  const empty = fs.mkdtempSync(path.join(os.tmpdir(), 'gutta-no-project-'));
  report.notAProject = await refusal({ command, folder: empty });
  fs.rmSync(empty, { recursive: true, force: true });
  process.stdout.write(JSON.stringify(report) + '\n');
})().catch((e) => {
  process.stderr.write(`studio: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
