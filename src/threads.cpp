#include "detexture/threads.h"

#include <omp.h>

#include <stdexcept>
#include <string>

namespace detexture {

int thread_count(int threads) { return threads > 0 ? threads : omp_get_max_threads(); }

ScopedThreads::ScopedThreads(int threads) {
  if (threads < 0)
    throw std::invalid_argument("the thread count must be 0 (all cores) or positive, got " +
                                std::to_string(threads));
  if (threads == 0) return;
  // omp_set_num_threads sets the nthreads ICV of the calling thread only, so
  // other threads of the caller (Python threads, say) keep theirs.
  previous_ = omp_get_max_threads();
  omp_set_num_threads(threads);
}

ScopedThreads::~ScopedThreads() {
  if (previous_ > 0) omp_set_num_threads(previous_);
}

}  // namespace detexture
