#include "simulation/monte_carlo.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace accelcal {

MonteCarloTiming RunTrials(const MonteCarloOptions& options,
                           const std::function<void(int)>& trial) {
  using Clock = std::chrono::steady_clock;
  const int hardware = std::max(1u, std::thread::hardware_concurrency());
  const int threads = std::max(
      1, std::min(options.threads > 0 ? options.threads : hardware, std::max(1, options.trials)));
  const bool show_progress = options.progress && isatty(STDERR_FILENO) && options.trials > 0;
  std::atomic<int> next{0};
  std::atomic<int> done{0};
  const auto start = Clock::now();
  auto worker = [&] {
    for (int i = next++; i < options.trials; i = next++) {
      trial(i);
      ++done;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  if (show_progress) {
    // The calling thread reports while the pool works, then joins the work itself.
    std::thread reporter([&] {
      while (done < options.trials) {
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
        const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        const int count = done;
        const double rate = count / std::max(elapsed, 1e-9);
        std::fprintf(stderr, "\r%s: %d/%d, %.0f/s, ETA %.0f s   ", options.label.c_str(), count,
                     options.trials, rate, rate > 0 ? (options.trials - count) / rate : 0.0);
      }
    });
    worker();
    for (std::thread& thread : pool) thread.join();
    reporter.join();
    std::fprintf(stderr, "\r%s: %d/%d done%20s\n", options.label.c_str(), options.trials,
                 options.trials, "");
  } else {
    worker();
    for (std::thread& thread : pool) thread.join();
  }
  MonteCarloTiming timing;
  timing.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  timing.trials_per_second = options.trials / std::max(timing.seconds, 1e-9);
  timing.threads = threads;
  return timing;
}

}  // namespace accelcal
