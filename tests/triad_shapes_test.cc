// "Unexplained" on the triad says what remains by its shape (issue 33, item 1): each class of
// cause outside the model is hidden in simulated sessions of several pose designs and seeds, and
// discovery must call the session unexplained with the hidden class named first (its check's
// shape class, estimation/discovery/check.h) in at least 80% of them. The shapes are added to the
// simulated pose means (counts), sized at several sigma of the pose means' noise:
//
//   cubic scale of x        x += c n_x^3                              orientation, on x
//   orientation offset      y += c n_x n_z                            orientation
//   warm-up and cool-down   every axis += c sin(pi t / T)             time, "rises then falls"
//   warm-up                 every axis += c (1 - exp(-4 t / T))       time, monotonic
//   slip in the mount       offsets change by (a, b, c) half-way      time, a step (named)
//   one pose disturbed      one pose moved by 3 n_p + N(0, 1) counts   pose order, one pose
//   jumps between poses     every pose's offset drawn anew            pose order, the scatter
//   x clipped near 1 g      x = min(x, L), L the output at 0.9 g at   full scale, on x
//                           the end where x is largest
//
// with n_p the pose's true gravity direction and t its time over a session of length T.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "estimation/triad/triad_discovery.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

TriadSimulationOptions Session() { return testing::TriadTestSimulationOptions(); }

TriadDiscoveryOptions Discovery() { return testing::TriadTestDiscovery(0.01); }

// Pose designs, each the directions in the order they are held.
enum class Design { kRandom40, kFacesTilted36, kCube26 };
const char* DesignName(Design design) {
  switch (design) {
    case Design::kRandom40:
      return "40 random directions";
    case Design::kFacesTilted36:
      return "6 faces held 4 times tilted 5-20 degrees, and 12 random";
    case Design::kCube26:
      return "26 cube directions (faces, edges, corners), shuffled";
  }
  return "";
}

std::array<double, 3> Normalised(std::array<double, 3> v) {
  const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (double& x : v) x /= norm;
  return v;
}

std::vector<std::array<double, 3>> Directions(Design design, RandomSource* random) {
  std::vector<std::array<double, 3>> directions;
  switch (design) {
    case Design::kRandom40:
      return RandomPoseDirections(40, random);
    case Design::kFacesTilted36: {
      for (int repeat = 0; repeat < 4; ++repeat) {
        for (const auto& face : SixPoseDirections()) {
          const double tilt = (5.0 + 15.0 * random->Uniform()) * M_PI / 180.0;
          const double azimuth = 2.0 * M_PI * random->Uniform();
          // Two unit vectors normal to the face.
          const int k = face[0] != 0.0 ? 0 : (face[1] != 0.0 ? 1 : 2);
          std::array<double, 3> a{}, b{};
          a[(k + 1) % 3] = 1.0;
          b[(k + 2) % 3] = 1.0;
          std::array<double, 3> n;
          for (int i = 0; i < 3; ++i)
            n[i] = std::cos(tilt) * face[i] +
                   std::sin(tilt) * (std::cos(azimuth) * a[i] + std::sin(azimuth) * b[i]);
          directions.push_back(Normalised(n));
        }
      }
      for (const auto& n : RandomPoseDirections(12, random)) directions.push_back(n);
      break;
    }
    case Design::kCube26: {
      for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
          for (int z = -1; z <= 1; ++z)
            if (x != 0 || y != 0 || z != 0)
              directions.push_back(Normalised({1.0 * x, 1.0 * y, 1.0 * z}));
      for (size_t i = directions.size() - 1; i > 0; --i) {
        const size_t j = static_cast<size_t>(random->Uniform() * (i + 1)) % (i + 1);
        std::swap(directions[i], directions[j]);
      }
      break;
    }
  }
  // Held in a random order, as by hand.
  for (size_t i = directions.size() - 1; i > 0; --i) {
    const size_t j = static_cast<size_t>(random->Uniform() * (i + 1)) % (i + 1);
    std::swap(directions[i], directions[j]);
  }
  return directions;
}

// A hidden cause: changes the pose means (counts) given the true directions.
using Hide = std::function<void(Design design, const std::vector<std::array<double, 3>>& directions,
                                RandomSource* random, std::vector<TriadPoseMean>* poses)>;

// The session's time of pose p on [0, 1].
double Phase(const std::vector<TriadPoseMean>& poses, size_t p) {
  const double first = poses.front().time_s, last = poses.back().time_s;
  return (poses[p].time_s - first) / (last - first);
}

struct ShapeCase {
  const char* id;
  const char* name;
  Hide hide;
  // The hidden class named first, judged on the result.
  std::function<bool(const TriadDiscoveryResult&)> named;
  // The designs it is hidden in (empty: all three).
  std::vector<Design> designs;
};

const ResidualCheck* First(const TriadDiscoveryResult& result) {
  if (result.verdict_code != Verdict::kUnexplained || result.remaining_checks.empty())
    return nullptr;
  return &result.checks[result.remaining_checks.front()];
}

bool FirstIs(const TriadDiscoveryResult& result, ShapeClass shape_class, int axis = -2,
             const char* in_description = nullptr) {
  const ResidualCheck* first = First(result);
  if (first == nullptr || first->shape_class != shape_class) return false;
  if (axis != -2 && first->axis != axis) return false;
  return in_description == nullptr || first->description.find(in_description) != std::string::npos;
}

const ShapeCase kCases[] = {
    {"CubicScaleOfX", "a cubic scale term of x",
     [](Design, const auto& n, RandomSource*, std::vector<TriadPoseMean>* poses) {
       for (size_t p = 0; p < poses->size(); ++p)
         (*poses)[p].mean[0] += 10.0 * std::pow(n[p][0], 3);
     },
     [](const TriadDiscoveryResult& r) { return FirstIs(r, ShapeClass::kOrientation, 0); }},
    {"OrientationOffset", "an offset of y that follows n_x n_z",
     [](Design, const auto& n, RandomSource*, std::vector<TriadPoseMean>* poses) {
       for (size_t p = 0; p < poses->size(); ++p) (*poses)[p].mean[1] += 8.0 * n[p][0] * n[p][2];
     },
     [](const TriadDiscoveryResult& r) { return FirstIs(r, ShapeClass::kOrientation); }},
    {"WarmUpAndCoolDown", "offsets that rise then fall over the session",
     [](Design, const auto&, RandomSource*, std::vector<TriadPoseMean>* poses) {
       for (size_t p = 0; p < poses->size(); ++p)
         for (int k = 0; k < 3; ++k) (*poses)[p].mean[k] += 2.0 * std::sin(M_PI * Phase(*poses, p));
     },
     [](const TriadDiscoveryResult& r) {
       return FirstIs(r, ShapeClass::kTime, -2, "rises then falls");
     }},
    {"WarmUp", "offsets that settle after a warm-up",
     [](Design, const auto&, RandomSource*, std::vector<TriadPoseMean>* poses) {
       for (size_t p = 0; p < poses->size(); ++p)
         for (int k = 0; k < 3; ++k)
           (*poses)[p].mean[k] += 3.0 * (1.0 - std::exp(-4.0 * Phase(*poses, p)));
     },
     [](const TriadDiscoveryResult& r) { return FirstIs(r, ShapeClass::kTime); }},
    {"SlipHalfWay", "a sensor that slipped in its mount half-way (offsets step)",
     [](Design, const auto&, RandomSource*, std::vector<TriadPoseMean>* poses) {
       const std::array<double, 3> step = {1.5, -1.0, 1.2};
       for (size_t p = poses->size() / 2; p < poses->size(); ++p)
         for (int k = 0; k < 3; ++k) (*poses)[p].mean[k] += step[k];
     },
     [](const TriadDiscoveryResult& r) {
       const ResidualCheck* first = First(r);
       return first != nullptr &&
              (first->name == "offset_step" || first->name == "calibration_step");
     }},
    {"OnePoseDisturbed", "one pose disturbed",
     [](Design, const auto& n, RandomSource* random, std::vector<TriadPoseMean>* poses) {
       // Along the pose's direction (what a static pose can see of an offset) and across it.
       const size_t p = static_cast<size_t>(random->Uniform() * poses->size()) % poses->size();
       for (int k = 0; k < 3; ++k)
         (*poses)[p].mean[k] += 3.0 * n[p][k] + 1.0 * random->StandardNormal();
     },
     [](const TriadDiscoveryResult& r) {
       const ResidualCheck* first = First(r);
       return first != nullptr && first->name == "one_pose";
     }},
    {"JumpsBetweenPoses", "offsets that jump from pose to pose",
     [](Design, const auto&, RandomSource* random, std::vector<TriadPoseMean>* poses) {
       for (auto& pose : *poses)
         for (int k = 0; k < 3; ++k) pose.mean[k] += 1.0 * random->StandardNormal();
     },
     [](const TriadDiscoveryResult& r) {
       const ResidualCheck* first = First(r);
       return first != nullptr && first->name == "chi2";
     }},
    // Clipped at 0.9 g among random directions, at 0.97 g among faces tilted by 5-20 degrees: two
    // poses clipped on average. (The cube's 26 directions hold one pose near each end of an axis:
    // one clipped pose is the one-pose check's.)
    {"ClippedNearOneG",
     "x clipped near 1 g",
     [](Design design, const auto& n, RandomSource*, std::vector<TriadPoseMean>* poses) {
       // The output at n_x = 0.9 from the poses themselves (least squares in n).
       double sxx = 0, sx = 0, sy = 0, sxy = 0;
       const double count = static_cast<double>(poses->size());
       for (size_t p = 0; p < poses->size(); ++p) {
         sx += n[p][0];
         sy += (*poses)[p].mean[0];
         sxx += n[p][0] * n[p][0];
         sxy += n[p][0] * (*poses)[p].mean[0];
       }
       const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
       const double intercept = (sy - slope * sx) / count;
       // The end of the range where the output is largest.
       const double level =
           intercept + std::abs(slope) * (design == Design::kRandom40 ? 0.9 : 0.97);
       for (auto& pose : *poses) {
         if (pose.mean[0] > level) {
           pose.mean[0] = level;
           pose.variance[0] = 0.0;  // every sample of the pose clipped
         }
       }
     },
     [](const TriadDiscoveryResult& r) {
       return FirstIs(r, ShapeClass::kFullScale, 0) &&
              First(r)->advice.find("clipping") != std::string::npos;
     },
     {Design::kRandom40, Design::kFacesTilted36}},
};

void PrintTo(const ShapeCase& c, std::ostream* os) { *os << c.name; }

class TriadShapeTest : public ::testing::TestWithParam<ShapeCase> {};

constexpr int kSeedsPerDesign = 20;

TEST_P(TriadShapeTest, IsNamedFirstInAtLeastEightyPercentOfSessions) {
  const ShapeCase& c = GetParam();
  int named = 0, sessions = 0;
  std::string misses;
  std::vector<Design> designs = c.designs;
  if (designs.empty()) designs = {Design::kRandom40, Design::kFacesTilted36, Design::kCube26};
  for (const Design design : designs) {
    int named_here = 0;
    for (int seed = 1; seed <= kSeedsPerDesign; ++seed) {
      RandomSource random(1000 + seed, static_cast<uint64_t>(design));
      const std::vector<std::array<double, 3>> directions = Directions(design, &random);
      std::vector<TriadPoseMean> poses = SimulateTriadPoses(Session(), directions, &random);
      c.hide(design, directions, &random, &poses);
      TriadDiscoveryResult result;
      const Status status = DiscoverTriad(poses, Discovery(), &result);
      ASSERT_TRUE(status.ok()) << status.message();
      ++sessions;
      if (c.named(result)) {
        ++named;
        ++named_here;
      } else if (misses.size() < 2000) {
        misses += std::string("\n  ") + DesignName(design) + ", seed " + std::to_string(seed) +
                  ": " + result.verdict;
      }
    }
    std::printf("%s, %s: named first in %d of %d\n", c.name, DesignName(design), named_here,
                kSeedsPerDesign);
  }
  EXPECT_GE(named, 0.8 * sessions) << c.name << "; misses:" << misses;
}

INSTANTIATE_TEST_SUITE_P(OutsideTheModel, TriadShapeTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<ShapeCase>& info) {
                           return std::string(info.param.id);
                         });

// The level of the whole procedure with every check above in its family: on 1000 null sessions of
// five designs (the three above, 15 and 60 random directions), white noise and nothing hidden,
// any verdict but "explained" at most alpha + 2 sd of the time, at alpha = 0.01 and 0.05.
TEST(TriadShapes, NullSessionsOfMixedDesignsHoldTheLevel) {
  constexpr int kSessions = 1000;
  const std::array<double, 2> alphas = {0.01, 0.05};
  std::array<int, 2> beyond{};
  std::array<std::string, 2> example;
  for (int s = 0; s < kSessions; ++s) {
    RandomSource random(77, static_cast<uint64_t>(s));
    std::vector<std::array<double, 3>> directions;
    switch (s % 5) {
      case 0:
        directions = Directions(Design::kRandom40, &random);
        break;
      case 1:
        directions = Directions(Design::kFacesTilted36, &random);
        break;
      case 2:
        directions = Directions(Design::kCube26, &random);
        break;
      case 3:
        directions = RandomPoseDirections(15, &random);
        break;
      default:
        directions = RandomPoseDirections(60, &random);
        break;
    }
    const std::vector<TriadPoseMean> poses = SimulateTriadPoses(Session(), directions, &random);
    for (size_t a = 0; a < alphas.size(); ++a) {
      TriadDiscoveryOptions options = Discovery();
      options.alpha = alphas[a];
      TriadDiscoveryResult result;
      const Status status = DiscoverTriad(poses, options, &result);
      ASSERT_TRUE(status.ok()) << status.message();
      if (result.verdict_code != Verdict::kExplained) {
        ++beyond[a];
        if (example[a].empty()) example[a] = "session " + std::to_string(s) + ": " + result.verdict;
      }
    }
  }
  for (size_t a = 0; a < alphas.size(); ++a) {
    const double alpha = alphas[a];
    const double limit = alpha + 2.0 * std::sqrt(alpha * (1.0 - alpha) / kSessions);
    std::printf("alpha = %g: %d of %d null sessions not explained (limit %.4f)\n", alpha, beyond[a],
                kSessions, limit);
    EXPECT_LE(beyond[a], limit * kSessions) << "first: " << example[a];
  }
}

// The time check's size comes with a sigma that means what it says: an x offset of c u^2 over the
// session (u on [-1, 1]: it falls then rises, by c at its turn against the ends' mean), 200
// sessions of 40 random directions; where the time check is named first, the stated height is
// within 2 of its stated sigmas of c in about 95% of them.
TEST(TriadShapes, TheTimeShapesSizeIsWithinItsSigma) {
  constexpr double kHeight = 2.0;  // counts
  int named = 0, within = 0;
  for (int s = 0; s < 200; ++s) {
    RandomSource random(91, static_cast<uint64_t>(s));
    std::vector<TriadPoseMean> poses =
        SimulateTriadPoses(Session(), RandomPoseDirections(40, &random), &random);
    for (size_t p = 0; p < poses.size(); ++p) {
      const double u = 2.0 * Phase(poses, p) - 1.0;
      poses[p].mean[0] += kHeight * u * u;
    }
    TriadDiscoveryResult result;
    ASSERT_TRUE(DiscoverTriad(poses, Discovery(), &result).ok());
    const ResidualCheck* first = First(result);
    if (first == nullptr || first->name != "time" || first->axis != 0) continue;
    double height = 0.0, sigma = 0.0;
    const size_t at = first->description.find(", by ");
    ASSERT_NE(at, std::string::npos) << first->description;
    ASSERT_EQ(std::sscanf(first->description.c_str() + at, ", by %lf +- %lf", &height, &sigma), 2)
        << first->description;
    ++named;
    within += std::abs(height - kHeight) <= 2.0 * sigma;
  }
  std::printf("time named first in %d of 200; stated height within 2 sigma of the truth in %d\n",
              named, within);
  ASSERT_GE(named, 150);
  const double rate = static_cast<double>(within) / named;
  EXPECT_GE(rate, 0.95 - 3.0 * std::sqrt(0.95 * 0.05 / named));
}

}  // namespace
}  // namespace accelcal
