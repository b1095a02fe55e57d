// The studio online and its tests (docs/studio.md, "Online", "Tests"): the commands
// `online` (connect to gutta.toml's [connection]: POST /api/online), `download` (asked
// first in the online panel, then POST /api/online/download with its progress from GET
// /api/online/progress) and `test` (POST /api/tests, the results in the tests panel).
// While ONLINE it asks GET /api/online twice a second for what the PLC holds: another
// program, or none, is said in the online panel with a Download button. Painting the
// power flow and the status bar's RUN/STOP is live.js's, from /api/live.
(function () {
  'use strict';
  const studio = window.guttaStudio;
  if (!studio) return;
  let downloading = false;

  const style = document.createElement('style');
  style.textContent =
    '.panel-body .test{margin:6px 0;padding:4px 6px;border-left:4px solid #16a34a}' +
    '.panel-body .test.failed{border-left-color:#dc2626;background:#fef2f2}' +
    '.test-status{font-weight:bold;color:#16a34a}.test.failed .test-status{color:#dc2626}' +
    '.test-line{color:#6b7280;font-family:monospace}.test-file-name{font-weight:bold;margin-top:6px}' +
    '.test-detail{font-size:11px;overflow-x:auto;background:#fff;padding:4px;margin:4px 0}' +
    '.tests-summary{font-weight:bold}.tests-summary.failed{color:#dc2626}' +
    '.tests-summary.passed{color:#16a34a}' +
    '.online-state{font-family:monospace;margin-bottom:6px}' +
    '.online-offer button,.download-confirm button{margin:4px 4px 0 0}' +
    'progress.download-progress{width:100%}';
  document.head.appendChild(style);

  // A request's JSON answer (a body is sent as JSON); a refusal throws an Error with
  // its code.
  function call(path, body) {
    return studio.call(path, body === undefined ? {} : { json: body });
  }

  function fail(error) {
    studio.notify({ code: error.code, message: error.message }, 'error');
  }

  function element(tag, className, text) {
    const e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  // ---- the online panel ----------------------------------------------------------
  function onlinePanel() {
    const panel = studio.panel('online', 'Online');
    if (!panel.querySelector('.online-state')) {
      panel.appendChild(element('div', 'online-state'));
      panel.appendChild(element('div', 'online-offer'));
      panel.appendChild(element('div', 'online-download'));
    }
    return panel;
  }

  // What the PLC holds, and a Download button when it is not this program.
  function showState(state) {
    if (!state || state.mode !== 'ONLINE') return;
    const panel = onlinePanel();
    const shown = panel.querySelector('.online-state');
    shown.dataset.program = state.program || '';
    shown.dataset.run = state.run === true ? 'RUN' : state.run === false ? 'STOP' : '';
    shown.textContent = 'PLC at ' + (state.address || '?') + ': ' +
      (state.run === true ? 'RUN' : state.run === false ? 'STOP' : 'no answer') +
      (state.program === 'same' ? ', runs this program' : '');
    const offer = panel.querySelector('.online-offer');
    const other = state.program === 'other' || state.program === 'none';
    if (other || (state.live === false && state.message)) {
      offer.hidden = false;
      if (offer.dataset.message !== state.message || offer.dataset.program !== state.program) {
        offer.dataset.message = state.message || '';
        offer.dataset.program = state.program || '';
        offer.textContent = '';
        offer.appendChild(element('div', 'message ' + (other ? 'error' : 'info'), state.message));
        if (other) {
          const button = element('button', 'offer-download', 'Download');
          button.type = 'button';
          button.addEventListener('click', function () { studio.run('download'); });
          offer.appendChild(button);
        }
      }
    } else {
      offer.hidden = true;
      offer.textContent = '';
      offer.dataset.message = '';
      offer.dataset.program = '';
    }
    if (studio.mode() === 'ONLINE') {
      studio.status({
        run: state.run === true ? 'RUN' : state.run === false ? 'STOP' : '',
        where: state.address || '',
        updated: state.updated,
      });
    }
  }

  function poll() {
    if (studio.mode() !== 'ONLINE' || downloading) {
      setTimeout(poll, 500);
      return;
    }
    call('/api/online', undefined)
      .then(function (state) {
        if (state.mode === 'EDIT' && studio.mode() === 'ONLINE') {
          // The connection ended (simulate or edit took over): the panel says so.
          onlinePanel().querySelector('.online-state').textContent = 'offline';
          return;
        }
        showState(state);
      })
      .catch(function () {})
      .then(function () { setTimeout(poll, 500); });
  }
  setTimeout(poll, 500);

  studio.command('online', function () {
    onlinePanel().querySelector('.online-state').textContent = 'connecting...';
    return call('/api/online', {}).then(function (state) {
      studio.setMode('ONLINE');
      showState(state);
      studio.notify('online: the PLC at ' + state.address, 'info');
    }, function (error) {
      onlinePanel().querySelector('.online-state').textContent = 'offline';
      fail(error);
    });
  });

  // ---- download ------------------------------------------------------------------
  // Asked first in the online panel: Download sends, Cancel leaves the PLC as it is.
  studio.command('download', function () {
    if (downloading) return;
    const place = onlinePanel().querySelector('.online-download');
    place.textContent = '';
    const ask = element('div', 'download-confirm');
    ask.appendChild(element('div', '', 'Download ' + (studio.file() || 'the program') +
      ' (as edited, saved or not) to the PLC? It replaces the program the PLC holds.'));
    const yes = element('button', 'confirm-download', 'Download');
    const no = element('button', 'cancel-download', 'Cancel');
    yes.type = 'button';
    no.type = 'button';
    ask.appendChild(yes);
    ask.appendChild(no);
    place.appendChild(ask);
    yes.focus();
    no.addEventListener('click', function () { place.textContent = ''; });
    yes.addEventListener('click', function () { send(place); });
  });

  function send(place) {
    downloading = true;
    place.textContent = '';
    const bar = element('progress', 'download-progress');
    bar.max = 1;
    bar.value = 0;
    const line = element('div', 'download-line', 'downloading...');
    place.appendChild(bar);
    place.appendChild(line);
    let following = true;
    function follow() {
      if (!following) return;
      call('/api/online/progress', undefined).then(function (p) {
        // A progress answer that arrives after the download's own answer is stale:
        // it must not write over the result.
        if (!following) return;
        if (p && p.total) {
          bar.max = p.total;
          bar.value = p.done;
          line.textContent = 'downloading: ' + p.done + ' of ' + p.total + ' bytes';
        }
      }).catch(function () {}).then(function () { setTimeout(follow, 100); });
    }
    follow();
    return call('/api/online/download', {}).then(function (answer) {
      following = false;
      const d = answer.download;
      bar.max = 1;
      bar.value = 1;
      line.className = 'download-line download-result';
      line.textContent = 'downloaded ' + d.pages + ' pages (' + d.bytes + ' bytes) in ' +
        d.seconds.toFixed(2) + ' s: the PLC ' + (d.run ? 'runs' : 'is in STOP');
      studio.setMode('ONLINE');
      showState(answer.state);
      studio.notify('downloaded to the PLC at ' + answer.state.address, 'info');
    }, function (error) {
      following = false;
      place.textContent = '';
      const shown = element('div', 'download-line download-error message error',
        (error.code ? error.code + ': ' : '') + error.message);
      if (error.code) shown.dataset.code = error.code;
      place.appendChild(shown);
      fail(error);
    }).then(function () { downloading = false; });
  }

  // ---- tests ---------------------------------------------------------------------
  studio.command('test', function () {
    const panel = studio.panel('tests', 'Tests');
    panel.textContent = '';
    panel.appendChild(element('div', 'tests-summary running', 'running the tests...'));
    return call('/api/tests', {}).then(function (run) {
      if (run.refused) {
        panel.textContent = '';
        const r = run.refused;
        const shown = element('div', 'tests-summary message error',
          r.code + ': ' + r.message + ': no test ran');
        shown.dataset.code = r.code;
        panel.appendChild(shown);
        return;
      }
      showTests(panel, run);
    }, function (error) {
      panel.textContent = '';
      const shown = element('div', 'tests-summary message error',
        (error.code ? error.code + ': ' : '') + error.message);
      if (error.code) shown.dataset.code = error.code;
      panel.appendChild(shown);
      fail(error);
    });
  });

  function showTests(panel, run) {
    panel.textContent = '';
    const summary = element('div', 'tests-summary ' + (run.failed ? 'failed' : 'passed'),
      run.passed + ' passed, ' + run.failed + ' failed' +
      (run.file_errors ? ', ' + run.file_errors + ' files did not run' : ''));
    summary.dataset.passed = String(run.passed);
    summary.dataset.failed = String(run.failed);
    panel.appendChild(summary);
    if (!run.files.length) {
      panel.appendChild(element('div', 'message info', 'the project has no .gtest files'));
    }
    run.files.forEach(function (file) {
      const f = element('div', 'test-file');
      f.dataset.file = file.file;
      f.appendChild(element('div', 'test-file-name', file.file));
      file.errors.forEach(function (e) { f.appendChild(element('div', 'test-error message error', e)); });
      file.tests.forEach(function (t) {
        const row = element('div', 'test ' + t.status);
        row.dataset.test = t.test;
        row.dataset.status = t.status;
        row.appendChild(element('span', 'test-status', t.status === 'passed' ? 'PASS' : 'FAIL'));
        row.appendChild(element('span', 'test-name', ' ' + t.test + ' '));
        const at = t.failure ? t.failure.line : t.line;
        const line = element('span', 'test-line', file.file + ':' + at);
        line.dataset.line = String(at);
        row.appendChild(line);
        if (t.failure) {
          row.appendChild(element('div', 'test-message', t.failure.message));
          row.appendChild(element('pre', 'test-detail', t.detail));
        }
        f.appendChild(row);
      });
      panel.appendChild(f);
    });
  }
})();
