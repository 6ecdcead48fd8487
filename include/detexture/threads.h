// Worker threads of the library's parallel loops (OpenMP), as a parameter of
// each call rather than a process-wide setting.
#pragma once

namespace detexture {

/// The number of worker threads a call with `threads` uses: `threads` itself
/// when > 0; for 0, what OpenMP would use (all cores, or OMP_NUM_THREADS).
int thread_count(int threads);

/// Sets the calling thread's OpenMP thread count for its lifetime and restores
/// the previous value when it ends, so that a library call with its own
/// `threads` leaves the caller's setting (and other threads') untouched.
/// `threads` = 0 changes nothing. Throws std::invalid_argument below 0.
class ScopedThreads {
 public:
  explicit ScopedThreads(int threads);
  ~ScopedThreads();
  ScopedThreads(const ScopedThreads&) = delete;
  ScopedThreads& operator=(const ScopedThreads&) = delete;

 private:
  int previous_ = 0;  ///< 0: nothing to restore
};

}  // namespace detexture
