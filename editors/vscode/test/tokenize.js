// Tokenizes files with the extension's TextMate grammar, as VS Code does (vscode-textmate
// over the oniguruma regex engine), and prints one JSON object: for every file, its lines,
// each a list of tokens {text, scopes}. Used by lsp/tests/vscode_package.rs, which holds
// the assertions; this script only reports. Usage: node test/tokenize.js FILE...
'use strict';

const fs = require('fs');
const path = require('path');
const textmate = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const grammarPath = path.join(__dirname, '..', 'syntaxes', 'gutta-lad.tmLanguage.json');

async function main(files) {
  const wasm = fs.readFileSync(require.resolve('vscode-oniguruma/release/onig.wasm'));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
      createOnigString: (text) => new oniguruma.OnigString(text),
    }),
    loadGrammar: async (scopeName) => {
      if (scopeName !== 'source.gutta-lad') return null;
      const text = fs.readFileSync(grammarPath, 'utf8');
      return textmate.parseRawGrammar(text, grammarPath);
    },
  });
  const grammar = await registry.loadGrammar('source.gutta-lad');
  if (!grammar) throw new Error('the grammar did not load');
  const result = {};
  for (const file of files) {
    const lines = fs.readFileSync(file, 'utf8').split(/\r?\n/);
    let stack = textmate.INITIAL;
    result[file] = lines.map((line) => {
      const tokenized = grammar.tokenizeLine(line, stack);
      stack = tokenized.ruleStack;
      return tokenized.tokens.map((t) => ({
        text: line.substring(t.startIndex, t.endIndex),
        scopes: t.scopes,
      }));
    });
  }
  process.stdout.write(JSON.stringify(result) + '\n');
}

main(process.argv.slice(2)).catch((e) => {
  process.stderr.write(`tokenize: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});
