#!/usr/bin/python3
"""Draws calibrate_imu --report's two figures: the whitened residual of every pose per axis
with the +-band that white noise stays within 95% of the time, and the norm of the specific
force corrected by the calibration over the whole log with the poses shaded (still, it should
sit on g).

calibrate_imu writes the inputs into a temporary folder and runs this with an argument
vector; to run it by hand:

    /usr/bin/python3 tools/plot_triad.py --json=triad_report.json --norm_csv=triad_norm.csv \
        --residuals_out=triad_residuals.png --norm_out=triad_norm.png

triad_report.json: {"gravity_mps2", "band", "chi2_per_dof", "poses": [{"start_s", "end_s",
"whitened_residual": [x, y, z]}]}; triad_norm.csv: t_s,norm_mps2.
Needs Debian's python3-matplotlib and python3-numpy (tools/run.sh installs them).
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

AXES = ("x", "y", "z")
COLOURS = ("tab:red", "tab:green", "tab:blue")


def draw_residuals(data, out):
    residuals = np.array([pose["whitened_residual"] for pose in data["poses"]], dtype=float)
    band = float(data["band"])
    poses = np.arange(1, len(residuals) + 1)
    figure, axes = plt.subplots(figsize=(10, 4.2))
    axes.axhspan(-band, band, color="0.9", label=f"±{band:g}")
    axes.axhline(0.0, color="0.5", linewidth=0.8)
    for k, (name, colour) in enumerate(zip(AXES, COLOURS)):
        # Side by side within a pose, so that three axes never hide one another.
        axes.plot(poses + (k - 1) * 0.2, residuals[:, k], "o", color=colour, markersize=5,
                  label=f"axis {name}")
    axes.set_xlabel("pose")
    axes.set_ylabel("whitened residual")
    axes.set_xticks(poses)
    axes.tick_params(axis="x", labelsize=7)
    axes.set_title(f"Whitened residual per pose (chi2/dof = {data['chi2_per_dof']:.3g})")
    # Headroom above the highest point for the legend, so that it hides no pose.
    low, high = min(-band, residuals.min()), max(band, residuals.max())
    axes.set_ylim(low - 0.1 * (high - low), high + 0.25 * (high - low))
    axes.legend(loc="upper right", fontsize=8, ncol=4)
    figure.tight_layout()
    figure.savefig(out, dpi=110)
    plt.close(figure)


def draw_norm(data, norm_csv, out):
    table = np.loadtxt(norm_csv, delimiter=",", skiprows=1, ndmin=2)
    if table.shape[0] == 0:
        raise ValueError(f"{norm_csv}: no samples")
    g = float(data["gravity_mps2"])
    figure, axes = plt.subplots(figsize=(10, 4.2))
    for i, pose in enumerate(data["poses"]):
        axes.axvspan(pose["start_s"], pose["end_s"], color="tab:green", alpha=0.15,
                     label="poses" if i == 0 else None)
    axes.plot(table[:, 0], table[:, 1], color="k", linewidth=0.6, label="|a| calibrated")
    axes.axhline(g, color="tab:red", linewidth=0.8, linestyle="--", label=f"g = {g:.6g}")
    # Motion reaches several g; the still parts, which are the point, sit within a fraction
    # of a percent of g, so the axis is held near g and the motion runs off it.
    axes.set_ylim(0.99 * g, 1.01 * g)
    axes.set_xlabel("t (s)")
    axes.set_ylabel("|a| (m/s²)")
    axes.set_title("Norm of the calibrated specific force; the poses shaded")
    axes.legend(loc="upper right", fontsize=8, framealpha=0.95)
    figure.tight_layout()
    figure.savefig(out, dpi=110)
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", required=True)
    parser.add_argument("--norm_csv", required=True)
    parser.add_argument("--residuals_out", required=True)
    parser.add_argument("--norm_out", required=True)
    args = parser.parse_args()
    try:
        with open(args.json) as handle:
            data = json.load(handle)
        draw_residuals(data, args.residuals_out)
        draw_norm(data, args.norm_csv, args.norm_out)
    except (OSError, ValueError, KeyError) as error:
        print(f"plot_triad.py: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
