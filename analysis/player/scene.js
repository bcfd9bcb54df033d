// The three.js renderer and scenes: one scene per engine (the grid layout) and one holding
// every engine (the overlay), each with the cloth, its grid lines, the held particles and
// the colliders.
var box, W, H, renderer, vc;
var colliderMat, heldMat, clothMat, edgeMat, crossMat;
var views, overlay;

function createRenderer() {
  box = document.getElementById("player-canvas-box");
  W = Math.max(600, Math.min(box.clientWidth || 1280, 1280));
  H = 560;
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(W, H);
  renderer.setClearColor(0xffffff, 1);
  box.insertBefore(renderer.domElement, box.firstChild);
  vc = THREE.VertexColors !== undefined ? THREE.VertexColors : true;
}
function createMaterials() {
  colliderMat = new THREE.MeshLambertMaterial({ color: 0xbdbdbd });
  heldMat = new THREE.PointsMaterial({ color: 0x202020, size: 6, sizeAttenuation: false });
  clothMat = new THREE.MeshLambertMaterial({ vertexColors: vc, side: THREE.DoubleSide });
  // faint grid lines: a flat cloth reads as a cloth; black at low opacity keeps every colour's hue
  edgeMat = new THREE.MeshBasicMaterial({ color: 0x000000, wireframe: true, transparent: true, opacity: 0.12 });
  // triangles where the cloth crosses itself, drawn over the cloth in red
  crossMat = new THREE.MeshBasicMaterial({ color: 0xd62728, side: THREE.DoubleSide, polygonOffset: true,
                                           polygonOffsetFactor: -2, polygonOffsetUnits: -2 });
}
// a geometry over the cloth's own positions whose index paint() sets to the crossing triangles
function crossingGeometry(g) {
  var c = new THREE.BufferGeometry();
  c.setAttribute ? c.setAttribute("position", g.attributes.position) : c.addAttribute("position", g.attributes.position);
  c.setIndex([]);
  return c;
}

function sceneWithLights() {
  var sc = new THREE.Scene();
  sc.add(new THREE.AmbientLight(0xffffff, 0.55));
  var l = new THREE.DirectionalLight(0xffffff, 0.55);
  l.position.set(2, 5, 3);
  sc.add(l);
  return sc;
}
// a plane as a 6 m square about its point, a capsule as a cylinder between two caps, each
// turned from the y axis onto its normal or axis
function turnedCollider(sh) {
  var dir = new THREE.Vector3().fromArray(sh.type === "plane" ? sh.normal : sh.axis);
  var len = dir.length();
  var m = new THREE.Object3D();
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
  return m;
}
function colliderMesh(sh) {
  var g = null;
  var m = null;
  if (sh.type === "sphere") g = new THREE.SphereGeometry(sh.radius, 40, 24);
  else if (sh.type === "box" && sh.half_extents)
    g = new THREE.BoxGeometry(2 * sh.half_extents[0], 2 * sh.half_extents[1], 2 * sh.half_extents[2]);
  else if (sh.type === "cylinder") g = new THREE.CylinderGeometry(sh.radius, sh.radius, sh.height, 48);
  if (sh.type === "plane" || sh.type === "capsule") m = turnedCollider(sh);
  if (!m) m = g ? new THREE.Mesh(g, colliderMat) : new THREE.Object3D();
  return m;
}
function addColliders(sc, s) {
  var meshes = [];
  s.shapes.forEach(function (sh) {
    var m = colliderMesh(sh);
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
function createViews() {
  views = engines.map(function (e) {
    var g = clothGeometry(e);
    var hg = new THREE.BufferGeometry();
    var hp = new THREE.BufferAttribute(new Float32Array(e.set.held.length * 3), 3);
    hg.setAttribute ? hg.setAttribute("position", hp) : hg.addAttribute("position", hp);
    var v = { e: e, geom: g, held: hg, cross: crossingGeometry(g), scene: sceneWithLights() };
    v.scene.add(new THREE.Mesh(g, clothMat));
    v.scene.add(new THREE.Mesh(g, edgeMat));
    v.scene.add(new THREE.Mesh(v.cross, crossMat));
    v.scene.add(new THREE.Points(hg, heldMat));
    v.colliders = addColliders(v.scene, e.set);
    return v;
  });
}
function createOverlay() {
  overlay = { scene: sceneWithLights(), meshes: [], colliders: [] };
  views.forEach(function (v) {
    var m = new THREE.Mesh(v.geom, clothMat);
    overlay.scene.add(m);
    m.add(new THREE.Mesh(v.geom, edgeMat));
    m.add(new THREE.Mesh(v.cross, crossMat));
    var h = new THREE.Points(v.held, heldMat);
    overlay.scene.add(h);
    overlay.meshes.push([m, h]);
  });
  overlay.colliders = addColliders(overlay.scene, sets[0]);
}
