// The payload's encodings (see player.py) and the colour map lookup.

function decode(b64) {  // base64 of little-endian float32
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
