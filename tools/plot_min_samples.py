#!/usr/bin/python3
"""Draws min_samples' JSON: the probability of deciding a wrong landmark against the number of
tilt-test samples N (log axes), the analytic curve of each design, the Monte Carlo points with
their error bars, the criterion and each design's N_min.

    build/bin/min_samples --data_dir=../shared/data/tp2-2018 --json=min_samples.json
    /usr/bin/python3 tools/plot_min_samples.py --json=min_samples.json --out=min_samples.png
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", required=True, help="min_samples' --json output")
    parser.add_argument("--out", default="min_samples.png", help="PNG to write")
    args = parser.parse_args()
    try:
        with open(args.json) as handle:
            result = json.load(handle)
    except (OSError, ValueError) as error:
        print(f"plot_min_samples: error: {error}", file=sys.stderr)
        return 2
    figure, axes = plt.subplots(figsize=(9, 6))
    styles = ["-", "--", "-.", ":"]
    for index, design in enumerate(result["designs"]):
        n = [point["n"] for point in design["curve"]]
        p = [max(point["p_wrong"], 1e-7) for point in design["curve"]]
        line, = axes.loglog(n, p, styles[index % 4], label=f'{design["name"]}: N_min = {design["n_min"]}')
        for check in design.get("monte_carlo", []):
            # Each check beside its own analytic value (x): subsets of the real test keep the
            # run's one noise realisation fixed, so their analytic value is not the curve's.
            axes.plot(check["n"], max(check["analytic"], 1e-7), "x", color=line.get_color(), markersize=9)
            if check["monte_carlo"] > 0:
                axes.errorbar(check["n"], check["monte_carlo"], yerr=check["monte_carlo_sd"], fmt="o" if
                              check["kind"] == "full_simulation" else "s", color=line.get_color(), capsize=3)
        if design["n_min"] > 0:
            axes.axvline(design["n_min"], color=line.get_color(), alpha=0.3)
    axes.axhline(result["max_error"], color="tab:red", linewidth=1, label=f'criterion P(wrong) = {result["max_error"]}')
    axes.set_xlabel("tilt-test samples N")
    axes.set_ylabel(f'P(deciding a wrong landmark; truth {result["truth"]})')
    axes.set_title("How many samples decide the landmark (circles: full simulation, squares: subsets of the real\n"
                   "test, x: the analytic value each Monte Carlo point checks)", fontsize=9)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(loc="best", fontsize=8)
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
