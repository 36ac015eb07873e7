#pragma once

#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

namespace mimpact::kernel {

// The times a Simulation stops at for its outputs, in increasing order: series start + k interval
// for k in [0, count), each held as one entry whatever its count (a schedule of 1e9 outputs takes
// the memory of one).
class OutputTimes {
 public:
  void add(double start, double interval, std::int64_t count) {
    if (count > 0) series_.push({start, start, interval, 0, count});
  }
  bool empty() const { return series_.empty(); }
  double next() const { return series_.top().next; }
  // Drops the next time (its series goes on to its following one).
  void pop() {
    Series series = series_.top();
    series_.pop();
    if (++series.k < series.count) {
      series.next = series.start + double(series.k) * series.interval;
      series_.push(series);
    }
  }

 private:
  struct Series {
    double next, start, interval;  // s
    std::int64_t k, count;
    bool operator>(const Series& other) const { return next > other.next; }
  };
  std::priority_queue<Series, std::vector<Series>, std::greater<Series>> series_;
};

}  // namespace mimpact::kernel
