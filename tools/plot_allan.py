#!/usr/bin/env python3
"""Log-log Allan deviation plot of `allan --json`'s output: per axis the measured deviation with
its confidence interval, the fitted model and its three terms (white noise N / sqrt(tau), bias
instability 0.664 B, random walk K sqrt(tau / 3)).

    plot_allan.py --json=allan.json --out=allan.png
"""
import argparse
import json
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--json", required=True)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.json) as f:
        data = json.load(f)
    unit = data["unit"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), sharey=True)
    for ax, name in zip(axes, ["x", "y", "z"]):
        axis = data["axes"][name]
        points = axis["points"]
        tau = np.array([p["tau_s"] for p in points])
        adev = np.array([p["adev"] for p in points])
        low = np.array([p["adev_low"] for p in points])
        high = np.array([p["adev_high"] for p in points])
        ax.errorbar(tau, adev, yerr=[adev - low, high - adev], fmt="o", color="k", ms=4,
                    capsize=2, label="measured, %.0f%% interval" % (100 * data["confidence"]))
        grid = np.logspace(math.log10(tau[0]), math.log10(tau[-1]), 200)
        n = axis["white_noise"].get("value", 0.0)
        b = axis["bias_instability"].get("value", 0.0)
        k = axis["random_walk"].get("value", 0.0)
        floor = math.sqrt(2 * math.log(2) / math.pi) * b
        model = np.sqrt(n * n / grid + floor * floor + k * k * grid / 3)
        ax.loglog(grid, model, "C0-", lw=2, label="model")
        if n > 0:
            ax.loglog(grid, n / np.sqrt(grid), "C1--", label="N = %.3g %s/sqrt(Hz)" % (n, unit))
        if b > 0:
            ax.loglog(grid, floor + 0 * grid, "C2--", label="0.664 B, B = %.3g %s" % (b, unit))
        if k > 0:
            ax.loglog(grid, k * np.sqrt(grid / 3), "C3--",
                      label="K = %.3g %s*sqrt(Hz)" % (k, unit))
        ax.set_title("axis " + name)
        ax.set_xlabel("tau (s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("Allan deviation (%s)" % unit)
    fig.suptitle("Allan deviation: %s (%s)" % (data["log"], data["selection"]), fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
