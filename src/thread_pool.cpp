#include "rigid_body_sim/thread_pool.hpp"

#include <algorithm>

namespace rigid_body {

ThreadPool::ThreadPool(std::size_t threads) : threads_(std::max<std::size_t>(1, threads)) {}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

std::size_t ThreadPool::resolve(std::size_t requested) {
  if (requested > 0) return requested;
  return std::max<std::size_t>(1, std::thread::hardware_concurrency());
}

void ThreadPool::startWorkers() {
  workers_.reserve(threads_ - 1);
  for (std::size_t i = 1; i < threads_; ++i) workers_.emplace_back([this] { work(); });
}

void ThreadPool::parallelFor(std::size_t blocks, const std::function<void(std::size_t block)>& body) {
  if (threads_ == 1 || blocks <= 1) {
    for (std::size_t block = 0; block < blocks; ++block) body(block);
    return;
  }
  if (workers_.empty()) startWorkers();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &body;
    blocks_ = blocks;
    next_block_ = 0;
    blocks_done_ = 0;
    ++generation_;
  }
  wake_.notify_all();
  runBlocks();
  spinWhile([&] { return blocks_done_.load(std::memory_order_acquire) != blocks; });
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return blocks_done_ == blocks_; });
  job_ = nullptr;
}

void ThreadPool::runBlocks() {
  // Blocks are taken one at a time under the lock: a block is many bodies' steps (tens of µs at least), so
  // the lock is not what bounds the pool.
  std::unique_lock<std::mutex> lock(mutex_);
  while (job_ != nullptr && next_block_ < blocks_) {
    const std::size_t block = next_block_++;
    const std::function<void(std::size_t)>& job = *job_;
    lock.unlock();
    job(block);
    lock.lock();
    if (++blocks_done_ == blocks_) done_.notify_one();
  }
}

void ThreadPool::work() {
  std::size_t seen = 0;
  while (true) {
    spinWhile([&] { return generation_.load(std::memory_order_acquire) == seen && !stopping_.load(); });
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
    }
    runBlocks();
  }
}

void forEachRange(ThreadPool* pool, std::size_t count, std::size_t per_block,
                  const std::function<void(std::size_t block, std::size_t first, std::size_t end)>& body) {
  per_block = std::max<std::size_t>(1, per_block);
  const std::size_t blocks = blockCount(count, per_block);
  const auto run = [&](std::size_t block) {
    const std::size_t first = block * per_block;  // < count: no wrap
    body(block, first, blockEnd(first, per_block, count));
  };
  if (pool == nullptr || pool->threads() == 1 || blocks < 2) {
    for (std::size_t block = 0; block < blocks; ++block) run(block);
    return;
  }
  pool->parallelFor(blocks, run);
}

}  // namespace rigid_body
