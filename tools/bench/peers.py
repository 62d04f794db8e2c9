#!/usr/bin/python3
"""The numpy/SciPy side of tools/bench/peers.sh (issue 9): the same problems accelcal
solves, written as a careful researcher would write them with numpy and SciPy, timed
in-process and checked against accelcal's estimates (tools/bench/peer_timing.cc).

Run with Debian's /usr/bin/python3 (python3-numpy, python3-scipy). Two commands:

  peers.py run --data_dir=DIR [--calibration_file=FILE] --accelcal_json=cc.json --json=py.json
      loads the data (scipy.io.loadmat for .mat, numpy for CSV), times each problem (median
      of time.perf_counter over repetitions; loading is outside the clock), compares every
      estimate with accelcal's, prints PASS/FAIL per check and exits 1 on a disagreement.
  peers.py table course=py.json [simulated=py_sim.json ...]
      prints the side-by-side table and the line `speedup baseline=X joint=Y` (the ratios
      numpy/SciPy time / accelcal time on the data labelled course).

The problems, with the names, signs and units of ../shared/spec/error-model.md:

  baseline  per axis k, y_i = m_k,i - f_k,i = b_k + s_k f_k,i + noise, with
            f_x = -g sin(theta), f_y = -g cos(theta): numpy.linalg.lstsq on the design
            matrix [1, f] and the covariance sigma_k^2 (A^T A)^-1 from the *stated*
            variance (not rescaled by the residuals, as curve_fit's default would).
  joint     bias and scale plus angle_offset (delta) and/or nonorthogonality (eps), from
            the whitened tilt-test residuals of the full model
                r_x = (m_x - (1 + s_x) fx - b_x) / sigma_x,  fx = -g sin(theta + delta)
                r_y = (m_y - (1 + s_y) (fy cos eps + fx sin eps) - b_y) / sigma_y
            and the run's endpoint tied to a landmark: each run sample corrected,
            a = (m - b)/(1 + s) per axis, then ay = (ay' - ax sin eps)/cos eps, integrated
            twice by the trapezoidal rule from p0, v0; r_end = (p_end - landmark)/sd, with
            sd^2 = sum_j w_j^2 sigma_k^2 / (1 + s_k)^2 at the baseline's s_k (fixed, so that
            the cost stays a chi-square). scipy.optimize.least_squares, method 'trf',
            started from the lstsq baseline, either with the analytic Jacobian (below) or
            with every default (a 2-point finite-difference Jacobian); the covariance is
            inv(J^T J) from the solver's Jacobian at the solution.
"""

import argparse
import json
import math
import multiprocessing
import os
import re
import sys
import time

import numpy as np
import scipy
import scipy.io
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import least_squares

COURSE_GRAVITY = 9.8  # m/s^2, the course's g (datos.txt never states one)
BASELINE_NAMES = ["bias_x", "scale_x", "bias_y", "scale_y"]
SUPPORTED_EFFECTS = ["angle_offset", "nonorthogonality"]

# Agreement with accelcal. Both sides solve the same least-squares problem to convergence,
# so they may differ only by rounding and by where each iteration stops, far below the
# statistical uncertainty: a thousandth of a sigma is already invisible in any printed
# estimate, and a relative 1e-3 on sigma is the same standard for the uncertainty. Tighter
# would test the stopping rules rather than the model: with 10^7 samples the cost is 1e7,
# and Ceres' relative function tolerance (1e-14) stops about 1e-4 sigma short of the
# optimum in the weakly determined directions (measured with one more Gauss-Newton step).
VALUE_TOLERANCE_SIGMA = 1e-3
STDDEV_TOLERANCE_RELATIVE = 1e-3
# chi-square is flat at the optimum: parameters 1e-3 sigma apart change it by about 1e-6
# each.
# What remains is rounding in sums of up to 2e7 squares, hence the relative term.
CHI2_TOLERANCE_ABSOLUTE = 1e-3
CHI2_TOLERANCE_RELATIVE = 1e-9


# ---------------------------------------------------------------------------------------
# Loading (outside the clock)
# ---------------------------------------------------------------------------------------


def numbers_in_brackets(text):
    match = re.search(r"\[([^\]]*)\]", text)
    if match is None:
        raise ValueError("no [ ... ] in %r" % text)
    return [float(token) for token in match.group(1).replace(",", " ").split()]


def read_datos_txt(path):
    """Initial position, velocity and stated noise variances from the course's datos.txt."""
    raw = open(path, "rb").read()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    conditions = {}
    for line in text.splitlines():
        key = line.split("=", 1)[0].lower()
        if "=" not in line:
            continue
        if "posici" in key:
            conditions["initial_position"] = numbers_in_brackets(line)
        elif "velocidad" in key:
            conditions["initial_velocity"] = numbers_in_brackets(line)
        elif "varianza" in key:
            conditions["noise_variance"] = numbers_in_brackets(line)
    for key in ("initial_position", "initial_velocity", "noise_variance"):
        if key not in conditions:
            raise ValueError("%s: no %s" % (path, key))
    conditions["gravity"] = COURSE_GRAVITY
    return conditions


def read_calibration(path):
    if path.endswith(".mat"):
        mat = scipy.io.loadmat(path)
        theta = np.asarray(mat["tita"], dtype=float).ravel()
        datos = np.asarray(mat["datos"], dtype=float)
        return theta, datos[:, 0].copy(), datos[:, 1].copy()
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    return table[:, 0].copy(), table[:, 1].copy(), table[:, 2].copy()


def load(data_dir, calibration_file):
    """The four inputs of a data folder, course layout or CSV layout."""
    data = {}
    if os.path.exists(os.path.join(data_dir, "ensayo.mat")):
        calibration = os.path.join(data_dir, "ensayo.mat")
        run = scipy.io.loadmat(os.path.join(data_dir, "acel.mat"))
        key = "Aerr" if "Aerr" in run else "acel"
        data["t"] = np.asarray(run["t"], dtype=float).ravel()
        data["run_x"] = np.asarray(run[key], dtype=float)[:, 0].copy()
        data["run_y"] = np.asarray(run[key], dtype=float)[:, 1].copy()
        points = scipy.io.loadmat(os.path.join(data_dir, "puntos.mat"))
        data["landmarks"] = {
            name: np.asarray(value, dtype=float).ravel()
            for name, value in points.items()
            if not name.startswith("__")
        }
        data.update(read_datos_txt(os.path.join(data_dir, "datos.txt")))
    else:
        calibration = os.path.join(data_dir, "calibration.csv")
        run = np.loadtxt(os.path.join(data_dir, "trajectory.csv"), delimiter=",", skiprows=1)
        data["t"], data["run_x"], data["run_y"] = run[:, 0], run[:, 1].copy(), run[:, 2].copy()
        data["landmarks"] = {}
        with open(os.path.join(data_dir, "landmarks.csv")) as lines:
            next(lines)
            for line in lines:
                if line.strip():
                    name, x, y = line.strip().split(",")
                    data["landmarks"][name] = np.array([float(x), float(y)])
        with open(os.path.join(data_dir, "scenario.json")) as stream:
            scenario = json.load(stream)
        for key in ("initial_position", "initial_velocity", "noise_variance"):
            data[key] = scenario[key]
        data["gravity"] = scenario.get("gravity", COURSE_GRAVITY)
    if calibration_file:
        calibration = calibration_file
    data["theta"], data["m_x"], data["m_y"] = read_calibration(calibration)
    data["calibration_file"] = calibration
    return data


# ---------------------------------------------------------------------------------------
# The baseline: numpy.linalg.lstsq per axis
# ---------------------------------------------------------------------------------------


def fit_baseline(theta, m_x, m_y, g, variance_x, variance_y):
    """Bias and scale per axis by ordinary least squares, covariance sigma^2 (A^T A)^-1."""
    f_x = -g * np.sin(theta)
    f_y = -g * np.cos(theta)
    values = np.zeros(4)
    covariance = np.zeros((4, 4))
    chi2 = []
    for first, f, m, variance in ((0, f_x, m_x, variance_x), (2, f_y, m_y, variance_y)):
        design = np.column_stack([np.ones_like(f), f])
        coefficients, residual_sum, _, _ = np.linalg.lstsq(design, m - f, rcond=None)
        values[first : first + 2] = coefficients
        covariance[first : first + 2, first : first + 2] = variance * np.linalg.inv(
            design.T @ design
        )
        chi2.append(residual_sum[0] / variance)
    return values, covariance, chi2


# ---------------------------------------------------------------------------------------
# The joint problem: scipy.optimize.least_squares
# ---------------------------------------------------------------------------------------


def endpoint_weights(count, dt):
    """w_j with p_end = p0 + v0 T + sum_j w_j a_j under the trapezoidal rule applied twice.

    v_k = v0 + dt/2 sum_{j=1..k} (a_j + a_{j-1}) and p_end = p0 + sum_k c_k v_k, with
    c_k = dt (dt/2 at both ends). a_j enters v_k for every k >= j (if j >= 1) and for
    every k >= j + 1, each time with dt/2, so w_j = dt/2 (C_j [j >= 1] + C_{j+1}) with
    C_j = sum_{k >= j} c_k.
    """
    c = np.full(count, dt)
    c[0] = c[-1] = dt / 2
    tail = np.append(np.cumsum(c[::-1])[::-1], 0.0)  # C_0 .. C_count
    weights = dt / 2 * (tail[:-1] + tail[1:])
    weights[0] = dt / 2 * tail[1]
    return weights


def double_integral(acceleration, dt):
    """p_end - p0 - v0 T for a sampled acceleration: the spec's recursion, with SciPy."""
    velocity = cumulative_trapezoid(acceleration, dx=dt, initial=0.0)
    return np.trapz(velocity, dx=dt)


class JointProblem:
    """Whitened residuals and their Jacobian; x = (b_x, s_x, b_y, s_y, chosen effects)."""

    def __init__(self, data, effects, landmark, baseline_scale_x, baseline_scale_y):
        self.theta = data["theta"]
        self.m_x = data["m_x"]
        self.m_y = data["m_y"]
        self.g = data["gravity"]
        self.sigma_x = math.sqrt(data["noise_variance"][0])
        self.sigma_y = math.sqrt(data["noise_variance"][1])
        self.effects = effects
        self.run_x = data["run_x"]
        self.run_y = data["run_y"]
        t = data["t"]
        count = len(t)
        dt = (t[-1] - t[0]) / (count - 1)
        self.weights = endpoint_weights(count, dt)
        self.weight_sum = self.weights.sum()
        duration = dt * (count - 1)
        self.offset = (
            np.asarray(data["initial_position"], dtype=float)
            + np.asarray(data["initial_velocity"], dtype=float) * duration
            - data["landmarks"][landmark]
        )
        # The run's noise through the double integration, at the baseline's scale factors.
        noise = (self.weights**2).sum()
        self.endpoint_sd = np.sqrt(
            noise
            * np.array(
                [
                    data["noise_variance"][0] / (1 + baseline_scale_x) ** 2,
                    data["noise_variance"][1] / (1 + baseline_scale_y) ** 2,
                ]
            )
        )

    def unpack(self, x):
        delta = x[4 + self.effects.index("angle_offset")] if "angle_offset" in self.effects else 0.0
        eps = (
            x[4 + self.effects.index("nonorthogonality")]
            if "nonorthogonality" in self.effects
            else 0.0
        )
        return x[0], x[1], x[2], x[3], delta, eps

    def parts(self, x):
        bias_x, scale_x, bias_y, scale_y, delta, eps = self.unpack(x)
        f_x = -self.g * np.sin(self.theta + delta)
        f_y = -self.g * np.cos(self.theta + delta)
        along_y = f_y * math.cos(eps) + f_x * math.sin(eps)
        r_x = (self.m_x - (1 + scale_x) * f_x - bias_x) / self.sigma_x
        r_y = (self.m_y - (1 + scale_y) * along_y - bias_y) / self.sigma_y
        # The endpoint is linear in the corrected accelerations, so the non-orthogonal
        # projection can be undone on the two weighted sums instead of per sample.
        sum_x = self.weights @ ((self.run_x - bias_x) / (1 + scale_x))
        sum_along_y = self.weights @ ((self.run_y - bias_y) / (1 + scale_y))
        sum_y = (sum_along_y - sum_x * math.sin(eps)) / math.cos(eps)
        r_end = (np.array([sum_x, sum_y]) + self.offset) / self.endpoint_sd
        return f_x, f_y, r_x, r_y, r_end, sum_x, sum_along_y

    def residuals(self, x):
        _, _, r_x, r_y, r_end, _, _ = self.parts(x)
        return np.concatenate([r_x, r_y, r_end])

    def jacobian(self, x):
        bias_x, scale_x, bias_y, scale_y, delta, eps = self.unpack(x)
        f_x, f_y, _, _, _, sum_x, sum_along_y = self.parts(x)
        n = len(self.theta)
        jacobian = np.zeros((2 * n + 2, 4 + len(self.effects)))
        rows_x = slice(0, n)
        rows_y = slice(n, 2 * n)
        cos_eps, sin_eps = math.cos(eps), math.sin(eps)
        jacobian[rows_x, 0] = -1 / self.sigma_x
        jacobian[rows_x, 1] = -f_x / self.sigma_x
        jacobian[rows_y, 2] = -1 / self.sigma_y
        jacobian[rows_y, 3] = -(f_y * cos_eps + f_x * sin_eps) / self.sigma_y
        # d f_x / d delta = f_y, d f_y / d delta = -f_x.
        for k, effect in enumerate(self.effects):
            column = 4 + k
            if effect == "angle_offset":
                jacobian[rows_x, column] = -(1 + scale_x) * f_y / self.sigma_x
                jacobian[rows_y, column] = (
                    -(1 + scale_y) * (-f_x * cos_eps + f_y * sin_eps) / self.sigma_y
                )
            elif effect == "nonorthogonality":
                jacobian[rows_y, column] = (
                    -(1 + scale_y) * (-f_y * sin_eps + f_x * cos_eps) / self.sigma_y
                )
        # Endpoint: d sum_x / d b_x = -W/(1 + s_x), d sum_x / d s_x = -sum_x/(1 + s_x),
        # likewise for y before the projection is undone.
        d_sum_x = np.array([-self.weight_sum, -sum_x]) / (1 + scale_x)
        d_sum_along_y = np.array([-self.weight_sum, -sum_along_y]) / (1 + scale_y)
        end_x, end_y = 2 * n, 2 * n + 1
        jacobian[end_x, 0:2] = d_sum_x / self.endpoint_sd[0]
        jacobian[end_y, 0:2] = -d_sum_x * sin_eps / cos_eps / self.endpoint_sd[1]
        jacobian[end_y, 2:4] = d_sum_along_y / cos_eps / self.endpoint_sd[1]
        if "nonorthogonality" in self.effects:
            column = 4 + self.effects.index("nonorthogonality")
            jacobian[end_y, column] = (
                (sum_along_y * sin_eps - sum_x) / cos_eps**2 / self.endpoint_sd[1]
            )
        return jacobian


# The two ways a researcher would call least_squares: with the analytic Jacobian above and
# tight tolerances (the defaults, 1e-8, already stop within 1e-7 sigma here, but the
# comparison should be limited by rounding, as accelcal's 1e-14 is), or with every default
# (method 'trf', a 2-point finite-difference Jacobian, tolerances 1e-8).
JACOBIANS = {
    "analytic": {"ftol": 1e-12, "xtol": 1e-12, "gtol": 1e-12},
    "2-point": {},
}


def fit_joint(data, effects, landmark, jacobian_kind):
    """The joint solve with covariance, from the loaded arrays (as SolveJoint does)."""
    variance_x, variance_y = data["noise_variance"]
    start, _, _ = fit_baseline(
        data["theta"], data["m_x"], data["m_y"], data["gravity"], variance_x, variance_y
    )
    problem = JointProblem(data, effects, landmark, start[1], start[3])
    x0 = np.concatenate([start, np.zeros(len(effects))])
    jac = problem.jacobian if jacobian_kind == "analytic" else jacobian_kind
    solution = least_squares(
        problem.residuals, x0, jac=jac, method="trf", **JACOBIANS[jacobian_kind]
    )
    jacobian = solution.jac
    covariance = np.linalg.inv(jacobian.T @ jacobian)
    _, _, r_x, r_y, r_end, _, _ = problem.parts(solution.x)
    # Only what the checks need: the solution's Jacobian would be 2N x p doubles.
    return {
        "x": solution.x,
        "covariance": covariance,
        "chi2": {"chi2_x": r_x @ r_x, "chi2_y": r_y @ r_y, "chi2_endpoint": r_end @ r_end},
        "evaluations": {"residuals": int(solution.nfev), "jacobian": int(solution.njev or 0)},
    }


# ---------------------------------------------------------------------------------------
# Timing and checks
# ---------------------------------------------------------------------------------------


def time_repeatedly(solve, repetitions, budget_s):
    """Times at most `repetitions` calls with time.perf_counter (fewer once `budget_s` is
    spent; at least one). Returns (result of the last call, list of seconds)."""
    seconds = []
    result = None
    for repetition in range(repetitions):
        if repetition > 0 and sum(seconds) >= budget_s:
            break
        start = time.perf_counter()
        result = solve()
        seconds.append(time.perf_counter() - start)
    return result, seconds


def time_with_limit(solve, repetitions, budget_s, limit_s):
    """time_repeatedly in a forked child, given up after `limit_s` seconds (None then).

    A solve that would take longer than the whole comparison is allowed cannot be stopped
    from inside SciPy; a forked child shares the loaded arrays without copying them and can
    be terminated. The clock still runs inside the process doing the work."""
    context = multiprocessing.get_context("fork")
    receiver, sender = context.Pipe(duplex=False)
    child = context.Process(
        target=lambda: sender.send(time_repeatedly(solve, repetitions, budget_s))
    )
    child.start()
    result = receiver.recv() if receiver.poll(limit_s) else None
    if result is None:
        child.terminate()
    child.join()
    return result


def timing_json(seconds):
    return {
        "seconds_median": float(np.median(seconds)),
        "seconds": seconds,
        "repetitions": len(seconds),
    }


class Checks:
    """PASS/FAIL lines, and the worst agreement seen per problem for the table."""

    def __init__(self):
        self.failed = 0
        self.worst = {}

    def record(self, problem, what, passed, line):
        passed = bool(passed)
        print("  %s  %-36s %s" % ("PASS" if passed else "FAIL", problem + " " + what, line))
        if not passed:
            self.failed += 1
        return passed

    def note(self, problem, shift_sigma, stddev_relative, passed):
        previous = self.worst.get(problem, (0.0, 0.0, True))
        self.worst[problem] = (
            max(previous[0], shift_sigma),
            max(previous[1], stddev_relative),
            previous[2] and passed,
        )

    def estimate(self, problem, names, values, covariance, reference):
        for i, name in enumerate(names):
            sigma_accelcal = reference["stddev"][name]
            shift = abs(values[i] - reference["parameters"][name]) / sigma_accelcal
            stddev = math.sqrt(covariance[i, i])
            relative = abs(stddev / sigma_accelcal - 1)
            passed = self.record(
                problem,
                name,
                shift <= VALUE_TOLERANCE_SIGMA and relative <= STDDEV_TOLERANCE_RELATIVE,
                "value %+.10e vs %+.10e (%.1e sigma), sigma %.6e vs %.6e (%.1e relative)"
                % (values[i], reference["parameters"][name], shift, stddev, sigma_accelcal,
                   relative),
            )
            self.note(problem, shift, relative, passed)

    def chi2(self, problem, name, value, reference):
        difference = abs(value - reference)
        passed = self.record(
            problem,
            name,
            difference <= CHI2_TOLERANCE_ABSOLUTE + CHI2_TOLERANCE_RELATIVE * abs(reference),
            "%.6f vs %.6f (difference %.1e)" % (value, reference, difference),
        )
        self.note(problem, 0.0, 0.0, passed)


def blas_library():
    """The BLAS/LAPACK numpy really uses (Debian's alternatives choose it at run time)."""
    try:
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "blas" in line or "lapack" in line}
    except OSError:
        return "unknown"
    names = sorted(
        {
            os.path.realpath(path)
            for path in paths
            if path.startswith("/") and "python3" not in path and ".cpython-" not in path
        }
    )
    return ", ".join(os.path.basename(os.path.dirname(name)) + "/" + os.path.basename(name)
                     for name in names) or "unknown"


def subsample(data, count):
    """Every k-th tilt-test sample, at most `count` of them (for the Jacobian self-check)."""
    step = max(1, len(data["theta"]) // count)
    smaller = dict(data)
    for key in ("theta", "m_x", "m_y"):
        smaller[key] = data[key][::step]
    return smaller


def check_jacobian(data, effects, landmark, reference, checks):
    """The analytic Jacobian against central differences at accelcal's solution."""
    data = subsample(data, 20001)
    variance_x, variance_y = data["noise_variance"]
    start, _, _ = fit_baseline(data["theta"], data["m_x"], data["m_y"], data["gravity"],
                               variance_x, variance_y)
    problem = JointProblem(data, effects, landmark, start[1], start[3])
    at = np.array([reference["parameters"][name] for name in BASELINE_NAMES + effects])
    analytic = problem.jacobian(at)
    numeric = np.empty_like(analytic)
    for column in range(len(at)):
        step = np.zeros_like(at)
        step[column] = 1e-6 * max(1.0, abs(at[column]))
        numeric[:, column] = (problem.residuals(at + step) - problem.residuals(at - step)) / (
            2 * step[column]
        )
    error = np.abs(analytic - numeric).max() / np.abs(analytic).max()
    checks.record("self-check", "analytic jacobian", error <= 1e-6,
                  "largest difference from central differences %.1e (of the largest entry)"
                  % error)


def run(arguments):
    with open(arguments.accelcal_json) as stream:
        accelcal = json.load(stream)
    data = load(arguments.data_dir, arguments.calibration_file)
    effects = [name for name in arguments.effects.split(",") if name]
    for effect in effects:
        if effect not in SUPPORTED_EFFECTS:
            sys.exit("peers.py: effect %s is not implemented here (only %s)"
                     % (effect, ", ".join(SUPPORTED_EFFECTS)))
    jacobians = [kind for kind in arguments.jacobians.split(",") if kind]
    for kind in jacobians:
        if kind not in JACOBIANS:
            sys.exit("peers.py: --jacobians takes %s, got %s" % (", ".join(JACOBIANS), kind))
    g = data["gravity"]
    variance_x, variance_y = data["noise_variance"]
    n = len(data["theta"])
    checks = Checks()
    print("peers.py: %s (%d tilt samples)" % (data["calibration_file"], n))

    # The same data on both sides, or every comparison below is meaningless.
    same = (
        accelcal["data"]["tilt_samples"] == n
        and accelcal["data"]["run_samples"] == len(data["t"])
        and accelcal["data"]["gravity"] == g
        and accelcal["data"]["noise_variance"] == [variance_x, variance_y]
    )
    checks.record("data", "", same, "accelcal read the same sample counts, g and variances")

    # The closed-form endpoint weights against SciPy's own trapezoidal integration
    # (outside the clock).
    t = data["t"]
    dt = (t[-1] - t[0]) / (len(t) - 1)
    by_weights = endpoint_weights(len(t), dt) @ data["run_x"]
    by_scipy = double_integral(data["run_x"], dt)
    checks.record(
        "self-check", "endpoint weights",
        abs(by_weights - by_scipy) <= 1e-9 * max(1.0, abs(by_scipy)),
        "sum w_j a_j = %.9f m, cumulative_trapezoid + trapz = %.9f m" % (by_weights, by_scipy),
    )

    output = {
        "data": {"calibration_file": data["calibration_file"], "tilt_samples": n},
        "timing": {
            "clock": "time.perf_counter",
            "statistic": "median over repetitions",
            "excludes": "interpreter start-up, imports and loading the files",
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "blas": blas_library(),
        },
        "problems": {},
    }
    problems = accelcal["problems"]

    if "baseline_closed_form" in problems or "baseline_ceres" in problems:
        (values, covariance, chi2), seconds = time_repeatedly(
            lambda: fit_baseline(data["theta"], data["m_x"], data["m_y"], g, variance_x,
                                 variance_y),
            arguments.repetitions,
            arguments.time_budget,
        )
        output["problems"]["baseline"] = {
            "solver": "numpy.linalg.lstsq per axis, covariance sigma^2 inv(A^T A)",
            "parameters": dict(zip(BASELINE_NAMES, values.tolist())),
            "stddev": dict(zip(BASELINE_NAMES, np.sqrt(np.diag(covariance)).tolist())),
            "timing": timing_json(seconds),
        }
        for name in ("baseline_closed_form", "baseline_ceres"):
            if name in problems:
                checks.estimate(name, BASELINE_NAMES, values, covariance, problems[name])
                checks.chi2(name, "chi2_x", chi2[0], problems[name]["chi2_x"])
                checks.chi2(name, "chi2_y", chi2[1], problems[name]["chi2_y"])

    if "joint" in problems and jacobians:
        reference = problems["joint"]
        same_problem = (reference["effects"] == ",".join(effects)
                        and reference["landmark"] == arguments.landmark)
        checks.record("joint", "problem", same_problem,
                      "accelcal solved effects %s tied to %s"
                      % (reference["effects"], reference["landmark"]))
        if "analytic" in jacobians:
            check_jacobian(data, effects, arguments.landmark, reference, checks)
        names = BASELINE_NAMES + effects
        for kind in jacobians:
            key = "joint" if kind == "analytic" else "joint_" + kind.replace("-", "")
            timed = time_with_limit(
                lambda: fit_joint(data, effects, arguments.landmark, kind),
                arguments.repetitions,
                arguments.time_budget,
                arguments.joint_time_limit,
            )
            if timed is None:
                reason = "took over %g s" % arguments.joint_time_limit
                output["problems"][key] = {"skipped": reason}
                print("  SKIP  %-36s %s" % (key, reason))
                continue
            fit, seconds = timed
            output["problems"][key] = {
                "solver": "scipy.optimize.least_squares(method='trf', jac=%s), "
                "covariance inv(J^T J)" % kind,
                "parameters": dict(zip(names, fit["x"].tolist())),
                "stddev": dict(zip(names, np.sqrt(np.diag(fit["covariance"])).tolist())),
                "evaluations": fit["evaluations"],
                "timing": timing_json(seconds),
            }
            checks.estimate(key, names, fit["x"], fit["covariance"], reference)
            for name in ("chi2_x", "chi2_y", "chi2_endpoint"):
                checks.chi2(key, name, fit["chi2"][name], reference[name])

    output["agreement"] = {
        problem: {"max_value_shift_sigma": worst[0], "max_stddev_relative": worst[1],
                  "passed": worst[2]}
        for problem, worst in checks.worst.items()
    }
    output["failed_checks"] = checks.failed
    with open(arguments.json, "w") as stream:
        json.dump({"accelcal": accelcal, "peers": output}, stream, indent=2)
    if checks.failed:
        print("peers.py: %d check(s) FAILED" % checks.failed)
        return 1
    return 0


# ---------------------------------------------------------------------------------------
# The side-by-side table
# ---------------------------------------------------------------------------------------


def format_seconds(seconds):
    if seconds < 1e-3:
        return "%.1f us" % (seconds * 1e6)
    if seconds < 1.0:
        return "%.2f ms" % (seconds * 1e3)
    return "%.2f s" % seconds


# (accelcal's problem, its solver, the peer's problem, the peer's solver)
ROWS = (
    ("baseline_closed_form", "baseline, closed form", "baseline", "numpy lstsq"),
    ("baseline_ceres", "baseline, Ceres", "baseline", "numpy lstsq"),
    ("joint", "joint, Ceres", "joint", "least_squares analytic J"),
    ("joint", "joint, Ceres", "joint_2point", "least_squares 2-point J"),
)


def table(arguments):
    rows = []
    speedup = {}
    header = None
    disagreements = 0
    for labelled in arguments.results:
        label, _, path = labelled.partition("=")
        with open(path) as stream:
            result = json.load(stream)
        accelcal, peers = result["accelcal"]["problems"], result["peers"]
        header = header or peers["timing"]
        if label == arguments.speedup_label:
            disagreements = peers["failed_checks"]
        data = "%s, N=%d" % (label, peers["data"]["tilt_samples"])
        for accelcal_name, accelcal_solver, peer_name, peer_solver in ROWS:
            if accelcal_name not in accelcal or peer_name not in peers["problems"]:
                continue
            accelcal_timing = accelcal[accelcal_name]["timing"]
            accelcal_s = accelcal_timing["seconds_median"]
            peer = peers["problems"][peer_name]
            row = ["%s / %s" % (accelcal_solver, peer_solver), data,
                   "%s (%d)" % (format_seconds(accelcal_s), accelcal_timing["repetitions"])]
            if "timing" in peer:
                peer_s = peer["timing"]["seconds_median"]
                ratio = peer_s / accelcal_s
                # The peer's estimates are checked against accelcal's solver of this row.
                check_key = accelcal_name if peer_name == "baseline" else peer_name
                worst = peers["agreement"][check_key]
                row += [
                    "%s (%d)" % (format_seconds(peer_s), peer["timing"]["repetitions"]),
                    "%.3g" % ratio,
                    "%s %.0e sigma, %.0e rel" % ("PASS" if worst["passed"] else "FAIL",
                                                 worst["max_value_shift_sigma"],
                                                 worst["max_stddev_relative"]),
                ]
                if label == arguments.speedup_label and peer_name in ("baseline", "joint"):
                    if accelcal_name in ("baseline_closed_form", "joint"):
                        speedup[peer_name] = ratio
            else:
                row += ["skipped", "-", "not run: " + peer["skipped"]]
            rows.append(row)

    print("Time per solve: the median of in-process repetitions (their count in parentheses),")
    print("excluding interpreter start-up, imports and file loading. accelcal: C++ Release,")
    print("1 thread, std::chrono::steady_clock. numpy %s, SciPy %s: time.perf_counter;"
          % (header["numpy"], header["scipy"]))
    print("BLAS/LAPACK %s." % header["blas"])
    print("ratio = numpy/SciPy time / accelcal time (> 1: accelcal faster).")
    print("agreement: the largest estimate difference in accelcal's sigmas and the largest")
    print("relative difference of sigma, against tolerances 1e-3 and 1e-3 (and chi-square).")
    print()
    titles = ("problem: accelcal / numpy-scipy", "data", "accelcal", "numpy/scipy", "ratio",
              "agreement")
    widths = [max(len(titles[i]), *(len(row[i]) for row in rows)) for i in range(len(titles))]
    print("  ".join("%-*s" % (widths[i], titles[i]) for i in range(len(titles))).rstrip())
    print("  ".join("-" * width for width in widths))
    for row in rows:
        print("  ".join("%-*s" % (widths[i], row[i]) for i in range(len(titles))).rstrip())
    print()
    if disagreements:
        sys.exit("peers.py table: no speedup line: %d check(s) failed on the %s data, so the "
                 "two sides did not solve the same problem" % (disagreements,
                                                               arguments.speedup_label))
    if "baseline" not in speedup or "joint" not in speedup:
        sys.exit("peers.py table: the %s results lack the baseline or the joint timing"
                 % arguments.speedup_label)
    print("speedup baseline=%.3g joint=%.3g" % (speedup["baseline"], speedup["joint"]))
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run_parser = commands.add_parser("run", help="time and check one data set")
    run_parser.add_argument("--data_dir", required=True)
    run_parser.add_argument("--calibration_file", default="",
                            help="a tilt test replacing the folder's (.mat or .csv)")
    run_parser.add_argument("--accelcal_json", required=True, help="peer_timing's JSON")
    run_parser.add_argument("--json", required=True, help="where to write both sides' results")
    run_parser.add_argument("--repetitions", type=int, default=11)
    run_parser.add_argument("--time_budget", type=float, default=30.0,
                            help="stop repeating a problem after this many seconds")
    run_parser.add_argument("--effects", default="angle_offset,nonorthogonality")
    run_parser.add_argument("--landmark", default="C")
    run_parser.add_argument("--jacobians", default="analytic,2-point",
                            help="joint solves to time: analytic, 2-point (comma-separated; "
                            "empty: none)")
    run_parser.add_argument("--joint_time_limit", type=float, default=240.0,
                            help="give up a joint solve after this many seconds; the table "
                            "says it was skipped")
    table_parser = commands.add_parser("table", help="print the side-by-side table")
    table_parser.add_argument("--speedup_label", default="course",
                              help="the data whose ratios make the speedup line")
    table_parser.add_argument("results", nargs="+", metavar="LABEL=FILE",
                              help="a run's --json, labelled for the table's data column")
    arguments = parser.parse_args()
    return run(arguments) if arguments.command == "run" else table(arguments)


if __name__ == "__main__":
    sys.exit(main())
