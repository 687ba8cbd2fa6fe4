// A small fixed pool of worker threads for the scene's independent bodies: parallelFor hands out blocks of
// an index range to the workers and to the calling thread, and returns when every block is done.
//
// Results do not depend on the thread count: the caller gives every block its own output, so what a block
// computes is the same whichever thread runs it and however many there are. Threads start on the first
// parallelFor that has more than one block to share, so a small scene never starts one.
//
// A step hands out several jobs in quick succession (the free steps, the narrow phases, the points, the
// islands' solves), with short serial stretches between them. A worker that has finished one therefore
// watches for the next for a while (kSpinTime) before it sleeps, and the caller watches for the last block
// likewise: waking a sleeping thread through a condition variable took longer than a small scene's whole
// job (docs/performance_log.md, "A pool that watches before it sleeps"). Nothing of the results changes.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rigid_body {

class ThreadPool {
 public:
  /// `threads` ≥ 1 in all, the calling thread included (1: everything runs on the caller).
  explicit ThreadPool(std::size_t threads = 1);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  std::size_t threads() const { return threads_; }

  /// Calls body(block) once for every block in [0, blocks), spread over the threads; returns when all are
  /// done. `body` must not throw. Not reentrant: one parallelFor at a time per pool.
  void parallelFor(std::size_t blocks, const std::function<void(std::size_t block)>& body);

  /// The threads a pool should have for "as many as the machine has" (0) or a request (≥ 1).
  static std::size_t resolve(std::size_t requested);

 private:
  void startWorkers();
  void work();
  void runBlocks();
  /// Watches `busy()` while it holds, for at most kSpinTime: between looks the CPU is told the thread waits
  /// (x86's pause, which leaves a hyperthread sibling its share of the core), and every so often the thread
  /// yields its core (the pool may have more threads than the machine has cores).
  template <class Busy>
  static void spinWhile(Busy busy) {
    const auto until = std::chrono::steady_clock::now() + kSpinTime;
    for (unsigned look = 1; busy(); ++look) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
      if (look % 64 != 0) continue;
      if (std::chrono::steady_clock::now() >= until) return;
      std::this_thread::yield();
    }
  }
  static constexpr std::chrono::microseconds kSpinTime{50};

  std::size_t threads_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  // The current job, read by the workers under mutex_ (generation_ changes once per parallelFor). The
  // atomics are written under mutex_ too; only the watching before a wait reads them without it.
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t blocks_ = 0;
  std::size_t next_block_ = 0;     // the next block to hand out
  std::atomic<std::size_t> blocks_done_{0};
  std::atomic<std::size_t> generation_{0};
  std::atomic<bool> stopping_{false};
};

/// `factor` blocks of `per_block` as one block, saturating at SIZE_MAX (a block size from 1 to SIZE_MAX).
inline std::size_t scaledBlock(std::size_t per_block, std::size_t factor) {
  return factor != 0 && per_block > SIZE_MAX / factor ? SIZE_MAX : factor * per_block;
}

/// The number of blocks of `per_block` (≥ 1) that cover `count`, and where the block starting at `first`
/// (< count) ends; neither can wrap.
inline std::size_t blockCount(std::size_t count, std::size_t per_block) {
  return count / per_block + (count % per_block != 0 ? 1 : 0);
}
inline std::size_t blockEnd(std::size_t first, std::size_t per_block, std::size_t count) {
  return count - first <= per_block ? count : first + per_block;
}

/// Calls body(block, first, end) for the blocks [first, end) of `per_block` indices (the last one shorter)
/// that cover [0, count), on `pool` where it has more than one thread and there is more than one block,
/// else on the caller in order. Any per_block from 1 to SIZE_MAX: no sum or product here can wrap.
void forEachRange(ThreadPool* pool, std::size_t count, std::size_t per_block,
                  const std::function<void(std::size_t block, std::size_t first, std::size_t end)>& body);

}  // namespace rigid_body
