#include "simulation/monte_carlo.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace accelcal {

MonteCarloTiming RunTrials(const MonteCarloOptions& options,
                           const std::function<void(int)>& trial) {
  using Clock = std::chrono::steady_clock;
  const int hardware = std::max(1u, std::thread::hardware_concurrency());
  const int threads = std::max(
      1, std::min(options.threads > 0 ? options.threads : hardware, std::max(1, options.trials)));
  std::atomic<int> next{0};
  const auto start = Clock::now();
  auto worker = [&] {
    for (int i = next++; i < options.trials; i = next++) {
      trial(i);
      if (options.progress != nullptr) options.progress->Advance();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  MonteCarloTiming timing;
  timing.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  timing.trials_per_second = options.trials / std::max(timing.seconds, 1e-9);
  timing.threads = threads;
  return timing;
}

}  // namespace accelcal
