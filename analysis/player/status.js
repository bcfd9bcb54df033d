// What the player shows, written to #player-status as JSON (for the tests, which read it with
// chromium --dump-dom): ready, errors, the views drawn, the time, colour, layout, engines
// shown, the canvas's place on the page and the blow-ups marked on the timeline.
var status = { ready: false, errors: [] };
var statusEl = document.getElementById("player-status");

function report() { if (statusEl) statusEl.textContent = JSON.stringify(status); }

function watchErrors() {
  window.addEventListener("error", function (e) { status.errors.push(String(e.message)); report(); });
}
