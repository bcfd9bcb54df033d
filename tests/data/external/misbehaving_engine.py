#!/usr/bin/env python3
"""An external engine that breaks the protocol in the way its argument names, at the first
step request (tests/reference/test_external_engine.cpp). Before that it answers the handshake
and the model as a good engine does; "good" answers every step with the cloth at rest,
counting step requests as force evaluations.

Modes: good, crash, hang, garbage, wrong-count, nan, early-exit, error, bad-version, noisy."""
import os
import struct
import sys
import time

MAGIC = b"CLBX"
mode = sys.argv[1]
inp, out = sys.stdin.buffer, sys.stdout.buffer


def receive():
    head = inp.read(16)
    if len(head) < 16:
        sys.exit(0)
    kind, size = struct.unpack("<IQ", head[4:])
    return kind, inp.read(size)


def send(kind, payload=b""):
    out.write(MAGIC + struct.pack("<IQ", kind, len(payload)) + payload)
    out.flush()


def state(t, x, count, nan=False):
    """A state at rest; its force-evaluation count is the number of step requests so far."""
    v = [0.0] * len(x)
    if nan:
        x = [float("nan")] * len(x)
    return struct.pack("<ddqq", t, 0.0, requests, count) + struct.pack("<%dd" % (2 * len(x)), *(x + v))


x0, t, P, requests = [], 0.0, 0, 0
while True:
    kind, payload = receive()
    if kind == 1:
        send(1, struct.pack("<II", 99 if mode == "bad-version" else 1, 0))
    elif kind == 2:
        P = struct.unpack("<q", payload[:8])[0]
        rows = 4 * 8 + 8 * 8  # counts and globals
        x0 = list(struct.unpack("<%dd" % (3 * P), payload[rows:rows + 24 * P]))
        send(2)
    elif kind in (3, 4, 5):
        if kind == 3:
            steps, dt = struct.unpack("<qd", payload)
            t += steps * dt
            requests += 1
        if mode == "crash":
            print("misbehaving_engine: about to crash on purpose", file=sys.stderr, flush=True)
            os.abort()
        elif mode == "hang":
            print("misbehaving_engine: hanging on purpose", file=sys.stderr, flush=True)
            time.sleep(3600)
        elif mode == "garbage":
            out.write(b"this is not a protocol frame at all")
            out.flush()
        elif mode == "wrong-count":
            send(6, state(t, x0[:-3], P - 1))
        elif mode == "early-exit":
            print("misbehaving_engine: leaving early", file=sys.stderr, flush=True)
            sys.exit(4)
        elif mode == "error":
            send(7, b"the engine cannot do this on purpose")
        elif mode == "noisy":
            sys.stderr.write("noise " * 100000)  # far more than a pipe holds
            send(6, state(t, x0, P))
        else:
            send(6, state(t, x0, P, nan=(mode == "nan")))
