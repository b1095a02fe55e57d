// gutta-cc monitor's live script (docs/ladder.md, "Live view"): listen to /events (one
// server-sent event per update, the latest at once on connect) and mark the drawing:
// the status bar (RUN/STOP, the PLC, the connection, the time of the last update);
// `data-value` (0/1) on every contact and coil with its operand's bit, powered or not;
// class `on` on energized contacts, coils, boxes and the wires they power
// (`data-after`) only while the PLC is in RUN and the values are fresh; `forced` on
// forced operands; values beside box pins, compare operands and timers/counters; and
// per STL line its logic result (`data-rlo`) and its operands' values. It only reads
// the events; the power flow and the STL status are computed by the monitor.
(function () {
  "use strict";
  // No update for this long: the values are stale (no power flow is shown).
  var STALE_MS = 2000;
  var SVG = "http://www.w3.org/2000/svg";

  var style = document.createElement("style");
  style.textContent =
    ".status{font-family:monospace;padding:4px 8px;background:#eee;border:1px solid #ccc}" +
    ".status .run{font-weight:bold;color:#1a7f37}.status .stop{font-weight:bold;color:#b3261e}" +
    ".status .stale-note{color:#b3261e}" +
    ".contact[data-value='1']:not(.on) .symbol-line,.coil[data-value='1']:not(.on) .symbol-line" +
    "{stroke:#1558b0;stroke-width:3}" +
    ".stl-line[data-rlo='1']{fill:#1a7f37;font-weight:bold}.stl-line[data-rlo='0']{fill:#555}" +
    ".forced-note{color:#b3261e;font-size:90%}";
  document.head.appendChild(style);

  // The status bar: `.status` (its text says RUN or STOP), then the message (#status).
  var message = document.getElementById("status");
  var bar = document.createElement("div");
  bar.className = "status";
  function part(cls) {
    var s = document.createElement("span");
    s.className = cls;
    bar.appendChild(s);
    bar.appendChild(document.createTextNode(" "));
    return s;
  }
  var runPart = part("state");
  var plcPart = part("plc");
  var connPart = part("connection");
  var timePart = part("time");
  var stalePart = part("stale-note");
  message.parentNode.insertBefore(bar, message);
  var forcedNote = document.createElement("p");
  forcedNote.className = "forced-note";
  forcedNote.hidden = true;
  message.parentNode.insertBefore(forcedNote, message.nextSibling);

  var networks = {};
  document.querySelectorAll("g.network").forEach(function (g) {
    networks[g.getAttribute("data-block") + "/" + g.getAttribute("data-network")] = g;
  });

  var last = null;        // the last state received
  var lastAt = 0;         // when (Date.now())
  var streamUp = false;   // the event stream is open
  var everUp = false;     // it has been open once

  function clearPower() {
    document.querySelectorAll(".on").forEach(function (e) { e.classList.remove("on"); });
    document.querySelectorAll(".stl-line[data-rlo]").forEach(function (e) { e.removeAttribute("data-rlo"); });
  }

  function clearValues() {
    clearPower();
    document.querySelectorAll(".forced").forEach(function (e) { e.classList.remove("forced"); });
    document.querySelectorAll(".value").forEach(function (e) { e.remove(); });
    document.querySelectorAll("[data-value]").forEach(function (e) { e.removeAttribute("data-value"); });
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

  function addressText(operand) {
    return operand.querySelector("text.address") || operand.querySelector("text");
  }

  function pad(n) { return (n < 10 ? "0" : "") + n; }

  function clock(ms) {
    var d = new Date(ms);
    return pad(d.getHours()) + ":" + pad(d.getMinutes()) + ":" + pad(d.getSeconds()) +
      "." + String(d.getMilliseconds() + 1000).slice(1);
  }

  // Stale: no event stream, no update for STALE_MS, or an update without values.
  function staleReason() {
    if (!streamUp) { return everUp ? "the monitor does not answer" : "connecting to the monitor"; }
    if (!last) { return "waiting for the first update"; }
    if (Date.now() - lastAt > STALE_MS) { return "no update for " + ((Date.now() - lastAt) / 1000).toFixed(1) + " s"; }
    if (!last.live) { return last.message || "no values"; }
    return "";
  }

  function showStatus() {
    var s = last || {};
    var run = s.run === true ? "RUN" : s.run === false ? "STOP" : "RUN/STOP unknown";
    runPart.textContent = run;
    runPart.className = "state " + (s.run === true ? "run" : s.run === false ? "stop" : "");
    plcPart.textContent = s.plc ? "PLC " + s.plc + " station " + s.station : "";
    connPart.textContent = streamUp ? (s.connection || "") :
      everUp ? "monitor not answering" : "connecting";
    timePart.textContent = lastAt ? "last update " + clock(s.time_ms || lastAt) : "";
    var reason = staleReason();
    var stopped = s.run === false && !reason;
    stalePart.textContent = reason ? "stale: " + reason :
      stopped ? "STOP: values shown, no power flow" : "";
    var stale = reason !== "";
    document.body.classList.toggle("stale", stale);
    document.body.classList.toggle("stopped", s.run === false);
    document.querySelectorAll("g.network").forEach(function (g) {
      g.classList.toggle("stale", stale);
    });
    message.textContent = s.message || "";
    return stale;
  }

  function apply(state) {
    last = state;
    lastAt = Date.now();
    if (showStatus()) {
      if (!state.live) { clearValues(); } else { clearPower(); }
      return;
    }
    var running = state.run === true;
    var values = state.values || {};
    var bits = state.bits || {};
    var forced = {};
    (state.forced || []).forEach(function (a) { forced[a] = true; });
    forcedNote.hidden = false;
    forcedNote.textContent = "Forced operands are marked in red; " + (state.forced_note || "");
    // Bits: every contact and coil, powered or not.
    document.querySelectorAll("g.contact, g.coil").forEach(function (e) {
      var a = e.getAttribute("data-operand");
      if (a && bits[a] !== undefined) {
        e.setAttribute("data-value", String(bits[a]));
      } else {
        e.removeAttribute("data-value");
      }
    });
    // Compare contacts: both operands' values.
    document.querySelectorAll("g.contact[data-kind='compare'] g.operand").forEach(function (o) {
      var a = o.getAttribute("data-operand");
      if (a && values[a] !== undefined) { showValue(addressText(o), values[a]); }
    });
    state.networks.forEach(function (n) {
      var g = networks[n.block + "/" + n.network];
      if (!g) { return; }
      var on = {};
      if (running) { n.on.forEach(function (id) { on[String(id)] = true; }); }
      g.querySelectorAll(".contact, .coil, .box").forEach(function (e) {
        e.classList.toggle("on", on[e.getAttribute("data-id")] === true);
      });
      g.querySelectorAll(".wire").forEach(function (w) {
        var after = (w.getAttribute("data-after") || "").split(" ");
        w.classList.toggle("on", running && after.some(function (a) { return a === "rail" || on[a] === true; }));
      });
      g.querySelectorAll(".box").forEach(function (b) {
        // Pins: `g.pin[data-operand]`.
        b.querySelectorAll("g.pin[data-operand]").forEach(function (o) {
          var a = o.getAttribute("data-operand");
          if (a && values[a] !== undefined) { showValue(addressText(o), values[a]); }
        });
        // A timer's or counter's current value: its number (`data-counted`), drawn
        // above the box as `g.operand.counted`.
        var counted = b.getAttribute("data-counted");
        var c = b.querySelector("g.operand.counted");
        if (counted && c && values[counted] !== undefined) {
          showValue(addressText(c), values[counted]);
        }
      });
    });
    // Networks shown as STL: each line's RLO and its operands' values.
    (state.stl || []).forEach(function (n) {
      var g = networks[n.block + "/" + n.network];
      if (!g) { return; }
      n.lines.forEach(function (line) {
        var t = g.querySelector(".stl-line[data-index='" + line.index + "']");
        if (!t) { return; }
        if (running && line.rlo !== null && line.rlo !== undefined) {
          t.setAttribute("data-rlo", String(line.rlo));
        } else {
          t.removeAttribute("data-rlo");
        }
        if (line.value) {
          var span = t.querySelector("tspan.value");
          if (!span) {
            span = document.createElementNS(SVG, "tspan");
            span.setAttribute("class", "value");
            t.appendChild(span);
          }
          var rlo = running && line.rlo !== null ? "   RLO " + line.rlo : "";
          span.textContent = "   // " + line.value + rlo;
        }
      });
    });
    document.querySelectorAll(".contact, .coil, .operand").forEach(function (e) {
      e.classList.toggle("forced", forced[e.getAttribute("data-operand")] === true);
    });
  }

  // Stale after STALE_MS without an update: take the power flow away.
  setInterval(function () {
    if (showStatus()) { clearPower(); }
  }, 250);

  var source = new EventSource("/events");
  source.onopen = function () { streamUp = everUp = true; showStatus(); };
  source.onmessage = function (e) {
    streamUp = everUp = true;
    try { apply(JSON.parse(e.data)); } catch (err) { message.textContent = "bad update: " + err; }
  };
  source.onerror = function () {
    // EventSource reconnects by itself; until then the values are stale.
    streamUp = false;
    if (showStatus()) { clearPower(); }
  };
  showStatus();
})();
