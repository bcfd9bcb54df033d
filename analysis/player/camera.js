// One camera for every view, orbiting around the middle of the whole run.
var camera, orbit;

function createCamera() {
  camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
  orbit = { target: new THREE.Vector3(), r: 5, theta: 0.7, phi: 1.0 };
}
// grow the box [lo, hi] by point x
function grow(lo, hi, x) {
  for (var a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], x[a]); hi[a] = Math.max(hi[a], x[a]); }
}
// the box of every engine's cloth over every frame it has (a blown-up engine's finite frames)
function clothBox(lo, hi) {
  engines.forEach(function (e) {
    for (var k = 0; k < e.frames; k++)
      for (var p = 0; p < e.n; p++) {
        var x = vertex(e, k, p);
        if (isFinite(x[0]) && isFinite(x[1]) && isFinite(x[2])) grow(lo, hi, x);
      }
  });
}
// ... and of the spheres, wherever they move
function sphereBox(lo, hi) {
  sets.forEach(function (s) {
    var S = s.shapes.length;
    s.shapes.forEach(function (sh, k) {
      if (sh.type !== "sphere") return;
      for (var f = 0; f < s.frames; f++) {
        var o = (f * S + k) * 3, c = [s.collider[o], s.collider[o + 1], s.collider[o + 2]];
        grow(lo, hi, [c[0] - sh.radius, c[1] - sh.radius, c[2] - sh.radius]);
        grow(lo, hi, [c[0] + sh.radius, c[1] + sh.radius, c[2] + sh.radius]);
      }
    });
  });
}
// aim at the middle of everything the run shows, far enough that it stays in view throughout
function fit() {
  var lo = [1e30, 1e30, 1e30], hi = [-1e30, -1e30, -1e30];
  clothBox(lo, hi);
  sphereBox(lo, hi);
  orbit.target.set((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  // far enough that the bounding sphere fits the view's height (35 degrees)
  orbit.r = 1.1 * 0.5 * Math.max(1e-3, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])) / Math.tan(17.5 * Math.PI / 180);
}
// the view's shape: 35 degrees across its shorter side, so that a tall narrow view (three
// engines side by side) shows the width that a wide one shows the height of
function setAspect(aspect) {
  camera.aspect = aspect;
  camera.fov = aspect >= 1 ? 35 : 2 * Math.atan(Math.tan(17.5 * Math.PI / 180) / aspect) * 180 / Math.PI;
  camera.updateProjectionMatrix();
}
function placeCamera() {
  var o = orbit;
  camera.position.set(o.target.x + o.r * Math.sin(o.phi) * Math.sin(o.theta),
                      o.target.y + o.r * Math.cos(o.phi),
                      o.target.z + o.r * Math.sin(o.phi) * Math.cos(o.theta));
  camera.lookAt(o.target);
}
