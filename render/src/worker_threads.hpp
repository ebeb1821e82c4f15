#pragma once
// Threads kept for a frame's parallel CPU work (the receiver mask, ShadowSetupPass): a software
// rasteriser's threads sit idle while the CPU works there, and starting threads afresh each frame
// cost ~0.3 ms on the thesis walk. The calling thread takes part 0; the others wait on a condition
// variable between runs (no spinning: they would take cores from the rasteriser).
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace forest::render {

class WorkerThreads {
 public:
  // `count` parts per run: the caller and count − 1 threads (count ≥ 1).
  explicit WorkerThreads(int count);
  ~WorkerThreads();
  WorkerThreads(const WorkerThreads&) = delete;
  WorkerThreads& operator=(const WorkerThreads&) = delete;

  int count() const { return static_cast<int>(threads_.size()) + 1; }
  // Runs work(0) … work(count() − 1), work(0) on the calling thread, and returns when all are
  // done; rethrows the first exception a part threw.
  void run(const std::function<void(int)>& work);

 private:
  void serve(int part);

  std::mutex mutex_;
  std::condition_variable started_, finished_;
  const std::function<void(int)>* work_ = nullptr;
  std::uint64_t generation_ = 0;
  int running_ = 0;
  bool stopping_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> threads_;
};

// One part per hardware thread (at least 1, at most 8).
int hardwareParts();

}  // namespace forest::render
