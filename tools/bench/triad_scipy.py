#!/usr/bin/python3
"""The numpy/SciPy side of tools/bench/triad_bench.sh (issue 20): calibrate_imu's pipeline on
a triad log, written as a competent numpy/SciPy user would write it, timed in-process and
checked against accelcal's results (tools/bench/triad_bench.cc's JSON).

Run with Debian's /usr/bin/python3 (python3-numpy, python3-scipy):

  triad_scipy.py --log=xsens_acc.mat --accelcal_json=cc.json [--json=py.json] [--min_ratio=10]

prints a PASS/FAIL line per check, both sides' median wall and CPU times per stage and the
ratios; exits 1 when a check fails, 3 when every check passes but the total's wall-time ratio
(numpy/SciPy over accelcal) is below --min_ratio, 2 on bad input.

The stages, as accelcal's (names and units of docs/triad.md, a = T K (u - b)):

  read    numpy.loadtxt of the 4 columns (t [s], x, y, z in counts), finiteness and strictly
          increasing time checked.
  imu_tk  detect: the initial rest's variance norm v_rest (samples up to the one nearest
          t_0 + rest), the sliding variance norm over a centred window of w samples from
          cumulative sums, the static intervals (norm < k v_rest) for k = 2..10 by
          numpy.diff on the boolean mask; then, for each k with >= 12 intervals of >= 100
          samples, scipy.optimize.least_squares (method 'lm', MINPACK, like Ceres' LM) on
          imu_tk's residuals g - |T K (u_i - b)| over the first 100 samples of each interval,
          from the same start (angles 0, gains 1, offsets 32768), with the analytic Jacobian;
          the k with the lowest cost is kept.
  ml      the poses (mean and variance of every sample of each used interval at the chosen k),
          the noise pooled per axis, and least_squares ('lm', analytic Jacobian) on the
          whitened pose residuals (ubar_p - b - K^-1 T^-1 g n_p) / sqrt(s^2 / N_p) over the 9
          parameters and one unit direction per pose, from imu_tk's solution; each n_p in a
          chart around its initial value n0: n = (n0 + alpha e1 + beta e2) / |...|, with e1, e2
          orthonormal to n0 (no pole, unlike two spherical angles); the rank of the
          column-normalised Jacobian checked at the start and at the solution, as accelcal
          does; the covariance of the 9 parameters, the 9x9 block of (J^T J)^-1 with the
          directions as nuisance parameters (QR of the column-normalised J, since the columns
          span ten orders of magnitude), chi2 and its p-value.
"""

import argparse
import json
import math
import sys
import time

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import least_squares
from scipy.stats import chi2 as chi2_distribution

PARAMETER_NAMES = [
    "misalignment_yz",
    "misalignment_zy",
    "misalignment_zx",
    "gain_x",
    "gain_y",
    "gain_z",
    "offset_x",
    "offset_y",
    "offset_z",
]
YZ, ZY, ZX, GX, GY, GZ, BX, BY, BZ = range(9)

# imu_tk's rules (estimation/triad/imu_tk_calibration.h).
WINDOW_SAMPLES = 101
INTERVAL_SAMPLES = 100
MIN_INTERVALS = 12
MULTIPLIERS = range(2, 11)
# accelcal's rank tolerance (estimation/triad/triad_ml_calibration.h).
RANK_TOLERANCE = 1e-4

# Agreement with accelcal.
# - imu_tk's costs: Ceres stops when an iteration lowers the cost by less than 1e-6 of it
#   (imu_tk keeps Ceres' default function tolerance), least_squares when by less than ftol;
#   both near the same minimum, so the costs agree to about 1e-6 relative.
# - imu_tk's parameters: stopping 1e-6 short of the minimum's cost moves the parameters along
#   the flattest direction; measured against the maximum-likelihood sigma (the only sigma in
#   play), a hundredth of it.
# - The maximum-likelihood fit: both sides solve to convergence (Ceres' tolerances 1e-14),
#   so a thousandth of a sigma, and a thousandth of sigma itself.
COST_TOLERANCE_RELATIVE = 1e-6
IMU_TK_TOLERANCE_SIGMA = 1e-2
ML_TOLERANCE_SIGMA = 1e-3
STDDEV_TOLERANCE_RELATIVE = 1e-3
CHI2_TOLERANCE_RELATIVE = 1e-6


class BadInput(Exception):
    pass


# ---------------------------------------------------------------------------------------
# read
# ---------------------------------------------------------------------------------------


def read_log(path):
    try:
        table = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as error:
        raise BadInput("%s: %s" % (path, error))
    if table.shape[1] != 4 or len(table) < 2:
        raise BadInput("%s: expected rows of 4 numbers (t [s], x, y, z)" % path)
    if not np.isfinite(table).all():
        raise BadInput("%s: a value is not a finite number" % path)
    t = table[:, 0]
    if not (np.diff(t) > 0).all():
        raise BadInput("%s: time does not increase strictly" % path)
    return t, np.ascontiguousarray(table[:, 1:])


# ---------------------------------------------------------------------------------------
# imu_tk: detector
# ---------------------------------------------------------------------------------------


def initial_rest_end(t, duration_s):
    """The sample nearest t_0 + duration_s (the later one on a tie), or the last."""
    end_s = t[0] + duration_s
    if end_s >= t[-1]:
        return len(t) - 1
    high = int(np.searchsorted(t, end_s, side="left"))
    low = high - 1
    return low if end_s - t[low] < t[high] - end_s else high


def sliding_variance_norm(u, window):
    """|(var_x, var_y, var_z)| over the window centred on each sample i = h .. n - h - 1.

    From cumulative sums of the values and their squares, taken after subtracting the first
    sample: for integer counts every sum is an integer below 2^53, so exact in doubles, and
    the only rounding is the final division (the two-pass variance rounds a little more)."""
    centred = u - u[0]
    zero = np.zeros((1, 3))
    sums = np.concatenate([zero, np.cumsum(centred, axis=0)])
    squares = np.concatenate([zero, np.cumsum(centred * centred, axis=0)])
    s1 = sums[window:] - sums[:-window]
    s2 = squares[window:] - squares[:-window]
    variance = (window * s2 - s1 * s1) / (window * (window - 1.0))
    return np.sqrt((variance * variance).sum(axis=1))


def static_intervals(norm, half, threshold):
    """(starts, ends) inclusive sample indices of the runs of norm < threshold."""
    still = np.concatenate([[False], norm < threshold, [False]]).astype(np.int8)
    edges = np.diff(still)
    starts = np.flatnonzero(edges == 1) + half
    ends = np.flatnonzero(edges == -1) - 1 + half
    return starts, ends


# ---------------------------------------------------------------------------------------
# imu_tk: the cost and its Jacobian
# ---------------------------------------------------------------------------------------


class ImuTkProblem:
    """r_i = g - |T K (u_i - b)| for the chosen samples, unweighted."""

    def __init__(self, u, gravity):
        self.u = u
        self.g = gravity

    def _force(self, x):
        d = self.u - x[BX:BZ + 1]
        v = d * x[GX:GZ + 1]
        a = np.empty_like(v)
        a[:, 0] = v[:, 0] - x[YZ] * v[:, 1] + x[ZY] * v[:, 2]
        a[:, 1] = v[:, 1] - x[ZX] * v[:, 2]
        a[:, 2] = v[:, 2]
        return d, v, a

    def residuals(self, x):
        _, _, a = self._force(x)
        return self.g - np.sqrt((a * a).sum(axis=1))

    def jacobian(self, x):
        d, v, a = self._force(x)
        e = a / np.sqrt((a * a).sum(axis=1))[:, None]  # dr/da = -e
        e0, e1, e2 = e[:, 0], e[:, 1], e[:, 2]
        j = np.empty((len(a), 9))
        j[:, YZ] = e0 * v[:, 1]
        j[:, ZY] = -e0 * v[:, 2]
        j[:, ZX] = e1 * v[:, 2]
        j[:, GX] = -e0 * d[:, 0]
        j[:, GY] = (x[YZ] * e0 - e1) * d[:, 1]
        j[:, GZ] = -(x[ZY] * e0 - x[ZX] * e1 + e2) * d[:, 2]
        j[:, BX] = e0 * x[GX]
        j[:, BY] = -(x[YZ] * e0 - e1) * x[GY]
        j[:, BZ] = (x[ZY] * e0 - x[ZX] * e1 + e2) * x[GZ]
        return j


def solve_imu_tk(u, gravity, initial):
    problem = ImuTkProblem(u, gravity)
    # x_scale='jac': MINPACK's own column scaling, as Ceres' LM scales by the Jacobian's
    # columns; without it the gains (1e-3) and offsets (3e4) make the steps useless.
    return least_squares(problem.residuals, initial, jac=problem.jacobian, method="lm",
                         x_scale="jac")


def calibrate_imu_tk(t, u, gravity, init_rest_s, initial, timing):
    start = stamp()
    half = WINDOW_SAMPLES // 2
    rest_end = initial_rest_end(t, init_rest_s)
    rest_variance = u[: rest_end + 1].var(axis=0, ddof=1)
    rest_norm = math.sqrt(rest_variance @ rest_variance)
    norm = sliding_variance_norm(u, WINDOW_SAMPLES)
    detected = [static_intervals(norm, half, k * rest_norm) for k in MULTIPLIERS]
    timing["detect"] = elapsed(start, stamp())
    sweep = []
    best = None
    offsets = np.arange(INTERVAL_SAMPLES)
    for k, (starts, ends) in zip(MULTIPLIERS, detected):
        used = ends - starts + 1 >= INTERVAL_SAMPLES
        entry = {"k": k, "detected_intervals": len(starts), "intervals": int(used.sum()),
                 "cost": None}
        if entry["intervals"] >= MIN_INTERVALS:
            samples = (starts[used][:, None] + offsets).ravel()
            solution = solve_imu_tk(u[samples], gravity, initial)
            entry.update(cost=solution.cost, x=solution.x, nfev=solution.nfev,
                         status=solution.status)
            if best is None or solution.cost < best["cost"]:
                best = dict(entry, starts=starts, ends=ends, used=used)
        sweep.append(entry)
    if best is None:
        raise BadInput("no threshold gives %d static intervals" % MIN_INTERVALS)
    return {"sweep": sweep, "best": best, "rest_end": rest_end, "rest_norm": rest_norm}


# ---------------------------------------------------------------------------------------
# ml: pose means, the whitened pose residuals and their Jacobian, covariance
# ---------------------------------------------------------------------------------------


def pose_means(u, starts, ends):
    """Mean and sample variance of every sample of each interval [start, end]."""
    counts = ends - starts + 1
    # reduceat over [start_0, end_0 + 1, start_1, ...]: the odd slots are the gaps.
    bounds = np.column_stack([starts, ends + 1]).ravel()
    if bounds[-1] == len(u):
        bounds = bounds[:-1]
    means = np.add.reduceat(u, bounds, axis=0)[::2] / counts[:, None]
    inside = np.repeat(np.arange(len(starts)), counts)
    rows = np.concatenate([np.arange(s, e + 1) for s, e in zip(starts, ends)])
    deviation = u[rows] - means[inside]
    variance = np.add.reduceat(deviation * deviation, np.cumsum(counts) - counts, axis=0)
    return means, variance / (counts - 1)[:, None], counts


def specific_force(x, u):
    v = (u - x[BX:BZ + 1]) * x[GX:GZ + 1]
    return np.column_stack([v[:, 0] - x[YZ] * v[:, 1] + x[ZY] * v[:, 2],
                            v[:, 1] - x[ZX] * v[:, 2], v[:, 2]])


class MlProblem:
    """x = (9 parameters, alpha_p, beta_p for each pose); 3 whitened residuals per pose."""

    def __init__(self, means, stddev, gravity, n0):
        self.means = means
        self.stddev = stddev  # P x 3, counts
        self.g = gravity
        self.count = len(means)
        self.n0 = n0
        # e1, e2: an orthonormal basis of the tangent plane at n0, from a cross product with
        # the x axis, or with y when n0 is within 26 degrees of x.
        helper = np.where(np.abs(n0[:, [0]]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
        e1 = np.cross(n0, helper)
        self.e1 = e1 / np.linalg.norm(e1, axis=1)[:, None]
        self.e2 = np.cross(n0, self.e1)

    def _directions(self, x):
        alpha = x[9::2, None]
        beta = x[10::2, None]
        m = self.n0 + alpha * self.e1 + beta * self.e2
        length = np.linalg.norm(m, axis=1)[:, None]
        return m / length, length

    def _predicted(self, x):
        n, length = self._directions(x)
        f = self.g * n
        vz = f[:, 2]
        vy = f[:, 1] + x[ZX] * vz
        vx = f[:, 0] + x[YZ] * vy - x[ZY] * vz
        v = np.column_stack([vx, vy, vz])
        return v, v / x[GX:GZ + 1] + x[BX:BZ + 1], n, length

    def residuals(self, x):
        _, u, _, _ = self._predicted(x)
        return ((self.means - u) / self.stddev).ravel()

    def jacobian(self, x):
        v, _, n, length = self._predicted(x)
        gain = x[GX:GZ + 1]
        p = self.count
        du = np.zeros((p, 3, 9 + 2 * p))
        du[:, 0, YZ] = v[:, 1] / gain[0]
        du[:, 0, ZY] = -v[:, 2] / gain[0]
        du[:, 0, ZX] = x[YZ] * v[:, 2] / gain[0]
        du[:, 1, ZX] = v[:, 2] / gain[1]
        for k in range(3):
            du[:, k, GX + k] = -v[:, k] / gain[k] ** 2
            du[:, k, BX + k] = 1.0
        # du/dn = g K^-1 T^-1, the same for every pose.
        inverse_t = np.array([[1.0, x[YZ], x[YZ] * x[ZX] - x[ZY]], [0, 1.0, x[ZX]], [0, 0, 1.0]])
        du_dn = self.g * inverse_t / gain[:, None]
        # dn/dalpha = (e1 - n (n . e1)) / |m|, likewise for beta.
        poses = np.arange(p)
        for column, e in ((9 + 2 * poses, self.e1), (10 + 2 * poses, self.e2)):
            dn = (e - n * (n * e).sum(axis=1)[:, None]) / length
            du[poses, :, column] = dn @ du_dn.T
        return (-du / self.stddev[:, :, None]).reshape(3 * p, 9 + 2 * p)


def rank_deficient(jacobian):
    scaled = jacobian / np.linalg.norm(jacobian, axis=0)
    singular = np.linalg.svd(scaled, compute_uv=False)
    return singular[-1] <= RANK_TOLERANCE * singular[0]


def calibrate_ml(u, imu_tk, gravity):
    best = imu_tk["best"]
    starts, ends = best["starts"][best["used"]], best["ends"][best["used"]]
    means, variances, counts = pose_means(u, starts, ends)
    pooled = ((counts - 1)[:, None] * variances).sum(axis=0) / (counts - 1).sum()
    stddev = np.sqrt(pooled / counts[:, None])
    force = specific_force(best["x"], means)
    n0 = force / np.linalg.norm(force, axis=1)[:, None]
    problem = MlProblem(means, stddev, gravity, n0)
    x0 = np.concatenate([best["x"], np.zeros(2 * len(means))])
    if rank_deficient(problem.jacobian(x0)):
        raise BadInput("the poses cannot determine the triad (rank-deficient Jacobian)")
    solution = least_squares(problem.residuals, x0, jac=problem.jacobian, method="lm",
                             x_scale="jac", ftol=1e-14, xtol=1e-14, gtol=1e-14, max_nfev=1000)
    jacobian = problem.jacobian(solution.x)
    if rank_deficient(jacobian):
        raise BadInput("the poses cannot determine the triad (rank-deficient Jacobian)")
    # (J^T J)^-1 = D (R^T R)^-1 D with J D = Q R.
    column_scale = 1.0 / np.linalg.norm(jacobian, axis=0)
    r = np.linalg.qr(jacobian * column_scale, mode="r")
    r_inverse = solve_triangular(r, np.eye(len(r)))
    block = r_inverse[:9] * column_scale[:9, None]
    covariance = block @ block.T
    residuals = problem.residuals(solution.x)
    chi2 = float(residuals @ residuals)
    dof = len(means) - 9
    return {
        "x": solution.x[:9],
        "covariance": covariance,
        "stddev": np.sqrt(np.diag(covariance)),
        "chi2": chi2,
        "dof": dof,
        "p_value": float(chi2_distribution.sf(chi2, dof)),
        "pooled_noise_variance": pooled,
        "pose_count": len(means),
        "sample_count": int(counts.sum()),
        "nfev": solution.nfev,
        "status": solution.status,
        "ml_problem": problem,
        "ml_x": solution.x,
    }


# ---------------------------------------------------------------------------------------
# The pipeline, timed
# ---------------------------------------------------------------------------------------


def stamp():
    """Wall time and the process's CPU time (every thread's, should BLAS start any)."""
    return time.perf_counter(), time.process_time()


def elapsed(start, stop):
    return stop[0] - start[0], stop[1] - start[1]


def run_pipeline(arguments, timing):
    initial = np.array([0, 0, 0, 1, 1, 1] + [arguments.initial_offset] * 3, dtype=float)
    start = stamp()
    t, u = read_log(arguments.log)
    read = stamp()
    imu_tk = calibrate_imu_tk(t, u, arguments.g, arguments.init_rest_s, initial, timing)
    swept = stamp()
    ml = calibrate_ml(u, imu_tk, arguments.g)
    stop = stamp()
    timing.update(read=elapsed(start, read), imu_tk=elapsed(read, swept),
                  ml=elapsed(swept, stop), total=elapsed(start, stop))
    return t, u, imu_tk, ml


class Checks:
    def __init__(self):
        self.failed = 0

    def record(self, what, passed, line):
        print("  %s  %-28s %s" % ("PASS" if passed else "FAIL", what, line))
        self.failed += not passed


def central_differences(function, x, relative_step=1e-6):
    columns = []
    for i in range(len(x)):
        step = np.zeros_like(x)
        step[i] = relative_step * max(1.0, abs(x[i]))
        columns.append((function(x + step) - function(x - step)) / (2 * step[i]))
    return np.column_stack(columns)


def check_jacobians(u, imu_tk, ml, gravity, checks):
    """Both analytic Jacobians against central differences, at the solutions (untimed)."""
    best = imu_tk["best"]
    starts = best["starts"][best["used"]]
    samples = (starts[:, None] + np.arange(INTERVAL_SAMPLES)).ravel()
    cases = [("imu_tk", ImuTkProblem(u[samples], gravity), best["x"]),
             ("ml", ml["ml_problem"], ml["ml_x"])]
    for name, problem, x in cases:
        analytic = problem.jacobian(x)
        numeric = central_differences(problem.residuals, x)
        # Per column, against the column's largest entry: the columns differ by 10^10.
        scale = np.abs(analytic).max(axis=0)
        error = (np.abs(analytic - numeric).max(axis=0) / scale).max()
        checks.record("jacobian " + name, error <= 1e-5,
                      "largest difference from central differences %.1e (of its column)"
                      % error)


def compare(accelcal, t, imu_tk, ml, gravity, init_rest_s, checks):
    cc_tk, cc_ml = accelcal["imu_tk"], accelcal["ml"]
    checks.record("configuration",
                  cc_tk["gravity_mps2"] == gravity and cc_tk["initial_rest"]["duration_s"]
                  == init_rest_s and cc_tk["detector"]["window_samples"] == WINDOW_SAMPLES
                  and cc_tk["detector"]["interval_samples"] == INTERVAL_SAMPLES
                  and cc_tk["detector"]["min_intervals"] == MIN_INTERVALS,
                  "g %g m/s^2, rest %g s, window %d, %d samples per interval, >= %d intervals"
                  % (gravity, init_rest_s, WINDOW_SAMPLES, INTERVAL_SAMPLES, MIN_INTERVALS))
    checks.record("samples", cc_tk["log"]["samples"] == len(t),
                  "%d rows read, %d by accelcal" % (len(t), cc_tk["log"]["samples"]))
    worst_cost = 0.0
    for mine, theirs in zip(imu_tk["sweep"], cc_tk["threshold_sweep"]):
        same_counts = (mine["k"] == theirs["k"]
                       and mine["detected_intervals"] == theirs["detected_intervals"]
                       and mine["intervals"] == theirs["intervals"])
        if mine["cost"] is None or theirs["cost"] is None:
            passed = same_counts and mine["cost"] is None and theirs["cost"] is None
            line = "intervals %d/%d vs %d/%d, not solved" % (
                mine["detected_intervals"], mine["intervals"], theirs["detected_intervals"],
                theirs["intervals"])
        else:
            relative = abs(mine["cost"] / theirs["cost"] - 1)
            worst_cost = max(worst_cost, relative)
            passed = same_counts and relative <= COST_TOLERANCE_RELATIVE
            line = "intervals %d vs %d, cost %.9f vs %.9f (%.1e relative)" % (
                mine["intervals"], theirs["intervals"], mine["cost"], theirs["cost"], relative)
        checks.record("imu_tk k=%d" % mine["k"], passed, line)
    best = imu_tk["best"]
    checks.record("imu_tk chosen k", best["k"] == cc_tk["chosen_k"],
                  "%d vs %d" % (best["k"], cc_tk["chosen_k"]))
    mine_intervals = [[int(s), int(e)] for s, e in zip(best["starts"], best["ends"])]
    theirs_intervals = [[item["start"], item["end"]] for item in cc_tk["intervals"]]
    checks.record("imu_tk intervals", mine_intervals == theirs_intervals,
                  "%d intervals at k=%d, every start and end" % (len(mine_intervals), best["k"]))
    sigma = cc_ml["stddev"]
    worst = {"imu_tk": 0.0, "ml": 0.0, "stddev": 0.0}
    for i, name in enumerate(PARAMETER_NAMES):
        shift = abs(best["x"][i] - cc_tk["parameters"][name]) / sigma[name]
        worst["imu_tk"] = max(worst["imu_tk"], shift)
        checks.record("imu_tk " + name, shift <= IMU_TK_TOLERANCE_SIGMA,
                      "%+.9e vs %+.9e (%.1e ml sigma)" % (best["x"][i], cc_tk["parameters"][name],
                                                          shift))
    for i, name in enumerate(PARAMETER_NAMES):
        shift = abs(ml["x"][i] - cc_ml["parameters"][name]) / sigma[name]
        relative = abs(ml["stddev"][i] / sigma[name] - 1)
        worst["ml"] = max(worst["ml"], shift)
        worst["stddev"] = max(worst["stddev"], relative)
        checks.record("ml " + name,
                      shift <= ML_TOLERANCE_SIGMA and relative <= STDDEV_TOLERANCE_RELATIVE,
                      "%+.9e vs %+.9e (%.1e sigma), sigma %.6e vs %.6e (%.1e relative)"
                      % (ml["x"][i], cc_ml["parameters"][name], shift, ml["stddev"][i],
                         sigma[name], relative))
    relative = abs(ml["chi2"] / cc_ml["chi2"] - 1)
    checks.record("ml chi2", relative <= CHI2_TOLERANCE_RELATIVE and ml["dof"] == cc_ml["dof"],
                  "%.6f vs %.6f on %d dof (%.1e relative)" % (ml["chi2"], cc_ml["chi2"],
                                                              ml["dof"], relative))
    pooled = np.array(accelcal["ml"]["pooled_noise_variance"])
    relative = np.abs(ml["pooled_noise_variance"] / pooled - 1).max()
    checks.record("ml noise", relative <= 1e-9 and ml["pose_count"] == cc_ml["pose_count"],
                  "%d poses, pooled variance %s counts^2 (%.1e relative)"
                  % (ml["pose_count"], np.array2string(ml["pooled_noise_variance"],
                                                      precision=4), relative))
    worst["cost"] = worst_cost
    return worst


def format_seconds(seconds):
    return "%.2f ms" % (1e3 * seconds) if seconds < 1 else "%.3f s" % seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--log", required=True)
    parser.add_argument("--accelcal_json", required=True, help="triad_bench's JSON")
    parser.add_argument("--json", default="", help="where to write this side's results")
    parser.add_argument("--g", type=float, default=9.81744)
    parser.add_argument("--init_rest_s", type=float, default=50.0)
    parser.add_argument("--initial_offset", type=float, default=32768.0)
    parser.add_argument("--repetitions", type=int, default=11)
    parser.add_argument("--min_ratio", type=float, default=0.0,
                        help="exit 3 when numpy/SciPy's total over accelcal's is below this")
    arguments = parser.parse_args()
    if arguments.repetitions < 1:
        print("triad_scipy.py: --repetitions must be at least 1", file=sys.stderr)
        return 2
    try:
        with open(arguments.accelcal_json) as stream:
            accelcal = json.load(stream)
        timings = []
        for _ in range(arguments.repetitions):
            timing = {}
            t, u, imu_tk, ml = run_pipeline(arguments, timing)
            timings.append(timing)
    except (BadInput, OSError, ValueError) as error:
        print("triad_scipy.py: error: %s" % error, file=sys.stderr)
        return 2

    checks = Checks()
    print("triad_scipy.py: %s, %d samples; numpy %s" % (arguments.log, len(t), np.__version__))
    worst = compare(accelcal, t, imu_tk, ml, arguments.g, arguments.init_rest_s, checks)
    check_jacobians(u, imu_tk, ml, arguments.g, checks)

    stages = ["read", "imu_tk", "detect", "ml", "total"]
    scipy_median = {}
    accelcal_median = {}
    for clock, key, index in (("wall", "seconds_median", 0), ("cpu", "cpu_seconds_median", 1)):
        for stage in stages:
            scipy_median[clock, stage] = float(
                np.median([timing[stage][index] for timing in timings]))
            accelcal_median[clock, stage] = accelcal["timing"]["stages"][stage][key]
    ratio = {key: scipy_median[key] / accelcal_median[key] for key in scipy_median}
    print("\nmedian of %d (accelcal) and %d (numpy/SciPy) runs; wall time, and CPU time"
          % (accelcal["timing"]["repetitions"], arguments.repetitions))
    print("%-18s %12s %12s %7s   %12s %12s %7s" % ("stage", "accelcal", "numpy/SciPy", "ratio",
                                                  "accelcal CPU", "numpy CPU", "ratio"))
    labels = {"detect": "  of which detect", "imu_tk": "imu_tk (k=2..10)",
              "ml": "ml + covariance"}
    for stage in stages:
        print("%-18s %12s %12s %7.2f   %12s %12s %7.2f"
              % (labels.get(stage, stage), format_seconds(accelcal_median["wall", stage]),
                 format_seconds(scipy_median["wall", stage]), ratio["wall", stage],
                 format_seconds(accelcal_median["cpu", stage]),
                 format_seconds(scipy_median["cpu", stage]), ratio["cpu", stage]))
    print("\nagreement: imu_tk costs %.1e relative, imu_tk parameters %.1e ml sigma, ml "
          "parameters %.1e sigma, ml sigma %.1e relative"
          % (worst["cost"], worst["imu_tk"], worst["ml"], worst["stddev"]))
    if checks.failed:
        print("triad_scipy.py: %d check(s) failed" % checks.failed)
    else:
        print("speedup total=%.2f (wall), %.2f (CPU)" % (ratio["wall", "total"],
                                                        ratio["cpu", "total"]))
    floor = accelcal["timing"].get("floor")
    times = max(arguments.min_ratio, 1.0)
    if floor is not None:
        solves = floor["solves"]
        fastest = solves[floor["fastest_linear_solver"]]
        print("\nfloor of any pipeline that reads this file and makes imu_tk's %d solves with "
              "ceres::Solve (accelcal's side, this run)" % floor["solved_k"])
        print("  %-50s %12s %12s" % ("", "wall", "CPU"))
        rows = [("the file's %d bytes read, nothing parsed" % floor["file_bytes"],
                 floor["read_bytes_seconds"], floor["read_bytes_cpu_seconds"])]
        for name in sorted(solves):
            rows.append(("the %d Ceres solves, %s" % (floor["solved_k"], name),
                         solves[name]["seconds"], solves[name]["cpu_seconds"]))
        rows.append(("floor: bytes + the faster solves, one core", floor["seconds"],
                     floor["cpu_seconds"]))
        rows.append(("floor with the solves split over two cores", floor["seconds_two_cores"],
                     floor["read_bytes_cpu_seconds"] + 0.5 * fastest["cpu_seconds"]))
        rows.append(("%.0fx numpy/SciPy's total needs at most" % times,
                     scipy_median["wall", "total"] / times, scipy_median["cpu", "total"] / times))
        for label, wall, cpu in rows:
            print("  %-50s %12s %12s" % (label, format_seconds(wall), format_seconds(cpu)))
        bound_wall = scipy_median["wall", "total"] / floor["seconds"]
        bound_cpu = scipy_median["cpu", "total"] / floor["cpu_seconds"]
        print("on one core no Ceres pipeline can beat numpy/SciPy by more than %.2fx (wall), "
              "%.2fx (CPU) here, before parsing, detection and the ML fit" % (bound_wall, bound_cpu))
    if arguments.json:
        with open(arguments.json, "w") as stream:
            json.dump({"timing": {"%s_%s" % key: value for key, value in scipy_median.items()},
                       "ratio": {"%s_%s" % key: value for key, value in ratio.items()},
                       "agreement": worst, "failed_checks": checks.failed}, stream, indent=2)
    if checks.failed:
        return 1
    return 3 if ratio["wall", "total"] < arguments.min_ratio else 0


if __name__ == "__main__":
    sys.exit(main())
