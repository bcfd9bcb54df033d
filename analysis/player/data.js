// The payload (window.CLOTHBENCH_PLAYER, written by player.py) decoded: one set per folder
// (its grid, triangles and colliders), one entry per engine (its positions over time).
var D = window.CLOTHBENCH_PLAYER;
var sets, engines, duration;

function loadSets() {
  return D.sets.map(function (s) {
    s.collider = decode(s.colliders);
    var nu = s.grid[0], nv = s.grid[1], idx = [];
    if (s.triangles) {
      s.index = s.triangles;
      return s;
    }
    for (var j = 0; j + 1 < nv; j++)
      for (var i = 0; i + 1 < nu; i++) {
        var a = j * nu + i, b = a + 1, c = a + nu, d = c + 1;
        idx.push(a, b, d, a, d, c);
      }
    s.index = idx;
    return s;
  });
}
function loadEngines() {
  return D.engines.map(function (e) {
    e.pos = dequantize(e.data);
    e.set = sets[e.set_index];
    e.n = e.set.particles || e.set.grid[0] * e.set.grid[1];
    return e;
  });
}
function loadData() {
  sets = loadSets();
  engines = loadEngines();
  duration = D.duration;
}
