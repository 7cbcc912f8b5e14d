// The run's timing report: statistics on hand-computed samples, merging, and the stopwatch's laps.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "system/timing.hpp"

namespace vkvo::system {
namespace {

TEST(TimingReport, StatisticsOfKnownSamples) {
  TimingReport report;
  for (int v = 1; v <= 20; ++v) report.add(Module::BA, double(v));  // 1..20 ms
  const auto s = report.stats(Module::BA);
  EXPECT_EQ(s.samples, 20u);
  EXPECT_DOUBLE_EQ(s.mean_ms, 10.5);
  EXPECT_DOUBLE_EQ(s.median_ms, 10.5);  // even count: mean of the middle two
  EXPECT_DOUBLE_EQ(s.p95_ms, 19.0);     // nearest rank: ceil(0.95 * 20) = 19th value
  EXPECT_DOUBLE_EQ(s.max_ms, 20.0);
  EXPECT_EQ(report.stats(Module::PE).samples, 0u);

  TimingReport other;
  other.add(Module::BA, 41.0);
  report.merge(other);
  EXPECT_EQ(report.stats(Module::BA).samples, 21u);
  EXPECT_DOUBLE_EQ(report.stats(Module::BA).median_ms, 11.0);
  EXPECT_DOUBLE_EQ(report.stats(Module::BA).max_ms, 41.0);
}

// Laps split the elapsed time: each lap starts where the previous ended, so they add up to the total.
TEST(Stopwatch, LapsRestartAndAddUpToTheTotal) {
  const Stopwatch total;
  Stopwatch watch;
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double first = watch.lap();
  const double second = watch.lap();
  EXPECT_GE(first, 20.0);
  EXPECT_LT(second, first) << "lap() restarts the watch";
  EXPECT_GE(second, 0.0);
  EXPECT_LE(first + second, total.ms());
}

}  // namespace
}  // namespace vkvo::system
