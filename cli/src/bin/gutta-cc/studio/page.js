// The GUTTA Studio page's script (docs/studio.md, "The page", "Keys", "Editing"). The
// server holds the program (the session) and answers every edit with the networks to
// redraw and the diagnostics; this script selects, asks for operands, sends edit
// operations and puts the answers in place. It makes `window.guttaStudio`, which the
// other scripts (live.js, online.js, source.js, inlined after it) use.
(function () {
  'use strict';
  const body = document.body;
  const status = document.querySelector('.status');
  const messages = document.querySelector('.messages');
  const editor = document.querySelector('main.editor');
  const panels = document.querySelector('.panels');
  const fileDiagnostics = document.createElement('div');
  fileDiagnostics.className = 'file-diagnostics';
  messages.after(fileDiagnostics);

  const state = {
    file: GUTTA_STATE.file,
    dirty: GUTTA_STATE.dirty,
    canUndo: GUTTA_STATE.can_undo,
    canRedo: GUTTA_STATE.can_redo,
    diagnostics: GUTTA_STATE.diagnostics,
    // The selection: {path} an element, {b, n} a network, or null.
    selection: null,
    clipboard: null,
  };
  const handlers = {};
  let asks = 0;
  const redrawHooks = [];

  // ---- requests ---------------------------------------------------------------

  // Every request of the page carries the token in a header (never in a Referer).
  // `init.json`: an object sent as the JSON body of a POST.
  function api(path, init) {
    const options = Object.assign({}, init || {});
    const headers = Object.assign({ 'X-Gutta-Token': GUTTA_TOKEN }, options.headers || {});
    if (options.json !== undefined) {
      options.method = options.method || 'POST';
      options.body = JSON.stringify(options.json);
      headers['Content-Type'] = 'application/json';
      delete options.json;
    }
    options.headers = headers;
    return fetch(path, options);
  }

  // A request's JSON answer; a refusal throws an Error carrying its code and path.
  async function call(path, init) {
    const answer = await api(path, init);
    let value = null;
    try {
      value = await answer.json();
    } catch (e) {
      value = null;
    }
    if (!answer.ok) {
      const error = new Error((value && value.message) || 'HTTP ' + answer.status);
      error.code = value && value.code;
      error.path = value && value.path;
      throw error;
    }
    return value;
  }

  function query(params) {
    return Object.keys(params)
      .map(function (k) { return encodeURIComponent(k) + '=' + encodeURIComponent(params[k]); })
      .join('&');
  }

  // ---- messages and status ------------------------------------------------------

  function notify(text, kind) {
    const line = document.createElement('div');
    line.className = 'message ' + (kind || 'info');
    if (text && typeof text === 'object') {
      if (text.code) line.dataset.code = text.code;
      line.textContent = (text.code ? text.code + ': ' : '') + (text.message || String(text));
      if (!kind) line.className = 'message error';
    } else {
      line.textContent = String(text);
    }
    messages.appendChild(line);
    while (messages.children.length > 3) messages.firstChild.remove();
    setTimeout(function () { line.remove(); }, kind === 'error' || line.dataset.code ? 8000 : 4000);
    return line;
  }

  function mode() {
    return body.dataset.mode || 'EDIT';
  }

  function setMode(m) {
    body.dataset.mode = m;
    status.dataset.mode = m;
    status.querySelector('.mode').textContent = m;
    if (m === 'EDIT') status.querySelector('.run').textContent = '';
  }

  function timeText(updated) {
    const when = typeof updated === 'number' ? new Date(updated) : new Date();
    return when.toLocaleTimeString();
  }

  function setStatus(s) {
    s = s || {};
    if (s.run !== undefined) status.querySelector('.run').textContent = s.run || '';
    if (s.where !== undefined) status.querySelector('.where').textContent = s.where || '';
    status.querySelector('.updated').textContent = timeText(s.updated);
  }

  function showErrors() {
    const count = state.diagnostics.filter(function (d) { return d.severity === 'error'; }).length;
    const shown = status.querySelector('.diagnostics');
    shown.dataset.errors = String(count);
    shown.textContent = count === 1 ? '1 error' : count + ' errors';
  }

  function showDirty() {
    document.querySelector('.toolbar .dirty').textContent = state.dirty ? '● unsaved' : '';
    const title = document.title.replace(/^\* /, '');
    document.title = state.dirty ? '* ' + title : title;
    body.dataset.dirty = state.dirty ? 'true' : 'false';
  }

  window.addEventListener('beforeunload', function (event) {
    if (state.dirty) {
      event.preventDefault();
      event.returnValue = '';
    }
  });

  // ---- the drawing ----------------------------------------------------------------

  // Each block's list of network views, by the block's place (blocks never come or go
  // with an edit): found once, not searched for at each update.
  const sections = [];
  editor.querySelectorAll('section.block').forEach(function (section) {
    sections[+section.dataset.b] = section.querySelector('.networks');
  });

  function sectionOf(b) {
    return sections[b] || null;
  }

  function viewOf(b, n) {
    const section = sectionOf(b);
    return section ? section.children[n] || null : null;
  }

  function networks() {
    const map = new Map();
    editor.querySelectorAll('g.network').forEach(function (g) {
      map.set(g.dataset.block + '/' + g.dataset.network, g);
    });
    return map;
  }

  function redrawn() {
    redrawHooks.forEach(function (fn) {
      try { fn(); } catch (e) { console.warn(e); }
    });
  }

  // An edit's answer put in place: its networks replace theirs, blocks lose what lies
  // beyond their count, diagnostics and markers follow.
  function applyUpdate(update) {
    update.networks.forEach(function (d) {
      const section = sectionOf(d.block);
      if (!section) return;
      let view = section.children[d.network];
      if (!view) {
        view = document.createElement('div');
        view.className = 'network-view';
        section.appendChild(view);
      }
      view.dataset.b = d.block;
      view.dataset.n = d.network;
      view.innerHTML = d.html;
    });
    update.blocks.forEach(function (shape, b) {
      const section = sectionOf(b);
      while (section && section.children.length > shape.networks) section.lastChild.remove();
    });
    // An edit's answer leaves the diagnostics out when they did not change.
    if (update.diagnostics !== undefined) state.diagnostics = update.diagnostics;
    state.dirty = update.dirty;
    state.canUndo = update.can_undo;
    state.canRedo = update.can_redo;
    showDiagnostics(new Set(update.networks.map(function (d) { return d.block + '/' + d.network; })));
    showErrors();
    showDirty();
    reselect();
    setStatus({});
    redrawn();
  }

  // ---- diagnostics on the rungs ---------------------------------------------------

  const NETWORK_PATH = /^blocks\[(\d+)\]\.networks\[(\d+)\]/;
  // What each network shows now ('b/n', '' the whole file): its diagnostics as JSON.
  let shownGroups = new Map();

  function diagnosticBox(d) {
    const box = document.createElement('div');
    box.className = 'diagnostic ' + d.severity;
    box.dataset.code = d.code;
    box.dataset.path = d.path;
    const code = document.createElement('span');
    code.className = 'code';
    code.textContent = d.code;
    const message = document.createElement('span');
    message.className = 'text';
    message.textContent = d.message + (d.label ? ' (' + d.label + ')' : '');
    box.append(code, message);
    if (d.help) {
      const help = document.createElement('div');
      help.className = 'help';
      help.textContent = 'help: ' + d.help;
      box.appendChild(help);
    }
    return box;
  }

  // One network's (or the file's) diagnostics drawn again: boxes under the rung, class
  // `error` on the elements at (or inside) their paths.
  function paintGroup(key, list) {
    const at = key ? key.split('/') : null;
    const view = at ? viewOf(+at[0], +at[1]) : null;
    const container = view || fileDiagnostics;
    if (view) {
      view.querySelectorAll(':scope > .diagnostic').forEach(function (d) { d.remove(); });
      view.querySelectorAll('.error').forEach(function (e) { e.classList.remove('error'); });
    } else if (!key) {
      fileDiagnostics.innerHTML = '';
    }
    list.forEach(function (d) {
      container.appendChild(diagnosticBox(d));
      if (!view) return;
      view.querySelectorAll('[data-path]').forEach(function (el) {
        const p = el.dataset.path;
        if (p === d.path || p.startsWith(d.path + '.')) el.classList.add('error');
      });
    });
  }

  // The diagnostics on the rungs; with `redrawn` (the 'b/n' keys just drawn again),
  // only those networks and the ones whose diagnostics changed are touched.
  function showDiagnostics(redrawnKeys) {
    const groups = new Map();
    state.diagnostics.forEach(function (d) {
      const at = NETWORK_PATH.exec(d.path);
      const key = at ? at[1] + '/' + at[2] : '';
      if (!groups.has(key)) groups.set(key, []);
      groups.get(key).push(d);
    });
    if (!redrawnKeys) {
      editor.querySelectorAll('.diagnostic').forEach(function (d) { d.remove(); });
      editor.querySelectorAll('.error').forEach(function (e) { e.classList.remove('error'); });
      shownGroups = new Map();
    }
    const next = new Map();
    const keys = new Set(Array.from(groups.keys()).concat(Array.from(shownGroups.keys())));
    if (redrawnKeys) redrawnKeys.forEach(function (k) { keys.add(k); });
    keys.forEach(function (key) {
      const list = groups.get(key) || [];
      const signature = list.length ? JSON.stringify(list) : undefined;
      if (signature) next.set(key, signature);
      const again = !redrawnKeys || redrawnKeys.has(key) || shownGroups.get(key) !== signature;
      if (again) paintGroup(key, list);
    });
    shownGroups = next;
  }

  // ---- selection and keyboard navigation -----------------------------------------

  function elements(scope) {
    return Array.from((scope || editor).querySelectorAll('.contact[data-path], .coil[data-path], .box[data-path]'));
  }

  function clearSelection() {
    editor.querySelectorAll('.selected').forEach(function (e) { e.classList.remove('selected'); });
  }

  function select(target) {
    clearSelection();
    if (!target) {
      state.selection = null;
      return;
    }
    if (target.classList.contains('network-view')) {
      state.selection = { b: +target.dataset.b, n: +target.dataset.n };
    } else {
      const view = target.closest('.network-view');
      state.selection = { path: target.dataset.path, b: +view.dataset.b, n: +view.dataset.n };
    }
    target.classList.add('selected');
  }

  function selectedElement() {
    if (!state.selection || !state.selection.path) return null;
    return editor.querySelector('[data-path="' + state.selection.path + '"]');
  }

  function selectedView() {
    return state.selection ? viewOf(state.selection.b, state.selection.n) : null;
  }

  // After a redraw the same path (or network) is selected again, if still there.
  function reselect() {
    if (!state.selection) return;
    const el = selectedElement();
    const view = selectedView();
    if (el) select(el);
    else if (view) select(view);
    else select(null);
  }

  editor.addEventListener('click', function (event) {
    const element = event.target.closest('.contact, .coil, .box');
    if (element && element.dataset.path) return select(element);
    if (element) {
      clearSelection();
      element.classList.add('selected');
      return;
    }
    const view = event.target.closest('.network-view');
    select(view);
  });

  editor.addEventListener('dblclick', function (event) {
    const element = event.target.closest('.contact[data-path], .coil[data-path], .box[data-path]');
    if (element) {
      select(element);
      run('operand');
    }
  });

  function allViews() {
    return Array.from(editor.querySelectorAll('.network-view'));
  }

  function moveSelection(key) {
    const views = allViews();
    const view = selectedView();
    if (!view) {
      const first = views[0];
      if (first) select(elements(first)[0] || first);
      return;
    }
    if (key === 'ArrowLeft' || key === 'ArrowRight') {
      const list = elements(view);
      if (!list.length) return;
      const el = selectedElement();
      let i = el ? list.indexOf(el) : -1;
      i = key === 'ArrowRight' ? Math.min(i + 1, list.length - 1) : Math.max(i - 1, 0);
      select(list[i]);
    } else {
      const i = views.indexOf(view) + (key === 'ArrowDown' ? 1 : -1);
      const next = views[Math.max(0, Math.min(views.length - 1, i))];
      select(elements(next)[0] || next);
    }
    const shown = selectedElement() || selectedView();
    if (shown && shown.scrollIntoView) shown.scrollIntoView({ block: 'nearest' });
  }

  // ---- the operand editor ---------------------------------------------------------

  // Ask for one operand or mnemonic in `input.operand-editor` with completion: the
  // text (Enter), or null (Esc). `ask.element`, `kind`, `mnemonic`, `pin` say what fits.
  function ask(request) {
    return new Promise(function (resolve) {
      const old = document.querySelector('.operand-popup');
      if (old) old.remove();
      const popup = document.createElement('div');
      popup.className = 'operand-popup';
      const label = document.createElement('label');
      label.textContent = request.label;
      const input = document.createElement('input');
      input.className = 'operand-editor';
      input.type = 'text';
      input.autocomplete = 'off';
      input.spellcheck = false;
      input.value = request.value || '';
      input.dataset.kind = request.kind || 'operand';
      input.dataset.element = request.element || '';
      input.dataset.seq = String(++asks);
      const list = document.createElement('ul');
      list.className = 'completions';
      popup.append(label, input, list);
      const anchor = request.anchor || selectedElement() || selectedView();
      const box = anchor && anchor.getBoundingClientRect ? anchor.getBoundingClientRect() : null;
      popup.style.left = Math.max(8, Math.min(window.innerWidth - 260, box ? box.left : 260)) + 'px';
      popup.style.top = Math.max(48, Math.min(window.innerHeight - 240, box ? box.bottom + 4 : 120)) + 'px';
      document.body.appendChild(popup);
      input.focus();
      input.select();
      let items = [];
      let active = -1;
      let asked = 0;
      let done = false;

      function finish(value) {
        if (done) return;
        done = true;
        popup.remove();
        resolve(value);
      }

      function paint() {
        list.innerHTML = '';
        items.forEach(function (item, i) {
          const li = document.createElement('li');
          li.textContent = item.label;
          li.dataset.label = item.label;
          if (item.detail) {
            const detail = document.createElement('span');
            detail.className = 'detail';
            detail.textContent = item.detail;
            li.appendChild(detail);
          }
          if (i === active) li.className = 'active';
          li.addEventListener('mousedown', function (e) {
            e.preventDefault();
            finish(item.label);
            request.chosen = item;
          });
          list.appendChild(li);
        });
      }

      function fetchItems() {
        if (request.kind === 'text') return;
        const mine = ++asked;
        const params = {
          file: state.file,
          kind: request.kind || 'operand',
          element: request.element || 'contact',
          pin: request.pin || 0,
          prefix: input.value,
        };
        if (request.mnemonic) params.mnemonic = request.mnemonic;
        call('/api/complete?' + query(params))
          .then(function (answer) {
            if (mine !== asked || done) return;
            items = answer.items.slice(0, 40);
            request.items = items;
            active = -1;
            paint();
          })
          .catch(function () {});
      }

      input.addEventListener('input', fetchItems);
      input.addEventListener('keydown', function (e) {
        if (e.key === 'Escape') {
          e.preventDefault();
          e.stopPropagation();
          finish(null);
        } else if (e.key === 'Enter') {
          e.preventDefault();
          e.stopPropagation();
          const chosen = active >= 0 ? items[active] : null;
          const value = chosen ? chosen.label : input.value.trim();
          request.chosen = chosen || items.find(function (i) {
            return i.label.toUpperCase() === value.toUpperCase();
          }) || null;
          if (value) finish(value);
        } else if (e.key === 'ArrowDown' || e.key === 'ArrowUp') {
          e.preventDefault();
          e.stopPropagation();
          if (!items.length) return;
          active = e.key === 'ArrowDown' ? Math.min(active + 1, items.length - 1) : Math.max(active - 1, 0);
          paint();
        } else if (e.key === 'Tab') {
          e.preventDefault();
          if (items.length) {
            input.value = items[Math.max(active, 0)].label;
            fetchItems();
          }
        } else {
          e.stopPropagation();
        }
      });
      input.addEventListener('blur', function () {
        setTimeout(function () { if (!done && document.activeElement !== input) finish(null); }, 150);
      });
      fetchItems();
    });
  }

  // ---- edits ------------------------------------------------------------------------

  async function send(edit) {
    try {
      const update = await call('/api/edit', { json: { file: state.file, edit: edit } });
      applyUpdate(update);
      return update;
    } catch (error) {
      notify(error, 'error');
      return null;
    }
  }

  // The elements' paths of network (b, n) with their tooltip, to find a new one.
  function signatures(b, n) {
    const view = viewOf(b, n);
    const set = new Set();
    if (view) elements(view).forEach(function (e) { set.add(e.dataset.path + '|' + tooltip(e)); });
    return set;
  }

  // The tooltip's first line (mnemonic and operands) without its source line; the
  // symbol lines under it are left out.
  function tooltip(el) {
    const t = el.querySelector('title');
    return t ? t.textContent.split('\n')[0].replace(/ \(line \d+\)$/, '') : '';
  }

  // Select the element of network (b, n) that was not there before (by its class).
  function selectNew(b, n, before, cls) {
    const view = viewOf(b, n);
    if (!view) return;
    const fresh = elements(view).filter(function (e) {
      return e.classList.contains(cls) && !before.has(e.dataset.path + '|' + tooltip(e));
    });
    if (fresh.length) select(fresh[0]);
  }

  function needElement() {
    const el = selectedElement();
    if (!el) notify('select an element first (click it, or use the arrow keys)', 'error');
    return el;
  }

  // An output: a coil, or a box nothing follows in its series.
  function isOutput(el) {
    if (el.classList.contains('coil')) return true;
    const m = /^(.*)\.series\[(\d+)\]$/.exec(el.dataset.path);
    if (!m) return true;
    const next = m[1] + '.series[' + (+m[2] + 1) + ']';
    const view = el.closest('.network-view');
    return !elements(view).some(function (e) {
      return e.dataset.path === next || e.dataset.path.startsWith(next + '.');
    });
  }

  // An element inserted around the selection: `make(operands)` the edit's element.
  async function insertElement(kind, mnemonic, label) {
    let el = selectedElement();
    const view = selectedView();
    if (!el && view) el = elements(view)[0];
    if (!el) return needElement();
    const b = state.selection.b;
    const n = state.selection.n;
    const value = await ask({ label: label, element: kind, mnemonic: mnemonic, pin: 0, anchor: el });
    if (value === null) return;
    const before = signatures(b, n);
    const path = el.dataset.path;
    const coilSelected = el.classList.contains('coil');
    let edit;
    if (kind === 'contact') {
      edit = { op: 'insert_contact', at: path, place: coilSelected ? 'before' : 'after', contact: mnemonic, operands: [value] };
    } else {
      const operands = mnemonic === '=' ? [value] : [value, '1'];
      edit = { op: 'insert_coil', at: path, place: coilSelected ? 'parallel' : 'after', coil: mnemonic, operands: operands };
    }
    if (await send(edit)) selectNew(b, n, before, kind);
  }

  // A box: its mnemonic, then each operand in STL order, then a contact for each
  // power input after the first (a CTU's R: the counter's reset path).
  async function insertBox() {
    const el = needElement();
    if (!el) return;
    const b = state.selection.b;
    const n = state.selection.n;
    const request = { label: 'box (mnemonic)', kind: 'mnemonic', element: 'box', anchor: el };
    const mnemonic = await ask(request);
    if (mnemonic === null) return;
    let item = request.chosen && request.chosen.label.toUpperCase() === mnemonic.toUpperCase()
      ? request.chosen : null;
    if (!item) {
      const found = await call('/api/complete?' + query({ file: state.file, kind: 'mnemonic', element: 'box', prefix: mnemonic }));
      item = found.items.find(function (i) { return i.label.toUpperCase() === mnemonic.toUpperCase(); });
      if (!item) return notify(mnemonic + ' is not a box of this PLC', 'error');
    }
    const names = item.operands || [];
    const operands = [];
    for (let i = 0; i < names.length; i++) {
      const v = await ask({ label: mnemonic.toUpperCase() + ' ' + names[i], element: 'box', mnemonic: mnemonic, pin: i, anchor: el });
      if (v === null) return;
      operands.push(v);
    }
    const inputs = [];
    const pins = item.inputs || [];
    for (let i = 0; i < pins.length; i++) {
      const v = await ask({ label: mnemonic.toUpperCase() + ' ' + pins[i] + ' (contact)', element: 'contact', mnemonic: 'LD', pin: 0, anchor: el });
      if (v === null) return;
      inputs.push({ contact: 'LD', operands: [v] });
    }
    const before = signatures(b, n);
    const edit = {
      op: 'insert_box', at: el.dataset.path, place: isOutput(el) ? 'parallel' : 'after',
      box: mnemonic.toUpperCase(), operands: operands, inputs: inputs,
    };
    if (await send(edit)) selectNew(b, n, before, 'box');
  }

  async function branch() {
    const el = needElement();
    if (!el) return;
    const b = state.selection.b;
    const n = state.selection.n;
    const output = el.classList.contains('coil');
    const value = await ask({
      label: output ? 'parallel coil operand' : 'parallel contact operand',
      element: output ? 'coil' : 'contact', anchor: el,
    });
    if (value === null) return;
    const before = signatures(b, n);
    const element = output ? { coil: '=', operands: [value] } : { contact: 'LD', operands: [value] };
    const edit = { op: 'wrap_parallel', at: el.dataset.path, count: 1, branch: element };
    if (await send(edit)) selectNew(b, n, before, output ? 'coil' : 'contact');
  }

  function networkPath(b, n) {
    return 'blocks[' + b + '].networks[' + n + ']';
  }

  async function deleteSelection() {
    const el = selectedElement();
    if (el) {
      const path = el.dataset.path;
      if (await send({ op: 'delete', at: path })) {
        const view = selectedView();
        if (view && !selectedElement()) select(elements(view)[0] || view);
      }
      return;
    }
    const view = selectedView();
    if (!view) return notify('select an element or a network first', 'error');
    const b = state.selection.b;
    const n = state.selection.n;
    if (await send({ op: 'delete_network', at: networkPath(b, n) })) {
      const next = viewOf(b, n) || viewOf(b, n - 1);
      select(next);
    }
  }

  // A new network after the selected one (or at the end of the first block): its
  // first contact and its coil asked, the contact selected.
  async function networkNew() {
    const b = state.selection ? state.selection.b : 0;
    const section = sectionOf(b);
    if (!section) return notify('the file has no block', 'error');
    const at = state.selection ? state.selection.n + 1 : section.children.length;
    const contact = await ask({ label: 'new network: first contact', element: 'contact', mnemonic: 'LD' });
    if (contact === null) return;
    const coil = await ask({ label: 'new network: coil', element: 'coil', mnemonic: '=' });
    if (coil === null) return;
    const network = {
      title: '', comment: '',
      rung: { series: [{ contact: 'LD', operands: [contact] }, { coil: '=', operands: [coil] }] },
    };
    if (await send({ op: 'insert_network', at: networkPath(b, at), network: network })) {
      const view = viewOf(b, at);
      if (view) {
        select(elements(view)[0] || view);
        view.scrollIntoView({ block: 'nearest' });
      }
    }
  }

  // Change the operands (Enter or double-click on an element).
  async function changeOperands() {
    const el = needElement();
    if (!el) return;
    const text = tooltip(el);
    const space = text.indexOf(' ');
    const mnemonic = space < 0 ? text : text.slice(0, space);
    const current = space < 0 ? [] : text.slice(space + 1).split(',').map(function (s) { return s.trim(); });
    const kind = el.classList.contains('contact') ? 'contact' : el.classList.contains('coil') ? 'coil' : 'box';
    const operands = current.slice();
    const count = kind === 'box' ? current.length : 1;
    for (let i = 0; i < Math.max(count, 1); i++) {
      const v = await ask({
        label: mnemonic + ' operand ' + (i + 1), element: kind, mnemonic: mnemonic, pin: i,
        value: current[i] || '', anchor: el,
      });
      if (v === null) return;
      operands[i] = v;
    }
    await send({ op: 'set_operands', at: el.dataset.path, operands: operands });
  }

  async function moveNetwork(by) {
    const view = selectedView();
    if (!view) return notify('select a network first', 'error');
    const b = state.selection.b;
    const n = state.selection.n;
    const to = n + by;
    if (to < 0 || to >= sectionOf(b).children.length) return;
    const path = state.selection.path;
    if (await send({ op: 'move_network', at: networkPath(b, n), to: to })) {
      state.selection = { b: b, n: to };
      select(viewOf(b, to));
      if (path) state.selection.path = null;
    }
  }

  async function editHeading(field) {
    const view = selectedView();
    if (!view) return notify('select a network first', 'error');
    const b = state.selection.b;
    const n = state.selection.n;
    // From the model: the drawing wraps long titles and comments (docs/ladder.md,
    // "Comments"), so its lines are not the source's.
    const model = await call('/api/model?' + query({ file: state.file }));
    const net = model.blocks[b] && model.blocks[b].networks[n];
    if (!net) return;
    const current = field === 'title' ? (net.title || '') : (net.comment || '').split('\n').join(' / ');
    const value = await ask({ label: 'network ' + field + (field === 'comment' ? ' (" / " between lines)' : ''), kind: 'text', value: current, anchor: view });
    if (value === null) return;
    const edit = field === 'title'
      ? { op: 'set_network_title', at: networkPath(b, n), title: value }
      : { op: 'set_network_comment', at: networkPath(b, n), comment: value.split(' / ').join('\n') };
    await send(edit);
  }

  async function copyNetwork() {
    const view = selectedView();
    if (!view) return;
    const model = await call('/api/model?' + query({ file: state.file }));
    const net = model.blocks[state.selection.b].networks[state.selection.n];
    state.clipboard = JSON.parse(JSON.stringify(net));
    delete state.clipboard.number;
    notify('network copied');
  }

  async function pasteNetwork() {
    if (!state.clipboard) return notify('nothing copied: Ctrl+C on a selected network', 'error');
    const b = state.selection ? state.selection.b : 0;
    const at = state.selection ? state.selection.n + 1 : sectionOf(b).children.length;
    if (await send({ op: 'insert_network', at: networkPath(b, at), network: state.clipboard })) {
      select(viewOf(b, at));
    }
  }

  async function history(which) {
    try {
      applyUpdate(await call('/api/' + which, { json: { file: state.file } }));
    } catch (error) {
      notify(error, 'error');
    }
  }

  async function save() {
    try {
      const answer = await call('/api/save', { json: { file: state.file } });
      state.dirty = answer.dirty;
      showDirty();
      setStatus({});
      notify('saved ' + state.file);
    } catch (error) {
      notify(error, 'error');
    }
  }

  // LAD <-> STL: each block's STL as the buffer holds it (read-only here).
  async function viewStl() {
    if (body.dataset.view === 'STL') {
      body.dataset.view = 'LAD';
      redrawn();
      return;
    }
    const sections = Array.from(editor.querySelectorAll('section.block'));
    for (const section of sections) {
      const answer = await call('/api/stl?' + query({ file: state.file, block: section.dataset.b }));
      let pre = section.querySelector('.stl-view');
      if (!pre) {
        pre = document.createElement('pre');
        pre.className = 'stl-view';
        section.appendChild(pre);
      }
      pre.textContent = answer.text;
    }
    body.dataset.view = 'STL';
    redrawn();
  }

  // The whole drawing of the open file again.
  async function reload() {
    showDrawing(await call('/api/drawing?' + query({ file: state.file })));
  }

  // `symbol-info`: the table of each network's symbols under its rung, on or off
  // (docs/ladder.md, "Symbol information"); the server draws every network so from now on.
  async function toggleSymbolInfo() {
    const on = document.body.dataset.symbolInfo !== 'on';
    const drawing = await call('/api/view', { json: { file: state.file, symbol_info: on } });
    document.body.dataset.symbolInfo = drawing.symbol_info ? 'on' : 'off';
    showDrawing(drawing);
  }

  // A drawing answer (`/api/drawing`, `/api/view`) shown: every network redrawn.
  function showDrawing(drawing) {
    drawing.blocks.forEach(function (block, b) {
      const section = sectionOf(b);
      if (!section) return;
      section.innerHTML = '';
      block.networks.forEach(function (d) {
        const view = document.createElement('div');
        view.className = 'network-view';
        view.dataset.b = d.block;
        view.dataset.n = d.network;
        view.innerHTML = d.html;
        section.appendChild(view);
      });
    });
    state.diagnostics = drawing.diagnostics;
    state.dirty = drawing.dirty;
    showDiagnostics();
    showErrors();
    showDirty();
    reselect();
    setStatus({});
    redrawn();
  }

  // ---- commands and keys ------------------------------------------------------------

  function command(name, handler) {
    handlers[name] = handler;
  }

  // Commands run one after another, in the order asked (a paste pressed while a copy
  // still fetches waits for it). `run` answers when its command is done.
  let queue = Promise.resolve();

  function run(name) {
    const handler = handlers[name];
    if (!handler) {
      notify(name + ': not available in this studio', 'error');
      return Promise.resolve();
    }
    // A handler that never settles (a live loop) holds the queue 10 s at most.
    const next = queue.then(function () {
      return Promise.race([handler(), new Promise(function (r) { setTimeout(r, 10000); })]);
    })
      .catch(function (error) { notify(error, 'error'); });
    queue = next;
    return next;
  }

  function editing(fn) {
    return function () {
      if (mode() !== 'EDIT') {
        notify('editing needs EDIT mode: press Esc or the Edit button first', 'error');
        return;
      }
      return fn();
    };
  }

  command('edit', function () { setMode('EDIT'); setStatus({ run: '', where: '' }); });
  command('contact-no', editing(function () { return insertElement('contact', 'LD', 'contact (NO) operand'); }));
  command('contact-nc', editing(function () { return insertElement('contact', 'LDN', 'contact (NC) operand'); }));
  command('coil', editing(function () { return insertElement('coil', '=', 'coil operand'); }));
  command('coil-set', editing(function () { return insertElement('coil', 'S', 'set coil operand'); }));
  command('coil-reset', editing(function () { return insertElement('coil', 'R', 'reset coil operand'); }));
  command('box', editing(insertBox));
  command('branch', editing(branch));
  command('delete', editing(deleteSelection));
  command('network-new', editing(networkNew));
  command('network-up', editing(function () { return moveNetwork(-1); }));
  command('network-down', editing(function () { return moveNetwork(1); }));
  command('network-title', editing(function () { return editHeading('title'); }));
  command('network-comment', editing(function () { return editHeading('comment'); }));
  command('network-copy', copyNetwork);
  command('network-paste', editing(pasteNetwork));
  command('operand', editing(changeOperands));
  command('undo', editing(function () { return history('undo'); }));
  command('redo', editing(function () { return history('redo'); }));
  command('save', save);
  command('view-stl', viewStl);
  command('symbol-info', toggleSymbolInfo);

  // Key -> command: Micro/WIN's F4 contact, F6 coil, F9 box (docs/studio.md, "Keys").
  const KEYS = {
    'F4': 'contact-no', 'Shift+F4': 'contact-nc',
    'F6': 'coil', 'Shift+F6': 'coil-set', 'Alt+F6': 'coil-reset',
    'F9': 'box', 'F7': 'branch', 'Delete': 'delete',
    'Insert': 'network-new', 'Ctrl+Enter': 'network-new',
    'Alt+ArrowUp': 'network-up', 'Alt+ArrowDown': 'network-down',
    'F2': 'network-title', 'Shift+F2': 'network-comment',
    'Ctrl+c': 'network-copy', 'Ctrl+v': 'network-paste',
    'Enter': 'operand',
    'Ctrl+z': 'undo', 'Ctrl+y': 'redo', 'Ctrl+Shift+z': 'redo', 'Ctrl+Shift+Z': 'redo',
    'Ctrl+s': 'save', 'F3': 'view-stl', 'Alt+i': 'symbol-info',
    'F5': 'simulate', 'Shift+F5': 'stop', 'Ctrl+F5': 'online',
    'Ctrl+d': 'download', 'Alt+t': 'test', 'Escape': 'edit',
  };

  function keyName(e) {
    let name = '';
    if (e.ctrlKey || e.metaKey) name += 'Ctrl+';
    if (e.altKey) name += 'Alt+';
    if (e.shiftKey && e.key.length > 1) name += 'Shift+';
    else if (e.shiftKey && (e.ctrlKey || e.metaKey)) name += 'Shift+';
    return name + e.key;
  }

  document.addEventListener('keydown', function (e) {
    const t = e.target;
    if (t && (t.tagName === 'INPUT' || t.tagName === 'TEXTAREA' || t.tagName === 'SELECT' || t.isContentEditable)) return;
    if (['ArrowUp', 'ArrowDown', 'ArrowLeft', 'ArrowRight'].indexOf(e.key) >= 0 && !e.altKey && !e.ctrlKey) {
      e.preventDefault();
      moveSelection(e.key);
      return;
    }
    const name = KEYS[keyName(e)];
    if (!name) return;
    if (name === 'network-copy' && !selectedView()) return;
    if (name === 'edit' && mode() === 'EDIT') {
      select(null);
      return;
    }
    e.preventDefault();
    run(name);
  });

  document.querySelector('.toolbar').addEventListener('click', function (e) {
    const button = e.target.closest('button[data-command]');
    if (button) run(button.dataset.command);
  });

  document.querySelectorAll('.sidebar li[data-file]').forEach(function (li) {
    li.addEventListener('click', function () {
      const params = new URLSearchParams(location.search);
      params.set('file', li.dataset.file);
      location.search = params.toString();
    });
  });

  // ---- panels -----------------------------------------------------------------------

  function panel(name, title) {
    let section = panels.querySelector('.panel[data-panel="' + name + '"]');
    if (!section) {
      section = document.createElement('section');
      section.className = 'panel';
      section.dataset.panel = name;
      const h = document.createElement('h3');
      h.textContent = title || name;
      const content = document.createElement('div');
      content.className = 'panel-body';
      section.append(h, content);
      panels.appendChild(section);
    }
    return section.querySelector('.panel-body');
  }

  window.guttaStudio = {
    api: api,
    command: command,
    run: run,
    mode: mode,
    setMode: setMode,
    status: setStatus,
    file: function () { return state.file; },
    networks: networks,
    onRedraw: function (fn) { redrawHooks.push(fn); },
    panel: panel,
    notify: notify,
    reload: reload,
    // Beyond the common API: the selection, the operand editor, one edit operation
    // sent and its answer put in place (the update, or null when refused).
    selection: function () { return state.selection; },
    ask: ask,
    edit: send,
    // A request's JSON answer (a refusal throws an Error with `code` and `path`), and
    // an object as a query string: what the other scripts ask the server with.
    call: call,
    query: query,
  };

  showDiagnostics();
  showErrors();
  showDirty();
  setStatus({});
  // When the page became interactive (ms since navigation start): the page bench.
  window.guttaStudioReady = performance.now();
})();
