// One camera for every view, orbiting around the reference's start.
var camera, orbit;

function createCamera() {
  camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
  orbit = { target: new THREE.Vector3(), r: 5, theta: 0.7, phi: 1.0 };
}
// aim at the middle of the first engine's start and its spheres
function fit() {
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
}
function placeCamera() {
  var o = orbit;
  camera.position.set(o.target.x + o.r * Math.sin(o.phi) * Math.sin(o.theta),
                      o.target.y + o.r * Math.cos(o.phi),
                      o.target.z + o.r * Math.sin(o.phi) * Math.cos(o.theta));
  camera.lookAt(o.target);
}
