#!/usr/bin/env python3
"""A mass-spring cloth for clothbench's external-engine protocol, version 1
(docs/external-engines.md): symplectic Euler, springs with dampers, gravity, air drag, held
axes and handles; colliders are ignored (no contact). clothbench runs it: requests on stdin."""
import struct
import sys

import numpy as np

MAGIC = b"CLBX"
HELLO, MODEL, STEP, GET_STATE, SET_STATE, STATE, ERROR = 1, 2, 3, 4, 5, 6, 7
VERSION = 1


def read_exact(stream, n):
    data = stream.read(n)
    if data is None or len(data) != n:
        sys.exit(0)  # the harness closed our input: we are done
    return data


def receive(stream):
    head = read_exact(stream, 16)
    if head[:4] != MAGIC:
        raise ValueError("not a protocol frame")
    kind, size = struct.unpack("<IQ", head[4:])
    return kind, read_exact(stream, size)


def send(stream, kind, payload=b""):
    stream.write(MAGIC + struct.pack("<IQ", kind, len(payload)) + payload)
    stream.flush()


class Fields:
    """Reads 8-byte little-endian fields of a payload in order."""

    def __init__(self, data):
        self.data, self.at = data, 0

    def take(self, dtype, n):
        out = np.frombuffer(self.data, dtype, n, self.at).copy()
        self.at += 8 * n
        return out

    def f64(self, n=1):
        return self.take("<f8", n)

    def i64(self, n=1):
        return self.take("<i8", n)


def motion(velocity, path, t):
    """Displacement of a motion at time t: a path's piecewise-linear one, else velocity t."""
    if len(path) == 0:
        return velocity * t
    times = path[:, 0]
    return np.array([np.interp(t, times, path[:, 1 + r]) for r in range(3)])


class Cloth:
    def __init__(self, payload):
        r = Fields(payload)
        P, S, C, H = (int(n) for n in r.i64(4))
        self.P, self.dt = P, r.f64()[0]
        self.gravity = r.f64(3).reshape(3, 1)
        self.drag = r.f64()[0]
        self.wind = r.f64(3).reshape(3, 1)
        # 3 by P arrays are sent row by row: all x, all y, all z
        self.x0 = r.f64(3 * P).reshape(3, P)
        self.v = r.f64(3 * P).reshape(3, P)
        self.mass = r.f64(P)
        self.free = r.f64(3 * P).reshape(3, P)
        ends = r.i64(2 * S).reshape(S, 2)
        self.a, self.b = ends[:, 0], ends[:, 1]
        self.rest, self.k, self.c = r.f64(S), r.f64(S), r.f64(S)
        for _ in range(C):  # type, path length, 8 geometry, 3 response, velocity, path
            n_path = int(r.i64(2)[1])
            r.f64(8 + 3 + 3 + 4 * n_path)
        self.handles = []
        for _ in range(H):
            n, n_path = (int(q) for q in r.i64(2))
            velocity = r.f64(3)
            particles = r.i64(n)
            self.handles.append((particles, velocity, r.f64(4 * n_path).reshape(n_path, 4)))
        self.x, self.t, self.dissipated, self.evals = self.x0.copy(), 0.0, 0.0, 0

    def accelerations(self):
        """Accelerations at the current state and the power the dampers and drag take (W)."""
        x, v = self.x, self.v
        d = x[:, self.b] - x[:, self.a]
        length = np.sqrt((d * d).sum(axis=0))
        vr = ((v[:, self.b] - v[:, self.a]) * d).sum(axis=0) / length
        s = (self.k * (length - self.rest) + self.c * vr) / length
        f = np.empty_like(x)
        for row in range(3):
            w = s * d[row]
            f[row] = np.bincount(self.a, w, self.P) - np.bincount(self.b, w, self.P)
        power = (self.c * vr * vr).sum()
        if self.drag != 0.0:
            f -= self.drag * (v - self.wind)
            power += self.drag * ((v * v).sum() - (self.wind[:, 0] @ v.sum(axis=1)))
        self.evals += 1
        return np.where(self.free > 0.0, f / self.mass + self.gravity, 0.0), power

    def step(self, h):
        for particles, velocity, path in self.handles:
            start = motion(velocity, path, self.t)
            end = motion(velocity, path, self.t + h)
            self.v[:, particles] = ((end - start) / h)[:, None]
        a, power = self.accelerations()
        self.dissipated += h * power
        self.v += h * a
        self.x += h * self.v
        self.t += h
        for particles, velocity, path in self.handles:
            self.x[:, particles] = self.x0[:, particles] + motion(velocity, path, self.t)[:, None]

    def state(self):
        head = struct.pack("<ddqq", self.t, self.dissipated, self.evals, self.P)
        return head + self.x.astype("<f8").tobytes() + self.v.astype("<f8").tobytes()


def main():
    inp, out = sys.stdin.buffer, sys.stdout.buffer
    cloth = None
    while True:
        kind, payload = receive(inp)
        if kind == HELLO:
            send(out, HELLO, struct.pack("<II", VERSION, 0))
        elif kind == MODEL:
            cloth = Cloth(payload)
            send(out, MODEL)
        elif kind == STEP:
            steps, h = struct.unpack("<qd", payload)
            for _ in range(steps):
                cloth.step(h)
            send(out, STATE, cloth.state())
        elif kind in (SET_STATE, GET_STATE):
            if kind == SET_STATE:
                r, P = Fields(payload), cloth.P
                cloth.t, cloth.x, cloth.v = r.f64()[0], r.f64(3 * P).reshape(3, P), r.f64(3 * P).reshape(3, P)
            send(out, STATE, cloth.state())
        else:
            send(out, ERROR, b"unknown request type %d" % kind)


if __name__ == "__main__":
    main()
