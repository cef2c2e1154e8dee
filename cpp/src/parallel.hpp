// The frame's independent work (each robot's λ, each robot's laser) on several threads. Results
// go to slots indexed by the work item, never to shared state in completion order, so a frame is
// the same for any number of threads.
//
// A small pool of our own rather than OpenMP or TBB: libgomp's workers do not survive fork() (a
// child process that uses OpenMP after its parent did hangs, as with multiprocessing's default
// start method or Dask's local workers), and TBB would be a new dependency for one parallel-for.
// This pool notices a fork and starts afresh in the child.
// Private to vwg's libraries (beside their sources, under cpp/): not installed.
#pragma once

#include <cstddef>
#include <functional>

namespace vwg {

/// The machine's cores (at least 1): the thread count a frame uses unless told otherwise.
unsigned default_threads();

/// Largest thread count accepted (a frame's work items are robots; more threads than cores only
/// adds switching).
inline constexpr unsigned kMaxThreads = 256;

/// Call body(i) for every i in [0, count), on up to `threads` threads (the caller's among them),
/// and return when all calls are done. Calls may run in any order and at the same time, so body
/// must write only to what item i owns. If some calls throw, every call still runs and the
/// exception of the lowest i is rethrown, whatever the timing. A parallel_for called from inside
/// another (or while another thread's is running) runs its items on the calling thread.
void parallel_for(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& body);

}  // namespace vwg
