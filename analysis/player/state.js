// What the reader chose (time, colour, layout, engines shown, playing), kept in the URL:
// #t=1.5&color=distance&layout=grid&engines=a,b
var state;

function initialState() {
  // it opens where the engines differ most (t = 0 shows every cloth alike); #t= overrides
  return { t: D.start_t || 0, color: "engine", layout: "grid", shown: engines.map(function () { return true; }),
           playing: false, speed: 1 };
}
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
