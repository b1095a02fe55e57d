// The studio's source script (docs/studio.md, "STL and symbols"): the STL view made
// editable (the page's `pre.stl-view` of each block, in place; Ctrl-Enter or leaving it
// applies it with PUT /api/stl; its diagnostics listed under it with their line;
// Ctrl-Space completes from the editor analysis), a network shown as STL (not one rung)
// edited in place on a double click, and the symbol table panel (add, change an
// address or a comment, rename everywhere). The logic is the server's; this only asks.
(function () {
  'use strict';
  const studio = window.guttaStudio;
  if (!studio) return;
  const editor = document.querySelector('main.editor');

  const style = document.createElement('style');
  style.textContent =
    '.stl-edit{display:none;margin:4px 0 12px}' +
    'body[data-view=STL] .stl-edit{display:block}' +
    'pre.stl-view.stl-editor{outline:none;border:1px solid #bbb}' +
    'pre.stl-view.stl-editor.dirty{border-color:#b45309}' +
    'textarea.stl-editor{box-sizing:border-box;width:100%;font:13px monospace;tab-size:8;padding:6px;border:1px solid #bbb}' +
    'textarea.stl-editor.dirty{border-color:#b45309}' +
    '.stl-diagnostics{list-style:none;margin:2px 0;padding:0;font:12px monospace}' +
    '.stl-diagnostic.error{color:#b91c1c}.stl-diagnostic.warning{color:#92400e}' +
    '.stl-completion{position:absolute;z-index:20;list-style:none;margin:0;padding:2px 0;background:#fff;' +
    'border:1px solid #888;font:12px monospace;max-height:180px;overflow:auto;min-width:200px}' +
    '.stl-completion li{padding:1px 6px;cursor:pointer}.stl-completion li.chosen{background:#dbeafe}' +
    '.stl-completion .detail{color:#666;margin-left:8px}' +
    '.stl-hover{font:12px monospace;color:#374151;white-space:pre-wrap;margin:2px 0}' +
    '.network-stl-edit{margin:4px 0 8px}' +
    '.symbols-panel table{border-collapse:collapse;font:12px monospace;width:100%}' +
    '.symbols-panel td,.symbols-panel th{padding:1px 2px;text-align:left;vertical-align:top}' +
    '.symbols-panel input{font:12px monospace;width:100%;box-sizing:border-box;border:1px solid transparent;background:transparent}' +
    '.symbols-panel input:focus{border-color:#888;background:#fff}' +
    '.symbols-panel .where{color:#666;font-size:11px}' +
    '.symbols-panel form{display:flex;flex-wrap:wrap;gap:2px;margin:4px 0}' +
    '.symbols-panel form input{border-color:#bbb;background:#fff;width:31%}' +
    '.symbols-panel .tables .dirty::after{content:" *";color:#b45309}';
  document.head.appendChild(style);

  const call = studio.call;
  const query = studio.query;

  // Byte offsets (the server's, UTF-8) and textarea positions (UTF-16).
  const encoder = new TextEncoder();
  function bytesBefore(text, index) {
    return encoder.encode(text.slice(0, index)).length;
  }
  function indexOfByte(text, bytes) {
    let seen = 0;
    for (let i = 0; i < text.length; i++) {
      if (seen >= bytes) return i;
      const c = text.codePointAt(i);
      seen += c < 0x80 ? 1 : c < 0x800 ? 2 : c < 0x10000 ? 3 : 4;
      if (c >= 0x10000) i++;
    }
    return text.length;
  }

  // ---- an editable piece of STL (a block, or one network) -----------------------------

  // The text of a `textarea`, or of the page's `pre.stl-view` made editable in place
  // (contenteditable plaintext): its value and caret as one string and an index.
  function surface(el) {
    if (el.tagName === 'TEXTAREA') {
      return {
        get: function () { return el.value; },
        set: function (t) { el.value = t; },
        caret: function () { return el.selectionStart; },
        setCaret: function (i) { el.setSelectionRange(i, i); },
      };
    }
    return {
      // Typing may leave <br> or <div> lines in it: innerText reads them as line breaks.
      get: function () { return el.innerText.replace(/\r\n?/g, '\n'); },
      set: function (t) { el.textContent = t; },
      caret: function () {
        const sel = window.getSelection();
        if (!sel.rangeCount || !el.contains(sel.anchorNode)) return this.get().length;
        const range = document.createRange();
        range.setStart(el, 0);
        range.setEnd(sel.anchorNode, sel.anchorOffset);
        let count = 0;
        const walk = function (node) {
          if (node.nodeType === 3) count += node.data.length;
          else if (node.nodeName === 'BR') count += 1;
          else node.childNodes.forEach(walk);
        };
        walk(range.cloneContents());
        return count;
      },
      setCaret: function (i) {
        const walker = document.createTreeWalker(el, NodeFilter.SHOW_TEXT);
        let node = walker.nextNode();
        let left = i;
        while (node && left > node.data.length) {
          left -= node.data.length;
          node = walker.nextNode();
        }
        const range = document.createRange();
        if (node) range.setStart(node, left);
        else range.selectNodeContents(el);
        range.collapse(!node);
        const sel = window.getSelection();
        sel.removeAllRanges();
        sel.addRange(range);
      },
    };
  }

  // `where`: {block, network?}; `host`: the element it goes into; `after`: applied;
  // `existing`: the page's `pre.stl-view` to make editable (else a textarea is made).
  function stlEditor(host, where, after, existing) {
    const box = document.createElement('div');
    box.className = where.network === undefined ? 'stl-edit' : 'network-stl-edit';
    const area = existing || document.createElement('textarea');
    area.classList.add('stl-editor');
    area.spellcheck = false;
    if (existing) area.setAttribute('contenteditable', 'plaintext-only');
    area.dataset.b = where.block;
    if (where.network !== undefined) area.dataset.n = where.network;
    const text = surface(area);
    const hover = document.createElement('div');
    hover.className = 'stl-hover';
    const list = document.createElement('ul');
    list.className = 'stl-diagnostics';
    if (existing) box.append(hover, list);
    else box.append(area, hover, list);
    if (existing) existing.after(box);
    else host.appendChild(box);
    let offset = 0;
    let completion = null;

    function fit() {
      if (!existing) area.rows = Math.min(40, Math.max(4, area.value.split('\n').length + 1));
    }

    // `force`: after applying; else a text being edited is left as it is.
    async function load(force) {
      const path = where.network === undefined
        ? '/api/stl/block?' + query({ file: studio.file(), block: where.block })
        : '/api/stl/network?' + query({ file: studio.file(), block: where.block, network: where.network });
      const answer = await call(path);
      offset = answer.offset;
      if (force || !area.classList.contains('dirty')) {
        // The same text is not set again: the caret stays where it is.
        if (text.get() !== answer.text) text.set(answer.text);
        area.classList.remove('dirty');
      }
      fit();
      await diagnose();
    }

    async function diagnose() {
      const answer = await call('/api/stl/diagnostics?' + query({ file: studio.file(), block: where.block }));
      list.innerHTML = '';
      const first = where.network === undefined ? 0 : null;
      answer.diagnostics.forEach(function (d) {
        const li = document.createElement('li');
        li.className = 'stl-diagnostic ' + d.severity;
        li.dataset.code = d.code;
        li.dataset.line = d.line;
        li.textContent = (first === 0 ? 'line ' + d.line + ': ' : '') + d.code + ' ' + d.message +
          (d.help ? ' (help: ' + d.help + ')' : '');
        list.appendChild(li);
      });
    }

    async function apply() {
      if (!area.classList.contains('dirty')) return;
      closeCompletion();
      const json = { file: studio.file(), block: where.block, text: text.get() };
      if (where.network !== undefined) json.network = where.network;
      try {
        await call('/api/stl', { method: 'PUT', body: JSON.stringify(json), headers: { 'Content-Type': 'application/json' } });
      } catch (error) {
        studio.notify(error, 'error');
        return;
      }
      area.classList.remove('dirty');
      await studio.reload();
      if (after) await after();
      else await load(true);
    }

    function closeCompletion() {
      if (completion) completion.remove();
      completion = null;
    }

    async function complete() {
      const at = text.caret();
      const answer = await call('/api/stl/complete?' + query({ file: studio.file(), offset: offset + bytesBefore(text.get(), at) }));
      closeCompletion();
      if (!answer.items.length) return;
      const from = indexOfByte(text.get(), answer.start - offset);
      const to = indexOfByte(text.get(), answer.end - offset);
      completion = document.createElement('ul');
      completion.className = 'stl-completion';
      answer.items.slice(0, 50).forEach(function (item, i) {
        const li = document.createElement('li');
        li.dataset.insert = item.insert;
        li.dataset.kind = item.kind;
        li.textContent = item.label;
        if (item.detail) {
          const d = document.createElement('span');
          d.className = 'detail';
          d.textContent = item.detail;
          li.appendChild(d);
        }
        if (i === 0) li.classList.add('chosen');
        li.addEventListener('mousedown', function (e) {
          e.preventDefault();
          choose(li);
        });
        completion.appendChild(li);
      });
      completion.dataset.from = from;
      completion.dataset.to = to;
      box.style.position = 'relative';
      completion.style.left = '8px';
      completion.style.top = Math.min(area.offsetHeight, 18 * (text.get().slice(0, at).split('\n').length)) + 'px';
      box.appendChild(completion);
    }

    function choose(li) {
      const from = +completion.dataset.from;
      const to = +completion.dataset.to;
      const value = text.get();
      text.set(value.slice(0, from) + li.dataset.insert + value.slice(to));
      area.classList.add('dirty');
      closeCompletion();
      area.focus();
      text.setCaret(from + li.dataset.insert.length);
    }

    function moveChoice(step) {
      const items = Array.from(completion.children);
      const at = items.findIndex(function (li) { return li.classList.contains('chosen'); });
      const next = Math.max(0, Math.min(items.length - 1, at + step));
      items.forEach(function (li, i) { li.classList.toggle('chosen', i === next); });
      items[next].scrollIntoView({ block: 'nearest' });
    }

    area.addEventListener('input', function () {
      area.classList.add('dirty');
      fit();
    });
    area.addEventListener('keydown', function (e) {
      if (completion) {
        if (e.key === 'ArrowDown' || e.key === 'ArrowUp') {
          e.preventDefault();
          moveChoice(e.key === 'ArrowDown' ? 1 : -1);
          return;
        }
        if (e.key === 'Enter' || e.key === 'Tab') {
          e.preventDefault();
          choose(completion.querySelector('li.chosen'));
          return;
        }
        if (e.key === 'Escape') {
          e.preventDefault();
          closeCompletion();
          return;
        }
      }
      if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) {
        e.preventDefault();
        apply();
      } else if (e.key === ' ' && e.ctrlKey) {
        e.preventDefault();
        complete().catch(function (error) { studio.notify(error, 'error'); });
      } else if (e.key === 'Escape' && where.network !== undefined) {
        e.preventDefault();
        box.remove();
      }
    });
    area.addEventListener('blur', function () {
      setTimeout(function () {
        if (document.activeElement !== area) apply();
      }, 0);
    });
    // Hover: what the analysis says about the word under the caret.
    area.addEventListener('click', async function () {
      try {
        const answer = await call('/api/stl/hover?' + query({ file: studio.file(), offset: offset + bytesBefore(text.get(), text.caret()) }));
        hover.textContent = answer ? answer.markdown.replace(/```\w*\n?/g, '') : '';
      } catch (e) {
        hover.textContent = '';
      }
    });
    area.title = 'Ctrl-Enter applies, Ctrl-Space completes';
    return { box: box, area: area, load: load };
  }

  // ---- the STL view made editable ---------------------------------------------------

  async function editableStl() {
    if (document.body.dataset.view !== 'STL') return;
    const sections = Array.from(editor.querySelectorAll('section.block'));
    for (const section of sections) {
      const pre = section.querySelector('pre.stl-view');
      if (!pre) continue;
      let box = section.querySelector(':scope > .stl-edit');
      if (!box) {
        const made = stlEditor(section, { block: +section.dataset.b }, null, pre);
        box = made.box;
        box.loader = made.load;
      }
      if (!pre.classList.contains('dirty') && document.activeElement !== pre) await box.loader();
    }
  }

  studio.onRedraw(function () {
    editableStl().catch(function (error) { studio.notify(error, 'error'); });
  });

  // A network shown as STL (not one rung): a double click edits its lines in place.
  editor.addEventListener('dblclick', function (e) {
    const view = e.target.closest && e.target.closest('.network-view');
    if (!view || !view.querySelector('g.network[data-reason]')) return;
    if (view.querySelector('.network-stl-edit')) return;
    const made = stlEditor(view, { block: +view.dataset.b, network: +view.dataset.n }, async function () {});
    made.load(true).then(function () { made.area.focus(); });
  });

  // ---- symbols ---------------------------------------------------------------------

  function cell(row, value, change) {
    const td = document.createElement('td');
    const input = document.createElement('input');
    input.value = value || '';
    input.addEventListener('change', function () { change(input.value.trim(), input); });
    input.addEventListener('keydown', function (e) {
      if (e.key === 'Enter') input.blur();
    });
    td.appendChild(input);
    row.appendChild(td);
    return input;
  }

  async function changeSymbols(json) {
    // Marked while the change and the table's new rows are on their way.
    studio.panel('symbols', 'Symbols').dataset.loading = '1';
    try {
      await call('/api/symbols', { json: json });
    } catch (error) {
      studio.notify(error, 'error');
      await showSymbols();
      return;
    }
    await studio.reload();
    await showSymbols();
  }

  async function showSymbols() {
    const body = studio.panel('symbols', 'Symbols');
    body.classList.add('symbols-panel');
    const answer = await call('/api/symbols');
    body.innerHTML = '';
    const form = document.createElement('form');
    form.className = 'symbol-add';
    ['name', 'address', 'comment'].forEach(function (field) {
      const input = document.createElement('input');
      input.name = field;
      input.placeholder = field;
      form.appendChild(input);
    });
    const add = document.createElement('button');
    add.type = 'submit';
    add.textContent = 'Add';
    add.dataset.op = 'add';
    form.appendChild(add);
    form.addEventListener('submit', function (e) {
      e.preventDefault();
      changeSymbols({
        op: 'add',
        name: form.elements.name.value.trim(),
        address: form.elements.address.value.trim(),
        comment: form.elements.comment.value.trim() || null,
      });
    });
    body.appendChild(form);
    if (answer.tables.length) {
      const tables = document.createElement('div');
      tables.className = 'tables';
      answer.tables.forEach(function (t) {
        const span = document.createElement('span');
        span.textContent = t.name;
        span.dataset.table = t.name;
        if (t.dirty) span.className = 'dirty';
        tables.appendChild(span);
      });
      body.appendChild(tables);
    }
    const table = document.createElement('table');
    const head = document.createElement('tr');
    ['name', 'address', 'comment'].forEach(function (h) {
      const th = document.createElement('th');
      th.textContent = h;
      head.appendChild(th);
    });
    table.appendChild(head);
    answer.symbols.forEach(function (s) {
      const row = document.createElement('tr');
      row.className = 'symbol';
      row.dataset.name = s.name;
      row.dataset.declared = s.declared;
      if (s.declared === 'var') {
        ['name', 'data_type', 'comment'].forEach(function (k) {
          const td = document.createElement('td');
          td.textContent = s[k] || '';
          row.appendChild(td);
        });
      } else {
        cell(row, s.name, function (to) {
          if (to && to !== s.name) changeSymbols({ op: 'rename', name: s.name, to: to });
        }).classList.add('symbol-name');
        cell(row, s.address, function (to) {
          if (to && to !== s.address) changeSymbols({ op: 'set', name: s.name, address: to });
        }).classList.add('symbol-address');
        cell(row, s.comment, function (to) {
          changeSymbols({ op: 'set', name: s.name, comment: to });
        }).classList.add('symbol-comment');
      }
      const where = document.createElement('tr');
      where.className = 'where';
      const td = document.createElement('td');
      td.colSpan = 3;
      td.textContent = s.declared === 'var'
        ? s.file + ' ' + s.block + ' ' + s.section
        : s.declared === 'table' ? s.file : s.file + ' SYMBOLS';
      where.appendChild(td);
      table.append(row, where);
    });
    body.appendChild(table);
    delete body.dataset.loading;
  }

  // The panel opens from the project view: a click on the side bar's symbols (or the
  // `symbols` command).
  studio.command('symbols', showSymbols);
  const listed = document.querySelector('.sidebar table.symbols');
  if (listed) {
    listed.style.cursor = 'pointer';
    listed.title = 'edit the symbols';
    const heading = listed.previousElementSibling;
    [listed, heading].forEach(function (el) {
      if (el) el.addEventListener('click', function () { studio.run('symbols'); });
    });
  }
})();
