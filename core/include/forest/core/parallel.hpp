#pragma once
// Work spread over the machine's cores: body(i) for every i in [0, count), each index once, taken
// by whichever thread is free next (so uneven items balance). Each body must touch only what its
// index owns; results in index order make the outcome the same on any number of cores.
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace forest {

// The threads parallelFor uses: the hardware's, 1 to 16.
inline int parallelThreads() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 16); }

template <typename Body>
void parallelFor(int count, const Body& body) {
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i; (i = next++) < count;) body(i);
  };
  const int threads = std::min(parallelThreads(), count);
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

}  // namespace forest
