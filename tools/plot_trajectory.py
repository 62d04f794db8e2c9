#!/usr/bin/python3
"""Draws the trajectory binary's outputs: raw and corrected paths, 1-sigma and 3-sigma
ellipses at the end and along the path, and the landmarks with their labels.

    build/bin/trajectory --data_dir=../shared/data/tp2-2018 --json=t.json --path_csv=path.csv
    /usr/bin/python3 tools/plot_trajectory.py --json=t.json --path_csv=path.csv --out=trajectory.png

Needs Debian's python3-matplotlib and python3-numpy (tools/run.sh installs them).
"""
import argparse
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402


def ellipse(center, covariance, radius, **style):
    """The set {p : (p - c)^T C^-1 (p - c) = radius^2}."""
    values, vectors = np.linalg.eigh(covariance)
    angle = np.degrees(np.arctan2(vectors[1, 1], vectors[0, 1]))
    return Ellipse(center, 2 * radius * np.sqrt(values[1]), 2 * radius * np.sqrt(values[0]),
                   angle=angle, fill=False, **style)


def read_path(path_csv):
    with open(path_csv, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if not rows:
        raise ValueError(f"{path_csv}: no path samples")
    return {key: np.array([float(row[key]) for row in rows]) for key in rows[0]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", required=True, help="the trajectory binary's --json output")
    parser.add_argument("--path_csv", required=True, help="the trajectory binary's --path_csv output")
    parser.add_argument("--out", default="trajectory.png", help="PNG to write")
    parser.add_argument("--ellipses_along_path", type=int, default=6,
                        help="number of 3-sigma ellipses drawn along the path")
    args = parser.parse_args()
    try:
        with open(args.json) as handle:
            result = json.load(handle)
        path = read_path(args.path_csv)
    except (OSError, ValueError, KeyError) as error:
        print(f"plot_trajectory: error: {error}", file=sys.stderr)
        return 2

    figure, axes = plt.subplots(figsize=(9, 7))
    axes.plot(path["raw_x_m"], path["raw_y_m"], color="0.55", linestyle="--", label="raw (uncorrected)")
    axes.plot(path["x_m"], path["y_m"], color="tab:blue", label="corrected")
    count = len(path["t_s"])
    along = np.linspace(0, count - 1, args.ellipses_along_path + 2).astype(int)[1:-1]
    for number, index in enumerate(along):
        covariance = np.array([[path["cov_xx"][index], path["cov_xy"][index]],
                               [path["cov_xy"][index], path["cov_yy"][index]]])
        axes.add_patch(ellipse((path["x_m"][index], path["y_m"][index]), covariance, 3,
                               color="tab:blue", alpha=0.35, linewidth=0.8,
                               label="3σ along the path" if number == 0 else None))
    end = np.array([result["endpoint"]["x"], result["endpoint"]["y"]])
    covariance = np.array(result["endpoint_covariance"])
    parameter_part = np.array(result["parameter_part"])
    axes.add_patch(ellipse(end, covariance, 1, color="tab:blue", linewidth=1.5, label="1σ (39%), total"))
    axes.add_patch(ellipse(end, covariance, 3, color="tab:blue", linewidth=1.5, linestyle=":",
                           label="3σ (98.9%), total"))
    axes.add_patch(ellipse(end, parameter_part, 3, color="tab:orange", linewidth=1.2,
                           label="3σ, parameters only"))
    axes.plot(*end, "o", color="tab:blue")
    axes.plot(result["raw_endpoint"]["x"], result["raw_endpoint"]["y"], "o", color="0.55")
    for landmark in result["landmarks"]:
        reached = landmark["name"] == result.get("reached")
        axes.plot(landmark["x"], landmark["y"], "*" if reached else "s", markersize=14 if reached else 8,
                  color="tab:green" if reached else "tab:red")
        axes.annotate(f'{landmark["name"]}  (d²={landmark["mahalanobis2"]:.2f})', (landmark["x"], landmark["y"]),
                      textcoords="offset points", xytext=(8, 6))
    verdict = f'reached {result["reached"]}' if result.get("reached") else "no landmark is consistent"
    p_value = "" if result["p_value"] is None else f" (p = {result['p_value']:.3g})"  # null: no landmarks
    axes.set_title(f"Dead reckoning with the baseline correction: {verdict}{p_value}")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_aspect("equal", adjustable="datalim")
    axes.grid(True, alpha=0.3)
    axes.legend(loc="best")
    figure.tight_layout()
    figure.savefig(args.out, dpi=120)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
