#include <noether/evaluation_threads.hpp>

#include <algorithm>
#include <exception>
#include <limits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace noether {

namespace {
thread_local int current_threads = 1;
}

int evaluation_threads() { return current_threads; }

EvaluationThreads::EvaluationThreads(int threads) : previous_(current_threads) {
  current_threads = std::max(1, threads);
}
EvaluationThreads::~EvaluationThreads() { current_threads = previous_; }

void parallel_for_each(std::size_t n, int threads, const std::function<void(std::size_t, int)>& body) {
#ifdef _OPENMP
  const int used = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), n));
#else
  const int used = 1;  // a build without OpenMP evaluates on the caller's thread
  (void)threads;
#endif
  if (used <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i, 0);
    return;
  }
  // Each thread's first failure (its lowest index: a thread takes its indices in order).
  std::vector<std::exception_ptr> error(static_cast<std::size_t>(used));
  std::vector<std::size_t> failed_at(static_cast<std::size_t>(used), std::numeric_limits<std::size_t>::max());
  // Chunks of 16 indices handed out in order (schedule(dynamic, 16)): each index once, whatever
  // number of threads the runtime grants, each thread's indices in increasing order; a chunk's
  // results are adjacent in memory, so two threads seldom write one cache line.
  const auto count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(dynamic, 16) num_threads(used)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
#ifdef _OPENMP
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
#else
    const std::size_t thread = 0;
#endif
    const auto i = static_cast<std::size_t>(k);
    try {
      body(i, static_cast<int>(thread));
    } catch (...) {
      if (!error[thread]) {
        error[thread] = std::current_exception();
        failed_at[thread] = i;
      }
    }
  }
  const auto first = std::min_element(failed_at.begin(), failed_at.end()) - failed_at.begin();
  if (error[static_cast<std::size_t>(first)]) std::rethrow_exception(error[static_cast<std::size_t>(first)]);
}

}  // namespace noether
