// The controls: time slider, play and step buttons, speed, colour and layout menus, a check
// box per engine, the blow-ups on the timeline, and the mouse on the canvas.
var slider, playBtn, colorSel, layoutSel, toggles;
var last = null;  // the time of the last animation frame while playing (ms), or null
var drag = null;

function tick(now) {
  if (!state.playing) return;
  if (last !== null) state.t = Math.min(duration, state.t + state.speed * (now - last) / 1000);
  last = now;
  draw();
  if (state.t >= duration) { state.playing = false; playBtn.textContent = "▶ play"; return; }
  requestAnimationFrame(tick);
}
function wireTimeControls() {
  slider = document.getElementById("player-slider");
  slider.max = String(duration);
  slider.step = String(D.step);
  slider.addEventListener("input", function () { state.t = parseFloat(slider.value); draw(); });
  playBtn = document.getElementById("player-play");
  playBtn.addEventListener("click", function () {
    state.playing = !state.playing;
    if (state.playing && state.t >= duration) state.t = 0;
    playBtn.textContent = state.playing ? "❚❚ pause" : "▶ play";
    last = null;
    if (state.playing) requestAnimationFrame(tick);
  });
  document.getElementById("player-back").addEventListener("click", function () { state.t = Math.max(0, Math.round(state.t / D.step - 1) * D.step); draw(); });
  document.getElementById("player-fwd").addEventListener("click", function () { state.t = Math.min(duration, Math.round(state.t / D.step + 1) * D.step); draw(); });
  document.getElementById("player-speed").addEventListener("change", function (ev) { state.speed = parseFloat(ev.target.value); });
}
function wireViewControls() {
  colorSel = document.getElementById("player-color");
  layoutSel = document.getElementById("player-layout");
  colorSel.addEventListener("change", function () { state.color = colorSel.value; draw(); });
  layoutSel.addEventListener("change", function () { state.layout = layoutSel.value; draw(); });
  toggles = document.getElementById("player-engines");
  engines.forEach(function (e, k) {
    var l = document.createElement("label"), c = document.createElement("input");
    c.type = "checkbox"; c.checked = true; c.dataset.engine = e.name;
    c.addEventListener("change", function () { state.shown[k] = c.checked; draw(); });
    l.appendChild(c); l.appendChild(document.createTextNode(" " + e.label));
    toggles.appendChild(l);
  });
}
// blow-ups on the timeline
function markBlowups() {
  var marks = document.getElementById("player-marks");
  status.marked = [];
  engines.forEach(function (e) {
    if (e.stable) return;
    var t = e.blowup_t !== null ? e.blowup_t : (e.frames - 1) * e.interval;
    var m = document.createElement("div");
    m.className = "player-mark";
    m.dataset.engine = e.name;
    m.style.left = (100 * Math.min(1, t / duration)) + "%";
    m.style.top = 14 * status.marked.length + "px";  // stacked: blow-ups can share a time
    document.getElementById("player-track").style.paddingBottom = 16 + 14 * status.marked.length + "px";
    m.title = e.label + (e.cause === "timeout" ? " stopped (timeout)" : " blew up (" + e.cause + ")") + " at " + t.toFixed(3) + " s";
    m.textContent = "✕ " + e.label;
    marks.appendChild(m);
    status.marked.push({ engine: e.name, t: t });
  });
}
function dragTo(ev) {
  if (!drag) return;
  var dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
  drag.x = ev.clientX; drag.y = ev.clientY;
  if (drag.pan) {
    var right = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 0), up = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 1);
    var s = orbit.r * 0.0015;
    orbit.target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
  } else {
    orbit.theta -= dx * 0.008;
    orbit.phi = Math.min(3.1, Math.max(0.05, orbit.phi - dy * 0.008));
  }
  draw();
}
// orbit (drag), pan (shift-drag or right drag), zoom (wheel): the camera every view shares
function wireMouse() {
  var cv = renderer.domElement;
  cv.addEventListener("contextmenu", function (ev) { ev.preventDefault(); });
  cv.addEventListener("mousedown", function (ev) { drag = { x: ev.clientX, y: ev.clientY, pan: ev.shiftKey || ev.button === 2 }; });
  window.addEventListener("mouseup", function () { drag = null; });
  window.addEventListener("mousemove", dragTo);
  cv.addEventListener("wheel", function (ev) { ev.preventDefault(); orbit.r *= Math.exp(0.001 * ev.deltaY); draw(); }, { passive: false });
}
