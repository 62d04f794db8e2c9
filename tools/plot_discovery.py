#!/usr/bin/python3
"""Draws discover's outputs: the baseline's residual against theta (binned means with their
standard errors) with the fitted signature of each named effect over it, and the endpoint
before and after with its 1-sigma and 3-sigma ellipses and the landmarks. With
--residuals_csv, a second row shows what the final model leaves, per axis, against theta and
against the sample's place in the test (time), with a running mean: structure the catalogue
does not explain shows there as a curve the running mean follows away from zero.

    build/bin/discover --data_dir=DIR --json=discover.json --bins_csv=bins.csv --residuals_csv=residuals.csv
    /usr/bin/python3 tools/plot_discovery.py --json=discover.json --bins_csv=bins.csv \
        --residuals_csv=residuals.csv --out=discovery.png

Needs Debian's python3-matplotlib and python3-numpy (tools/run.sh installs them).
"""
import argparse
import csv
import json
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402


def axis_aligned_ellipse(center, sigma_x, sigma_y, radius, **style):
    return Ellipse(center, 2 * radius * sigma_x, 2 * radius * sigma_y, fill=False, **style)


def read_residuals(path):
    """The residuals CSV as arrays; an empty cell (a non-finite residual) reads as NaN."""
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if not rows:
        raise ValueError(f"{path}: no samples")
    columns = {}
    for key in ("sample", "theta_rad", "residual_x", "residual_y", "outlier_x", "outlier_y"):
        columns[key] = np.array([float(row[key]) if row[key] != "" else np.nan for row in rows])
    return columns


def running_mean(values, window):
    """The centred mean of the finite values among `window` consecutive ones; NaN where fewer
    than half the window is there (the ends), whose means would be noisier than the band."""
    finite = np.isfinite(values)
    filled = np.where(finite, values, 0.0)
    kernel = np.ones(window)
    sums = np.convolve(filled, kernel, mode="same")
    counts = np.convolve(finite.astype(float), kernel, mode="same")
    return np.where(counts >= 0.5 * window, sums / np.maximum(counts, 1), np.nan)


def draw_remains(axes_, x_values, residuals, noise, against, sort):
    """Both axes' final residuals against `x_values` as a faint cloud (outliers marked) on the
    left scale, and their running means on a zoomed right scale with the band a running mean
    of noise alone stays in 95% of the time, so structure shows as a mean leaving its band."""
    count = len(x_values)
    # Wide enough that a structure of a tenth of the noise shows, narrow enough to follow a
    # few cycles over the test.
    window = max(5, count // 16)
    means = axes_.twinx()
    inliers_all = []
    outliers = []
    largest = 0.0
    for axis_name, color in (("x", "tab:blue"), ("y", "tab:orange")):
        residual = residuals[f"residual_{axis_name}"]
        outlier = residuals[f"outlier_{axis_name}"] > 0
        order = np.argsort(x_values, kind="stable") if sort else np.arange(count)
        xs, ys, out = x_values[order], residual[order], outlier[order]
        inlier = np.isfinite(ys) & ~out
        inliers_all.append(ys[inlier])
        axes_.plot(xs[inlier], ys[inlier], ".", color=color, markersize=1.5, alpha=0.15)
        if np.any(out):
            outliers.append((xs[out], ys[out], color, axis_name))
        mean = running_mean(np.where(inlier, ys, np.nan), window)
        means.plot(xs, mean, "-", color=color, linewidth=1.8, label=f"{axis_name}: running mean of {window} rows")
        # The band: 2 sigma of a mean of `window` rows of the noise model (AR(1) between rows
        # `stride` samples apart, when the rows are a decimation of the test).
        model = noise.get(axis_name, {}).get("model", {})
        variance, rho = model.get("variance"), model.get("correlation") or 0.0
        if variance:
            stride = max(1.0, float(np.median(np.diff(residuals["sample"])))) if count > 1 else 1.0
            rho_rows = rho ** stride if rho > 0 else 0.0
            half = 2.0 * np.sqrt(variance / window * (1 + rho_rows) / (1 - rho_rows))
            means.axhspan(-half, half, color=color, alpha=0.08, linewidth=0)
            largest = max(largest, 1.5 * half)
        finite = mean[np.isfinite(mean)]
        if finite.size:
            largest = max(largest, 1.2 * float(np.max(np.abs(finite))))
    axes_.axhline(0.0, color="0.3", linewidth=0.8)
    # Scale the cloud to the inliers, so a few outliers do not flatten it.
    inliers = np.concatenate(inliers_all) if inliers_all else np.array([])
    inliers = inliers[np.isfinite(inliers)]
    if inliers.size > 10:
        low, high = np.percentile(inliers, [0.5, 99.5])
        pad = 0.15 * (high - low) if high > low else 1.0
        axes_.set_ylim(low - pad, high + pad)
    # Outliers beyond the frame are drawn at its edge.
    low, high = axes_.get_ylim()
    for xs, ys, color, axis_name in outliers:
        axes_.plot(xs, np.clip(ys, low, high), "x", color=color, markersize=6,
                   label=f"{axis_name}: {len(xs)} set aside as outliers (at the edge when beyond it)")
    if largest > 0:
        means.set_ylim(-largest, largest)
    axes_.set_xlabel(against)
    axes_.set_ylabel("final residual (m/s²), points")
    means.set_ylabel("running mean (m/s²); band: noise alone, 95%")
    axes_.grid(True, alpha=0.3)
    handles, labels = axes_.get_legend_handles_labels()
    more_handles, more_labels = means.get_legend_handles_labels()
    means.legend(handles + more_handles, labels + more_labels, loc="upper right")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", required=True, help="discover's --json output")
    parser.add_argument("--bins_csv", required=True, help="discover's --bins_csv output")
    parser.add_argument("--residuals_csv", default="",
                        help="discover's --residuals_csv output: adds what the final model leaves")
    parser.add_argument("--out", default="discovery.png", help="PNG to write")
    args = parser.parse_args()
    try:
        with open(args.json) as handle:
            result = json.load(handle)
        with open(args.bins_csv, newline="") as handle:
            rows = list(csv.DictReader(handle))
        bins = {key: np.array([float(row[key]) for row in rows]) for key in rows[0]}
        residuals = read_residuals(args.residuals_csv) if args.residuals_csv else None
    except (OSError, ValueError, KeyError, IndexError) as error:
        print(f"plot_discovery: error: {error}", file=sys.stderr)
        return 2

    named = [effect["name"] for effect in result["effects"]]
    # The report shows the figure about 900-1000 px wide: a figure 9 in wide at 120 dpi is shown
    # near its own size, so text at 10-11 pt stays legible (issue 18: three panels side by side
    # at 16 in were shrunk to ~6 px text). The panels stack: the two axes side by side, the
    # endpoint below them, then what the final model leaves, against theta and against time.
    plt.rcParams.update({"font.size": 11, "legend.fontsize": 9, "axes.titlesize": 11})
    rows = 2 if residuals is None else 4
    heights = [3.8, 4.6] + ([3.6, 3.6] if residuals is not None else [])
    figure = plt.figure(figsize=(9, sum(heights) + 1.2))
    grid = figure.add_gridspec(rows, 2, height_ratios=heights)
    axes = [figure.add_subplot(grid[0, 0]), figure.add_subplot(grid[0, 1]), figure.add_subplot(grid[1, :])]
    if residuals is not None:
        remains_theta = figure.add_subplot(grid[2, :])
        remains_time = figure.add_subplot(grid[3, :])
        draw_remains(remains_theta, residuals["theta_rad"], residuals, result.get("noise", {}), "θ (rad)",
                     sort=True)
        remains_theta.set_title("what the final model leaves, against θ")
        draw_remains(remains_time, residuals["sample"], residuals, result.get("noise", {}),
                     "sample (place in the test)", sort=False)
        remains_time.set_title("what the final model leaves, against time")
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
        axes_.legend(loc="best")

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
    axes_.legend(loc="best")
    axes_.set_title("endpoint before and after (1σ solid, 3σ dotted)")
    title = result["verdict"]
    code = result.get("verdict_code", "")
    if code and not title.startswith(code.replace("_", " ")):
        title = f"{code}: {title}"
    lines = textwrap.wrap(textwrap.shorten(title, width=480, placeholder=" ..."), width=95)
    figure.suptitle("\n".join(lines), fontsize=11)
    # Room at the top for the verdict's lines.
    figure.tight_layout(rect=(0, 0, 1, 1 - 0.2 * len(lines) / figure.get_figheight()))
    figure.savefig(args.out, dpi=120)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
