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
import textwrap

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
    markers = {"full_simulation": "o", "real_test_subsets": "s", "real_test_even_subsets": "s"}
    drawn = set()  # the kinds of marker on the figure, which the title explains
    for index, design in enumerate(result["designs"]):
        n = [point["n"] for point in design["curve"]]
        p = [max(point["p_wrong"], 1e-7) for point in design["curve"]]
        line, = axes.loglog(n, p, styles[index % 4], label=f'{design["name"]}: N_min = {design["n_min"] or "none"}')
        for check in design.get("monte_carlo", []):
            # Each check beside its own analytic value (x): subsets of the real test keep the
            # run's one noise realisation fixed, so their analytic value is not the curve's.
            axes.plot(check["n"], max(check["analytic"], 1e-7), "x", color=line.get_color(), markersize=9)
            drawn.add("x")
            marker = markers.get(check["kind"], "o")
            if check["monte_carlo"] > 0:
                axes.errorbar(check["n"], check["monte_carlo"], yerr=check["monte_carlo_sd"], fmt=marker,
                              color=line.get_color(), capsize=3)
                drawn.add(marker)
            elif check.get("repetitions", 0) > 0:
                # No trial wrong: a log axis has no 0, so the point is drawn at 1/repetitions
                # as an upper bound.
                axes.plot(check["n"], 1.0 / check["repetitions"], "v", color=line.get_color(), markersize=8)
                drawn.add("v")
        if design["n_min"] is not None:  # null: none up to the limit
            axes.axvline(design["n_min"], color=line.get_color(), alpha=0.3)
    axes.axhline(result["max_error"], color="tab:red", linewidth=1, label=f'criterion P(wrong) = {result["max_error"]}')
    axes.set_xlabel("tilt-test samples N")
    axes.set_ylabel(f'P(deciding a wrong landmark; truth {result["truth"]})')
    # The title names only the markers drawn (issue 18: it promised Monte Carlo points that a
    # run without --repetitions does not have).
    meanings = [("o", "circles: full simulation"), ("s", "squares: subsets of the real test"),
                ("v", "triangles: no trial wrong, at 1/repetitions"),
                ("x", "x: the analytic value each Monte Carlo point checks")]
    legend = [text for marker, text in meanings if marker in drawn]
    title = "How many samples decide the landmark"
    if legend:
        title += " (" + "; ".join(legend) + ")"
    else:
        title += " (analytic curves only: no Monte Carlo check in this run; min_samples --repetitions adds them)"
    axes.set_title("\n".join(textwrap.wrap(title, width=95)), fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(loc="best", fontsize=9)
    figure.tight_layout()
    # The title in the PNG's metadata too, so a test can read what the figure promises.
    figure.savefig(args.out, dpi=110, metadata={"Title": title})
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
