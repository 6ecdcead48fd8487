// libFuzzer harness for the OBJ, OFF, STL and PCD readers (src/io/read_*.cpp;
// FUZZ_FORMAT picks one at compile time), with the round-trip oracle: a
// cloud that reads must write in the same format (every encoding) and read
// back with the same positions, normals, faces and extras.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "detexture/io/face_list.h"
#include "oracle.h"
#include "read_obj.h"
#include "read_off.h"
#include "read_pcd.h"
#include "read_stl.h"
#include "write_obj.h"
#include "write_off.h"
#include "write_pcd.h"
#include "write_stl.h"

using namespace detexture;

namespace {

PointCloud read(std::string_view bytes, const std::string& path) {
  ReadReport report;
#if FUZZ_FORMAT == 0
  return io_detail::read_obj(bytes, path, report);
#elif FUZZ_FORMAT == 1
  return io_detail::read_off(bytes, path, report);
#elif FUZZ_FORMAT == 2
  return io_detail::read_stl(bytes, path, report);
#else
  return io_detail::read_pcd(bytes, path, report);
#endif
}

// The encodings of the format: 0 = ascii, 1 = binary, 2 = compressed.
std::vector<int> encodings() {
#if FUZZ_FORMAT == 2
  return {0, 1};
#elif FUZZ_FORMAT == 3
  return {0, 1, 2};
#else
  return {0};
#endif
}

void write(io_detail::OutputBuffer& out, const PointCloud& cloud, int encoding) {
  const std::string path = "fuzz-output";
#if FUZZ_FORMAT == 0
  (void)encoding;
  io_detail::write_obj(out, cloud, path, nullptr);
#elif FUZZ_FORMAT == 1
  (void)encoding;
  io_detail::write_off(out, cloud, path, nullptr);
#elif FUZZ_FORMAT == 2
  io_detail::write_stl(out, cloud, encoding == 0, path, nullptr);
#else
  io_detail::write_pcd(out, cloud,
                       encoding == 0   ? io_detail::PcdData::Ascii
                       : encoding == 1 ? io_detail::PcdData::Binary
                                       : io_detail::PcdData::BinaryCompressed,
                       path, nullptr);
#endif
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = "fuzz-input";
  PointCloud cloud;
  try {
    cloud = read(bytes, path);
  } catch (const std::runtime_error&) {
    return 0;
  }
  for (const int encoding : encodings()) {
    // Binary STL holds floats: compare with the cloud rounded to float.
    PointCloud expected = cloud;
    if (FUZZ_FORMAT == 2 && encoding == 1) {
      bool fits = true;
      for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i)
        for (int d = 0; d < 3; ++d) fits = fits && std::abs(cloud.positions(i, d)) <= 3.4e38;
      if (!fits) continue;  // refused by the writer, as documented
      expected.positions = cloud.positions.cast<float>().cast<double>();
    }
    const std::string written =
        fuzz::written_bytes([&](io_detail::OutputBuffer& out) { write(out, cloud, encoding); });
    PointCloud back;
    try {
      back = read(written, path);
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      fuzz::fail("what was written cannot be read back");
    }
    if (FUZZ_FORMAT == 2) {
      // STL renumbers vertices by first use and welds equal positions:
      // compare the triangles' corner positions instead.
      const FaceList a = face_list(expected), b = face_list(back);
      if (a.size() != b.size()) fuzz::fail("triangle counts differ");
      for (std::size_t k = 0; k < a.indices.size(); ++k)
        for (int d = 0; d < 3; ++d)
          if (expected.positions(a.indices[k], d) != back.positions(b.indices[k], d))
            fuzz::fail("triangle corners differ");
      continue;
    }
    fuzz::expect_same_matrix(expected.positions, back.positions, "positions differ");
    fuzz::expect_same_matrix(expected.normals, back.normals, "normals differ");
    const FaceList a = face_list(expected), b = face_list(back);
    if (FUZZ_FORMAT != 3 && (a.indices != b.indices || a.offsets != b.offsets))
      fuzz::fail("faces differ");
    if (expected.extras.size() != back.extras.size()) fuzz::fail("extras differ");
    for (std::size_t k = 0; k < expected.extras.size(); ++k)
      for (std::size_t i = 0; i < expected.extras[k].values.size(); ++i)
        if (!fuzz::same(expected.extras[k].values[i], back.extras[k].values[i]))
          fuzz::fail("extra values differ");
  }
  return 0;
}
