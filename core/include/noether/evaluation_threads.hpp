#pragma once
// Threads inside one evaluation (docs/user-guide.md, "Threads"): a potential may evaluate its
// independent parts — the pairs of bodies — on several threads and then sum them on one, in a
// fixed order, so that its result is the same, bit for bit, for any number of threads.
// The number is per calling thread: 1 unless the caller set more with EvaluationThreads (a run
// sets `noether run --threads`'s for its integration; ensemble samples, each on a thread of its
// own, keep 1).
#include <cstddef>
#include <functional>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

// The threads an evaluation made on the calling thread may use (≥ 1).
int evaluation_threads();

// Sets evaluation_threads() for the calling thread while in scope (values below 1 count as 1).
class EvaluationThreads {
 public:
  explicit EvaluationThreads(int threads);
  ~EvaluationThreads();
  EvaluationThreads(const EvaluationThreads&) = delete;
  EvaluationThreads& operator=(const EvaluationThreads&) = delete;

 private:
  int previous_;
};

// Calls body(i, thread) once for each i in [0, n), on min(threads, n) threads (`thread` in
// [0, threads): an index for per-thread scratch), in chunks of 16 indices handed out in order,
// so each thread sees its indices in increasing order. When bodies
// throw, every index still runs and the exception of the lowest index is rethrown here. One
// thread (or n < 2): a plain loop on the caller's thread, which stops at the first exception.
void parallel_for_each(std::size_t n, int threads, const std::function<void(std::size_t, int)>& body);

}  // namespace noether

#pragma GCC visibility pop
