// The thread count as a parameter of the API (threads.h, RemoveTextureParams::threads).
#include "detexture/threads.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <stdexcept>

#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

TEST(Threads, ScopedThreadsSetsAndRestoresTheCallersCount) {
  omp_set_num_threads(3);
  {
    const ScopedThreads scope(1);
    EXPECT_EQ(omp_get_max_threads(), 1);
    EXPECT_EQ(thread_count(0), 1);
  }
  EXPECT_EQ(omp_get_max_threads(), 3);
  {
    const ScopedThreads scope(0);  // 0 changes nothing
    EXPECT_EQ(omp_get_max_threads(), 3);
  }
  EXPECT_EQ(thread_count(5), 5);
  EXPECT_EQ(thread_count(0), 3);
  EXPECT_THROW(ScopedThreads(-1), std::invalid_argument);
}

TEST(Threads, RemoveTextureTakesTheCountWithoutChangingTheCallers) {
  const auto s = test::bumpy_plane(41, 0.03, 0.05);
  RemoveTextureParams p;
  p.radius = {0.08, Length::Unit::Absolute};
  omp_set_num_threads(2);
  p.threads = 1;
  const RemoveTextureResult one = remove_texture(s.P, s.N, p);
  EXPECT_EQ(omp_get_max_threads(), 2);
  p.threads = 2;
  const RemoveTextureResult two = remove_texture(s.P, s.N, p);
  EXPECT_TRUE(one.positions == two.positions);
  EXPECT_TRUE(one.normals == two.normals);
  p.threads = -1;
  EXPECT_THROW(validate(p), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
