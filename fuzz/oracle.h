// The round-trip oracle shared by the fuzz harnesses: whatever a reader
// accepts, the writer must write, and reading that back must give the same
// cloud. Anything else aborts, which libFuzzer reports as a crash.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"

namespace detexture::fuzz {

[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "round-trip oracle: %s\n", what);
  std::abort();
}

inline bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

inline void expect_same_matrix(const Matrix3& a, const Matrix3& b, const char* what) {
  if (a.rows() != b.rows()) fail(what);
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (int d = 0; d < 3; ++d)
      if (!same(a(i, d), b(i, d))) fail(what);
}

/// The bytes `write` puts into an OutputBuffer (through open_memstream).
template <class Write>
std::string written_bytes(const Write& write) {
  char* data = nullptr;
  std::size_t size = 0;
  std::FILE* file = open_memstream(&data, &size);
  if (!file) fail("open_memstream failed");
  try {
    const std::string path = "fuzz-output";
    io_detail::OutputBuffer out(file, path);
    write(out);
    out.flush();
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "the writer refused what the reader accepted: %s\n", e.what());
    fail("writer refused a cloud that was read");
  }
  std::fclose(file);
  std::string bytes(data, size);
  std::free(data);
  return bytes;
}

}  // namespace detexture::fuzz
