// libFuzzer harness for the PLY reader (src/io/read_ply.cpp, ply_header.cpp),
// with the round-trip oracle: a cloud that reads must write (binary little
// and big endian, ascii) and read back equal.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "oracle.h"
#include "read_ply.h"
#include "write_ply.h"

using namespace detexture;

namespace {

void expect_same_cloud(const PointCloud& a, const PointCloud& b) {
  fuzz::expect_same_matrix(a.positions, b.positions, "positions differ");
  fuzz::expect_same_matrix(a.normals, b.normals, "normals differ");
  if (a.comments != b.comments) fuzz::fail("comments differ");
  if (a.extras.size() != b.extras.size()) fuzz::fail("extras differ");
  for (std::size_t k = 0; k < a.extras.size(); ++k) {
    if (a.extras[k].name != b.extras[k].name || a.extras[k].type != b.extras[k].type)
      fuzz::fail("an extra's name or type differs");
    for (std::size_t i = 0; i < a.extras[k].values.size(); ++i)
      if (!fuzz::same(a.extras[k].values[i], b.extras[k].values[i]))
        fuzz::fail("extra values differ");
  }
  if (a.other_elements.size() != b.other_elements.size()) fuzz::fail("elements differ");
  for (std::size_t k = 0; k < a.other_elements.size(); ++k) {
    const OtherElement &x = a.other_elements[k], &y = b.other_elements[k];
    if (x.name != y.name || x.row_offsets != y.row_offsets ||
        x.properties.size() != y.properties.size())
      fuzz::fail("an element's name or rows differ");
    for (std::size_t p = 0; p < x.properties.size(); ++p)
      if (x.properties[p].name != y.properties[p].name ||
          x.properties[p].type != y.properties[p].type ||
          x.properties[p].is_list != y.properties[p].is_list ||
          (x.properties[p].is_list && x.properties[p].count_type != y.properties[p].count_type))
        fuzz::fail("an element's property differs");
    for (std::size_t i = 0; i < x.values.size(); ++i)
      if (!fuzz::same(x.values[i], y.values[i])) fuzz::fail("element values differ");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = "fuzz.ply";
  PointCloud cloud;
  try {
    ReadReport report;
    cloud = io_detail::read_ply(bytes, path, report);
  } catch (const std::runtime_error&) {
    return 0;  // refused with a message: fine
  }
  for (const PlyEncoding encoding :
       {PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian, PlyEncoding::Ascii}) {
    const std::string written = fuzz::written_bytes(
        [&](io_detail::OutputBuffer& out) { io_detail::write_ply(out, cloud, encoding, path); });
    PointCloud back;
    try {
      ReadReport report;
      back = io_detail::read_ply(written, path, report);
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      fuzz::fail("what was written cannot be read back");
    }
    expect_same_cloud(cloud, back);
  }
  return 0;
}
