// The GUTTA Studio page's script (docs/studio.md): thin by design. It keeps the token
// for its requests, marks a clicked element `selected`, and shows in the status bar
// when it last read the project. Drawing, checks and files are the server's.
(function () {
  'use strict';
  const status = document.querySelector('.status');

  // Every request of the page carries the token in a header (never in a Referer).
  function api(path, options) {
    const init = Object.assign({}, options || {});
    init.headers = Object.assign({ 'X-Gutta-Token': GUTTA_TOKEN }, init.headers || {});
    return fetch(path, init);
  }
  window.guttaStudio = { api: api };

  document.addEventListener('click', function (event) {
    const element = event.target.closest('.contact, .coil, .box');
    document.querySelectorAll('.selected').forEach(function (e) {
      if (e !== element) e.classList.remove('selected');
    });
    if (element) element.classList.add('selected');
  });

  function refresh() {
    api('/api/project')
      .then(function (answer) {
        if (!answer.ok) throw new Error('HTTP ' + answer.status);
        return answer.json();
      })
      .then(function (project) {
        const errors = project.diagnostics.errors;
        const shown = status.querySelector('.diagnostics');
        shown.dataset.errors = String(errors);
        shown.textContent = errors === 1 ? '1 error' : errors + ' errors';
        status.querySelector('.updated').textContent =
          new Date().toLocaleTimeString();
      })
      .catch(function (error) {
        status.querySelector('.updated').textContent = 'server: ' + error.message;
      });
  }
  refresh();
})();
