// One view at time t: the cloth's positions and colours, the held particles, the colliders.
var GREY = [0.62, 0.62, 0.62];

function paintCloth(v, e, f, t) {
  var pos = v.geom.attributes.position.array, col = v.geom.attributes.color.array;
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
}
// the triangles of frame f where engine e's cloth crosses itself, red over the cloth
function paintCrossings(v, e, f) {
  var tris = f.past || !e.crossings ? null : e.crossings[f.k], idx = [], I = e.set.index;
  if (tris) tris.forEach(function (t) { idx.push(I[3 * t], I[3 * t + 1], I[3 * t + 2]); });
  v.cross.setIndex(idx);
}
// the colliders' meshes where set s has them at time t
function placeColliders(meshes, s, t) {
  var kc = Math.min(Math.round(t / s.interval), s.frames - 1), S = s.shapes.length;
  meshes.forEach(function (m, c) {
    var o = (kc * S + c) * 3;
    m.position.set(s.collider[o], s.collider[o + 1], s.collider[o + 2]);
  });
}
function paint(v, t) {
  var e = v.e, f = frameOf(e, t);
  paintCloth(v, e, f, t);
  paintCrossings(v, e, f);
  var hp = v.held.attributes.position.array;
  e.set.held.forEach(function (p, k) { var x = vertex(e, f.k, p); hp[3 * k] = x[0]; hp[3 * k + 1] = x[1]; hp[3 * k + 2] = x[2]; });
  v.held.attributes.position.needsUpdate = true;
  placeColliders(v.colliders, e.set, t);
  return f;
}
