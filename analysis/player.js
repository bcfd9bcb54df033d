// The report's 3D player: every engine's cloth over time, side by side (one shared camera) or
// overlaid, coloured by engine, strain or distance to the reference. Reads CLOTHBENCH_PLAYER
// (written by analysis/player.py) and THREE (Debian's libjs-three, inlined before this script).
// State in the URL: #t=1.5&color=distance&layout=grid&engines=a,b. What it shows is written to
// #player-status as JSON (for the tests, which read it with chromium --dump-dom).
(function () {
  "use strict";
  var D = window.CLOTHBENCH_PLAYER;
  var status = { ready: false, errors: [] };
  var statusEl = document.getElementById("player-status");
  function report() { if (statusEl) statusEl.textContent = JSON.stringify(status); }
  window.addEventListener("error", function (e) { status.errors.push(String(e.message)); report(); });

  function decode(b64) {
    var s = atob(b64), n = s.length, bytes = new Uint8Array(n);
    for (var k = 0; k < n; k++) bytes[k] = s.charCodeAt(k);
    return new Float32Array(bytes.buffer);
  }
  function dequantize(d) {  // uint16 steps above lo (see player.py's _quantized)
    var s = atob(d.q), n = s.length / 2, out = new Float32Array(n);
    for (var k = 0; k < n; k++) {
      var a = k % 3;
      out[k] = d.lo[a] + d.step[a] * (s.charCodeAt(2 * k) | (s.charCodeAt(2 * k + 1) << 8));
    }
    return out;
  }
  function lut(stops, v) {  // colour of v in [0, 1] from a list of [r, g, b] stops (0..1)
    v = Math.min(1, Math.max(0, v)) * (stops.length - 1);
    var k = Math.min(stops.length - 2, Math.floor(v)), f = v - k, a = stops[k], b = stops[k + 1];
    return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
  }

  // --- data -----------------------------------------------------------------------------------
  var sets = D.sets.map(function (s) {
    s.collider = decode(s.colliders);
    var nu = s.grid[0], nv = s.grid[1], idx = [];
    for (var j = 0; j + 1 < nv; j++)
      for (var i = 0; i + 1 < nu; i++) {
        var a = j * nu + i, b = a + 1, c = a + nu, d = c + 1;
        idx.push(a, b, d, a, d, c);
      }
    s.index = idx;
    return s;
  });
  var engines = D.engines.map(function (e) {
    e.pos = dequantize(e.data);
    e.set = sets[e.set_index];
    e.n = e.set.grid[0] * e.set.grid[1];
    return e;
  });
  var duration = D.duration;

  // --- state ----------------------------------------------------------------------------------
  var state = { t: 0, color: "engine", layout: "grid", shown: engines.map(function () { return true; }),
                playing: false, speed: 1 };
  function parseHash() {
    var h = (location.hash || "").replace(/^#/, "");
    h.split("&").forEach(function (kv) {
      var p = kv.split("="), key = p[0], v = decodeURIComponent(p[1] || "");
      if (key === "t" && isFinite(parseFloat(v))) state.t = Math.min(duration, Math.max(0, parseFloat(v)));
      if (key === "color" && ["engine", "strain", "distance"].indexOf(v) >= 0) state.color = v;
      if (key === "layout" && ["grid", "overlay"].indexOf(v) >= 0) state.layout = v;
      if (key === "engines" && v) {
        var names = v.split(",");
        state.shown = engines.map(function (e) { return names.indexOf(e.name) >= 0 || names.indexOf(e.label) >= 0; });
      }
    });
  }
  function writeHash() {
    var names = engines.filter(function (e, k) { return state.shown[k]; }).map(function (e) { return e.name; });
    var h = "#t=" + state.t.toFixed(3) + "&color=" + state.color + "&layout=" + state.layout;
    if (names.length !== engines.length) h += "&engines=" + names.join(",");
    if (history.replaceState) history.replaceState(null, "", h);
  }

  // frame of engine e at time t: its last frame once it has none left (blown up)
  function frameOf(e, t) {
    var k = Math.round(t / e.interval);
    return { k: Math.min(k, e.frames - 1), past: k > e.frames - 1 || (e.blowup_t !== null && t >= e.blowup_t) };
  }
  function vertex(e, k, p) { var o = (k * e.n + p) * 3; return [e.pos[o], e.pos[o + 1], e.pos[o + 2]]; }

  function strainOf(e, k) {
    var s = e.set, nu = s.grid[0], nv = s.grid[1], out = new Float32Array(e.n), cnt = new Float32Array(e.n);
    s.springs.forEach(function (o) {
      var di = o[0], dj = o[1], rest = Math.hypot(di * s.spacing[0], dj * s.spacing[1]);
      if (!(rest > 0)) return;
      for (var j = Math.max(0, -dj); j < nv - Math.max(0, dj); j++)
        for (var i = Math.max(0, -di); i < nu - Math.max(0, di); i++) {
          var a = j * nu + i, b = (j + dj) * nu + i + di, x = vertex(e, k, a), y = vertex(e, k, b);
          var v = Math.abs(Math.hypot(y[0] - x[0], y[1] - x[1], y[2] - x[2]) / rest - 1);
          out[a] += v; out[b] += v; cnt[a]++; cnt[b]++;
        }
    });
    for (var p = 0; p < e.n; p++) out[p] = cnt[p] ? out[p] / cnt[p] : 0;
    return out;
  }
  function distanceOf(e, k, t) {  // mm, to the reference at the same time; null without one
    var r = engines[e.ref];
    if (!r || r.n !== e.n) return null;
    var kr = Math.round(t / r.interval);
    if (kr > r.frames - 1) return null;
    var out = new Float32Array(e.n);
    for (var p = 0; p < e.n; p++) {
      var x = vertex(e, k, p), y = vertex(r, kr, p);
      out[p] = 1000 * Math.hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
    }
    return out;
  }

  // --- three.js scene -------------------------------------------------------------------------
  var box = document.getElementById("player-canvas-box");
  var W = Math.max(600, Math.min(box.clientWidth || 1280, 1280)), H = 560;
  var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(W, H);
  renderer.setClearColor(0xffffff, 1);
  box.insertBefore(renderer.domElement, box.firstChild);
  var vc = THREE.VertexColors !== undefined ? THREE.VertexColors : true;

  function sceneWithLights() {
    var sc = new THREE.Scene();
    sc.add(new THREE.AmbientLight(0xffffff, 0.55));
    var l = new THREE.DirectionalLight(0xffffff, 0.55);
    l.position.set(2, 5, 3);
    sc.add(l);
    return sc;
  }
  var colliderMat = new THREE.MeshLambertMaterial({ color: 0xbdbdbd });
  function addColliders(sc, s) {
    var meshes = [];
    s.shapes.forEach(function (sh) {
      var g = null;
      var m = null;
      if (sh.type === "sphere") g = new THREE.SphereGeometry(sh.radius, 40, 24);
      else if (sh.type === "box" && sh.half_extents)
        g = new THREE.BoxGeometry(2 * sh.half_extents[0], 2 * sh.half_extents[1], 2 * sh.half_extents[2]);
      else if (sh.type === "cylinder") g = new THREE.CylinderGeometry(sh.radius, sh.radius, sh.height, 48);
      if (sh.type === "plane" || sh.type === "capsule") {
        // a plane as a 6 m square about its point, a capsule as a cylinder between two caps,
        // each turned from the y axis onto its normal or axis
        var dir = new THREE.Vector3().fromArray(sh.type === "plane" ? sh.normal : sh.axis);
        var len = dir.length();
        m = new THREE.Object3D();
        if (sh.type === "plane") {
          var sq = new THREE.Mesh(new THREE.BoxGeometry(6, 0.002, 6), colliderMat);
          m.add(sq);
        } else {
          m.add(new THREE.Mesh(new THREE.CylinderGeometry(sh.radius, sh.radius, len, 32), colliderMat));
          [-0.5, 0.5].forEach(function (f) {
            var cap = new THREE.Mesh(new THREE.SphereGeometry(sh.radius, 24, 16), colliderMat);
            cap.position.set(0, f * len, 0);
            m.add(cap);
          });
        }
        m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), dir.normalize());
      }
      if (!m) m = g ? new THREE.Mesh(g, colliderMat) : new THREE.Object3D();
      sc.add(m);
      meshes.push(m);
    });
    return meshes;
  }
  function clothGeometry(e) {
    var g = new THREE.BufferGeometry();
    g.setAttribute ? g.setAttribute("position", new THREE.BufferAttribute(new Float32Array(e.n * 3), 3))
                   : g.addAttribute("position", new THREE.BufferAttribute(new Float32Array(e.n * 3), 3));
    var col = new THREE.BufferAttribute(new Float32Array(e.n * 3), 3);
    g.setAttribute ? g.setAttribute("color", col) : g.addAttribute("color", col);
    g.setIndex(e.set.index);
    return g;
  }
  var heldMat = new THREE.PointsMaterial({ color: 0x202020, size: 6, sizeAttenuation: false });
  var clothMat = new THREE.MeshLambertMaterial({ vertexColors: vc, side: THREE.DoubleSide });
  // faint grid lines: a flat cloth reads as a cloth; black at low opacity keeps every colour's hue
  var edgeMat = new THREE.MeshBasicMaterial({ color: 0x000000, wireframe: true, transparent: true, opacity: 0.12 });
  var views = engines.map(function (e) {
    var g = clothGeometry(e);
    var hg = new THREE.BufferGeometry();
    var hp = new THREE.BufferAttribute(new Float32Array(e.set.held.length * 3), 3);
    hg.setAttribute ? hg.setAttribute("position", hp) : hg.addAttribute("position", hp);
    var v = { e: e, geom: g, held: hg, scene: sceneWithLights() };
    v.scene.add(new THREE.Mesh(g, clothMat));
    v.scene.add(new THREE.Mesh(g, edgeMat));
    v.scene.add(new THREE.Points(hg, heldMat));
    v.colliders = addColliders(v.scene, e.set);
    return v;
  });
  var overlay = { scene: sceneWithLights(), meshes: [], colliders: [] };
  views.forEach(function (v) {
    var m = new THREE.Mesh(v.geom, clothMat);
    overlay.scene.add(m);
    m.add(new THREE.Mesh(v.geom, edgeMat));
    var h = new THREE.Points(v.held, heldMat);
    overlay.scene.add(h);
    overlay.meshes.push([m, h]);
  });
  overlay.colliders = addColliders(overlay.scene, sets[0]);

  // one camera for every view: orbit around the reference's start
  var camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
  var orbit = { target: new THREE.Vector3(), r: 5, theta: 0.7, phi: 1.0 };
  (function fit() {
    var e = engines[0], lo = [1e30, 1e30, 1e30], hi = [-1e30, -1e30, -1e30];
    for (var p = 0; p < e.n; p++) {
      var x = vertex(e, 0, p);
      for (var a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], x[a]); hi[a] = Math.max(hi[a], x[a]); }
    }
    e.set.shapes.forEach(function (sh, k) {
      if (sh.type !== "sphere") return;
      for (var a = 0; a < 3; a++) {
        lo[a] = Math.min(lo[a], e.set.collider[k * 3 + a] - sh.radius);
        hi[a] = Math.max(hi[a], e.set.collider[k * 3 + a] + sh.radius);
      }
    });
    orbit.target.set((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
    // far enough that the bounding sphere fits the view's height (35 degrees)
    orbit.r = 1.1 * 0.5 * Math.max(1e-3, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])) / Math.tan(17.5 * Math.PI / 180);
  })();
  function placeCamera() {
    var o = orbit;
    camera.position.set(o.target.x + o.r * Math.sin(o.phi) * Math.sin(o.theta),
                        o.target.y + o.r * Math.cos(o.phi),
                        o.target.z + o.r * Math.sin(o.phi) * Math.cos(o.theta));
    camera.lookAt(o.target);
  }

  // --- colours --------------------------------------------------------------------------------
  var GREY = [0.62, 0.62, 0.62];
  function paint(v, t) {
    var e = v.e, f = frameOf(e, t), pos = v.geom.attributes.position.array, col = v.geom.attributes.color.array;
    pos.set(e.pos.subarray(f.k * e.n * 3, (f.k + 1) * e.n * 3));
    var values = null, scale = 1, stops = D.colormap;
    if (state.color === "strain") { values = strainOf(e, f.k); scale = D.strain_scale; }
    if (state.color === "distance") { values = distanceOf(e, f.k, t); scale = D.distance_scale_mm; }
    for (var p = 0; p < e.n; p++) {
      var c = f.past ? GREY : values ? lut(stops, values[p] / scale) : state.color === "distance" ? GREY : e.rgb;
      col[3 * p] = c[0]; col[3 * p + 1] = c[1]; col[3 * p + 2] = c[2];
    }
    v.geom.attributes.position.needsUpdate = true;
    v.geom.attributes.color.needsUpdate = true;
    v.geom.computeVertexNormals();
    var hp = v.held.attributes.position.array;
    e.set.held.forEach(function (p, k) { var x = vertex(e, f.k, p); hp[3 * k] = x[0]; hp[3 * k + 1] = x[1]; hp[3 * k + 2] = x[2]; });
    v.held.attributes.position.needsUpdate = true;
    var kc = Math.min(Math.round(t / e.set.interval), e.set.frames - 1), S = e.set.shapes.length;
    v.colliders.forEach(function (m, s) {
      var o = (kc * S + s) * 3;
      m.position.set(e.set.collider[o], e.set.collider[o + 1], e.set.collider[o + 2]);
    });
    return f;
  }

  // --- layout and drawing ---------------------------------------------------------------------
  var labelBox = document.getElementById("player-labels");
  function cells(n) {
    var cols = Math.max(1, Math.ceil(Math.sqrt(n * 1.6))), rows = Math.max(1, Math.ceil(n / cols));
    while (cols > 1 && (cols - 1) * rows >= n) cols--;
    return { cols: cols, rows: rows };
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
    if (state.layout === "grid") {
      var c = cells(shown.length), w = Math.floor(W / c.cols), h = Math.floor(H / c.rows);
      shown.forEach(function (v, n) {
        var x = (n % c.cols) * w, yTop = Math.floor(n / c.cols) * h;
        renderer.setScissor(x, H - yTop - h, w, h);
        renderer.setViewport(x, H - yTop - h, w, h);
        camera.aspect = w / h;
        camera.updateProjectionMatrix();
        renderer.render(v.scene, camera);
        var f = frames[views.indexOf(v)];
        addLabel(v.e, f, x, yTop, w);
        status.views.push({ engine: v.e.name, x: x, y: yTop, w: w, h: h, greyed: f.past });
      });
    } else {
      views.forEach(function (v, k) { overlay.meshes[k][0].visible = overlay.meshes[k][1].visible = state.shown[k]; });
      var e0 = shown.length ? shown[0].e : engines[0], kc = Math.min(Math.round(t / e0.set.interval), e0.set.frames - 1);
      overlay.colliders.forEach(function (m, s) {
        var o = (kc * e0.set.shapes.length + s) * 3;
        m.position.set(e0.set.collider[o], e0.set.collider[o + 1], e0.set.collider[o + 2]);
      });
      camera.aspect = W / H;
      camera.updateProjectionMatrix();
      renderer.render(overlay.scene, camera);
      shown.forEach(function (v, n) {
        var f = frames[views.indexOf(v)];
        addLabel(v.e, f, 0, n * 20, W);
        status.views.push({ engine: v.e.name, x: 0, y: 0, w: W, h: H, greyed: f.past });
      });
    }
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

  // --- controls -------------------------------------------------------------------------------
  var slider = document.getElementById("player-slider");
  slider.max = String(duration);
  slider.step = String(D.step);
  slider.addEventListener("input", function () { state.t = parseFloat(slider.value); draw(); });
  var playBtn = document.getElementById("player-play");
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
  var colorSel = document.getElementById("player-color"), layoutSel = document.getElementById("player-layout");
  colorSel.addEventListener("change", function () { state.color = colorSel.value; draw(); });
  layoutSel.addEventListener("change", function () { state.layout = layoutSel.value; draw(); });
  var toggles = document.getElementById("player-engines");
  engines.forEach(function (e, k) {
    var l = document.createElement("label"), c = document.createElement("input");
    c.type = "checkbox"; c.checked = true; c.dataset.engine = e.name;
    c.addEventListener("change", function () { state.shown[k] = c.checked; draw(); });
    l.appendChild(c); l.appendChild(document.createTextNode(" " + e.label));
    toggles.appendChild(l);
  });
  // blow-ups on the timeline
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
  var last = null;
  function tick(now) {
    if (!state.playing) return;
    if (last !== null) state.t = Math.min(duration, state.t + state.speed * (now - last) / 1000);
    last = now;
    draw();
    if (state.t >= duration) { state.playing = false; playBtn.textContent = "▶ play"; return; }
    requestAnimationFrame(tick);
  }
  // orbit (drag), pan (shift-drag or right drag), zoom (wheel): the camera every view shares
  var drag = null, cv = renderer.domElement;
  cv.addEventListener("contextmenu", function (ev) { ev.preventDefault(); });
  cv.addEventListener("mousedown", function (ev) { drag = { x: ev.clientX, y: ev.clientY, pan: ev.shiftKey || ev.button === 2 }; });
  window.addEventListener("mouseup", function () { drag = null; });
  window.addEventListener("mousemove", function (ev) {
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
  });
  cv.addEventListener("wheel", function (ev) { ev.preventDefault(); orbit.r *= Math.exp(0.001 * ev.deltaY); draw(); }, { passive: false });

  parseHash();
  colorSel.value = state.color;
  layoutSel.value = state.layout;
  Array.prototype.forEach.call(toggles.querySelectorAll("input"), function (c, k) { c.checked = state.shown[k]; });
  window.addEventListener("hashchange", function () { parseHash(); draw(); });
  draw();
  status.ready = true;
  report();
})();
