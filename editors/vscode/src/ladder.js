// "GUTTA: Show as ladder" (docs/editors.md, "Show as ladder"): runs
// `gutta-cc ladder FILE -o TMP.html`, reads the page it writes and gives it back with a
// Content-Security-Policy that allows exactly the page's own inline <style> and <script>
// elements (by their SHA-256) and nothing else: no network, no other script. Plain Node
// (child_process, crypto): no `vscode` module here, so test/ladder.js runs it against the
// real gutta-cc.
'use strict';

const { execFile } = require('child_process');
const crypto = require('crypto');
const fs = require('fs');
const os = require('os');
const path = require('path');

/**
 * What `gutta-cc ladder` draws for a .lad file: the project's folder when the nearest
 * gutta.toml above the file lists it in `[program] sources` (the file alone would miss the
 * project's symbol tables and other sources), else the file alone.
 * @param {string} file an absolute path
 * @returns {{input: string, cwd: string, project: boolean}}
 */
function ladderInput(file) {
  for (let dir = path.dirname(file); ; dir = path.dirname(dir)) {
    const manifest = path.join(dir, 'gutta.toml');
    if (fs.existsSync(manifest)) {
      const text = fs.readFileSync(manifest, 'utf8');
      const list = /^\s*sources\s*=\s*\[([^\]]*)\]/m.exec(text);
      const sources = list ? [...list[1].matchAll(/"((?:[^"\\]|\\.)*)"|'([^']*)'/g)] : [];
      const listed = sources.some((m) => path.resolve(dir, (m[1] !== undefined ? m[1].replace(/\\\\/g, '\\') : m[2])) === file);
      return listed ? { input: dir, cwd: dir, project: true } : { input: file, cwd: path.dirname(file), project: false };
    }
    if (path.dirname(dir) === dir) return { input: file, cwd: path.dirname(file), project: false };
  }
}

/**
 * Draw `file` with `command ladder INPUT -o TMP.html` (INPUT: `ladderInput(file)`) and
 * resolve with the page's HTML.
 * Rejects with gutta-cc's own message when it fails (a program with errors: its
 * diagnostics), or with how to install it when it does not start.
 * @param {{command: string, file: string, env?: object, timeoutMs?: number}} options
 * @returns {Promise<string>}
 */
function drawLadder(options) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'gutta-ladder-'));
  const out = path.join(dir, `${path.basename(options.file, path.extname(options.file))}.html`);
  const { input, cwd } = ladderInput(options.file);
  const args = ['ladder', input, '-o', out];
  return new Promise((resolve, reject) => {
    execFile(
      options.command,
      args,
      {
        cwd,
        env: { ...(options.env || process.env), NO_COLOR: '1' },
        timeout: options.timeoutMs || 30000,
        maxBuffer: 16 * 1024 * 1024,
      },
      (error, stdout, stderr) => {
        try {
          if (error && error.code === 'ENOENT') {
            reject(
              new Error(
                `could not start \`${options.command}\`. Install gutta-cc ` +
                  '(`cargo install --locked --path cli`) or set `gutta.cc.path`.',
              ),
            );
          } else if (error) {
            const why = (stderr || stdout || error.message).trim();
            const status = error.code !== undefined && error.code !== null ? `exit ${error.code}` : `${error.signal}`;
            reject(new Error(`\`${options.command} ladder\` failed (${status}):\n${why}`));
          } else {
            resolve(fs.readFileSync(out, 'utf8'));
          }
        } catch (e) {
          reject(e);
        } finally {
          fs.rmSync(dir, { recursive: true, force: true });
        }
      },
    );
  });
}

/**
 * The CSP source of each inline `<tag>` element of `html`: `'sha256-BASE64'` of its text.
 * @param {string} html
 * @param {'style' | 'script'} tag
 * @returns {string[]}
 */
function inlineHashes(html, tag) {
  const element = new RegExp(`<${tag}(\\s[^>]*)?>([\\s\\S]*?)</${tag}\\s*>`, 'gi');
  const hashes = [];
  for (const m of html.matchAll(element)) {
    if (m[1] && /\ssrc\s*=/i.test(m[1])) continue; // not inline
    hashes.push(`'sha256-${crypto.createHash('sha256').update(m[2], 'utf8').digest('base64')}'`);
  }
  return [...new Set(hashes)];
}

/**
 * The CSP sources of the page's `style="..."` attributes: `'unsafe-hashes'` and the
 * SHA-256 of each value (entities decoded, as the browser hashes it); none without any.
 * @param {string} html
 * @returns {string[]}
 */
function styleAttributeHashes(html) {
  const entities = { amp: '&', lt: '<', gt: '>', quot: '"', apos: "'" };
  const decode = (v) =>
    v.replace(/&(#x[0-9a-f]+|#\d+|[a-z]+);/gi, (whole, name) => {
      if (name[0] !== '#') return entities[name.toLowerCase()] || whole;
      return String.fromCodePoint(name[1] === 'x' || name[1] === 'X' ? parseInt(name.slice(2), 16) : parseInt(name.slice(1), 10));
    });
  const hashes = new Set();
  for (const m of html.matchAll(/<[a-z][^>]*?\sstyle\s*=\s*(?:"([^"]*)"|'([^']*)')/gi)) {
    const value = decode(m[1] !== undefined ? m[1] : m[2]);
    hashes.add(`'sha256-${crypto.createHash('sha256').update(value, 'utf8').digest('base64')}'`);
  }
  return hashes.size ? ["'unsafe-hashes'", ...hashes] : [];
}

/**
 * The Content-Security-Policy for a ladder page: nothing by default; its inline styles
 * (elements and `style` attributes) and scripts by hash (none allowed when it has none).
 * @param {string} page
 */
function ladderPolicy(page) {
  const styles = [...inlineHashes(page, 'style'), ...styleAttributeHashes(page)];
  const scripts = inlineHashes(page, 'script');
  return [
    "default-src 'none'",
    `style-src ${styles.length ? styles.join(' ') : "'none'"}`,
    `script-src ${scripts.length ? scripts.join(' ') : "'none'"}`,
  ].join('; ');
}

/** The drawing is black on white whatever VS Code's theme (the webview would otherwise
 * give the page the theme's background, dark in a dark theme). */
const WEBVIEW_STYLE = '<style>html,body{background:#fff;color-scheme:light}</style>';

/**
 * The webview's HTML: gutta-cc's page with the white background first in its <head>, and
 * before it the policy allowing the result's inline styles and scripts.
 * @param {string} page
 */
function ladderWebviewHtml(page) {
  const head = /<head(\s[^>]*)?>/i.exec(page);
  const at = head ? head.index + head[0].length : -1;
  const body = head
    ? `${page.slice(0, at)}\n${WEBVIEW_STYLE}${page.slice(at)}`
    : `<!DOCTYPE html>\n<html><head>${WEBVIEW_STYLE}</head><body>${page}</body></html>\n`;
  const meta = `<meta http-equiv="Content-Security-Policy" content="${ladderPolicy(body)}">`;
  const start = /<head(\s[^>]*)?>/i.exec(body);
  const after = start.index + start[0].length;
  return `${body.slice(0, after)}\n${meta}${body.slice(after)}`;
}

/**
 * The webview's HTML when the file cannot be drawn: the reason, as text.
 * @param {string} file
 * @param {string} message
 */
function ladderErrorHtml(file, message) {
  const text = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'">
<title>${text(path.basename(file))}</title>
</head>
<body><h1>${text(path.basename(file))} cannot be drawn</h1><pre class="error">${text(message)}</pre></body>
</html>
`;
}

module.exports = { WEBVIEW_STYLE, ladderInput, drawLadder, inlineHashes, styleAttributeHashes, ladderPolicy, ladderWebviewHtml, ladderErrorHtml };
