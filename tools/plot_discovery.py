#!/usr/bin/python3
"""Draws discover's outputs: the baseline's residual against theta (binned means with their
standard errors) with the fitted signature of each named effect over it, and the endpoint
before and after with its 1-sigma and 3-sigma ellipses and the landmarks.

    build/bin/discover --data_dir=DIR --json=discover.json --bins_csv=bins.csv
    /usr/bin/python3 tools/plot_discovery.py --json=discover.json --bins_csv=bins.csv --out=discovery.png

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


def axis_aligned_ellipse(center, sigma_x, sigma_y, radius, **style):
    return Ellipse(center, 2 * radius * sigma_x, 2 * radius * sigma_y, fill=False, **style)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", required=True, help="discover's --json output")
    parser.add_argument("--bins_csv", required=True, help="discover's --bins_csv output")
    parser.add_argument("--out", default="discovery.png", help="PNG to write")
    args = parser.parse_args()
    try:
        with open(args.json) as handle:
            result = json.load(handle)
        with open(args.bins_csv, newline="") as handle:
            rows = list(csv.DictReader(handle))
        bins = {key: np.array([float(row[key]) for row in rows]) for key in rows[0]}
    except (OSError, ValueError, KeyError, IndexError) as error:
        print(f"plot_discovery: error: {error}", file=sys.stderr)
        return 2

    named = [effect["name"] for effect in result["effects"]]
    figure, axes = plt.subplots(1, 3, figsize=(16, 5.2), gridspec_kw={"width_ratios": [1, 1, 1.1]})
    for axis_index, axis_name in enumerate(("x", "y")):
        axes_ = axes[axis_index]
        theta = bins["theta_rad"]
        axes_.errorbar(theta, bins[f"mean_{axis_name}"], yerr=bins[f"se_{axis_name}"], fmt="o", markersize=3,
                       color="tab:blue", label="baseline residual (bin mean ± 1 s.e.)")
        axes_.axhline(0.0, color="0.5", linewidth=0.8)
        signature = bins[f"signature_{axis_name}"]
        if named and np.any(np.abs(signature) > 0):
            axes_.plot(theta, signature, color="tab:red", linewidth=2, label="fitted: " + ", ".join(named))
        axes_.set_xlabel("θ (rad)")
        axes_.set_ylabel(f"residual of a{axis_name} (m/s²)")
        axes_.set_title(f"{axis_name} axis: what the baseline leaves")
        axes_.grid(True, alpha=0.3)
        axes_.legend(loc="best", fontsize=8)

    axes_ = axes[2]
    for side, color in (("baseline", "tab:blue"), ("extended", "tab:red")):
        end = result[side]["endpoint"]
        sd = result[side]["endpoint_stddev"]
        center = (end["x"], end["y"])
        axes_.plot(*center, "o", color=color, label=f"{side} endpoint")
        for radius, style in ((1, "-"), (3, ":")):
            axes_.add_patch(axis_aligned_ellipse(center, sd["x"], sd["y"], radius, color=color, linestyle=style))
    for landmark in result["baseline"]["landmarks"]:
        axes_.plot(landmark["x"], landmark["y"], "s", color="tab:green")
        axes_.annotate(landmark["name"], (landmark["x"], landmark["y"]), textcoords="offset points", xytext=(6, 6))
    axes_.set_xlabel("x (m)")
    axes_.set_ylabel("y (m)")
    axes_.set_aspect("equal", adjustable="datalim")
    axes_.grid(True, alpha=0.3)
    axes_.legend(loc="best", fontsize=8)
    axes_.set_title("endpoint before and after (1σ solid, 3σ dotted)")
    figure.suptitle(result["verdict"], fontsize=10)
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
