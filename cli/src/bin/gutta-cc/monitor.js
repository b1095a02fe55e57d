// gutta-cc monitor's live script (docs/ladder.md, "Live view"): fetch /state ten times
// a second and mark the drawing: class `on` on energized contacts, coils, boxes and the
// wires they power (`data-after`), `forced` on forced operands, values beside box pins.
// It only reads /state; the power flow is computed by the monitor.
(function () {
  "use strict";
  var status = document.getElementById("status");
  var networks = {};
  document.querySelectorAll("g.network").forEach(function (g) {
    networks[g.getAttribute("data-block") + "/" + g.getAttribute("data-network")] = g;
  });
  var SVG = "http://www.w3.org/2000/svg";

  function clear() {
    document.querySelectorAll(".on").forEach(function (e) { e.classList.remove("on"); });
    document.querySelectorAll(".forced").forEach(function (e) { e.classList.remove("forced"); });
    document.querySelectorAll("tspan.value").forEach(function (e) { e.remove(); });
  }

  // The value `text` after the given <text> element, in a tspan of class `value`.
  function showValue(textElement, text) {
    if (!textElement) { return; }
    var span = textElement.querySelector("tspan.value");
    if (!span) {
      span = document.createElementNS(SVG, "tspan");
      span.setAttribute("class", "value");
      textElement.appendChild(span);
    }
    span.textContent = " = " + text;
  }

  function apply(state) {
    status.textContent = state.message || "";
    document.body.classList.toggle("stale", !state.live);
    if (!state.live) { clear(); return; }
    var values = state.values || {};
    var forced = {};
    (state.forced || []).forEach(function (a) { forced[a] = true; });
    state.networks.forEach(function (n) {
      var g = networks[n.block + "/" + n.network];
      if (!g) { return; }
      var on = {};
      n.on.forEach(function (id) { on[String(id)] = true; });
      g.querySelectorAll(".contact, .coil, .box").forEach(function (e) {
        e.classList.toggle("on", on[e.getAttribute("data-id")] === true);
      });
      g.querySelectorAll(".wire").forEach(function (w) {
        var after = (w.getAttribute("data-after") || "").split(" ");
        w.classList.toggle("on", after.some(function (a) { return a === "rail" || on[a] === true; }));
      });
      g.querySelectorAll(".box").forEach(function (b) {
        b.querySelectorAll(".pin-operand .operand").forEach(function (o) {
          var a = o.getAttribute("data-operand");
          if (a && values[a] !== undefined) {
            showValue(o.querySelector("text.address") || o.querySelector("text"), values[a]);
          }
        });
        var title = b.querySelector("text.title");
        // A timer's or counter's title is its number (`T37`): its current value.
        var number = title && title.firstChild ? title.firstChild.nodeValue : "";
        if (number && values[number] !== undefined) {
          showValue(title, values[number]);
        }
      });
    });
    document.querySelectorAll(".contact, .coil, .operand").forEach(function (e) {
      e.classList.toggle("forced", forced[e.getAttribute("data-operand")] === true);
    });
  }

  function tick() {
    fetch("/state", { cache: "no-store" })
      .then(function (r) { return r.json(); })
      .then(apply)
      .catch(function (e) {
        clear();
        status.textContent = "the monitor does not answer: " + e;
      })
      .then(function () { setTimeout(tick, 100); });
  }
  tick();
})();
