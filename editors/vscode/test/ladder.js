// Runs the "Show as ladder" functions (src/ladder.js) against a real gutta-cc:
// `node test/ladder.js GUTTA_CC PROJECT_SOURCE LONE_FILE BAD_FILE OUT_DIR`. For the source
// of a project and for a file outside any project it reports what gutta-cc is asked to
// draw, and writes the webview's HTML to OUT_DIR (project.html, lone.html) with its
// policy, and the same for a page given a `style` attribute (styled.html); for a file
// with an error, gutta-cc's message and the error page; for a missing executable, the
// refusal. Prints what it saw as JSON; lsp/tests/vscode_package.rs holds
// the assertions.
'use strict';

const fs = require('fs');
const path = require('path');
const { WEBVIEW_STYLE, ladderInput, drawLadder, ladderPolicy, ladderWebviewHtml, ladderErrorHtml } = require(
  path.join(__dirname, '..', 'src', 'ladder.js'),
);

const [command, projectSource, lone, bad, outDir] = process.argv.slice(2);
const report = {};

async function failure(options) {
  try {
    await drawLadder(options);
    return null;
  } catch (e) {
    return e.message;
  }
}

(async () => {
  for (const [name, file] of [
    ['project', projectSource],
    ['lone', lone],
  ]) {
    const page = await drawLadder({ command, file });
    const html = ladderWebviewHtml(page);
    fs.writeFileSync(path.join(outDir, `${name}.html`), html);
    report[name] = {
      input: ladderInput(file),
      policy: /http-equiv="Content-Security-Policy" content="([^"]*)"/.exec(html)[1],
      pageInHtml: html.includes(page.slice(page.indexOf('<body'))),
      white: html.includes(WEBVIEW_STYLE),
    };
  }
  // A page with a style attribute (none of gutta-cc's has one yet): allowed by its hash.
  const page = await drawLadder({ command, file: lone });
  const styled = page.replace('<body>', '<body>\n<p id="styled" style="color: rgb(0, 0, 255); content: &quot;x&quot;">styled</p>');
  fs.writeFileSync(path.join(outDir, 'styled.html'), ladderWebviewHtml(styled));
  report.styledPolicy = ladderPolicy(styled);
  report.policyOfPage = ladderPolicy(page);
  report.bad = await failure({ command, file: bad });
  report.badHtml = ladderErrorHtml(bad, report.bad || '');
  report.missing = await failure({ command: path.join(outDir, 'no-such-gutta-cc'), file: lone });
  process.stdout.write(JSON.stringify(report) + '\n');
})().catch((e) => {
  process.stderr.write(`ladder: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
