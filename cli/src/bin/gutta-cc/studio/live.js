// The studio's live view (docs/studio.md, "Simulate" and "Live state"): the commands
// `simulate`, `stop` and `edit`; while SIMULATE or ONLINE it polls /api/live (the next
// request when the last one answered, at most every POLL_MS) and marks the drawing:
// class `on` on energized contacts, coils, boxes and the wires they power (`data-after`),
// values beside operands, `forced` on forced operands, RUN/STOP, the scan count or the
// PLC's address and the time of the update in the status bar. A click on an input
// contact in SIMULATE toggles it; the watch panel reads, writes and forces variables.
// Power flow and values are the server's; this script only paints them.
(function () {
  'use strict';
  const studio = window.guttaStudio;
  if (!studio) return;
  const SVG = 'http://www.w3.org/2000/svg';
  // 40 updates a second at most (the bar is 20).
  const POLL_MS = 25;
  const FORMATS = ['', 'bool', 'int', 'uint', 'hex', 'real'];
  let last = null; // the last /api/live state painted
  let updates = 0; // states painted since the page opened (the browser test reads it)
  const watch = []; // watch rows: {operand, format, answer}

  // A request's JSON, or an Error carrying the answer's code.
  function call(path, json) {
    const init = json === undefined ? { method: 'POST' } : { method: 'POST', json: json };
    return answer(studio.api(path, init));
  }
  function answer(request) {
    return request.then(function (response) {
      return response.json().then(function (body) {
        if (response.ok) return body;
        const refusal = body && body.error ? body.error : body || {};
        const error = new Error(refusal.message || 'HTTP ' + response.status);
        error.code = refusal.code;
        throw error;
      });
    });
  }
  function fail(error) {
    studio.notify(error, 'error');
  }

  function isLive() {
    const mode = studio.mode();
    return mode === 'SIMULATE' || mode === 'ONLINE';
  }

  // ---- commands ----------------------------------------------------------------
  studio.command('simulate', function () {
    const request = studio.mode() === 'SIMULATE' && last && last.run === false
      ? call('/api/live/run')
      : call('/api/simulate');
    return request.then(function (state) {
      studio.setMode('SIMULATE');
      paint(state);
      studio.notify('simulating ' + (studio.file() || 'the program') + ': RUN', 'info');
    }, fail);
  });
  studio.command('stop', function () {
    if (!isLive()) {
      studio.notify('nothing runs: simulate or go online first', 'error');
      return;
    }
    return call('/api/live/stop').then(paint, fail);
  });
  studio.command('edit', function () {
    return call('/api/edit-mode').then(function () {
      studio.setMode('EDIT');
      last = null;
      clear();
      studio.status({ run: '', where: '', updated: '' });
    }, fail);
  });

  // ---- painting ----------------------------------------------------------------
  function clear() {
    studio.networks().forEach(function (g) {
      const p = parts.get(g);
      if (p) {
        p.on = null;
        p.forced = null;
        p.values.forEach(function (v) { v.shown = null; });
      }
    });
    document.querySelectorAll('.network .on').forEach(function (e) { e.classList.remove('on'); });
    document.querySelectorAll('.network .forced').forEach(function (e) { e.classList.remove('forced'); });
    document.querySelectorAll('.network [data-value]').forEach(function (e) { e.removeAttribute('data-value'); });
    document.querySelectorAll('.network .stl-line[data-rlo]').forEach(function (e) { e.removeAttribute('data-rlo'); });
    document.querySelectorAll('.network tspan.value').forEach(function (e) { e.remove(); });
  }

  // `text` after the <text> element `t`, in a tspan of class `value` (written only when
  // it changed).
  function showValue(t, text) {
    if (!t) return;
    let span = t.querySelector('tspan.value');
    if (!span) {
      span = document.createElementNS(SVG, 'tspan');
      span.setAttribute('class', 'value');
      t.appendChild(span);
    }
    const shown = ' = ' + text;
    if (span.textContent !== shown) span.textContent = shown;
  }

  // What painting needs of one drawn network, found once per <g> (a redrawn network
  // is a new element, so its parts are found again): its elements by id, its wires
  // with what powers them, the texts that show values, what can be marked forced,
  // and what was painted last (so an unchanged network costs a comparison).
  const parts = new WeakMap();
  function partsOf(g) {
    let p = parts.get(g);
    if (p) return p;
    p = { elements: [], wires: [], values: [], marks: [], bits: [], lines: [], on: null, forced: null };
    g.querySelectorAll('.contact, .coil, .box').forEach(function (e) {
      p.elements.push({ e: e, id: e.getAttribute('data-id') });
    });
    g.querySelectorAll('.wire').forEach(function (w) {
      p.wires.push({ e: w, after: (w.getAttribute('data-after') || '').split(' ') });
    });
    g.querySelectorAll('.operand[data-operand]').forEach(function (o) {
      const a = o.getAttribute('data-operand');
      const t = o.querySelector('text.address') || o.querySelector('text');
      if (a && t) p.values.push({ address: a, text: t, shown: null });
    });
    // A timer's or counter's number is the `.operand.counted` above its box (its kind
    // is the box's title): its current value shows there, as every operand's does.
    g.querySelectorAll('.contact, .coil, .operand').forEach(function (e) {
      const a = e.getAttribute('data-operand');
      if (a) p.marks.push({ e: e, address: a });
    });
    // Contacts and coils carry their operand's bit (`data-value`), powered or not.
    g.querySelectorAll('.contact[data-operand], .coil[data-operand]').forEach(function (e) {
      p.bits.push({ e: e, address: e.getAttribute('data-operand') });
    });
    g.querySelectorAll('.stl-line[data-index]').forEach(function (t) {
      p.lines[Number(t.getAttribute('data-index'))] = t;
    });
    parts.set(g, p);
    return p;
  }

  function paint(state) {
    if (!state || !state.mode) return;
    if (state.mode === 'EDIT') {
      // The server went back to EDIT (another tab, a restart): so does the page.
      if (isLive()) studio.setMode('EDIT');
      last = null;
      clear();
      return;
    }
    last = state;
    updates += 1;
    document.body.dataset.liveUpdates = String(updates);
    const values = state.values || {};
    const forcedList = state.forced || [];
    const forced = new Set(forcedList);
    const forcedKey = forcedList.join(' ');
    const byNetwork = new Map();
    (state.networks || []).forEach(function (n) {
      byNetwork.set(n.block + '/' + n.network, n.on);
    });
    const bits = state.bits || {};
    const stlLines = new Map();
    (state.stl || []).forEach(function (n) {
      stlLines.set(n.block + '/' + n.network, n.lines);
    });
    studio.networks().forEach(function (g, key) {
      const p = partsOf(g);
      const listed = byNetwork.has(key);
      const list = byNetwork.get(key) || [];
      // Not listed (STOP, stale values): nothing on, not even the rail's wires.
      const onKey = listed ? list.join(' ') : '-';
      if (p.on !== onKey) {
        p.on = onKey;
        const on = new Set(list.map(String));
        p.elements.forEach(function (x) { x.e.classList.toggle('on', on.has(x.id)); });
        p.wires.forEach(function (w) {
          w.e.classList.toggle('on', listed && w.after.some(function (a) {
            return a === 'rail' || on.has(a);
          }));
        });
      }
      p.values.forEach(function (v) {
        const value = values[v.address];
        if (value !== undefined && value !== v.shown) {
          v.shown = value;
          showValue(v.text, value);
        }
      });
      p.bits.forEach(function (b) {
        const bit = bits[b.address];
        if (bit === undefined) {
          b.e.removeAttribute('data-value');
        } else if (b.e.getAttribute('data-value') !== String(bit)) {
          b.e.setAttribute('data-value', String(bit));
        }
      });
      // STL lines: the logic result after each (in RUN; none in STOP).
      const lines = stlLines.get(key) || [];
      lines.forEach(function (line) {
        const t = p.lines[line.index];
        if (!t) return;
        if (line.rlo === null || line.rlo === undefined) t.removeAttribute('data-rlo');
        else t.setAttribute('data-rlo', String(line.rlo));
      });
      if (p.forced !== forcedKey) {
        p.forced = forcedKey;
        p.marks.forEach(function (m) { m.e.classList.toggle('forced', forced.has(m.address)); });
      }
    });
    studio.status({
      run: state.run === true ? 'RUN' : state.run === false ? 'STOP' : '',
      where: state.mode === 'SIMULATE' ? 'scan ' + state.scans : state.address || '',
      updated: state.updated || Date.now(),
    });
  }
  studio.onRedraw(function () {
    if (last && isLive()) paint(last);
  });

  // ---- polling -----------------------------------------------------------------
  function tick() {
    if (!isLive()) {
      setTimeout(tick, 100);
      return;
    }
    const started = Date.now();
    answer(studio.api('/api/live'))
      .then(function (state) {
        const painting = performance.now();
        document.body.dataset.liveFetchMs = String(Date.now() - started);
        // An answer that arrives after `edit` is not painted.
        if (isLive()) paint(state);
        document.body.dataset.livePaintMs = String(Math.round(performance.now() - painting));
      })
      .then(readWatch)
      .catch(function (error) {
        studio.status({ run: '', where: '', updated: 'no answer: ' + error.message });
      })
      .then(function () {
        setTimeout(tick, Math.max(0, POLL_MS - (Date.now() - started)));
      });
  }
  tick();

  // ---- a click on an input contact ---------------------------------------------
  document.addEventListener('click', function (event) {
    if (studio.mode() !== 'SIMULATE') return;
    const contact = event.target.closest && event.target.closest('.contact[data-operand]');
    if (!contact) return;
    const operand = contact.getAttribute('data-operand');
    if (!/^I\d+\.\d$/.test(operand)) return;
    call('/api/live/toggle', { operand: operand }).then(paint, fail);
  });

  // ---- the watch table ----------------------------------------------------------
  // Its layout fits the side panel: per row, the operand, its address, format and
  // value on one line; the new value and Write / Force / Release / remove under it.
  const STYLE = '.watch-add{display:flex;gap:4px;margin-bottom:6px}.watch-add input{flex:1;min-width:0}' +
    '.watch-row{border-top:1px solid #e5e7eb;padding:3px 0}.watch-line{display:flex;gap:6px;align-items:center}' +
    '.watch-name{font-weight:bold}.watch-address{color:#6b7280;font-family:monospace}' +
    '.watch-value{margin-left:auto;font-family:monospace;color:#1558b0}.watch-row.forced .watch-value{color:#b3261e;font-weight:bold}' +
    '.watch-row.error .watch-value{color:#b3261e;font-family:inherit;font-size:12px}' +
    '.watch-new{width:70px}.watch-line button{padding:0 4px}';
  let panel = null;
  function watchPanel() {
    if (panel) return panel;
    panel = studio.panel('watch', 'Watch');
    panel.classList.add('watch');
    const style = document.createElement('style');
    style.textContent = STYLE;
    document.head.appendChild(style);
    panel.innerHTML =
      '<form class="watch-add"><input class="watch-operand" placeholder="symbol or address" ' +
      'autocomplete="off"><select class="watch-format"></select><button type="submit">Add</button></form>' +
      '<div class="watch-rows"></div>';
    const select = panel.querySelector('.watch-format');
    fillFormats(select);
    panel.querySelector('.watch-add').addEventListener('submit', function (event) {
      event.preventDefault();
      const input = panel.querySelector('.watch-operand');
      const operand = input.value.trim();
      if (!operand) return;
      watch.push({ operand: operand, format: select.value, answer: null });
      input.value = '';
      renderWatch();
      readWatch();
    });
    renderWatch();
    return panel;
  }

  function fillFormats(select) {
    FORMATS.forEach(function (f) {
      const option = document.createElement('option');
      option.value = f;
      option.textContent = f || 'own';
      select.appendChild(option);
    });
  }

  function renderWatch() {
    const rows = watchPanel().querySelector('.watch-rows');
    rows.textContent = '';
    watch.forEach(function (row, index) {
      const div = document.createElement('div');
      div.className = 'watch-row';
      div.dataset.operand = row.operand;
      div.innerHTML =
        '<div class="watch-line"><span class="watch-name"></span><span class="watch-address"></span>' +
        '<select class="watch-row-format" title="format"></select><span class="watch-value"></span></div>' +
        '<div class="watch-line"><input class="watch-new" placeholder="value">' +
        '<button type="button" data-watch="write">Write</button>' +
        '<button type="button" data-watch="force">Force</button>' +
        '<button type="button" data-watch="release">Release</button>' +
        '<button type="button" data-watch="remove" title="remove the row">x</button></div>';
      div.querySelector('.watch-name').textContent = row.operand;
      const select = div.querySelector('.watch-row-format');
      fillFormats(select);
      select.value = row.format;
      select.addEventListener('change', function () {
        row.format = select.value;
        readWatch();
      });
      div.addEventListener('click', function (event) {
        const action = event.target.getAttribute && event.target.getAttribute('data-watch');
        if (!action) return;
        const value = div.querySelector('.watch-new').value.trim();
        const operand = row.format ? row.operand + ':' + row.format : row.operand;
        let request;
        if (action === 'remove') {
          watch.splice(index, 1);
          renderWatch();
          return;
        } else if (action === 'write') {
          request = call('/api/live/write', { operand: operand, value: value });
        } else if (action === 'force') {
          request = call('/api/live/force', { operand: operand, value: value });
        } else {
          request = call('/api/live/force', { operand: row.operand, value: null });
        }
        request.then(function (state) { paint(state); return readWatch(); }, fail);
      });
      rows.appendChild(div);
      showRow(div, row);
    });
  }

  function showRow(tr, row) {
    const a = row.answer;
    tr.querySelector('.watch-address').textContent = a && a.address ? a.address : '';
    const value = tr.querySelector('.watch-value');
    value.textContent = a ? (a.error ? '[' + a.error.code + '] ' + a.error.message : a.value) : '';
    tr.classList.toggle('forced', !!(a && a.forced));
    tr.classList.toggle('error', !!(a && a.error));
  }

  function readWatch() {
    if (!watch.length || !isLive()) return null;
    const rows = watch.map(function (r) { return { operand: r.operand, format: r.format || null }; });
    return call('/api/live/read', { rows: rows }).then(function (answer) {
      const trs = watchPanel().querySelectorAll('.watch-row');
      answer.rows.forEach(function (a, i) {
        if (!watch[i]) return;
        watch[i].answer = a;
        if (trs[i]) showRow(trs[i], watch[i]);
      });
    });
  }

  // The panel exists from the start: operands can be added before simulating.
  watchPanel();
})();
