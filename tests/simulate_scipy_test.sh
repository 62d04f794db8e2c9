#!/usr/bin/env bash
# The simulator's .mat files read by an independent reader (scipy.io.loadmat, as a
# MATLAB/Octave user's tools would): the course's variable names, shapes and classes,
# and the same numbers accelcal's own loader sees. Skips (exit 77) without scipy.
set -euo pipefail
bin_dir=$1
/usr/bin/python3 -c "import scipy.io" 2>/dev/null || { echo "SKIP: no python3-scipy"; exit 77; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$bin_dir/simulate" --out_dir="$scratch/sim" --seed=5 --set=angle_offset=0.004 >/dev/null
/usr/bin/python3 - "$scratch/sim" <<'PY'
import json, math, sys
import numpy as np
import scipy.io as sio
d = sys.argv[1]
ensayo = sio.loadmat(f"{d}/ensayo.mat")
acel = sio.loadmat(f"{d}/acel.mat")
puntos = sio.loadmat(f"{d}/puntos.mat")
truth = json.load(open(f"{d}/truth.json"))
assert ensayo["tita"].shape == (20001, 1) and ensayo["tita"].dtype == np.float64, ensayo["tita"].shape
assert ensayo["datos"].shape == (20001, 2)
assert abs(ensayo["tita"][-1, 0] - 2 * math.pi) < 1e-12
assert acel["t"].shape == (6000, 1) and acel["Aerr"].shape == (6000, 2)
assert abs(acel["t"][-1, 0] - 59.99) < 1e-9
assert sorted(k for k in puntos if not k.startswith("__")) == ["A", "B", "C", "D"]
assert puntos["C"].shape == (1, 2)
assert truth["parameters"]["angle_offset"] == 0.004 and truth["reached_landmark"] == "C"
# The baseline fit by numpy on scipy's reading recovers bias_x within 4 sigma.
theta = ensayo["tita"].ravel()
f = -9.8 * np.sin(theta)
A = np.c_[np.ones_like(f), f]
b, s = np.linalg.lstsq(A, ensayo["datos"][:, 0] - f, rcond=None)[0]
assert abs(b - truth["parameters"]["bias_x"]) < 4 * math.sqrt(0.25 / 20001), b
print(f"scipy reads the simulated course layout: bias_x {b:.5f} (truth {truth['parameters']['bias_x']})")
PY
