// Per-frame quantities of one engine: which frame to show, a vertex, strain and distance.

// frame of engine e at time t: its last frame once it has none left (blown up)
function frameOf(e, t) {
  var k = Math.round(t / e.interval);
  return { k: Math.min(k, e.frames - 1), past: k > e.frames - 1 || (e.blowup_t !== null && t >= e.blowup_t) };
}
function vertex(e, k, p) { var o = (k * e.n + p) * 3; return [e.pos[o], e.pos[o + 1], e.pos[o + 2]]; }

// a mesh's strain over its edges [a, b, rest]
function edgeStrainOf(e, k) {
  var out = new Float32Array(e.n), cnt = new Float32Array(e.n);
  e.set.edges.forEach(function (g) {
    var x = vertex(e, k, g[0]), y = vertex(e, k, g[1]);
    var v = Math.abs(Math.hypot(y[0] - x[0], y[1] - x[1], y[2] - x[2]) / g[2] - 1);
    out[g[0]] += v; out[g[1]] += v; cnt[g[0]]++; cnt[g[1]]++;
  });
  for (var p = 0; p < e.n; p++) out[p] = cnt[p] ? out[p] / cnt[p] : 0;
  return out;
}
function strainOf(e, k) {
  if (e.set.edges) return edgeStrainOf(e, k);
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
