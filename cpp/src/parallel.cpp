#include "src/parallel.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace vwg {

namespace {

// Set on pool threads, and on a caller while its items run: a nested parallel_for runs inline.
thread_local bool t_in_parallel = false;

class Pool {
 public:
  Pool() : pid_(getpid()) {}
  // Never destroyed (see instance()): its threads sleep until the process ends.
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  /// The process's pool; after a fork, a fresh one (the parent's threads do not exist in the
  /// child, and its locks may be held by them: the old pool is left as it is, unused).
  static Pool& instance() {
    static std::mutex guard;
    static Pool* current = nullptr;
    const std::lock_guard<std::mutex> lock(guard);
    if (!current || current->pid_ != getpid()) current = new Pool();
    return *current;
  }

  /// False if another thread's job is running (the caller then runs its items itself).
  bool run(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body) {
    const std::unique_lock<std::mutex> job(job_, std::try_to_lock);
    if (!job) return false;
    const unsigned helpers = static_cast<unsigned>(std::min<std::size_t>(threads - 1, count - 1));
    grow(helpers);
    {
      const std::lock_guard<std::mutex> lock(m_);
      body_ = &body;
      count_ = count;
      next_.store(0, std::memory_order_relaxed);
      failed_at_ = std::numeric_limits<std::size_t>::max();
      error_ = nullptr;
      wanted_ = helpers;
      running_ = helpers;
      ++generation_;
    }
    wake_.notify_all();
    drain();
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [&] { return running_ == 0; });
    body_ = nullptr;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    return true;
  }

 private:
  void grow(unsigned helpers) {
    while (threads_.size() < helpers) {
      const auto k = static_cast<unsigned>(threads_.size());
      threads_.emplace_back([this, k] { serve(k); });
    }
  }

  void serve(unsigned k) {
    t_in_parallel = true;
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(m_);
        wake_.wait(lock, [&] { return generation_ != seen; });
        seen = generation_;
        if (k >= wanted_) continue;  // not needed for this job
      }
      drain();
      const std::lock_guard<std::mutex> lock(m_);
      if (--running_ == 0) done_.notify_one();
    }
  }

  void drain() {
    for (std::size_t i = next_.fetch_add(1, std::memory_order_relaxed); i < count_;
         i = next_.fetch_add(1, std::memory_order_relaxed)) {
      try {
        (*body_)(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(m_);
        if (i < failed_at_) {
          failed_at_ = i;
          error_ = std::current_exception();
        }
      }
    }
  }

  pid_t pid_;
  std::mutex job_;  // one job at a time
  std::mutex m_;    // the fields below
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  std::uint64_t generation_ = 0;
  unsigned wanted_ = 0, running_ = 0;
  const std::function<void(std::size_t)>* body_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::size_t> next_{0};
  std::size_t failed_at_ = 0;
  std::exception_ptr error_;
};

void run_inline(std::size_t count, const std::function<void(std::size_t)>& body) {
  std::exception_ptr first;
  for (std::size_t i = 0; i < count; ++i) {
    try {
      body(i);
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace

unsigned default_threads() { return std::clamp(std::thread::hardware_concurrency(), 1u, kMaxThreads); }

void parallel_for(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body) {
  if (count == 0) return;
  if (threads <= 1 || count == 1 || t_in_parallel) {
    run_inline(count, body);
    return;
  }
  t_in_parallel = true;
  struct Reset {
    ~Reset() { t_in_parallel = false; }
  } reset;
  if (!Pool::instance().run(count, std::min(threads, kMaxThreads), body)) run_inline(count, body);
}

}  // namespace vwg
