"""Simulated hand-held triad sessions, for the many-devices tests and measurements: a device
held still in several orientations, with gravity along a random direction in each, turned
between holds, read through a known a = T K (u - b) (models/triad.h, docs/triad.md) plus white
noise, rounded to counts of a 16-bit ADC centred near mid-scale.

  /usr/bin/python3 tests/python/hand_held.py OUT_DIR DEVICES [SEED]
writes OUT_DIR/device_NN.csv (t,ax,ay,az) and OUT_DIR/truth.csv.
"""
import os
import sys

import numpy as np

RATE_HZ = 100.0
NOISE_MPS2 = 0.02  # white noise of every axis, m/s^2


def truth_of(rng):
    return {
        "misalignment_yz": rng.normal(0, 2e-3), "misalignment_zy": rng.normal(0, 2e-3),
        "misalignment_zx": rng.normal(0, 2e-3),
        "gain_x": 2e-3 * (1 + rng.normal(0, 0.02)), "gain_y": 2e-3 * (1 + rng.normal(0, 0.02)),
        "gain_z": 2e-3 * (1 + rng.normal(0, 0.02)),
        "offset_x": 32768 + rng.normal(0, 150), "offset_y": 32768 + rng.normal(0, 150),
        "offset_z": 32768 + rng.normal(0, 150),
    }


def outputs(truth, a):
    """u = b + K^-1 T^-1 a for specific forces a (N, 3)."""
    t = np.array([[1, -truth["misalignment_yz"], truth["misalignment_zy"]],
                  [0, 1, -truth["misalignment_zx"]], [0, 0, 1]])
    k = np.diag([truth["gain_x"], truth["gain_y"], truth["gain_z"]])
    b = np.array([truth["offset_x"], truth["offset_y"], truth["offset_z"]])
    return b + a @ np.linalg.inv(t @ k).T


def session(rng, truth, g=9.81, poses=24, hold_s=4.0, turn_s=1.5):
    """(t, u): holds of hold_s along random directions, turns of turn_s between them."""
    directions = rng.normal(size=(poses, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    segments = []
    for p in range(poses):
        n = int(hold_s * RATE_HZ)
        segments.append(np.tile(g * directions[p], (n, 1)))
        if p + 1 < poses:  # a turn: gravity swung to the next direction, plus the hand's push
            m = int(turn_s * RATE_HZ)
            s = np.linspace(0, 1, m)[:, None]
            swung = (1 - s) * directions[p] + s * directions[p + 1]
            swung /= np.linalg.norm(swung, axis=1, keepdims=True)
            push = 3.0 * np.sin(np.pi * s) * rng.normal(size=3)
            segments.append(g * swung + push)
    a = np.vstack(segments)
    a = a + rng.normal(0, NOISE_MPS2, size=a.shape)
    u = np.round(outputs(truth, a))
    return np.arange(len(u)) / RATE_HZ, u


def write_devices(out_dir, count, seed=1):
    """Writes count devices' logs and their truths; returns [(path, truth)]."""
    os.makedirs(out_dir, exist_ok=True)
    rng = np.random.default_rng(seed)
    written = []
    for d in range(count):
        truth = truth_of(rng)
        t, u = session(rng, truth)
        path = os.path.join(out_dir, f"device_{d:02d}.csv")
        with open(path, "w") as f:
            f.write("t,ax,ay,az\n")
            for ti, ui in zip(t, u):
                f.write(f"{ti:.2f},{ui[0]:.0f},{ui[1]:.0f},{ui[2]:.0f}\n")
        written.append((path, truth))
    with open(os.path.join(out_dir, "truth.csv"), "w") as f:
        names = list(written[0][1])
        f.write("device," + ",".join(names) + "\n")
        for path, truth in written:
            f.write(os.path.basename(path) + "," + ",".join(repr(truth[n]) for n in names) + "\n")
    return written


if __name__ == "__main__":
    write_devices(sys.argv[1], int(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else 1)
