#pragma once
// The project's one parallel loop, on oneTBB's work-stealing pool. An exception thrown by
// any iteration cancels the remaining ones and is rethrown on the calling thread once every
// running iteration has returned (oneTBB's own guarantee), so no exception crosses a thread
// boundary unobserved.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>

namespace tlsmon {

// body(i) for every i in [0, n), on at most `threads` threads (0 = as many as the machine
// has cores). Iterations must be independent: the order in which they run is unspecified, so
// a result that must not depend on the thread count is written per i, never accumulated.
template <class Body>
void parallel_for(std::size_t n, Body&& body, unsigned threads = 0) {
    if (n == 0) return;
    const int concurrency =
        threads == 0 ? tbb::task_arena::automatic : static_cast<int>(std::max(1u, threads));
    tbb::task_arena arena(concurrency);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
                          });
    });
}

}  // namespace tlsmon
