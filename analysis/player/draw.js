// Drawing: every shown engine in its own cell of a grid (one camera) or all in one overlay,
// with a label each, the colour bar, the time, and the status.
var labelBox;

function cells(n) {
  var cols = Math.max(1, Math.ceil(Math.sqrt(n * 1.6))), rows = Math.max(1, Math.ceil(n / cols));
  while (cols > 1 && (cols - 1) * rows >= n) cols--;
  return { cols: cols, rows: rows };
}
function drawGrid(shown, frames) {
  var c = cells(shown.length), w = Math.floor(W / c.cols), h = Math.floor(H / c.rows);
  shown.forEach(function (v, n) {
    var x = (n % c.cols) * w, yTop = Math.floor(n / c.cols) * h;
    renderer.setScissor(x, H - yTop - h, w, h);
    renderer.setViewport(x, H - yTop - h, w, h);
    setAspect(w / h);
    renderer.render(v.scene, camera);
    var f = frames[views.indexOf(v)];
    addLabel(v.e, f, x, yTop, w);
    status.views.push({ engine: v.e.name, x: x, y: yTop, w: w, h: h, greyed: f.past });
  });
}
function drawOverlay(shown, frames, t) {
  views.forEach(function (v, k) { overlay.meshes[k][0].visible = overlay.meshes[k][1].visible = state.shown[k]; });
  // the colliders where the first shown engine's set has them
  var e0 = shown.length ? shown[0].e : engines[0];
  placeColliders(overlay.colliders, e0.set, t);
  setAspect(W / H);
  renderer.render(overlay.scene, camera);
  shown.forEach(function (v, n) {
    var f = frames[views.indexOf(v)];
    addLabel(v.e, f, 0, n * 20, W);
    status.views.push({ engine: v.e.name, x: 0, y: 0, w: W, h: H, greyed: f.past });
  });
}
function draw() {
  var t = state.t, shown = [];
  views.forEach(function (v, k) { if (state.shown[k]) shown.push(v); });
  status.views = [];
  labelBox.innerHTML = "";
  renderer.setScissorTest(true);
  renderer.setScissor(0, 0, W, H);
  renderer.setViewport(0, 0, W, H);
  renderer.clear();
  placeCamera();
  var frames = views.map(function (v) { return paint(v, t); });
  if (state.layout === "grid") drawGrid(shown, frames);
  else drawOverlay(shown, frames, t);
  renderer.setScissorTest(false);
  document.getElementById("player-time").textContent = "t = " + t.toFixed(3) + " s";
  document.getElementById("player-slider").value = String(t);
  status.t = t; status.color = state.color; status.layout = state.layout;
  status.shown = shown.map(function (v) { return v.e.name; });
  var rect = renderer.domElement.getBoundingClientRect();
  status.canvas = { x: rect.left + window.scrollX, y: rect.top + window.scrollY, w: W, h: H };
  drawColorbar();
  writeHash();
  report();
}
function addLabel(e, f, x, y, w) {
  var d = document.createElement("div");
  d.className = "player-label" + (f.past ? " gone" : "");
  d.style.left = x + 4 + "px"; d.style.top = y + 2 + "px"; d.style.maxWidth = w - 8 + "px";
  var sw = "rgb(" + e.rgb.map(function (c) { return Math.round(255 * c); }).join(",") + ")";
  d.innerHTML = '<span class="sw" style="background:' + sw + '"></span>';
  d.appendChild(document.createTextNode(e.label + (e.name === engines[e.ref].name && state.color === "distance" ? " (reference)" : "") +
    (f.past ? " · " + (e.cause === "timeout" ? "stopped (timeout)" : "blew up") + " at " +
     (e.blowup_t !== null ? e.blowup_t.toFixed(3) : ((e.frames - 1) * e.interval).toFixed(3)) + " s" +
     (e.cause && e.cause !== "timeout" ? " (" + e.cause + ")" : "") + ", greyed" : "")));
  labelBox.appendChild(d);
}
function drawColorbar() {
  var bar = document.getElementById("player-colorbar"), cv = bar.querySelector("canvas"), ctx = cv.getContext("2d");
  var text = bar.querySelector(".cb-text");
  if (state.color === "engine") { bar.style.visibility = "hidden"; return; }
  bar.style.visibility = "visible";
  for (var x = 0; x < cv.width; x++) {
    var c = lut(D.colormap, x / (cv.width - 1));
    ctx.fillStyle = "rgb(" + c.map(function (v) { return Math.round(255 * v); }).join(",") + ")";
    ctx.fillRect(x, 0, 1, cv.height);
  }
  var s = state.color === "strain" ? D.strain_scale : D.distance_scale_mm;
  var unit = state.color === "strain" ? "strain |l/l0 − 1| per vertex, mean over its springs (dimensionless)"
                                      : "distance to the reference engine at the same time (mm)";
  bar.querySelector(".cb-lo").textContent = "0";
  bar.querySelector(".cb-hi").textContent = "≥ " + (state.color === "strain" ? s.toPrecision(2) : s.toPrecision(3));
  text.textContent = unit;
}
