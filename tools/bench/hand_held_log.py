#!/usr/bin/env python3
"""A synthetic hand-held triad log for the scale benchmarks (tools/bench/triad_scale_bench.sh,
stream_scale_bench.sh).

The logs of tools/bench/triad_scale_bench.sh and stream_scale_bench.sh (100 Hz, holds of 3-20 s
in random directions at least 30 deg apart, 1.5 s turns with a (1 - cos) profile, a triad of
~4000 counts/g with offsets near 32768, off-diagonal angles of a few mrad, 3 counts of white
noise, rounded to counts; imu_tk's ASCII layout t x y z), written in pieces of 10^6 rows so that
10^7 rows need no more memory than 10^6.

  hand_held_log.py ROWS PATH SEED
"""
import sys
import numpy as np

rows, path, seed = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
rng = np.random.default_rng(seed)
rate_hz, turn_s, g = 100.0, 1.5, 9.81
gain = np.array([9.81 / 4000.0, 9.81 / 4050.0, 9.81 / 3950.0])  # (m/s^2) per count
offset = np.array([32768.0 + 40.0, 32768.0 - 25.0, 32768.0 + 10.0])
T = np.array([[1.0, -0.003, 0.002], [0.0, 1.0, -0.004], [0.0, 0.0, 1.0]])  # a = T K (u - b)
M = np.linalg.inv(T @ np.diag(gain))


def random_direction():
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def pieces_of(count_wanted, start):
    n = start
    pieces, count = [], 0
    while count < count_wanted:
        hold = int(rng.uniform(3.0, 20.0) * rate_hz)
        pieces.append(np.tile(n, (hold, 1)))
        count += hold
        while True:
            m = random_direction()
            if np.degrees(np.arccos(np.clip(n @ m, -1, 1))) > 30.0:
                break
        turn = int(turn_s * rate_hz)
        axis = np.cross(n, m)
        axis /= np.linalg.norm(axis)
        angle = np.arccos(np.clip(n @ m, -1, 1))
        tau = np.arange(1, turn + 1) / turn
        phi = angle * (1 - np.cos(np.pi * tau)) / 2
        pieces.append(np.outer(np.cos(phi), n) + np.outer(np.sin(phi), np.cross(axis, n)))
        count += turn
        n = m
    return np.concatenate(pieces), n


with open(path, "w") as f:
    done, direction = 0, random_direction()
    while done < rows:
        chunk, direction = pieces_of(min(1000000, rows - done), direction)
        chunk = chunk[: rows - done]
        u = np.round(g * chunk @ M.T + offset + rng.normal(scale=3.0, size=chunk.shape))
        t = (done + np.arange(len(chunk))) / rate_hz
        np.savetxt(f, np.column_stack([t, u]), fmt=["%.2f", "%d", "%d", "%d"])
        done += len(chunk)
