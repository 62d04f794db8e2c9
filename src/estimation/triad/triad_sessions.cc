#include "estimation/triad/triad_sessions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/format.h"
#include "common/statistics.h"
#include "estimation/statistics/chi_square.h"

namespace accelcal {
namespace {

double QStatistic(const std::vector<std::vector<SessionEstimate>>& groups, double tau2) {
  double q = 0.0;
  for (const std::vector<SessionEstimate>& group : groups) {
    double sum_w = 0.0, sum_wx = 0.0;
    for (const SessionEstimate& s : group) {
      const double w = 1.0 / (tau2 + s.variance);
      sum_w += w;
      sum_wx += w * s.value;
    }
    const double mu = sum_wx / sum_w;
    for (const SessionEstimate& s : group)
      q += (s.value - mu) * (s.value - mu) / (tau2 + s.variance);
  }
  return q;
}

// The tau^2 >= 0 with Q(tau^2) = target (Q decreases in tau^2), 0 when Q(0) <= target.
double SolveQ(const std::vector<std::vector<SessionEstimate>>& groups, double target) {
  if (QStatistic(groups, 0.0) <= target) return 0.0;
  // Q(tau^2) <= (sum of squares about the plain means) / tau^2, so this bracket holds.
  double spread = 0.0, smallest_variance = std::numeric_limits<double>::infinity();
  for (const std::vector<SessionEstimate>& group : groups) {
    double mean = 0.0;
    for (const SessionEstimate& s : group) mean += s.value / group.size();
    for (const SessionEstimate& s : group) {
      spread += (s.value - mean) * (s.value - mean);
      smallest_variance = std::min(smallest_variance, s.variance);
    }
  }
  double low = 0.0, high = std::max(spread / target, smallest_variance);
  while (QStatistic(groups, high) > target) high *= 2.0;
  for (int i = 0; i < 200 && high - low > 1e-14 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (QStatistic(groups, middle) > target ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

}  // namespace

Status EstimateBetweenSessionVariance(const std::vector<std::vector<SessionEstimate>>& groups,
                                      double confidence, BetweenSessionVariance* between) {
  if (!(confidence > 0.0 && confidence < 1.0))
    return Status::Error("confidence " + std::to_string(confidence) + " is not in (0, 1)");
  if (groups.empty()) return Status::Error("no device's sessions to combine");
  double dof = 0.0;
  for (size_t g = 0; g < groups.size(); ++g) {
    if (groups[g].size() < 2) {
      return Status::Error("device " + std::to_string(g + 1) + " has " +
                           std::to_string(groups[g].size()) +
                           " session(s); a between-session variance needs at least 2");
    }
    for (const SessionEstimate& s : groups[g]) {
      if (!std::isfinite(s.value) || !(s.variance > 0.0) || !std::isfinite(s.variance)) {
        return Status::Error("a session's estimate or its variance is not finite and positive");
      }
    }
    dof += groups[g].size() - 1.0;
  }
  *between = BetweenSessionVariance();
  between->confidence = confidence;
  between->degrees_of_freedom = dof;
  between->q_at_zero = QStatistic(groups, 0.0);
  between->homogeneity_p = ChiSquareSurvival(between->q_at_zero, dof);
  between->variance = SolveQ(groups, dof);
  between->stddev = std::sqrt(between->variance);
  const double alpha = 1.0 - confidence;
  between->stddev_low = std::sqrt(SolveQ(groups, ChiSquareQuantile(1.0 - alpha / 2.0, dof)));
  between->stddev_high = std::sqrt(SolveQ(groups, ChiSquareQuantile(alpha / 2.0, dof)));
  return Status::Ok();
}

RandomEffectsEstimate CombineSessions(const std::vector<SessionEstimate>& sessions,
                                      const BetweenSessionVariance& between) {
  RandomEffectsEstimate estimate;
  estimate.session_count = static_cast<int>(sessions.size());
  estimate.between = between;
  double sum_w = 0.0, sum_wx = 0.0, sum_c = 0.0;
  for (const SessionEstimate& s : sessions) {
    const double w = 1.0 / (between.variance + s.variance);
    sum_w += w;
    sum_wx += w * s.value;
    sum_c += s.variance;
  }
  const double mean_within = sum_c / sessions.size();
  estimate.common = sum_wx / sum_w;
  estimate.common_stddev = std::sqrt(1.0 / sum_w);
  estimate.within_stddev = std::sqrt(mean_within);
  estimate.new_session_stddev = std::sqrt(between.variance + mean_within + 1.0 / sum_w);
  estimate.interval_multiplier =
      StudentTQuantile(0.5 * (1.0 + between.confidence), between.degrees_of_freedom);
  return estimate;
}

Status EstimateRandomEffects(const std::vector<SessionEstimate>& sessions, double confidence,
                             RandomEffectsEstimate* estimate) {
  BetweenSessionVariance between;
  ACCELCAL_RETURN_IF_ERROR(EstimateBetweenSessionVariance({sessions}, confidence, &between));
  *estimate = CombineSessions(sessions, between);
  return Status::Ok();
}

Status EstimateArraySessionVariance(const std::vector<std::vector<SessionEstimate>>& devices,
                                    ArraySessionVariance* array) {
  const size_t device_count = devices.size();
  if (device_count < 2) return Status::Error("an array's session variance needs 2 devices");
  const size_t session_count = devices[0].size();
  if (session_count < 2) return Status::Error("an array's session variance needs 2 sessions");
  std::vector<std::vector<double>> deviation(device_count);
  double mean_within = 0.0;
  for (size_t d = 0; d < device_count; ++d) {
    if (devices[d].size() != session_count)
      return Status::Error("every device of an array needs the same sessions");
    double mean = 0.0;
    for (const SessionEstimate& s : devices[d]) mean += s.value / session_count;
    for (const SessionEstimate& s : devices[d]) {
      deviation[d].push_back(s.value - mean);
      mean_within += s.variance / (device_count * session_count);
    }
  }
  double sum_common = 0.0, sum_rest = 0.0, sum_all = 0.0;
  for (size_t s = 0; s < session_count; ++s) {
    double common = 0.0;
    for (size_t d = 0; d < device_count; ++d) common += deviation[d][s] / device_count;
    sum_common += device_count * common * common;
    for (size_t d = 0; d < device_count; ++d) {
      sum_rest += (deviation[d][s] - common) * (deviation[d][s] - common);
      sum_all += deviation[d][s] * deviation[d][s];
    }
  }
  const double dof_session = session_count - 1.0;
  const double dof_device = (device_count - 1.0) * dof_session;
  const double ms_session = sum_common / dof_session;
  const double ms_device = sum_rest / dof_device;
  const double a1 = 1.0 / device_count, a2 = 1.0 - a1;
  const double total = a1 * ms_session + a2 * ms_device;
  *array = ArraySessionVariance();
  array->common_variance = std::max(0.0, (ms_session - ms_device) / device_count);
  array->device_variance = std::max(0.0, ms_device - mean_within);
  array->common_share = sum_all > 0.0 ? sum_common / sum_all : 0.0;
  array->total_variance = std::max(total, mean_within);
  const double denominator = (a1 * ms_session) * (a1 * ms_session) / dof_session +
                             (a2 * ms_device) * (a2 * ms_device) / dof_device;
  // All deviations zero: nothing was estimated, and the floor (known within variance) holds.
  array->degrees_of_freedom = denominator > 0.0 ? total * total / denominator : 1e9;
  return Status::Ok();
}

Status CheckSessionDrift(const std::vector<std::vector<SessionEstimate>>& by_parameter,
                         double level, SessionDriftCheck* check) {
  *check = SessionDriftCheck();
  check->level = level;
  check->parameter_count = static_cast<int>(by_parameter.size());
  if (!(level > 0.0 && level < 1.0))
    return Status::Error("the drift check's level " + std::to_string(level) + " is not in (0, 1)");
  if (by_parameter.empty()) return Status::Error("no parameter to check for drift");
  const size_t session_count = by_parameter[0].size();
  for (const std::vector<SessionEstimate>& sessions : by_parameter) {
    if (sessions.size() != session_count)
      return Status::Error("every parameter of the drift check needs the same sessions");
  }
  if (session_count < 3) {
    check->not_checked =
        "leaving one session out needs 3 sessions or more (2 others to "
        "estimate the between-session sigma from); " +
        std::to_string(session_count) + " given";
    return Status::Ok();
  }
  check->checked = true;
  check->parameter_level = level / check->parameter_count;
  check->degrees_of_freedom = session_count - 2.0;
  check->multiplier =
      StudentTQuantile(1.0 - 0.5 * check->parameter_level, check->degrees_of_freedom);
  for (size_t s = 0; s < session_count; ++s) {
    SessionDrift drift;
    drift.session = static_cast<int>(s);
    for (int p = 0; p < check->parameter_count; ++p) {
      std::vector<SessionEstimate> others;
      for (size_t o = 0; o < session_count; ++o) {
        if (o != s) others.push_back(by_parameter[p][o]);
      }
      RandomEffectsEstimate estimate;
      ACCELCAL_RETURN_IF_ERROR(EstimateRandomEffects(others, 0.95, &estimate));
      SessionDeviation deviation;
      deviation.parameter = p;
      deviation.value = by_parameter[p][s].value;
      deviation.others_common = estimate.common;
      deviation.others_new_session_stddev = estimate.new_session_stddev;
      deviation.deviation = (deviation.value - estimate.common) / estimate.new_session_stddev;
      deviation.p_value =
          2.0 * (1.0 - StudentTCdf(std::fabs(deviation.deviation), check->degrees_of_freedom));
      if (p == 0 || deviation.p_value < drift.largest.p_value) drift.largest = deviation;
      if (deviation.p_value < check->parameter_level) drift.outside.push_back(deviation);
    }
    if (drift.drifting()) check->drifting.push_back(drift.session);
    check->sessions.push_back(drift);
  }
  return Status::Ok();
}

std::vector<SessionEstimate> SessionEstimatesOf(const std::vector<TriadMlResult>& sessions,
                                                int index) {
  std::vector<SessionEstimate> estimates;
  for (const TriadMlResult& ml : sessions)
    estimates.push_back({ml.parameters[index], ml.covariance[index][index]});
  return estimates;
}

namespace {

// A device's gain moves by well under 1% between sessions and its offset by far less than
// 1 m/s^2; sessions that differ by more are not one device (or not in one unit).
constexpr double kMaxGainChange = 0.05;              // relative, from the sessions' median
constexpr double kMaxOffsetChangeMps2 = 0.5 * 9.81;  // half of g

Status CheckOneDevice(const std::vector<TriadMlResult>& sessions) {
  for (int k = 0; k < 3; ++k) {
    std::vector<double> gains;
    std::vector<double> offsets;
    for (const TriadMlResult& session : sessions) {
      gains.push_back(session.parameters[kTriadGainX + k]);
      offsets.push_back(session.parameters[kTriadOffsetX + k]);
    }
    const double gain = UpperMedian(gains);
    const double offset = UpperMedian(offsets);
    for (size_t s = 0; s < sessions.size(); ++s) {
      const double gain_change = std::abs(gains[s] - gain) / std::abs(gain);
      const double offset_change_mps2 = std::abs(offsets[s] - offset) * std::abs(gain);
      if (gain_change <= kMaxGainChange && offset_change_mps2 <= kMaxOffsetChangeMps2) continue;
      const bool gain_off = gain_change > kMaxGainChange;
      return Status::Error(StringPrintf(
          "session %zu is not the same device as the others: its %s is %.6g against the "
          "sessions' median %.6g (%s), where one device's gain moves by well under 1%% and its "
          "offset by far less than 1 m/s^2 between sessions; give sessions of one device, "
          "logged in one unit",
          s + 1, TriadParameterInfos()[(gain_off ? kTriadGainX : kTriadOffsetX) + k].name,
          gain_off ? gains[s] : offsets[s], gain_off ? gain : offset,
          (gain_off ? StringPrintf("%.3g%% apart", 100.0 * gain_change)
                    : StringPrintf("%.3g m/s^2 apart", offset_change_mps2))
              .c_str()));
    }
  }
  return Status::Ok();
}

}  // namespace

std::vector<std::vector<SessionEstimate>> TriadSessionEstimates(
    const std::vector<TriadMlResult>& sessions) {
  std::vector<std::vector<SessionEstimate>> by_parameter;
  for (int p = 0; p < kTriadParameterCount; ++p)
    by_parameter.push_back(SessionEstimatesOf(sessions, p));
  return by_parameter;
}

Status CombineTriadSessions(const std::vector<TriadMlResult>& sessions, double confidence,
                            TriadRandomEffects* combined) {
  ACCELCAL_RETURN_IF_ERROR(CheckOneDevice(sessions));
  for (int p = 0; p < kTriadParameterCount; ++p) {
    ACCELCAL_RETURN_IF_ERROR(
        EstimateRandomEffects(SessionEstimatesOf(sessions, p), confidence, &(*combined)[p])
            .WithContext(TriadParameterInfos()[p].name));
  }
  return Status::Ok();
}

}  // namespace accelcal
