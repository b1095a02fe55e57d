// The GUTTA Studio launcher (docs/editors.md, "Open Studio"): starts
// `gutta-cc studio --no-open FOLDER`, reads the first line it prints
// (`gutta-cc studio: http://HOST:PORT/?token=TOKEN`), and gives back the address and a
// stop() that ends the process. The webview's page is `studioHtml`: the studio in an
// iframe, the webview's CSP allowing only that frame. Plain Node (child_process): no
// `vscode` module here, so test/studio.js runs it against the real gutta-cc.
'use strict';

const { spawn } = require('child_process');

/** The line gutta-cc studio prints first, exactly (issue 27's fixed decision). */
const FIRST_LINE = /^gutta-cc studio: (http:\/\/([^/\s]+)\/\?token=([A-Za-z0-9_-]+))$/;

/**
 * The studio's address from its first stdout line, or null.
 * @param {string} line
 * @returns {{url: string, origin: string, host: string, token: string} | null}
 */
function parseStudioLine(line) {
  const m = FIRST_LINE.exec(line.replace(/\r$/, ''));
  if (!m) return null;
  return { url: m[1], origin: `http://${m[2]}`, host: m[2], token: m[3] };
}

/**
 * Start `command studio --no-open folder` and wait for its address.
 * @param {{command: string, folder: string, env?: object, timeoutMs?: number}} options
 * @returns {Promise<{url: string, origin: string, host: string, token: string,
 *   process: import('child_process').ChildProcess, exited: Promise<{code: number|null, signal: string|null}>,
 *   stop: () => Promise<{code: number|null, signal: string|null}>}>}
 */
function launchStudio(options) {
  const child = spawn(options.command, ['studio', '--no-open', options.folder], {
    cwd: options.folder,
    env: options.env || process.env,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  const exited = new Promise((resolve) => {
    child.on('exit', (code, signal) => resolve({ code, signal }));
    child.on('error', () => resolve({ code: null, signal: null }));
  });
  const stop = async () => {
    if (child.exitCode === null && child.signalCode === null) {
      // Ctrl-C: the studio ends and exits 0; a process that does not, is killed.
      child.kill('SIGINT');
      const late = setTimeout(() => child.kill('SIGKILL'), 3000);
      const result = await exited;
      clearTimeout(late);
      return result;
    }
    return exited;
  };
  return new Promise((resolve, reject) => {
    let out = '';
    let err = '';
    let done = false;
    const fail = (why) => {
      if (done) return;
      done = true;
      clearTimeout(timer);
      stop().then(() => reject(new Error(why)));
    };
    const timer = setTimeout(
      () => fail(`${options.command} studio printed no address in time${err ? `: ${err.trim()}` : ''}`),
      options.timeoutMs || 30000,
    );
    child.stdout.setEncoding('utf8');
    child.stderr.setEncoding('utf8');
    child.stderr.on('data', (chunk) => {
      err += chunk;
    });
    child.stdout.on('data', (chunk) => {
      if (done) return;
      out += chunk;
      const end = out.indexOf('\n');
      if (end < 0) return;
      const first = out.slice(0, end);
      const address = parseStudioLine(first);
      if (!address) {
        fail(`${options.command} studio printed \`${first}\`, not its address`);
        return;
      }
      done = true;
      clearTimeout(timer);
      resolve({ ...address, process: child, exited, stop });
    });
    child.on('error', (e) =>
      fail(`could not start \`${options.command}\` (${e.message}). Install gutta-cc ` +
        '(`cargo install --locked --path cli`) or set `gutta.cc.path`.'),
    );
    child.on('exit', (code) => {
      fail(`${options.command} studio ended (exit ${code})${err ? `: ${err.trim()}` : ''}`);
    });
  });
}

/**
 * The webview's HTML: the studio at `url` in a frame filling the panel. Its CSP allows
 * only that frame (the studio's own origin); the studio's page then talks to its own
 * origin, which the studio accepts.
 * @param {string} url
 * @param {string} origin
 */
function studioHtml(url, origin) {
  const quote = (s) => s.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;');
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; frame-src ${quote(origin)}; style-src 'unsafe-inline'">
<style>html,body,iframe{margin:0;padding:0;border:0;width:100%;height:100%;overflow:hidden}</style>
<title>GUTTA Studio</title>
</head>
<body><iframe src="${quote(url)}" title="GUTTA Studio"></iframe></body>
</html>
`;
}

module.exports = { launchStudio, parseStudioLine, studioHtml };
