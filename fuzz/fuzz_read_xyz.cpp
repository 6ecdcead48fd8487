// libFuzzer harness for the XYZ reader (src/io/read_xyz.cpp), with the
// round-trip oracle: a cloud that reads must write (space- and
// comma-separated) and read back equal.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "oracle.h"
#include "read_xyz.h"
#include "write_xyz.h"

using namespace detexture;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = "fuzz.xyz";
  PointCloud cloud;
  try {
    ReadReport report;
    cloud = io_detail::read_xyz(bytes, path, report);
  } catch (const std::runtime_error&) {
    return 0;
  }
  for (const char separator : {' ', ','}) {
    const std::string written = fuzz::written_bytes(
        [&](io_detail::OutputBuffer& out) { io_detail::write_xyz(out, cloud, separator); });
    PointCloud back;
    try {
      ReadReport report;
      back = io_detail::read_xyz(written, path, report);
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      fuzz::fail("what was written cannot be read back");
    }
    fuzz::expect_same_matrix(cloud.positions, back.positions, "positions differ");
    fuzz::expect_same_matrix(cloud.normals, back.normals, "normals differ");
    if (cloud.extras.size() != back.extras.size()) fuzz::fail("extra columns differ");
    for (std::size_t k = 0; k < cloud.extras.size(); ++k)
      for (std::size_t i = 0; i < cloud.extras[k].values.size(); ++i)
        if (!fuzz::same(cloud.extras[k].values[i], back.extras[k].values[i]))
          fuzz::fail("extra values differ");
  }
  return 0;
}
