// The start, in the order the page needs it: errors are caught first; the data, the scenes
// and the controls come next; the URL's choices last, then the first drawing.
function start() {
  watchErrors();
  loadData();
  state = initialState();
  createRenderer();
  createMaterials();
  createViews();
  createOverlay();
  createCamera();
  fit();
  labelBox = document.getElementById("player-labels");
  wireTimeControls();
  wireViewControls();
  markBlowups();
  wireMouse();
  parseHash();
  colorSel.value = state.color;
  layoutSel.value = state.layout;
  Array.prototype.forEach.call(toggles.querySelectorAll("input"), function (c, k) { c.checked = state.shown[k]; });
  window.addEventListener("hashchange", function () { parseHash(); draw(); });
  draw();
  status.ready = true;
  report();
}

start();
